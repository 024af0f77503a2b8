// Shared plumbing for links over a SerialPort (private).
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "leafdig/devices/errors.hpp"
#include "leafdig/devices/transports/serial_port.hpp"

namespace leafdig::devices::detail {

using PortOpener = std::function<std::unique_ptr<SerialPort>(const std::string&, const SerialSettings&)>;

inline PortOpener orDefault(PortOpener o) {
  if (o) return o;
  return [](const std::string& p, const SerialSettings& s) { return openSerialPort(p, s); };
}

// Reads for `d` and returns everything received.
inline std::string readFor(SerialPort& port, std::chrono::milliseconds d) {
  std::string got;
  const auto end = std::chrono::steady_clock::now() + d;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    const auto b = port.read(4096, left);
    got.append(b.begin(), b.end());
  }
  return got;
}

// Reads until `done(buffer)` or the timeout; returns the buffer.
template <class Pred>
std::string readUntil(SerialPort& port, std::chrono::milliseconds timeout, Pred done) {
  std::string got;
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (!done(got)) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    const auto b = port.read(4096, std::min(left, std::chrono::milliseconds(50)));
    got.append(b.begin(), b.end());
  }
  return got;
}

// Reads until the line has been quiet for `quiet` (at most `limit`).
inline void drain(SerialPort& port, std::chrono::milliseconds quiet, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end)
    if (port.read(4096, quiet).empty()) return;
}

inline void sleepFor(double seconds) {
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

}  // namespace leafdig::devices::detail
