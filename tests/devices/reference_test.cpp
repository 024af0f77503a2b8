// The reference receiver (issue 29): receiver poses and the frame change against hand-solved
// cases, the pairing of stylus and reference records (a turning pot, a dropped reference record,
// a jump, a silent receiver), and the FASTRAK emulator with two receivers over a real
// pseudo-terminal — read by our driver, and by VRPN's vrpn_Tracker_Fastrak command sequence and
// record rules (docs/devices.md, "A reference receiver": VRPN), parsed here as VRPN does.
#include "leafdig/devices/links/reference.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>

#include "device_test_support.hpp"
#include "leafdig/devices/links/links.hpp"
#include "leafdig/devices/pose.hpp"
#include "leafdig/devices/transports/serial_port.hpp"

namespace dev = leafdig::devices;
using dev::Vec3;
using dev::testing::Collector;
using dev::testing::dist;
using namespace std::chrono_literals;

namespace {

constexpr double kRad = 3.14159265358979323846 / 180.0;

Vec3 apply(const dev::Rotation& r, const Vec3& v) {
  return {r[0] * v[0] + r[1] * v[1] + r[2] * v[2], r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
          r[6] * v[0] + r[7] * v[1] + r[8] * v[2]};
}

void expectNear(const Vec3& got, const Vec3& want, double tol) {
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], tol) << "component " << i;
}

dev::StylusSample record(int station, const Vec3& p, const Vec3& euler, std::string raw = "r") {
  dev::StylusSample s;
  s.station = station;
  s.positionMm = p;
  s.orientationDeg = euler;
  s.raw = std::move(raw);
  return s;
}

// A point fixed on a pot that turns by `deg` about the vertical through `centre`, with the
// reference receiver fixed on the pot at `ref0` / `euler0` (before the turn): both records of
// one output cycle as the transmitter reports them.
struct TurningPot {
  Eigen::Vector3d centre{20, -30, -100}, ref0{-90, -100, -140}, point0{35, 10, 60};
  Vec3 euler0{35, 12, -8};
  [[nodiscard]] Eigen::Isometry3d turn(double deg) const {
    return Eigen::Translation3d(centre) * Eigen::AngleAxisd(deg * kRad, Eigen::Vector3d::UnitZ()) *
           Eigen::Translation3d(-centre);
  }
  [[nodiscard]] dev::StylusSample stylus(double deg) const {
    const Eigen::Vector3d p = turn(deg) * point0;
    return record(1, {p.x(), p.y(), p.z()}, {0, 0, 0}, "S");
  }
  [[nodiscard]] dev::StylusSample reference(double deg) const {
    const Eigen::Vector3d p = turn(deg) * ref0;
    const dev::Rotation r0 = dev::rotationFromEulerDeg(euler0);
    Eigen::Matrix3d m;
    m << r0[0], r0[1], r0[2], r0[3], r0[4], r0[5], r0[6], r0[7], r0[8];
    const Eigen::Matrix3d turned = turn(deg).linear() * m;
    const dev::Rotation rt{turned(0, 0), turned(0, 1), turned(0, 2), turned(1, 0), turned(1, 1),
                           turned(1, 2), turned(2, 0), turned(2, 1), turned(2, 2)};
    return record(2, {p.x(), p.y(), p.z()}, dev::eulerDegFromRotation(rt), "R");
  }
  // The point in the reference receiver's frame, worked out from the pot before it turned.
  [[nodiscard]] Vec3 inReference() const {
    const dev::Rotation r0 = dev::rotationFromEulerDeg(euler0);
    const Eigen::Vector3d d = point0 - ref0;
    // R^T d
    return {r0[0] * d.x() + r0[3] * d.y() + r0[6] * d.z(), r0[1] * d.x() + r0[4] * d.y() + r0[7] * d.z(),
            r0[2] * d.x() + r0[5] * d.y() + r0[8] * d.z()};
  }
};

}  // namespace

// ---- poses ----------------------------------------------------------------------------------
TEST(ReceiverPose, EulerAnglesTurnAboutZThenYThenXAsPolhemusDefinesThem) {
  // Azimuth 90°: the receiver's x axis is the transmitter's y.
  expectNear(apply(dev::rotationFromEulerDeg({90, 0, 0}), {1, 0, 0}), {0, 1, 0}, 1e-12);
  // Elevation 90°: its x axis points down the transmitter's z (rotation about y takes x to -z).
  expectNear(apply(dev::rotationFromEulerDeg({0, 90, 0}), {1, 0, 0}), {0, 0, -1}, 1e-12);
  // Roll 90°: its y axis is the transmitter's z.
  expectNear(apply(dev::rotationFromEulerDeg({0, 0, 90}), {0, 1, 0}), {0, 0, 1}, 1e-12);
  // Azimuth then elevation: x goes to y by the azimuth, and the elevation (about the receiver's
  // own y, now the transmitter's -x) tips it... worked by hand: Rz(90)·Ry(90)·x = Rz(90)·(-z) = -z.
  expectNear(apply(dev::rotationFromEulerDeg({90, 90, 0}), {1, 0, 0}), {0, 0, -1}, 1e-12);
  expectNear(apply(dev::rotationFromEulerDeg({90, 90, 0}), {0, 1, 0}), {-1, 0, 0}, 1e-12);
}

TEST(ReceiverPose, EulerAnglesAndQuaternionsRoundTrip) {
  for (const Vec3 e : {Vec3{35, 12, -8}, Vec3{-170, 80, 179}, Vec3{0.5, -89, 45}, Vec3{120, -33, -120}}) {
    const Vec3 back = dev::eulerDegFromRotation(dev::rotationFromEulerDeg(e));
    expectNear(back, e, 1e-9);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(e[0] * kRad, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(e[1] * kRad, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(e[2] * kRad, Eigen::Vector3d::UnitX()));
    EXPECT_LT(dev::rotationBetweenDeg(dev::rotationFromQuaternion({q.w(), q.x(), q.y(), q.z()}),
                                      dev::rotationFromEulerDeg(e)),
              1e-6);
  }
  EXPECT_NEAR(dev::rotationBetweenDeg(dev::rotationFromEulerDeg({10, 0, 0}), dev::rotationFromEulerDeg({40, 0, 0})),
              30.0, 1e-9);
}

TEST(ReceiverPose, AStylusSampleInTheReferenceFrameHandSolved) {
  // The reference at (100, 0, 0) turned 90° in azimuth: its x axis is the transmitter's y, so
  // the transmitter's point (100, 10, 5) is 10 mm along its x and 5 mm along its z.
  const auto ref = dev::poseOf(record(2, {100, 0, 0}, {90, 0, 0}));
  ASSERT_TRUE(ref);
  const dev::StylusSample s = dev::inFrameOf(record(1, {100, 10, 5}, {90, 0, 0}), *ref);
  expectNear(s.positionMm, {10, 0, 5}, 1e-12);
  ASSERT_TRUE(s.orientationDeg);
  expectNear(*s.orientationDeg, {0, 0, 0}, 1e-9);  // the stylus held as the reference is
  dev::StylusSample none;
  EXPECT_FALSE(dev::poseOf(none)) << "a record without angles has no pose";
}

// ---- pairing --------------------------------------------------------------------------------
TEST(ReferenceFrame, AStylusOnATurningPotStaysWhereItIsOnThePot) {
  TurningPot pot;
  dev::ReferenceFrame frame;
  std::vector<dev::StylusSample> out;
  for (int i = 0; i <= 600; ++i) {  // 30° in 600 cycles (10 s at 60 Hz)
    const double deg = 30.0 * i / 600.0;
    frame.push(pot.stylus(deg), out);
    frame.push(pot.reference(deg), out);
  }
  ASSERT_EQ(out.size(), 601u);
  const Vec3 want = pot.inReference();
  double worst = 0;
  for (const auto& s : out) worst = std::max(worst, dist(s.positionMm, want));
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(out.front().raw, "SR") << "the delivered sample keeps both records of its cycle";
  EXPECT_TRUE(frame.problem().empty());
  EXPECT_EQ(frame.stats().paired, 601u);
  // Without the reference, the same stylus wanders by the turn: 30° at 43 mm from the axis.
  EXPECT_GT(dist(pot.stylus(0).positionMm, pot.stylus(30).positionMm), 20.0);
}

TEST(ReferenceFrame, ADroppedReferenceRecordWithholdsItsCycleInsteadOfPairingAnother) {
  TurningPot pot;
  dev::ReferenceFrame frame;
  std::vector<dev::StylusSample> out;
  frame.push(pot.stylus(0), out);
  frame.push(pot.reference(0), out);
  frame.push(pot.stylus(1), out);  // its reference record is lost on the wire
  frame.push(pot.stylus(2), out);
  frame.push(pot.reference(2), out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(frame.stats().withheld, 1u);
  for (const auto& s : out) EXPECT_LT(dist(s.positionMm, pot.inReference()), 1e-9);
  EXPECT_TRUE(frame.problem().empty()) << "one lost record is not a silent receiver";
}

TEST(ReferenceFrame, AJumpPausesTheStylusWithWordsUntilTheReferenceIsStillAgain) {
  TurningPot pot;
  dev::ReferenceOptions o;
  o.steadyRecords = 5;
  dev::ReferenceFrame frame(o);
  std::vector<dev::StylusSample> out;
  frame.push(pot.stylus(0), out);
  frame.push(pot.reference(0), out);
  // The receiver is knocked: 25 mm between two records.
  dev::StylusSample knocked = pot.reference(0);
  knocked.positionMm[0] += 25.0;
  frame.push(pot.stylus(0), out);
  frame.push(knocked, out);
  EXPECT_EQ(out.size(), 1u) << "the cycle of the jump is not delivered";
  EXPECT_NE(frame.problem().find("reference receiver 2 jumped 25.0 mm"), std::string::npos) << frame.problem();
  EXPECT_NE(frame.remedy().find("hold the pot still"), std::string::npos);
  for (int i = 0; i < 4; ++i) {
    frame.push(pot.stylus(0), out);
    frame.push(knocked, out);
  }
  EXPECT_EQ(out.size(), 1u) << "paused while the reference settles";
  EXPECT_FALSE(frame.problem().empty());
  frame.push(pot.stylus(0), out);
  frame.push(knocked, out);
  EXPECT_TRUE(frame.problem().empty()) << "still for 5 records: the stylus flows again";
  EXPECT_EQ(out.size(), 2u);
  EXPECT_EQ(frame.stats().jumps, 1u);
  // A turn of more than 5° between two records is a jump too.
  frame.push(pot.stylus(0), out);
  frame.push(pot.reference(8), out);
  EXPECT_NE(frame.problem().find("8.0°"), std::string::npos) << frame.problem();
}

TEST(ReferenceFrame, ASilentReferenceReceiverPausesTheStylusAndSaysWhereToLook) {
  TurningPot pot;
  dev::ReferenceOptions o;
  o.steadyRecords = 3;
  dev::ReferenceFrame frame(o);
  std::vector<dev::StylusSample> out;
  frame.push(pot.stylus(0), out);
  frame.push(pot.reference(0), out);
  for (int i = 0; i < 7; ++i) frame.push(pot.stylus(0), out);  // the reference's cable is out
  EXPECT_EQ(out.size(), 1u);
  EXPECT_NE(frame.problem().find("reference receiver 2 stopped reporting"), std::string::npos) << frame.problem();
  EXPECT_NE(frame.remedy().find("socket 2"), std::string::npos);
  EXPECT_EQ(frame.stats().silences, 1u);
  for (int i = 0; i < 4; ++i) {
    frame.push(pot.stylus(0), out);
    frame.push(pot.reference(0), out);
  }
  EXPECT_TRUE(frame.problem().empty());
  EXPECT_GE(out.size(), 2u) << "it flows again once the reference is back and still";
  // A reference record without angles cannot hold the frame: said, nothing delivered.
  dev::StylusSample flat = pot.reference(0);
  flat.orientationDeg.reset();
  const std::size_t before = out.size();
  frame.push(pot.stylus(0), out);
  frame.push(flat, out);
  EXPECT_EQ(out.size(), before);
  EXPECT_NE(frame.problem().find("carry no orientation"), std::string::npos);
}

// ---- over a pseudo-terminal -------------------------------------------------------------------
namespace {

// The pot turning 30° in 3 s with a receiver on it, and a stylus resting on a point of the pot.
class PotReceiver final : public dev::sim::StylusMotion {
 public:
  PotReceiver(TurningPot pot, bool stylus) : pot_(pot), stylus_(stylus) {}
  [[nodiscard]] State at(double t, std::uint64_t) const override {
    const double deg = std::min(30.0, 10.0 * t);
    const dev::StylusSample s = stylus_ ? pot_.stylus(deg) : pot_.reference(deg);
    State st;
    st.positionMm = st.truthMm = s.positionMm;
    st.orientationDeg = *s.orientationDeg;
    return st;
  }

 private:
  TurningPot pot_;
  bool stylus_;
};

}  // namespace

struct ReferenceCase {
  const char* name;
  dev::DigitizerKind kind;
  bool binary;
  double toleranceMm;  // the records' resolution at the stylus' 170 mm from the receiver
};

void PrintTo(const ReferenceCase& c, std::ostream* os) {
  *os << c.name;
}

class TrackerWithAReferenceReceiver : public ::testing::TestWithParam<ReferenceCase> {};

TEST_P(TrackerWithAReferenceReceiver, TheDriverDeliversTheStylusInTheReferenceFrameOfATurningPot) {
  const ReferenceCase c = GetParam();
  TurningPot pot;
  dev::sim::EmulatorOptions eo;
  const auto stylus = std::make_shared<PotReceiver>(pot, true);
  const auto reference = std::make_shared<PotReceiver>(pot, false);
  std::unique_ptr<dev::sim::Emulator> emu;
  switch (c.kind) {
    case dev::DigitizerKind::Patriot: emu = dev::sim::makePatriot(stylus, eo, reference); break;
    case dev::DigitizerKind::Liberty: emu = dev::sim::makeLiberty(stylus, eo, reference); break;
    default: emu = dev::sim::makeFastrak(stylus, eo, reference);
  }
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.kind = c.kind;
  cfg.port = emu->path();
  cfg.binary = c.binary;
  cfg.referenceStation = 2;
  Collector col;
  dev::Driver driver(dev::makeDigitizerLink(cfg), col.callbacks());
  driver.start();
  // 60 cycles a second or more: 3.5 s covers the whole turn.
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.stylus.size() >= 210; }, 20s)) << col.statusLog();
  driver.stop();
  emu->stop();
  std::lock_guard lock(col.mutex);
  const Vec3 want = pot.inReference();
  double worst = 0;
  for (const auto& s : col.stylus) worst = std::max(worst, dist(s.positionMm, want));
  EXPECT_LT(worst, c.toleranceMm);
  EXPECT_GT(dist(pot.stylus(0).positionMm, pot.stylus(30).positionMm), 20.0);
  EXPECT_TRUE(col.sawState(dev::LinkState::Streaming, "(reference receiver 2)")) << col.statusLog();
  EXPECT_GT(col.stylus.back().raw.size(), 2 * 20U) << "both receivers' records are kept";
}

// ASCII FASTRAK records hold 0.01 cm and 0.01°: about 0.1 mm here; Polhemus ASCII columns and
// every binary record are finer.
INSTANTIATE_TEST_SUITE_P(Devices, TrackerWithAReferenceReceiver,
                         ::testing::Values(ReferenceCase{"FastrakAscii", dev::DigitizerKind::Fastrak, false, 0.2},
                                           ReferenceCase{"FastrakBinary", dev::DigitizerKind::Fastrak, true, 1e-3},
                                           ReferenceCase{"PatriotAscii", dev::DigitizerKind::Patriot, false, 0.05},
                                           ReferenceCase{"LibertyBinary", dev::DigitizerKind::Liberty, true, 1e-3}),
                         [](const auto& info) { return std::string(info.param.name); });

namespace {

// The reference receiver knocked 25 mm aside at 1 s (it slipped on the pot): a jump.
class KnockedReceiver final : public dev::sim::StylusMotion {
 public:
  [[nodiscard]] State at(double t, std::uint64_t) const override {
    State st;
    st.positionMm = st.truthMm = {-90.0 + (t >= 1.0 ? 25.0 : 0.0), -100.0, -140.0};
    st.orientationDeg = {35, 12, -8};
    return st;
  }
};

}  // namespace

// Through the driver: the knock is a warning that names the jump and the remedy, the stylus is
// withheld meanwhile, and once the receiver is still again the stream goes on.
TEST(FastrakReference, AKnockedReferenceReceiverPausesTheStylusWithWordsThroughTheDriver) {
  TurningPot pot;
  dev::sim::EmulatorOptions eo;
  auto emu = dev::sim::makeFastrak(std::make_shared<PotReceiver>(pot, true), eo, std::make_shared<KnockedReceiver>());
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.port = emu->path();
  cfg.referenceStation = 2;
  Collector col;
  dev::Driver driver(dev::makeDigitizerLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.sawState(dev::LinkState::Warning, "jumped 25.0 mm"); }, 20s))
      << col.statusLog();
  const std::size_t warnedAt = col.stylusCount();
  ASSERT_TRUE(col.waitFor(
      [](Collector& k) {
        return !k.statuses.empty() && k.statuses.back().state == dev::LinkState::Streaming &&
               k.sawState(dev::LinkState::Warning);
      },
      20s))
      << col.statusLog();
  ASSERT_TRUE(col.waitFor([&](Collector& k) { return k.stylus.size() > warnedAt + 30; }, 20s));
  driver.stop();
  emu->stop();
  std::lock_guard lock(col.mutex);
  bool remedy = false;
  for (const auto& st : col.statuses) remedy = remedy || st.remedy.find("hold the pot still") != std::string::npos;
  EXPECT_TRUE(remedy) << col.statusLog();
}

namespace {

// The reference receiver's cable pulled at 1 s: its records stop making sense (the tracker
// prints "nan" columns, which no decoder takes), the stylus' records go on.
class UnpluggedReceiver final : public dev::sim::StylusMotion {
 public:
  [[nodiscard]] State at(double t, std::uint64_t) const override {
    State st;
    const double v = t >= 1.0 ? std::nan("") : -90.0;
    st.positionMm = st.truthMm = {v, -100.0, -140.0};
    st.orientationDeg = {35, 12, -8};
    return st;
  }
};

}  // namespace

// A silent reference receiver holds the stylus back for as long as it is silent, with words
// that say where to look — and the tracker, still sending the stylus' records, is not taken for
// a stalled one (no re-initialising every second, whose words would blame the wrong cable).
TEST(FastrakReference, ASilentReferenceReceiverPausesTheStylusWithoutReinitialisingTheTracker) {
  TurningPot pot;
  dev::sim::EmulatorOptions eo;
  auto emu = dev::sim::makeFastrak(std::make_shared<PotReceiver>(pot, true), eo, std::make_shared<UnpluggedReceiver>());
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.port = emu->path();
  cfg.referenceStation = 2;
  Collector col;
  dev::Driver driver(dev::makeDigitizerLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor(
      [](Collector& k) { return k.sawState(dev::LinkState::Warning, "reference receiver 2 stopped reporting"); }, 20s))
      << col.statusLog();
  const std::size_t before = col.stylusCount();
  std::this_thread::sleep_for(2500ms);  // more than the stall watchdog's second, twice
  driver.stop();
  emu->stop();
  std::lock_guard lock(col.mutex);
  EXPECT_EQ(col.stylus.size(), before) << "nothing delivered while the reference is silent";
  EXPECT_FALSE(col.sawState(dev::LinkState::Warning, "re-initialising")) << col.statusLog();
  EXPECT_EQ(driver.status().reconnects, 0) << col.statusLog();
}

TEST(FastrakReference, AReceiverTheTrackerDoesNotHaveIsAConfigurationErrorInWords) {
  dev::sim::EmulatorOptions eo;
  auto emu = dev::sim::makeFastrak(dev::testing::quickStylus(), eo);
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.port = emu->path();
  cfg.referenceStation = 5;
  Collector col;
  dev::Driver driver(dev::makeDigitizerLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.sawState(dev::LinkState::Error); }, 10s)) << col.statusLog();
  driver.stop();
  emu->stop();
  std::lock_guard lock(col.mutex);
  EXPECT_TRUE(col.sawState(dev::LinkState::Error, "no reference receiver 5")) << col.statusLog();
  EXPECT_TRUE(col.stylus.empty());
}

// VRPN's vrpn_Tracker_Fastrak with two stations: 'c', 'S' (a 55-byte status starting '2'),
// then per station "O<st>,2,11[,16],0" (the stylus' list with its switch), "e1,0", 'f'
// (binary), 'C'. Its parser: sync on '0', the station byte in '1'..num_stations fixes the
// record's length, byte 3 a space or a letter, the last byte a space.
TEST(FastrakReference, VrpnsFastrakSequenceReadsBothStationsFromTheEmulator) {
  TurningPot pot;
  dev::sim::EmulatorOptions eo;
  auto emu =
      dev::sim::makeFastrak(std::make_shared<PotReceiver>(pot, true), eo, std::make_shared<PotReceiver>(pot, false));
  emu->start();
  dev::SerialSettings settings;
  settings.baud = 115200;
  auto port = dev::openSerialPort(emu->path(), settings);
  const auto readFor = [&](std::chrono::milliseconds d) {
    std::string got;
    const auto until = std::chrono::steady_clock::now() + d;
    while (std::chrono::steady_clock::now() < until) {
      const auto b = port->read(4096, 20ms);
      got.append(b.begin(), b.end());
    }
    return got;
  };
  port->write("c");
  (void)readFor(200ms);
  port->write("S");
  const std::string status = readFor(300ms);
  ASSERT_EQ(status.size(), 55u);
  EXPECT_EQ(status[0], '2');
  EXPECT_EQ(status.back(), '\n');
  port->write("O1,2,11,16,0\r");
  port->write("O2,2,11,0\r");
  port->write("e1,0\r");
  port->write("x0.2,0.2,0.8,0.8\r");
  port->write("f");
  port->write("C");
  const std::string stream = readFor(1500ms);
  port->write("c");
  emu->stop();
  const std::size_t length[3] = {0, 3 + 12 + 16 + 2 + 1, 3 + 12 + 16 + 1};  // 34 and 32 bytes
  int records[3] = {0, 0, 0}, resyncs = 0;
  std::size_t i = 0;
  while (i < stream.size()) {
    if (stream[i] != '0' || i + 1 >= stream.size() || stream[i + 1] < '1' || stream[i + 1] > '2') {
      ++i;
      ++resyncs;
      continue;
    }
    const int st = stream[i + 1] - '0';
    if (i + length[st] > stream.size()) break;
    const std::string r = stream.substr(i, length[st]);
    ASSERT_TRUE(r[2] == ' ' || std::isalpha(static_cast<unsigned char>(r[2])));
    ASSERT_EQ(r.back(), ' ') << "station " << st;
    float q[4];
    std::memcpy(q, r.data() + 15, sizeof q);
    EXPECT_NEAR(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), 1.0, 1e-4);
    ++records[st];
    i += length[st];
  }
  EXPECT_EQ(resyncs, 0) << "every byte belonged to a record";
  EXPECT_GT(records[1], 40);
  EXPECT_NEAR(records[2], records[1], 1) << "one record of each station per cycle";
}
