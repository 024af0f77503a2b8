// leafdig's commands in one table. Each command file registers its commands (the CLI11
// subcommand and the function that runs it; main.cpp calls every family's add…Commands, so
// this file includes none of them); main parses once, and the table runs the one
// command chosen inside the one error map (failure.hpp) and returns its exit code.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace leafdig::cli {

class CommandTable {
 public:
  using Run = std::function<int()>;

  // `command` is a leaf of the command tree (`capture`, `sessions approve`); `run` returns
  // the exit code and throws what failed. `inputContext` goes before a bad input's message
  // ("cannot export: ").
  void add(CLI::App* command, Run run, std::string inputContext = {});

  // After parsing: runs the command CLI11 chose; a failure is reported on `err` through the
  // error map. Returns the process's exit code (1 if no registered command was chosen).
  [[nodiscard]] int run(std::ostream& err) const;

  // Every registered command's full name ("sessions approve"), in registration order.
  [[nodiscard]] std::vector<std::string> names() const;

 private:
  struct Entry {
    CLI::App* command;
    Run run;
    std::string inputContext;
  };
  std::vector<Entry> entries_;
};

// A seed as typed: a whole number from 0 to 18446744073709551615 (2^64 - 1). CLI11 alone would
// turn -1 or 2^64 into 2^64 - 1 without a word.
inline CLI::Validator seedText() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits =
            !text.empty() && text.size() <= 20 && text.find_first_not_of("0123456789") == std::string::npos;
        if (digits && (text.size() < 20 || text <= "18446744073709551615")) return {};
        return "a seed is a whole number from 0 to 18446744073709551615, not " + text;
      },
      "SEED");
}

}  // namespace leafdig::cli
