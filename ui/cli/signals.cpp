#include "signals.hpp"

#include <atomic>
#include <csignal>

#include "leafdig/db/event_store.hpp"

namespace leafdig::cli {
namespace {

std::atomic<bool> signalled{false};
std::atomic<bool> captureRunning{false};

void onSignal(int /*signal*/) {
  signalled = true;
  if (!captureRunning) db::requestInterrupt();
}

}  // namespace

void installSignalHandlers() {
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
}

bool interrupted() {
  return signalled;
}

void setCaptureRunning(bool running) {
  captureRunning = running;
}

}  // namespace leafdig::cli
