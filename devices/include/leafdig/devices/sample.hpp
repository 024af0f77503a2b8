// What devices deliver: stylus samples and caliper readings, each stamped once with a
// monotonic time at capture and carrying the raw record it was decoded from.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace leafdig::devices {

using Clock = std::chrono::steady_clock;
using Vec3 = std::array<double, 3>;

struct StylusSample {
  Clock::time_point t{};  // monotonic, taken once when the bytes arrived
  // When the device took the record, by its own clock (RecordClock: a streaming digitizer's
  // record count at its rate); absent where the protocol gives nothing better than arrival.
  std::optional<Clock::time_point> deviceTime;
  int station = 1;                                  // receiver / arm number (1-based)
  Vec3 positionMm{};                                // device frame, millimetres
  std::optional<Vec3> orientationDeg;               // azimuth, elevation, roll (degrees)
  std::optional<std::array<double, 4>> quaternion;  // w, x, y, z
  bool button = false;                              // stylus switch / pedal held
  std::string status = "ok";                        // "ok" or the device's status code
  std::string rawUnit;                              // unit on the wire: "in", "cm" or "mm"
  std::string raw;                                  // the record's bytes exactly as received
  // The first sample the driver delivers after it (re)connected: the stream broke before it (a
  // reset, an unplug, a stall) and a press that was under way is lost, whatever the button
  // says now.
  bool streamBegins = false;
};

struct CaliperReading {
  Clock::time_point t{};
  double valueMm = 0.0;   // normalised
  double rawValue = 0.0;  // as printed by the gauge, in `unit`
  std::string unit;       // "mm" or "in": the unit on the wire
  std::string flag;       // gauge flag (Sylvac tolerance '<' '=' '>'), empty when none
  std::string raw;        // the record's bytes exactly as received
};

// Counters every codec keeps. A record that fails validation is dropped and counted; bytes
// skipped while resynchronising are counted; nothing corrupt becomes a sample.
struct DecodeStats {
  std::uint64_t records = 0;         // valid records delivered
  std::uint64_t dropped = 0;         // records that failed validation
  std::uint64_t discardedBytes = 0;  // bytes skipped while looking for a record start
  std::uint64_t statusWarnings = 0;  // valid records whose status byte was not "ok"
  std::uint64_t replies = 0;         // non-sample lines (command replies, banners) seen
};

// Raw record as printable text: printable ASCII kept, CR/LF/TAB as \r \n \t, anything
// else as \xNN (a backslash as \\). Safe to store and to put in JSON. With `keepLineEnds`
// CR, LF and TAB stay as they are (for JSON, which escapes them itself).
[[nodiscard]] std::string printableRaw(std::string_view raw, bool keepLineEnds = false);

constexpr double kMmPerInch = 25.4;

}  // namespace leafdig::devices
