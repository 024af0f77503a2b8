// MicroScribe legacy serial HCI (docs/devices.md). Only packet headers have the
// top bit set; data bytes carry 7 bits, angles arrive as two 7-bit bytes (hi, lo).
// Kinematics: modified (Craig) Denavit-Hartenberg, joint i transform
//   RotX(alpha_i) · TransX(a_i) · RotZ(theta_i) · TransZ(d_i), tip at tipOffset along z6.
#include "leafdig/devices/codecs/microscribe.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace leafdig::devices::microscribe {
namespace {

constexpr double kMmPerMilliInch = 0.0254;

std::int16_t angleToI16(double deg) {
  const double v = std::round(deg / 180.0 * 32768.0);
  return static_cast<std::int16_t>(std::clamp(v, -32768.0, 32767.0));
}
void put16(std::vector<std::uint8_t>& out, std::int32_t v) {
  const auto u = static_cast<std::uint16_t>(v);
  out.push_back(static_cast<std::uint8_t>(u >> 8));
  out.push_back(static_cast<std::uint8_t>(u & 0xff));
}
std::int16_t get16(std::span<const std::uint8_t> b, std::size_t i) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>((b[i] << 8) | b[i + 1]));
}

Eigen::Isometry3d jointTransform(double alphaDeg, double a, double thetaDeg, double d) {
  constexpr double k = std::numbers::pi / 180.0;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.rotate(Eigen::AngleAxisd(alphaDeg * k, Eigen::Vector3d::UnitX()));
  t.translate(Eigen::Vector3d(a, 0, 0));
  t.rotate(Eigen::AngleAxisd(thetaDeg * k, Eigen::Vector3d::UnitZ()));
  t.translate(Eigen::Vector3d(0, 0, d));
  return t;
}

}  // namespace

Arm referenceArm() {
  Arm arm;
  arm.alphaDeg = {0, -90, 0, -90, 90, -90};
  arm.aMm = {0, 0, 260.40, 24.31, 0, 0};
  arm.dMm = {210.82, 0, 0, 234.85, 0, 134.01};  // d5: the standard stylus tip
  arm.countsPerRev = {16384, 16384, 16384, 16384, 16384, 16384};
  arm.tipOffsetMm = 0.0;
  // What the arm reports is quantised (int16 angles, 0.001 in lengths): use the same values
  // the host will decode, so emulator and driver agree to the bit.
  Arm q;
  (void)decodeDhParams(encodeDhParams(arm), q);
  q.countsPerRev = arm.countsPerRev;
  q.tipOffsetMm = arm.tipOffsetMm;
  return q;
}

std::vector<std::uint8_t> encodeDhParams(const Arm& arm) {
  std::vector<std::uint8_t> out;
  for (double a : arm.alphaDeg) put16(out, angleToI16(a));
  for (double a : arm.aMm) put16(out, static_cast<std::int32_t>(std::lround(a / kMmPerMilliInch)));
  for (double d : arm.dMm) put16(out, static_cast<std::int32_t>(std::lround(d / kMmPerMilliInch)));
  return out;
}

bool decodeDhParams(std::span<const std::uint8_t> b, Arm& arm) {
  if (b.size() != 36) return false;
  for (std::size_t i = 0; i < 6; ++i) {
    arm.alphaDeg[i] = get16(b, 2 * i) / 32768.0 * 180.0;
    arm.aMm[i] = get16(b, 12 + 2 * i) * kMmPerMilliInch;
    arm.dMm[i] = get16(b, 24 + 2 * i) * kMmPerMilliInch;
  }
  return true;
}

std::vector<std::uint8_t> encodeMaxCounts(const Arm& arm) {
  std::vector<std::uint8_t> out;
  for (int c : arm.countsPerRev) put16(out, c - 1);
  return out;
}

bool decodeMaxCounts(std::span<const std::uint8_t> b, Arm& arm) {
  if (b.size() != 12) return false;
  for (std::size_t i = 0; i < 6; ++i) {
    const int c = static_cast<std::uint16_t>(get16(b, 2 * i)) + 1;
    if (c < 2 || c > 16384) return false;  // 14-bit packets cannot carry more
    arm.countsPerRev[i] = c;
  }
  return true;
}

Vec3 forwardKinematics(const Arm& arm, const std::array<double, 6>& j, Vec3* direction) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < 6; ++i) t = t * jointTransform(arm.alphaDeg[i], arm.aMm[i], j[i], arm.dMm[i]);
  const Eigen::Vector3d tip = t * Eigen::Vector3d(0, 0, arm.tipOffsetMm);
  if (direction) {
    const Eigen::Vector3d z = t.linear().col(2);
    *direction = {z.x(), z.y(), z.z()};
  }
  return {tip.x(), tip.y(), tip.z()};
}

bool inverseKinematics(const Arm& arm, const Vec3& target, std::array<double, 6>& j) {
  const Eigen::Vector3d goal(target[0], target[1], target[2]);
  for (int iter = 0; iter < 200; ++iter) {
    const Vec3 p = forwardKinematics(arm, j);
    const Eigen::Vector3d e = goal - Eigen::Vector3d(p[0], p[1], p[2]);
    if (e.norm() < 1e-3) return true;
    Eigen::Matrix<double, 3, 6> jac;
    for (std::size_t k = 0; k < 6; ++k) {
      auto q = j;
      q[k] += 1e-4;
      const Vec3 pk = forwardKinematics(arm, q);
      jac.col(static_cast<Eigen::Index>(k)) =
          (Eigen::Vector3d(pk[0], pk[1], pk[2]) - Eigen::Vector3d(p[0], p[1], p[2])) / 1e-4;
    }
    const double lambda = 1.0;
    const Eigen::Matrix3d a = jac * jac.transpose() + lambda * Eigen::Matrix3d::Identity();
    const Eigen::Matrix<double, 6, 1> dq = jac.transpose() * a.ldlt().solve(e);
    for (std::size_t k = 0; k < 6; ++k) j[k] += std::clamp(dq(static_cast<Eigen::Index>(k)), -10.0, 10.0);
  }
  const Vec3 p = forwardKinematics(arm, j);
  return std::hypot(p[0] - target[0], p[1] - target[1], p[2] - target[2]) < 0.01;
}

std::vector<std::uint8_t> encodePacket(const Packet& p) {
  std::vector<std::uint8_t> out{static_cast<std::uint8_t>(0x80 | kCmdAngles6),
                                static_cast<std::uint8_t>(p.buttons & 0x7f)};
  for (int c : p.counts) {
    const int v = c & 0x3fff;
    out.push_back(static_cast<std::uint8_t>(v >> 7));
    out.push_back(static_cast<std::uint8_t>(v & 0x7f));
  }
  return out;
}

void decode(DecoderState& st, std::span<const std::uint8_t> bytes, std::vector<StylusSample>& out) {
  st.pending.insert(st.pending.end(), bytes.begin(), bytes.end());
  const auto& p = st.pending;
  constexpr std::size_t kLen = 14;
  std::size_t pos = 0;
  while (pos < p.size()) {
    if (p[pos] != (0x80 | kCmdAngles6)) {
      ++st.stats.discardedBytes;
      ++pos;
      continue;
    }
    if (p.size() - pos < kLen) break;
    bool ok = true;
    std::size_t bad = 0;
    for (std::size_t i = 1; i < kLen && ok; ++i)
      if (p[pos + i] & 0x80) {
        ok = false;
        bad = i;
      }
    if (!ok) {  // a header inside: this packet was truncated
      ++st.stats.dropped;
      pos += bad;
      continue;
    }
    Packet pk;
    pk.buttons = p[pos + 1];
    std::array<double, 6> joints{};
    for (std::size_t k = 0; k < 6; ++k) {
      pk.counts[k] = (p[pos + 2 + 2 * k] << 7) | p[pos + 3 + 2 * k];
      if (pk.counts[k] >= st.arm.countsPerRev[k] || st.arm.countsPerRev[k] <= 0)
        ok = false;
      else
        joints[k] = 360.0 * pk.counts[k] / st.arm.countsPerRev[k];
    }
    if (!ok || (pk.buttons & ~0x03) != 0) {
      ++st.stats.dropped;
      pos += 1;
      continue;
    }
    StylusSample s;
    s.positionMm = forwardKinematics(st.arm, joints);
    s.button = (pk.buttons & 0x03) != 0;
    s.rawUnit = "mm";
    s.raw.assign(reinterpret_cast<const char*>(p.data() + pos), kLen);
    ++st.stats.records;
    out.push_back(std::move(s));
    pos += kLen;
  }
  st.pending.erase(st.pending.begin(), st.pending.begin() + static_cast<std::ptrdiff_t>(pos));
}

}  // namespace leafdig::devices::microscribe
