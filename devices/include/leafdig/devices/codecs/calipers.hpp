// Caliper and gauge codecs. Pure functions over bytes with their state in small structs.
// Formats and sources: docs/devices.md ("Calipers").
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "leafdig/devices/sample.hpp"

namespace leafdig::devices::calipers {

// Parses a gauge's number text ("-12.34", "+012,345", " 1.5mm", "0.0450in"). Accepts '.' or
// ',' as the decimal mark and an optional unit suffix. Returns nullopt for anything else.
struct Number {
  double value = 0;
  std::string unit;
};
[[nodiscard]] std::optional<Number> parseNumber(std::string_view text);

// ---- HID boot-keyboard reports (keyboard-wedge gauges, Mitutoyo USB-ITN keyboard mode) --
// Edge-triggered: a key counts when its usage appears that was not in the previous report.
// Digits from the main row or the keypad, '-', '+' (Shift+'=' or KP '+'), '.', ',', letters
// for unit suffixes; Enter, KP Enter or Tab end a reading.
struct HidKeyboardState {
  bool reportId = false;            // reports start with a report-ID byte
  std::string defaultUnit = "mm";   // when the gauge types no unit
  std::set<std::uint8_t> previous;  // usages down in the previous report
  std::string text;                 // typed so far
  DecodeStats stats;
};
void decodeHidReport(HidKeyboardState& state, std::span<const std::uint8_t> report, std::vector<CaliperReading>& out);
// The reports a keyboard wedge sends to type `text` (press + release per character).
// `keypad` uses keypad usages for digits, '.', '-' and Enter.
[[nodiscard]] std::vector<std::vector<std::uint8_t>> encodeHidText(const std::string& text, bool keypad = false,
                                                                   bool reportId = false);

// ---- Mitutoyo standard ASCII: "01A+0000.123\r"; errors "91<code>\r" ---------------------
struct MitutoyoState {
  std::string unit = "mm";  // "mm", "in", or "auto": 5 decimals or more means inch
  std::string pending;
  DecodeStats stats;
  std::vector<std::string> errors;  // gauge error replies seen ("91" + code)
};
void decodeMitutoyo(MitutoyoState& state, std::span<const std::uint8_t> bytes, std::vector<CaliperReading>& out);
[[nodiscard]] std::string encodeMitutoyo(double value, int decimals, int channel = 1);

// ---- Mitutoyo U-WAVE: "DT1" group(2) channel(2) ±value unit(M|I|0) CR -------------------
struct UWaveState {
  std::string defaultUnit = "mm";
  std::string pending;
  DecodeStats stats;
};
void decodeUWave(UWaveState& state, std::span<const std::uint8_t> bytes, std::vector<CaliperReading>& out);
[[nodiscard]] std::string encodeUWave(double value, const std::string& unit, int group = 0, int channel = 5);

// ---- Digimatic SPC: 13 nibbles (F F F F sign d1..d6 point unit) --------------------------
// `nibbles` holds one nibble per byte (0..15). Returns nullopt for an invalid frame.
[[nodiscard]] std::optional<CaliperReading> decodeDigimatic(std::span<const std::uint8_t> nibbles);
[[nodiscard]] std::array<std::uint8_t, 13> encodeDigimatic(double value, int decimals, bool inch);
// The 52 bits on the wire, each nibble LSB first (one bit per byte, 0/1).
[[nodiscard]] std::vector<std::uint8_t> digimaticBits(const std::array<std::uint8_t, 13>& nibbles);
[[nodiscard]] std::optional<std::array<std::uint8_t, 13>> digimaticNibbles(std::span<const std::uint8_t> bits);

// ---- Sylvac: "+012.345\r" (sign may be a space), "ERR0".."ERR3", "SY…" identification,
// command echoes; tolerance flags '<' '=' '>' appended.
struct SylvacState {
  std::string unit = "mm";  // follows MM / IN replies and commands seen
  std::string pending;
  DecodeStats stats;
  std::vector<std::string> errors;  // "ERR0".."ERR3"
  std::string identification;       // last "SY…" or ID? reply
};
void decodeSylvac(SylvacState& state, std::span<const std::uint8_t> bytes, std::vector<CaliperReading>& out);
[[nodiscard]] std::string encodeSylvac(double value, int decimals);
[[nodiscard]] const char* sylvacErrorMeaning(char code);  // '0'..'3'

}  // namespace leafdig::devices::calipers
