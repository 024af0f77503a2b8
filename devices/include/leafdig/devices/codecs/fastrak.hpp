// Polhemus FASTRAK (and InterSense, same dialect) records: ASCII fixed columns and binary.
// Pure functions over bytes; the decoder's state is the small struct below.
// Byte layouts: docs/devices.md ("Digitizers").
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "leafdig/devices/sample.hpp"

namespace leafdig::devices::fastrak {

// Output-list items we understand (manual p.57): 0 space, 1 CR LF, 2 x,y,z, 4 az,el,roll,
// 11 quaternion, 16 stylus switch, 52/54 extended-precision x,y,z / az,el,roll.
struct Format {
  std::vector<int> items{2, 4, 1};  // the power-on default list
  bool binary = false;
  bool centimetres = false;  // false: inches (power-on default)
  int stations = 1;          // records for stations 1..stations are accepted
};

// Record length in bytes for a list; throws std::invalid_argument for an unknown item.
[[nodiscard]] std::size_t recordLength(const Format& format);
// "O1,2,4,16,1\r" for station 1.
[[nodiscard]] std::string outputListCommand(const Format& format, int station = 1);

struct DecoderState {
  Format format;
  std::string pending;       // bytes not yet consumed
  bool synced = true;        // at a record boundary (the stream start, or a record just ended)
  char lastConsumed = '\n';  // the byte before `pending` (a line end makes a boundary)
  DecodeStats stats;
};

// Appends every complete, valid record in `bytes` (plus what was pending) to `out`.
// Invalid records are dropped and counted; "2..." reply lines are skipped and counted.
void decode(DecoderState& state, std::span<const std::uint8_t> bytes, std::vector<StylusSample>& out);

// Encoding, for the emulator and the tests: the record a FASTRAK sends for this sample
// (position in the format's unit, status "ok" → space, otherwise its first letter).
[[nodiscard]] std::string encode(const Format& format, const StylusSample& sample);

// The 'S' status record ("21S…", 55 bytes with CR LF) and its parse.
struct Status {
  int station = 1;
  bool binary = false, centimetres = false, compensation = false, continuous = false;
};
[[nodiscard]] std::string encodeStatus(const Status& status);
// Returns false unless `line` is a well-formed status record.
[[nodiscard]] bool parseStatus(std::string_view line, Status& status);

}  // namespace leafdig::devices::fastrak
