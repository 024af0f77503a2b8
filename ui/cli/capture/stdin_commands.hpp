// Commands on standard input for the captures (keys in a terminal, lines from a script): a
// thread reads lines until stopped or the input ends, and hands each line that is not blank to
// `onLine` (on that thread). The end of input stops nothing else: the capture goes on with its
// stylus and caliper.
#pragma once

#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <functional>
#include <string>
#include <thread>
#include <utility>

namespace leafdig::cli {

class StdinCommands {
 public:
  explicit StdinCommands(std::function<void(const std::string&)> onLine)
      : thread_([this, onLine = std::move(onLine)] {
          std::string line;
          while (!done_) {
            pollfd p{0, POLLIN, 0};
            if (::poll(&p, 1, 100) <= 0) continue;
            char buf[256];
            const ssize_t n = ::read(0, buf, sizeof buf);
            if (n <= 0) return;
            line.append(buf, static_cast<std::size_t>(n));
            for (auto nl = line.find('\n'); nl != std::string::npos; nl = line.find('\n')) {
              const std::string cmd = line.substr(0, nl);
              line.erase(0, nl + 1);
              if (cmd.find_first_not_of(" \t\r") != std::string::npos) onLine(cmd);
            }
          }
        }) {}
  StdinCommands(const StdinCommands&) = delete;
  StdinCommands& operator=(const StdinCommands&) = delete;
  ~StdinCommands() { stop(); }
  // Stops reading (within 0.1 s) and joins. Idempotent.
  void stop() {
    done_ = true;
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::atomic<bool> done_{false};
  std::thread thread_;
};

}  // namespace leafdig::cli
