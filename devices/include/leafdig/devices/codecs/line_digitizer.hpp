// A configurable line digitizer: any device that sends one record per line (or per fixed
// length, or after sync bytes) with x, y, z (and optionally angles, a button, a status).
// Configured by a JSON file (docs/devices.md, "Generic line digitizer"), e.g.
//   {"init": ["c", "*0.2", "u", "O1,2,16,1\r"], "poll": "P", "start": "C", "stop": "c",
//    "framing": {"terminator": "\r\n", "max_length": 200},
//    "fields": {"mode": "columns", "x": [3,7], "y": [10,7], "z": [17,7], "button": [24,2]},
//    "unit": "cm", "axes": ["x", "y", "-z"], "baud": 115200}
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <regex>
#include <span>
#include <string>
#include <vector>

#include "leafdig/devices/sample.hpp"

namespace leafdig::devices::line {

enum class FieldMode { Columns, Tokens, Regex };

struct Field {  // Columns: {start, width}; Tokens: {index, 0}; Regex: {group, 0}
  int a = -1, b = 0;
  [[nodiscard]] bool present() const { return a >= 0; }
};

struct Config {
  std::vector<std::string> init;    // sent verbatim (include "\r" where needed); "*N" sleeps N s
  std::string poll;                 // sent to request a record (polled mode), empty: stream
  std::string start, stop;          // stream on / off
  std::string terminator = "\r\n";  // framing by terminator, or
  std::size_t length = 0;           // fixed length (when > 0), optionally after
  std::string sync;                 //   sync bytes at the start of every record
  std::size_t maxLength = 256;      // longer lines are dropped
  FieldMode mode = FieldMode::Tokens;
  std::string regex;  // ECMAScript, for FieldMode::Regex
  Field x{0}, y{1}, z{2}, az, el, roll, button, station, status;
  std::string tokenSeparators = " \t,;";
  double scaleToMm = 1.0;  // from "unit": mm 1, cm 10, in 25.4, m 1000
  std::string unit = "mm";
  std::array<int, 3> axisMap{0, 1, 2};  // output axis i takes input axis axisMap[i]
  std::array<double, 3> axisSign{1, 1, 1};
  std::string okStatus;  // status text meaning "fine" (empty: any)
  int baud = 9600;
};

// Parses the JSON configuration; throws std::invalid_argument naming the bad key.
[[nodiscard]] Config parseConfig(const std::string& jsonText);

struct DecoderState {
  Config config;
  std::optional<std::regex> compiled;  // built on first use
  std::string pending;
  DecodeStats stats;
};

void decode(DecoderState& state, std::span<const std::uint8_t> bytes, std::vector<StylusSample>& out);

// One record's text → sample; false when a field is missing or not a number.
[[nodiscard]] bool parseRecord(DecoderState& state, const std::string& record, StylusSample& s);

}  // namespace leafdig::devices::line
