#pragma once
// One error type per failure class at the model boundary. The command line maps them to
// exit codes: InputError -> 2 (the user's file or options must change), IoError -> 1.
#include <stdexcept>
#include <string>

namespace leafdig::model {

// The input (a marker file, an option) is wrong. The message names where (file, row,
// point, key) and what to do; it is shown to the user as it is.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reading or writing a file failed in the operating system (disk full, permission, ...).
// The message carries the path and the OS's own words.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Something doubtful that was still produced (never a NaN in the output): a capture that
// looks wrong (a row reversed, the last row not at the base), or geometry that had to be
// mended (an envelope that does not exist at some parameter, a radius overshooting below 0).
struct Warning {
  std::string name{};      // the kind as a word, e.g. "last-row-not-at-base" (empty for geometry)
  std::string message{};   // operator-readable, says what was done instead
  std::string organ{};     // geometry: the organ, e.g. "midrib", "lateral-3-left"
  double parameter = 0.0;  // geometry: the first parameter t where it happens
};

}  // namespace leafdig::model
