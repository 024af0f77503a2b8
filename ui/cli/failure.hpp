// The one map from every failure the command line meets to the README's exit code and the
// words it prints (docs/decisions.md, "One error map, one command table, one signal handler"). Commands throw; the
// command table (commands.hpp) catches once and reports through here.
//
//   family                        exit  words
//   bad input (model::InputError,  2    the message as it is (it names file, row, point
//     std::invalid_argument,              and what to do)
//     acquisition::SessionError,
//     a device's Config error)
//   a store's refusal (StoreError  2    message and "what to do"
//     NotLeafdig, TooNew, Corrupt,
//     Input, Refused, Tampered)
//   I/O, disk full, busy,          1    message (with the OS's words) and "what to do"
//     unreachable, a device
//   interrupted (a signal)        130   message
//   anything else                  1    "internal error: …" (a bug: please report it)
#pragma once

#include <exception>
#include <iosfwd>
#include <string>

namespace leafdig::cli {

struct Failure {
  int exitCode = 1;
  std::string family;   // "input", "refused", "io", "interrupted", "internal" (for tests)
  std::string message;  // one line, without "leafdig: "
  std::string remedy;   // "what to do", or empty
};

// What `error` is, in the map above. `inputContext` goes before the message of a bad
// input ("cannot export: ").
[[nodiscard]] Failure describeFailure(const std::exception_ptr& error, const std::string& inputContext = {});

// Prints the failure ("leafdig: …" and "  what to do: …") to `out` and returns its exit code.
int reportFailure(const std::exception_ptr& error, std::ostream& out, const std::string& inputContext = {});

}  // namespace leafdig::cli
