// Byte-vector tests for every codec, including the records quoted in the research notes.
#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "leafdig/devices/codecs/calipers.hpp"
#include "leafdig/devices/codecs/fastrak.hpp"
#include "leafdig/devices/codecs/line_digitizer.hpp"
#include "leafdig/devices/codecs/microscribe.hpp"
#include "leafdig/devices/codecs/polhemus.hpp"
#include "leafdig/devices/codecs/record_clock.hpp"

namespace dev = leafdig::devices;
namespace {

std::vector<std::uint8_t> bytes(const std::string& s) {
  return {s.begin(), s.end()};
}
std::vector<std::uint8_t> hex(std::initializer_list<int> v) {
  std::vector<std::uint8_t> b;
  for (int x : v) b.push_back(static_cast<std::uint8_t>(x));
  return b;
}

template <class State, class Out>
void feed(State& st, const std::string& s, Out& out, void (*fn)(State&, std::span<const std::uint8_t>, Out&)) {
  const auto b = bytes(s);
  fn(st, b, out);
}

// ---- FASTRAK ------------------------------------------------------------------------------
dev::fastrak::DecoderState fastrakDefault() {
  dev::fastrak::DecoderState st;
  st.format.items = {2, 4, 1};
  st.format.stations = 4;
  return st;
}

TEST(FastrakAscii, DecodesTheDefaultListRecordWhoseFieldsTouch) {
  // SoundScapeRenderer's record (docs/devices.md): "30.01-150.70" touch.
  auto st = fastrakDefault();
  std::vector<dev::StylusSample> out;
  feed(st, "02   20.40 -61.06  30.01-150.70 -42.08 156.93\r\n", out, dev::fastrak::decode);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].station, 2);
  EXPECT_DOUBLE_EQ(out[0].positionMm[0], 518.16);  // 20.40 in
  EXPECT_DOUBLE_EQ(out[0].positionMm[1], -1550.924);
  EXPECT_DOUBLE_EQ(out[0].positionMm[2], 762.254);
  ASSERT_TRUE(out[0].orientationDeg);
  EXPECT_DOUBLE_EQ((*out[0].orientationDeg)[0], -150.70);
  EXPECT_DOUBLE_EQ((*out[0].orientationDeg)[1], -42.08);
  EXPECT_DOUBLE_EQ((*out[0].orientationDeg)[2], 156.93);
  EXPECT_EQ(out[0].status, "ok");
  EXPECT_EQ(out[0].rawUnit, "in");
  EXPECT_EQ(out[0].raw.size(), 47u);
  EXPECT_EQ(st.stats.records, 1u);
}

TEST(FastrakAscii, DecodesRecordsSplitAtEveryByte) {
  auto st = fastrakDefault();
  std::vector<dev::StylusSample> out;
  const std::string rec = "01    1.00   2.00   3.00   0.00   0.00   0.00\r\n";
  for (char c : rec + rec) feed(st, std::string(1, c), out, dev::fastrak::decode);
  EXPECT_EQ(out.size(), 2u);
  EXPECT_EQ(st.stats.dropped + st.stats.discardedBytes, 0u);
}

TEST(FastrakAscii, KeepsAStatusLetterAsAWarningNotAnError) {
  auto st = fastrakDefault();
  std::vector<dev::StylusSample> out;
  feed(st, "01x   1.00   2.00   3.00   0.00   0.00   0.00\r\n", out, dev::fastrak::decode);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].status, "x");
  EXPECT_EQ(st.stats.statusWarnings, 1u);
}

TEST(FastrakAscii, ResynchronisesAfterGarbageAndATruncatedRecord) {
  auto st = fastrakDefault();
  std::vector<dev::StylusSample> out;
  const std::string good = "01    1.00   2.00   3.00   0.00   0.00   0.00\r\n";
  feed(st, "\xff\x13garbage 01 0\r\n" + good + good.substr(0, 20) + good + good, out, dev::fastrak::decode);
  ASSERT_EQ(out.size(), 3u);
  for (const auto& s : out) EXPECT_DOUBLE_EQ(s.positionMm[0], 25.4);
  EXPECT_GE(st.stats.dropped + st.stats.discardedBytes, 1u);
}

TEST(FastrakAscii, NeverTurnsACorruptColumnIntoAPoint) {
  auto st = fastrakDefault();
  std::vector<dev::StylusSample> out;
  // a digit replaced by a letter, a sign in the middle, a missing decimal point
  feed(st, "01    1.0a   2.00   3.00   0.00   0.00   0.00\r\n", out, dev::fastrak::decode);
  feed(st, "01    1-00   2.00   3.00   0.00   0.00   0.00\r\n", out, dev::fastrak::decode);
  feed(st, "01    1000   2.00   3.00   0.00   0.00   0.00\r\n", out, dev::fastrak::decode);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(st.stats.dropped, 3u);
}

TEST(FastrakAscii, SkipsCommandRepliesBetweenRecords) {
  auto st = fastrakDefault();
  std::vector<dev::StylusSample> out;
  const std::string good = "01    1.00   2.00   3.00   0.00   0.00   0.00\r\n";
  dev::fastrak::Status status{1, false, true, false, true};
  feed(st, good + dev::fastrak::encodeStatus(status) + "2 E*ERROR* Q *ERROR* EC -99\r\n" + good, out,
       dev::fastrak::decode);
  EXPECT_EQ(out.size(), 2u);
  EXPECT_EQ(st.stats.replies, 2u);
  EXPECT_EQ(st.stats.dropped, 0u);
}

TEST(FastrakAscii, ReadsTheStylusFromItem16) {
  dev::fastrak::DecoderState st;
  st.format.items = {2, 4, 16, 1};
  st.format.centimetres = true;
  std::vector<dev::StylusSample> out;
  feed(st, "01   -0.09  -0.16   0.03  10.03 -45.46   0.16 1\r\n", out, dev::fastrak::decode);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].button);
  EXPECT_DOUBLE_EQ(out[0].positionMm[0], -0.9);
  EXPECT_EQ(out[0].rawUnit, "cm");
  EXPECT_EQ(dev::fastrak::recordLength(st.format), 49u);
  EXPECT_EQ(dev::fastrak::outputListCommand(st.format), "O1,2,4,16,1\r");
}

TEST(FastrakBinary, DecodesTheResearchNotesExample) {
  // x=10.0 y=-5.5 z=3.25 q=(1,0,0,0), list 2,11,0 (docs/devices.md)
  dev::fastrak::DecoderState st;
  st.format.items = {2, 11, 0};
  st.format.binary = true;
  std::vector<dev::StylusSample> out;
  const auto b = hex({0x30, 0x31, 0x20, 0x00, 0x00, 0x20, 0x41, 0x00, 0x00, 0xb0, 0xc0, 0x00, 0x00, 0x50, 0x40, 0x00,
                      0x00, 0x80, 0x3f, 0,    0,    0,    0,    0,    0,    0,    0,    0,    0,    0,    0,    0x20});
  ASSERT_EQ(b.size(), 32u);
  dev::fastrak::decode(st, b, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].positionMm[0], 254.0);
  EXPECT_DOUBLE_EQ(out[0].positionMm[1], -139.7);
  EXPECT_DOUBLE_EQ(out[0].positionMm[2], 82.55);
  ASSERT_TRUE(out[0].quaternion);
  EXPECT_DOUBLE_EQ((*out[0].quaternion)[0], 1.0);
}

TEST(FastrakBinary, RejectsAFlippedQuaternionAndATrailerMismatch) {
  dev::fastrak::Format f;
  f.items = {2, 11, 16, 0};
  f.binary = true;
  dev::StylusSample s;
  s.positionMm = {10, 20, 30};
  s.quaternion = std::array<double, 4>{0.5, 0.5, 0.5, 0.5};
  const std::string rec = dev::fastrak::encode(f, s);
  EXPECT_EQ(rec.size(), 34u);
  dev::fastrak::DecoderState st;
  st.format = f;
  std::vector<dev::StylusSample> out;
  std::string flipped = rec;
  flipped[17] ^= 0x40;  // inside the quaternion: the norm is no longer 1
  std::string trailer = rec;
  trailer.back() = 'X';
  feed(st, flipped, out, dev::fastrak::decode);
  feed(st, trailer, out, dev::fastrak::decode);
  feed(st, rec, out, dev::fastrak::decode);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].positionMm[0], 10.0, 1e-4);
}

TEST(FastrakEncode, RoundTripsEveryItemInAsciiAndBinary) {
  for (bool binary : {false, true}) {
    dev::fastrak::Format f;
    f.items = {2, 4, 11, 16, 52, 54, 0, 1};
    f.binary = binary;
    f.centimetres = true;
    dev::StylusSample s;
    s.positionMm = {123.4, -56.7, 8.9};
    s.orientationDeg = dev::Vec3{-170.25, 45.5, 3.0};
    s.quaternion = std::array<double, 4>{0.7071, 0.7071, 0, 0};
    s.button = true;
    const std::string rec = dev::fastrak::encode(f, s);
    EXPECT_EQ(rec.size(), dev::fastrak::recordLength(f));
    dev::fastrak::DecoderState st;
    st.format = f;
    std::vector<dev::StylusSample> out;
    feed(st, rec, out, dev::fastrak::decode);
    ASSERT_EQ(out.size(), 1u) << (binary ? "binary" : "ascii");
    EXPECT_NEAR(out[0].positionMm[0], 123.4, 1e-3);
    EXPECT_NEAR(out[0].positionMm[1], -56.7, 1e-3);
    EXPECT_TRUE(out[0].button);
  }
}

TEST(FastrakStatus, ParsesTheFlags) {
  dev::fastrak::Status in{1, true, true, false, true}, out;
  const std::string line = dev::fastrak::encodeStatus(in);
  EXPECT_EQ(line.size(), 55u);
  ASSERT_TRUE(dev::fastrak::parseStatus(line, out));
  EXPECT_TRUE(out.binary);
  EXPECT_TRUE(out.centimetres);
  EXPECT_TRUE(out.continuous);
  EXPECT_FALSE(dev::fastrak::parseStatus("21Q00A", out));
}

TEST(FastrakFormat, RejectsUnknownItems) {
  dev::fastrak::Format f;
  f.items = {2, 99};
  EXPECT_THROW((void)dev::fastrak::recordLength(f), std::invalid_argument);
}

// ---- Patriot / Liberty --------------------------------------------------------------------
TEST(LibertyBinary, DecodesTheVrpnFrame) {
  // "LY" station 1 'C' err 0, size 33; x=10 y=-5.5 z=3.25 q=(1,0,0,0) ts=123456 ms, ' '
  dev::polhemus::DecoderState st;
  st.format.model = dev::polhemus::Model::Liberty;
  st.format.items = {2, 7, 8, 0};
  st.format.binary = true;
  st.format.centimetres = false;
  const auto b = hex({0x4c, 0x59, 0x01, 0x43, 0x00, 0x00, 0x21, 0x00, 0x00, 0x00, 0x20, 0x41, 0x00, 0x00,
                      0xb0, 0xc0, 0x00, 0x00, 0x50, 0x40, 0x00, 0x00, 0x80, 0x3f, 0,    0,    0,    0,
                      0,    0,    0,    0,    0,    0,    0,    0,    0x40, 0xe2, 0x01, 0x00, 0x20});
  ASSERT_EQ(b.size(), 41u);
  std::vector<dev::StylusSample> out;
  dev::polhemus::decode(st, b, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].positionMm[0], 254.0);
  EXPECT_DOUBLE_EQ(out[0].positionMm[1], -139.7);
  EXPECT_EQ(out[0].station, 1);
  // The same frame tagged "PA" is not a Liberty frame.
  auto pa = b;
  pa[0] = 'P';
  pa[1] = 'A';
  dev::polhemus::decode(st, pa, out);
  EXPECT_EQ(out.size(), 1u);
}

TEST(PatriotAscii, RoundTripsAndSkipsTextLines) {
  dev::polhemus::Format f;
  dev::StylusSample s;
  s.positionMm = {-1234.5, 67.8, 0.0};
  s.orientationDeg = dev::Vec3{10, 20, 30};
  s.button = true;
  const std::string rec = dev::polhemus::encode(f, s, 7, 1000);
  EXPECT_EQ(rec.size(), dev::polhemus::asciiLength(f));
  dev::polhemus::DecoderState st;
  st.format = f;
  std::vector<dev::StylusSample> out;
  feed(st, "patriot ready!\r\n" + rec + "\x01\x02zz" + rec.substr(0, 30) + "\r\n" + rec, out, dev::polhemus::decode);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].positionMm[0], -1234.5, 0.01);
  EXPECT_TRUE(out[0].button);
  EXPECT_EQ(st.stats.replies, 1u);
}

TEST(PolhemusBinary, ResynchronisesOnTheTag) {
  dev::polhemus::Format f;
  f.binary = true;
  f.items = {2, 5, 10, 0};
  dev::StylusSample s;
  s.positionMm = {1, 2, 3};
  const std::string rec = dev::polhemus::encode(f, s, 1, 2);
  EXPECT_EQ(rec.substr(0, 2), "PA");
  dev::polhemus::DecoderState st;
  st.format = f;
  std::vector<dev::StylusSample> out;
  std::string bad = rec;
  bad[6] = 5;  // wrong payload size
  feed(st, "PAPA" + rec + bad + rec.substr(0, 10) + rec, out, dev::polhemus::decode);
  EXPECT_EQ(out.size(), 2u);
}

// How the two independent public readers of Polhemus ASCII records take a line apart: they
// split it on white space (SoundScapeRenderer's trackerpolhemus.cpp reads the Patriot line
// with `>>` into header, x, y, z, azimuth, elevation, roll; SofaDefrost's PolhemusUSB.py
// splits the Liberty's `O*,2,7,1` reply on CR LF and then on white space: "ID+Err", x, y, z,
// then the quaternion). Our decoder reads fixed columns; both must give the same numbers.
std::vector<double> whitespaceFields(const std::string& line) {
  std::vector<double> v;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    std::size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) v.push_back(std::stod(line.substr(i, j - i)));
    i = j;
  }
  return v;
}

TEST(PatriotAscii, DecodesTheSixtyByteLineSoundScapeRendererDescribes) {
  // SSR: "The data coming from the Polhemus Patriot is similar [to the Fastrak's 47-byte
  // line], except that only two sockets are available and each of the 6 degrees of freedom
  // are represented by 9 bytes, leading to a total of 60 ASCII bytes" — the station header,
  // x y z and azimuth elevation roll (`O*,2,5,1`), CR LF. Lines written out by hand, in cm
  // (the Patriot's `U1`), the second from station 2 with a negative zero and a full field.
  const std::string line1 = " 1     12.345   -5.678   10.000   90.000  -45.500  179.990\r\n";
  const std::string line2 = " 2   -100.250   -0.000  123.456 -179.990   89.999    0.001\r\n";
  ASSERT_EQ(line1.size(), 60u);
  ASSERT_EQ(line2.size(), 60u);
  dev::polhemus::DecoderState st;
  st.format.model = dev::polhemus::Model::Patriot;
  st.format.items = {2, 5, 1};
  ASSERT_EQ(dev::polhemus::asciiLength(st.format), 60u);
  std::vector<dev::StylusSample> out;
  // Two lines in one read, the second split inside its first field.
  feed(st, line1 + line2.substr(0, 9), out, dev::polhemus::decode);
  feed(st, line2.substr(9), out, dev::polhemus::decode);
  ASSERT_EQ(out.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const auto expected = whitespaceFields(k == 0 ? line1 : line2);  // as SSR reads it
    ASSERT_EQ(expected.size(), 7u);
    EXPECT_EQ(out[k].station, static_cast<int>(expected[0]));
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(out[k].positionMm[i], expected[1 + i] * 10.0, 1e-9) << k << i;
    ASSERT_TRUE(out[k].orientationDeg);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR((*out[k].orientationDeg)[i], expected[4 + i], 1e-9) << k << i;
    EXPECT_EQ(out[k].rawUnit, "cm");
    EXPECT_EQ(out[k].raw.size(), 60u);
  }
  // A line one byte short (a lost character) is not taken for a record.
  std::string shortLine = line1;
  shortLine.erase(20, 1);
  dev::polhemus::DecoderState st2;
  st2.format = st.format;
  std::vector<dev::StylusSample> none;
  feed(st2, shortLine, none, dev::polhemus::decode);
  EXPECT_TRUE(none.empty());
}

TEST(LibertyAscii, DecodesTheRepliesSofaDefrostSplitsIntoPositionAndQuaternion) {
  // SofaDefrost's PolhemusUSB.py configures `U1` (cm) and `O*,2,7,1`, sends `p`, and splits
  // the reply on CR LF: one line per sensor, "[ID+Err, x, y, z, …]" with the quaternion
  // (w, x, y, z) after the position. Two sensors in one reply, written out by hand: the
  // station and error character, a space, 9-character columns (quaternion to 4 decimals).
  const std::string reply =
      " 1     25.400  -12.700    3.175   1.0000   0.0000   0.0000   0.0000\r\n"
      " 2      0.500   60.000  -45.125   0.7071   0.0000   0.7071   0.0000\r\n";
  dev::polhemus::DecoderState st;
  st.format.model = dev::polhemus::Model::Liberty;
  st.format.items = {2, 7, 1};
  st.format.stations = 4;
  ASSERT_EQ(reply.size(), 2 * dev::polhemus::asciiLength(st.format));
  std::vector<dev::StylusSample> out;
  feed(st, reply, out, dev::polhemus::decode);
  ASSERT_EQ(out.size(), 2u);
  std::size_t start = 0;
  for (std::size_t k = 0; k < 2; ++k) {
    const std::size_t end = reply.find("\r\n", start);
    const auto tokens = whitespaceFields(reply.substr(start, end - start));  // as PolhemusUSB.py reads it
    start = end + 2;
    ASSERT_EQ(tokens.size(), 8u);
    EXPECT_EQ(out[k].station, static_cast<int>(tokens[0]));
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(out[k].positionMm[i], tokens[1 + i] * 10.0, 1e-9);
    ASSERT_TRUE(out[k].quaternion);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR((*out[k].quaternion)[i], tokens[4 + i], 1e-9);
  }
  // A quaternion that is not of unit length (a garbled digit) is refused.
  std::string garbled = reply.substr(0, reply.find("\r\n") + 2);
  garbled[garbled.find("1.0000")] = '7';
  dev::polhemus::DecoderState st2;
  st2.format = st.format;
  std::vector<dev::StylusSample> none;
  feed(st2, garbled, none, dev::polhemus::decode);
  EXPECT_TRUE(none.empty());
}

// The stylus layout VRPN's vrpn_Tracker_Liberty asks for with a button ("O1,2,7,8,10,0"):
// an 8-byte header ("LY"/"PA", station, command, error, reserved, payload size LE), x y z in
// inches and the quaternion w x y z as little-endian IEEE floats, the timestamp (ms) and the
// stylus button as little-endian uint32, and the trailing space VRPN checks for. The bytes
// are written out here, not produced by leafdig's encoder.
std::vector<std::uint8_t> vrpnStylusFrame(char a, char b) {
  return hex({a,    b,    0x01, 0x50, 0x00, 0x00, 0x25, 0x00,                          // header; 37 payload bytes
              0x00, 0x00, 0xc0, 0x3f,                                                  // x  1.5 in
              0x00, 0x00, 0x00, 0xc0,                                                  // y -2.0 in
              0x00, 0x00, 0x80, 0x3e,                                                  // z  0.25 in
              0x00, 0x00, 0x80, 0x3f, 0,    0,    0,    0,    0, 0, 0, 0, 0, 0, 0, 0,  // q = (1, 0, 0, 0)
              0xe8, 0x03, 0x00, 0x00,                                                  // timestamp 1000 ms
              0x01, 0x00, 0x00, 0x00,                                                  // stylus button down
              0x20});
}

TEST(LibertyBinary, DecodesVrpnsStylusLayoutWithTheButtonWord) {
  for (const auto& [model, tag] : {std::pair{dev::polhemus::Model::Liberty, std::string("LY")},
                                   std::pair{dev::polhemus::Model::Patriot, std::string("PA")}}) {
    dev::polhemus::DecoderState st;
    st.format.model = model;
    st.format.items = {2, 7, 8, 10, 0};
    st.format.binary = true;
    st.format.centimetres = false;
    const auto frame = vrpnStylusFrame(tag[0], tag[1]);
    ASSERT_EQ(frame.size(), 8u + 37u);
    EXPECT_EQ(dev::polhemus::payloadLength(st.format), 37u);
    std::vector<dev::StylusSample> out;
    // Two frames, the second split in the middle of its x.
    auto bytes = frame;
    bytes.insert(bytes.end(), frame.begin(), frame.begin() + 10);
    dev::polhemus::decode(st, bytes, out);
    dev::polhemus::decode(st, std::vector<std::uint8_t>(frame.begin() + 10, frame.end()), out);
    ASSERT_EQ(out.size(), 2u) << tag;
    for (const auto& s : out) {
      EXPECT_NEAR(s.positionMm[0], 38.1, 1e-6) << tag;  // inches to mm
      EXPECT_NEAR(s.positionMm[1], -50.8, 1e-6) << tag;
      EXPECT_NEAR(s.positionMm[2], 6.35, 1e-6) << tag;
      EXPECT_TRUE(s.button) << tag;
      EXPECT_EQ(s.station, 1) << tag;
    }
  }
}

// ---- MicroScribe --------------------------------------------------------------------------
// Craig's modified Denavit–Hartenberg link transform, written out as its closed-form matrix
// (an independent computation of the pose: leafdig's code composes Eigen rotations).
using Mat4 = std::array<std::array<double, 4>, 4>;
Mat4 craigLink(double alphaDeg, double a, double thetaDeg, double d) {
  const double k = std::acos(-1.0) / 180.0;
  const double ca = std::cos(alphaDeg * k), sa = std::sin(alphaDeg * k);
  const double ct = std::cos(thetaDeg * k), st = std::sin(thetaDeg * k);
  return {{{ct, -st, 0, a}, {st * ca, ct * ca, -sa, -sa * d}, {st * sa, ct * sa, ca, ca * d}, {0, 0, 0, 1}}};
}
Mat4 times(const Mat4& x, const Mat4& y) {
  Mat4 r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) r[i][j] += x[i][k] * y[k][j];
  return r;
}

TEST(MicroScribe, TheTipFromAPacketMatchesAnIndependentDhChain) {
  dev::microscribe::DecoderState st;
  st.arm = dev::microscribe::referenceArm();
  const std::array<std::array<int, 6>, 3> poses{
      {{0, 4096, 8192, 12000, 300, 16000}, {15955, 1234, 5678, 9012, 3456, 7890}, {8192, 15000, 2000, 100, 16383, 42}}};
  for (const auto& counts : poses) {
    // The packet as the HCI sends it: 0x83, buttons, then each count as two 7-bit bytes.
    std::vector<std::uint8_t> packet{0x83, 0x02};
    for (int c : counts) {
      packet.push_back(static_cast<std::uint8_t>(c >> 7));
      packet.push_back(static_cast<std::uint8_t>(c & 0x7f));
    }
    std::vector<dev::StylusSample> out;
    dev::microscribe::decode(st, packet, out);
    ASSERT_EQ(out.size(), 1u);
    Mat4 t{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
    for (std::size_t i = 0; i < 6; ++i)
      t = times(
          t, craigLink(st.arm.alphaDeg[i], st.arm.aMm[i], 360.0 * counts[i] / st.arm.countsPerRev[i], st.arm.dMm[i]));
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_NEAR(out[0].positionMm[static_cast<std::size_t>(axis)], t[static_cast<std::size_t>(axis)][3], 1e-9)
          << "axis " << axis;
    EXPECT_TRUE(out[0].button);  // 0x02: the arm's first button (as VRPN maps it)
  }
  // No button, the second button, and a buttons byte with bits no arm has.
  for (const auto& [buttons, pressed, kept] :
       {std::tuple{0x00, false, true}, std::tuple{0x01, true, true}, std::tuple{0x04, false, false}}) {
    std::vector<std::uint8_t> packet{0x83, static_cast<std::uint8_t>(buttons), 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1};
    std::vector<dev::StylusSample> out;
    dev::microscribe::decode(st, packet, out);
    ASSERT_EQ(out.size(), kept ? 1u : 0u) << buttons;
    if (kept) {
      EXPECT_EQ(out[0].button, pressed) << buttons;
    }
  }
}

TEST(MicroScribe, DecodesTheResearchNotesPacket) {
  // Host sends 03; the arm answers 83 01 7C 53 …: right pedal, angle0 = (0x7C<<7)|0x53 = 15955.
  dev::microscribe::DecoderState st;
  st.arm = dev::microscribe::referenceArm();
  const auto b = hex({0x83, 0x01, 0x7C, 0x53, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  std::vector<dev::StylusSample> out;
  dev::microscribe::decode(st, b, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].button);
  std::array<double, 6> j{360.0 * 15955 / 16384, 0, 0, 0, 0, 0};
  const auto p = dev::microscribe::forwardKinematics(st.arm, j);
  EXPECT_DOUBLE_EQ(out[0].positionMm[0], p[0]);
  EXPECT_DOUBLE_EQ(out[0].positionMm[2], p[2]);
}

TEST(MicroScribe, DhParametersRoundTripAndKinematicsInvert) {
  const auto arm = dev::microscribe::referenceArm();
  dev::microscribe::Arm back;
  ASSERT_TRUE(dev::microscribe::decodeDhParams(dev::microscribe::encodeDhParams(arm), back));
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_DOUBLE_EQ(back.alphaDeg[i], arm.alphaDeg[i]);
    EXPECT_DOUBLE_EQ(back.dMm[i], arm.dMm[i]);
  }
  std::array<double, 6> j{0, -30, 60, 0, 60, 0};
  const dev::Vec3 target{420, 35, -20};
  ASSERT_TRUE(dev::microscribe::inverseKinematics(arm, target, j));
  const auto p = dev::microscribe::forwardKinematics(arm, j);
  EXPECT_NEAR(p[0], 420, 0.01);
  EXPECT_NEAR(p[1], 35, 0.01);
  EXPECT_NEAR(p[2], -20, 0.01);
}

TEST(MicroScribe, DropsATruncatedPacketAndKeepsTheNext) {
  dev::microscribe::DecoderState st;
  st.arm = dev::microscribe::referenceArm();
  dev::microscribe::Packet p;
  p.counts = {100, 200, 300, 400, 500, 600};
  const auto full = dev::microscribe::encodePacket(p);
  std::vector<std::uint8_t> b(full.begin(), full.begin() + 6);
  b.insert(b.end(), full.begin(), full.end());
  std::vector<dev::StylusSample> out;
  dev::microscribe::decode(st, b, out);
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ(st.stats.dropped, 1u);
}

// ---- generic line digitizer ---------------------------------------------------------------
TEST(LineDigitizer, ColumnsWithAxisMapAndUnits) {
  dev::line::DecoderState st;
  st.config = dev::line::parseConfig(R"({"fields": {"mode": "columns", "x": [3,7], "y": [10,7], "z": [17,7],
      "button": [25,1]}, "unit": "cm", "axes": ["x", "-z", "y"]})");
  std::vector<dev::StylusSample> out;
  feed(st, "01   -0.09  -0.16   0.03 1\r\n", out, dev::line::decode);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].positionMm[0], -0.9);
  EXPECT_DOUBLE_EQ(out[0].positionMm[1], -0.3);
  EXPECT_DOUBLE_EQ(out[0].positionMm[2], -1.6);
  EXPECT_TRUE(out[0].button);
}

TEST(LineDigitizer, TokensAndRegexAndSyncFraming) {
  dev::line::DecoderState tok;
  tok.config = dev::line::parseConfig(R"({"fields": {"mode": "tokens", "x": 1, "y": 2, "z": 3, "button": 0}})");
  std::vector<dev::StylusSample> out;
  feed(tok, "1, 10.5, -2, 3e1\r\nnot a record\r\n", out, dev::line::decode);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].positionMm[2], 30.0);
  EXPECT_EQ(tok.stats.dropped, 1u);

  dev::line::DecoderState rx;
  rx.config = dev::line::parseConfig(
      R"J({"framing": {"terminator": "\n", "sync": "#"}, "fields": {"mode": "regex",
          "regex": "X=(-?[0-9.]+) Y=(-?[0-9.]+) Z=(-?[0-9.]+)", "x": 1, "y": 2, "z": 3}, "unit": "in"})J");
  out.clear();
  feed(rx, "junk#X=1 Y=2 Z=3\n#X=1 Y=oops Z=3\n", out, dev::line::decode);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].positionMm[0], 25.4);
}

TEST(LineDigitizer, BadConfigurationsNameTheProblem) {
  const auto message = [](const char* json) {
    try {
      (void)dev::line::parseConfig(json);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(R"({"unit": "furlong"})").find("unit"), std::string::npos);
  EXPECT_NE(message(R"({"fields": {"mode": "columns"}})").find("x, y and z"), std::string::npos);
  EXPECT_NE(message(R"J({"fields": {"mode": "regex", "regex": "("}})J").find("regex"), std::string::npos);
  EXPECT_NE(message(R"({"axes": ["x", "x", "z"]})").find("twice"), std::string::npos);
  EXPECT_NE(message("{not json").find("JSON"), std::string::npos);
}

// ---- calipers -----------------------------------------------------------------------------
TEST(HidKeyboard, DecodesTheResearchNotesReportsForMinus12_34) {
  const std::vector<std::vector<int>> keys = {{0x2D}, {0x1E}, {0x1F}, {0x37}, {0x20}, {0x21}, {0x28}};
  dev::calipers::HidKeyboardState st;
  std::vector<dev::CaliperReading> out;
  int reports = 0;
  for (const auto& k : keys) {
    std::vector<std::uint8_t> press(8, 0), release(8, 0);
    press[2] = static_cast<std::uint8_t>(k[0]);
    dev::calipers::decodeHidReport(st, press, out);
    dev::calipers::decodeHidReport(st, release, out);
    reports += 2;
  }
  EXPECT_EQ(reports, 14);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].valueMm, -12.34);
  EXPECT_EQ(out[0].raw, "-12.34");
}

TEST(HidKeyboard, IsEdgeTriggeredSoRepeatedDigitsNeedARelease) {
  dev::calipers::HidKeyboardState st;
  std::vector<dev::CaliperReading> out;
  std::vector<std::uint8_t> one(8, 0), enter(8, 0), none(8, 0);
  one[2] = 0x1E;
  enter[2] = 0x28;
  dev::calipers::decodeHidReport(st, one, out);
  dev::calipers::decodeHidReport(st, one, out);  // held: still one '1'
  dev::calipers::decodeHidReport(st, none, out);
  dev::calipers::decodeHidReport(st, one, out);  // pressed again: '11'
  dev::calipers::decodeHidReport(st, enter, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].valueMm, 11.0);
}

TEST(HidKeyboard, KeypadCommaTabReportIdAndUnitSuffix) {
  for (bool reportId : {false, true}) {
    dev::calipers::HidKeyboardState st;
    st.reportId = reportId;
    std::vector<dev::CaliperReading> out;
    for (const auto& r : dev::calipers::encodeHidText("0,125\t", true, reportId))
      dev::calipers::decodeHidReport(st, r, out);
    for (const auto& r : dev::calipers::encodeHidText("+1.5in\n", false, reportId))
      dev::calipers::decodeHidReport(st, r, out);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_DOUBLE_EQ(out[0].valueMm, 0.125);
    EXPECT_EQ(out[1].unit, "in");
    EXPECT_DOUBLE_EQ(out[1].valueMm, 38.1);
  }
}

TEST(HidKeyboard, DropsTextThatIsNotANumber) {
  dev::calipers::HidKeyboardState st;
  std::vector<dev::CaliperReading> out;
  for (const auto& r : dev::calipers::encodeHidText("1.2.3\nab\n-\n", false, false))
    dev::calipers::decodeHidReport(st, r, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(st.stats.dropped, 3u);
}

TEST(MitutoyoAscii, DecodesDataAndErrors) {
  dev::calipers::MitutoyoState st;
  std::vector<dev::CaliperReading> out;
  feed(st, "01A+0000.123\r01A-0012.500\r911\r01A+00.0.123\r", out, dev::calipers::decodeMitutoyo);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].valueMm, 0.123);
  EXPECT_DOUBLE_EQ(out[1].valueMm, -12.5);
  ASSERT_EQ(st.errors.size(), 1u);
  EXPECT_EQ(st.errors[0], "911");
  EXPECT_EQ(st.stats.dropped, 1u);
  EXPECT_EQ(dev::calipers::encodeMitutoyo(0.123, 3), "01A+0000.123\r");
}

TEST(MitutoyoAscii, AutoUnitReadsFiveDecimalsAsInches) {
  dev::calipers::MitutoyoState st;
  st.unit = "auto";
  std::vector<dev::CaliperReading> out;
  feed(st, "01A+00.12345\r", out, dev::calipers::decodeMitutoyo);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].unit, "in");
  EXPECT_NEAR(out[0].valueMm, 0.12345 * 25.4, 1e-9);
}

TEST(UWave, DecodesMeasurementLines) {
  dev::calipers::UWaveState st;
  std::vector<dev::CaliperReading> out;
  feed(st, "DT10005+00000020.06M\rST1000051\rDT10005-00000000.50I\rDT1000X+1M\r", out, dev::calipers::decodeUWave);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].valueMm, 20.06);
  EXPECT_DOUBLE_EQ(out[1].valueMm, -12.7);
  EXPECT_EQ(st.stats.replies, 1u);
  EXPECT_EQ(st.stats.dropped, 1u);
  EXPECT_EQ(dev::calipers::encodeUWave(20.06, "mm"), "DT10005+00000020.06M\r");
}

TEST(Digimatic, DecodesTheResearchNotesFrame) {
  const std::vector<std::uint8_t> n{0xF, 0xF, 0xF, 0xF, 8, 0, 1, 2, 3, 4, 5, 3, 0};
  const auto r = dev::calipers::decodeDigimatic(n);
  ASSERT_TRUE(r);
  EXPECT_DOUBLE_EQ(r->valueMm, -12.345);
  std::array<std::uint8_t, 13> a{};
  std::copy(n.begin(), n.end(), a.begin());
  const auto bits = dev::calipers::digimaticBits(a);
  ASSERT_EQ(bits.size(), 52u);
  EXPECT_EQ((std::vector<std::uint8_t>(bits.begin() + 16, bits.begin() + 20)), (std::vector<std::uint8_t>{0, 0, 0, 1}));
  EXPECT_EQ(dev::calipers::digimaticNibbles(bits), a);
  EXPECT_EQ(dev::calipers::encodeDigimatic(-12.345, 3, false), a);
}

TEST(Digimatic, RejectsInvalidFrames) {
  std::vector<std::uint8_t> n{0xF, 0xF, 0xF, 0xF, 0, 0, 1, 2, 3, 4, 5, 3, 0};
  auto bad = n;
  bad[0] = 0xE;
  EXPECT_FALSE(dev::calipers::decodeDigimatic(bad));
  bad = n;
  bad[4] = 1;
  EXPECT_FALSE(dev::calipers::decodeDigimatic(bad));
  bad = n;
  bad[7] = 10;
  EXPECT_FALSE(dev::calipers::decodeDigimatic(bad));
  bad = n;
  bad[11] = 6;
  EXPECT_FALSE(dev::calipers::decodeDigimatic(bad));
  bad = n;
  bad[12] = 2;
  EXPECT_FALSE(dev::calipers::decodeDigimatic(bad));
  EXPECT_FALSE(dev::calipers::decodeDigimatic(std::vector<std::uint8_t>(12, 0xF)));
  const auto inch =
      dev::calipers::decodeDigimatic(std::vector<std::uint8_t>{0xF, 0xF, 0xF, 0xF, 0, 0, 0, 1, 0, 0, 0, 4, 1});
  ASSERT_TRUE(inch);
  EXPECT_EQ(inch->unit, "in");
  EXPECT_NEAR(inch->valueMm, 0.1 * 25.4, 1e-9);
}

TEST(Sylvac, DecodesValuesEchoesErrorsAndUnits) {
  dev::calipers::SylvacState st;
  std::vector<dev::CaliperReading> out;
  feed(st, "SY304.0\r?\r+012.345\r 001.500\r-000.100=\rERR2\rIN\r+00.12345\rBAT?\rhello\r", out,
       dev::calipers::decodeSylvac);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_DOUBLE_EQ(out[0].valueMm, 12.345);
  EXPECT_DOUBLE_EQ(out[1].valueMm, 1.5);
  EXPECT_DOUBLE_EQ(out[2].valueMm, -0.1);
  EXPECT_EQ(out[2].flag, "=");
  EXPECT_EQ(out[3].unit, "in");
  EXPECT_NEAR(out[3].valueMm, 3.13563, 1e-9);
  EXPECT_EQ(st.identification, "SY304.0");
  ASSERT_EQ(st.errors.size(), 1u);
  EXPECT_STREQ(dev::calipers::sylvacErrorMeaning(st.errors[0][3]), "parity error (the port must be 4800 7E2)");
  EXPECT_EQ(st.stats.dropped, 1u);
  EXPECT_EQ(dev::calipers::encodeSylvac(12.345, 3), "+012.345\r");
}

TEST(CaliperNumbers, ParsesWhatGaugesTypeAndNothingElse) {
  EXPECT_DOUBLE_EQ(dev::calipers::parseNumber(" -0,50 mm")->value, -0.5);
  EXPECT_EQ(dev::calipers::parseNumber("1.5\"")->unit, "in");
  EXPECT_FALSE(dev::calipers::parseNumber("1e3"));
  EXPECT_FALSE(dev::calipers::parseNumber("--1"));
  EXPECT_FALSE(dev::calipers::parseNumber("nan"));
  EXPECT_FALSE(dev::calipers::parseNumber(""));
  EXPECT_FALSE(std::signbit(dev::calipers::parseNumber("-0.000")->value));
}

}  // namespace

// ---- the device's clock (issue 26) ----------------------------------------------------------

namespace {

using leafdig::devices::Clock;
using leafdig::devices::RecordClock;

Clock::time_point at(double seconds) {
  return Clock::time_point{} + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}
double seconds(Clock::time_point t) {
  return std::chrono::duration<double>(t - Clock::time_point{}).count();
}

TEST(RecordClock, RecordsDeliveredInDelayedBurstsAreTimedByTheirCount) {
  // A FASTRAK at 120 Hz read by a busy host: most records 2–6 ms late, but now and then the
  // host does not read for up to 0.6 s and gets them all at once.
  RecordClock clock(1.0 / 120);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(0.002, 0.006);
  double heldUntil = -1;
  std::vector<double> device, arrival;
  for (int k = 0; k < 2400; ++k) {
    const double made = 10.0 + k / 120.0;
    if (k % 300 == 150) heldUntil = made + 0.6;  // a 0.6 s burst every 2.5 s
    const double got = made < heldUntil ? heldUntil : made + jitter(rng);
    arrival.push_back(got);
    device.push_back(seconds(clock.stamp(at(got))));
  }
  // Once a little-delayed record has been seen (the anchor settles within a few records and
  // then moves by microseconds), every record is one period after the one before, bursts or not.
  for (std::size_t k = 1; k < device.size(); ++k) {
    if (k > 60) {
      ASSERT_NEAR(device[k] - device[k - 1], 1.0 / 120, 5e-5) << k;
    }
    ASSERT_LE(device[k], arrival[k] + 1e-9) << "never later than it arrived";
    ASSERT_NEAR(device[k] - device[k - 1], 1.0 / 120, 0.004) << k;
  }
  EXPECT_NEAR(device.back() - device.front(), 2399 / 120.0, 0.004);
  // A press from record 140 to 182 (0.35 s) that straddles the burst at 150: by arrival it
  // looks held almost twice as long.
  EXPECT_NEAR(device[182] - device[140], 0.35, 1e-4);
  EXPECT_GT(arrival[182] - arrival[140], 0.6);
}

// A 120 Hz stream of `records` made from t = 10 s, stamped as the host read them:
// `arrival(k, made, jitter)` says when it read record k (jitter: 2–6 ms, drawn for each).
std::vector<double> stampedAt120(int records, unsigned seed,
                                 const std::function<double(int, double, double)>& arrival) {
  RecordClock clock(1.0 / 120);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(0.002, 0.006);
  std::vector<double> device;
  for (int k = 0; k < records; ++k) {
    const double made = 10.0 + k / 120.0;
    const double j = jitter(rng);
    device.push_back(seconds(clock.stamp(at(arrival(k, made, j)))));
  }
  return device;
}

// Once the anchor has settled, every record one period after the one before.
void expectOnePeriodApart(const std::vector<double>& device) {
  for (std::size_t k = 61; k < device.size(); ++k) ASSERT_NEAR(device[k] - device[k - 1], 1.0 / 120, 5e-5) << k;
}

TEST(RecordClock, AHostThatDoesNotReadForSecondsKeepsTheCountOfWhatItThenReadsAtOnce) {
  // A starved station PC: the driver does not read for 1.6 s, then reads every record the
  // FASTRAK made meanwhile at once, then one every 2–6 ms again. Nothing was lost: the records
  // keep their count, so a press made while nobody read (records 200 to 242, 0.35 s) is 0.35 s
  // long and the records before it are still 1/120 s apart.
  const std::vector<double> device = stampedAt120(900, 11, [](int k, double made, double jitter) {
    return k >= 120 && k < 312 ? 10.0 + 312 / 120.0 : made + jitter;  // 1.6 s unread
  });
  expectOnePeriodApart(device);
  EXPECT_NEAR(device[242] - device[200], 0.35, 1e-4);
  EXPECT_NEAR(device[199] - device[170], 29 / 120.0, 1e-4);
}

TEST(RecordClock, AHostSlowForSecondsIsNotTakenForAnotherRate) {
  // For six seconds the host reads every record at least 0.1 s late (a compile on the
  // station PC), then promptly again: the least delay of a block or two moves and comes back,
  // which is no rate. Every record stays 1/120 s after the one before.
  expectOnePeriodApart(stampedAt120(
      4800, 5, [](int k, double made, double jitter) { return made + (k >= 600 && k < 1300 ? 0.1 : 0.0) + jitter; }));
}

TEST(RecordClock, AGapStartsANewCountAndAnotherRateIsTakenUp) {
  RecordClock clock(1.0 / 120);
  for (int k = 0; k < 100; ++k) (void)clock.stamp(at(1.0 + k / 120.0));
  // An unplug: two seconds without records, then the stream again. For a second they might be
  // records a starved host read late, so they go on with the count; then, none having come as
  // early as the count wants, the count moves on by the records missing (once) and the stream
  // is timed as it comes.
  std::vector<double> after;
  for (int k = 0; k < 240; ++k) after.push_back(seconds(clock.stamp(at(4.0 + k / 120.0))));
  EXPECT_NEAR(after[0], 1.0 + 100 / 120.0, 1e-6);
  EXPECT_NEAR(after[239], 4.0 + 239 / 120.0, 1e-6);
  int jumps = 0;
  for (std::size_t k = 1; k < after.size(); ++k) {
    if (std::abs(after[k] - after[k - 1] - 1 / 120.0) < 1e-6) continue;
    ++jumps;
    EXPECT_GE(k, 120U) << "not before a second of the stream has shown the loss";
    EXPECT_NEAR(after[k] - after[k - 1], 4.0 - (1.0 + 100 / 120.0) + 1 / 120.0, 1e-6);
  }
  EXPECT_EQ(jumps, 1);
  // A stream that really runs at 100 Hz (a serial line too slow for 120): after a few blocks
  // its records are timed 10 ms apart.
  RecordClock slow(1.0 / 120);
  std::vector<double> device;
  for (int k = 0; k < 3000; ++k) device.push_back(seconds(slow.stamp(at(20.0 + k / 100.0))));
  EXPECT_NEAR(device[2999] - device[2998], 0.01, 1e-6);
  EXPECT_NEAR(device[2999] - device[2500], 4.99, 1e-3);
}

}  // namespace
