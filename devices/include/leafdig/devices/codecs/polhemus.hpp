// Polhemus Patriot and Liberty records: ASCII fixed columns and binary frames with the
// 8-byte "PA"/"LY" header. Pure functions; state in the struct.
//
// Binary frame: 'L','Y' (Liberty) or 'P','A' (Patriot), u8 station (1-based, binary),
// u8 command that produced it ('C' continuous, 'P' single), u8 error (0 = fine),
// u8 reserved, u16 LE payload size, then the payload items, little endian.
// ASCII record: station as 2 characters, 1 error character (space = fine), 1 space, then
// 9-character columns per value, CR LF (item 1). docs/devices.md lists the items.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "leafdig/devices/sample.hpp"

namespace leafdig::devices::polhemus {

enum class Model { Patriot, Liberty };
[[nodiscard]] const char* toString(Model m);

// Items: 0 space, 1 CR LF, 2 x,y,z, 5 az,el,roll, 7 quaternion, 8 timestamp (ms),
// 9 frame count, 10 stylus (bit 0), 11 distortion level (Liberty).
struct Format {
  Model model = Model::Patriot;
  std::vector<int> items{2, 5, 10, 1};
  bool binary = false;
  bool centimetres = true;
  int stations = 2;
};

[[nodiscard]] std::size_t payloadLength(const Format& format);      // binary payload bytes
[[nodiscard]] std::size_t asciiLength(const Format& format);        // ASCII record bytes
[[nodiscard]] std::string outputListCommand(const Format& format);  // "O*,2,5,10,1\r"

struct DecoderState {
  Format format;
  std::string pending;
  bool synced = true;        // at a record boundary (the stream start, or a record just ended)
  char lastConsumed = '\n';  // the byte before `pending` (a line end makes a boundary)
  DecodeStats stats;
};

void decode(DecoderState& state, std::span<const std::uint8_t> bytes, std::vector<StylusSample>& out);

// Encodes one record as the tracker sends it. `frame` and `timestampMs` fill items 8/9;
// `command` is 'C' in continuous mode and 'P' for a single record.
[[nodiscard]] std::string encode(const Format& format, const StylusSample& sample, std::uint32_t frame,
                                 std::uint32_t timestampMs, char command = 'C');

}  // namespace leafdig::devices::polhemus
