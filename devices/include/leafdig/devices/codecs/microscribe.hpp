// MicroScribe legacy serial HCI (firmware "MSCR"): handshake, configuration replies,
// 7-bit angle packets, and the host-side forward kinematics from the DH parameters the
// arm reports (SDK "Format DH0.5"; modified Denavit-Hartenberg, docs/devices.md).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "leafdig/devices/sample.hpp"

namespace leafdig::devices::microscribe {

constexpr std::uint8_t kCmdDhParams = 0xC0;     // 36 bytes: alpha0..5, a0..5, d0..5 (int16 BE)
constexpr std::uint8_t kCmdMaxCounts = 0xC6;    // 12 bytes: counts per rev - 1, 6 × u16 BE
constexpr std::uint8_t kCmdProductName = 0xC8;  // NUL-terminated strings C8..CE
constexpr std::uint8_t kCmdModel = 0xCA;
constexpr std::uint8_t kCmdSerial = 0xCB;
constexpr std::uint8_t kCmdFirmware = 0xCE;
constexpr std::uint8_t kCmdEnd = 0xC5;      // back to baud detection
constexpr std::uint8_t kCmdAngles6 = 0x03;  // button byte + 6 angles

// Physical parameters, in the arm's units: angles as int16 (−32768 = −180°), lengths in
// 0.001 inch. `counts` are encoder counts per revolution.
struct Arm {
  std::array<double, 6> alphaDeg{}, aMm{}, dMm{};
  std::array<int, 6> countsPerRev{};
  double tipOffsetMm = 0.0;  // extra tip length along z6 for a non-standard stylus
};

// A plausible 6-joint arm (MicroScribe-3DX-like lengths) used by the emulator.
[[nodiscard]] Arm referenceArm();

[[nodiscard]] std::vector<std::uint8_t> encodeDhParams(const Arm& arm);
[[nodiscard]] bool decodeDhParams(std::span<const std::uint8_t> bytes, Arm& arm);
[[nodiscard]] std::vector<std::uint8_t> encodeMaxCounts(const Arm& arm);
[[nodiscard]] bool decodeMaxCounts(std::span<const std::uint8_t> bytes, Arm& arm);

// Tip position (mm) for joint angles (degrees). Tool z axis in `direction` when non-null.
[[nodiscard]] Vec3 forwardKinematics(const Arm& arm, const std::array<double, 6>& jointsDeg, Vec3* direction = nullptr);
// Joint angles that put the tip at `target`, starting from `seed` (damped least squares).
// For the emulator; returns false when it does not converge to 0.01 mm.
[[nodiscard]] bool inverseKinematics(const Arm& arm, const Vec3& target, std::array<double, 6>& joints);

struct Packet {
  std::uint8_t buttons = 0;     // bit 0 right/single pedal, bit 1 left pedal
  std::array<int, 6> counts{};  // 14-bit encoder counts
};
[[nodiscard]] std::vector<std::uint8_t> encodePacket(const Packet& packet);

struct DecoderState {
  Arm arm;  // from the arm's C0/C6 replies
  std::vector<std::uint8_t> pending;
  DecodeStats stats;
};

// Decodes 6-angle packets (0x83 header) into samples: tip position from the kinematics,
// button = any pedal. A header byte has its top bit set, data bytes never: resync is a
// scan for the next header.
void decode(DecoderState& state, std::span<const std::uint8_t> bytes, std::vector<StylusSample>& out);

}  // namespace leafdig::devices::microscribe
