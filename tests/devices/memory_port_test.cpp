// Drivers over the in-memory serial line (no pseudo-terminal): the test plays the gauge with
// the byte strings of its manual, and breaks the cable the ways real cables break.
#include <gtest/gtest.h>

#include <string>

#include "device_test_support.hpp"
#include "leafdig/devices/links/links.hpp"
#include "leafdig/devices/transports/memory_serial_port.hpp"

namespace dev = leafdig::devices;
using dev::testing::Collector;
using namespace std::chrono_literals;

namespace {

dev::CaliperConfig mitutoyoOn(dev::MemorySerialLine& line) {
  dev::CaliperConfig c;
  c.kind = dev::CaliperKind::Mitutoyo;
  c.port = "/dev/memory-mitutoyo";
  c.openPort = line.opener();
  return c;
}

// A duplex Sylvac as its manual describes it: `MM` switches to millimetres (no answer),
// `ID?` answers the identification, `?` answers `[sign][int].[frac]CR` with the reading.
dev::MemorySerialLine::Responder sylvacAnswering(const std::string& reading) {
  return [reading](const std::string& written) -> std::string {
    if (written == "ID?\r") return "SY304.0\r";
    if (written == "?\r") return reading;
    return "";
  };
}

}  // namespace

TEST(MemoryLine, MitutoyoDataButtonReadingsInTheManualsFormatArrive) {
  dev::MemorySerialLine line;
  Collector col;
  dev::Driver driver(dev::makeCaliperLink(mitutoyoOn(line)), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([&](Collector&) { return line.opens() == 1; })) << col.statusLog();
  // Mitutoyo's standard ASCII output (QM-Height manual 99MAF600B §6.2.2): 01A, sign, 8 chars, CR.
  line.feed("01A+0000.123\r");
  line.feed("01A-0012.500\r01A+0003.2");  // a record split across reads
  line.feed("50\r");
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() >= 3; })) << col.statusLog();
  driver.stop();
  std::lock_guard lock(col.mutex);
  EXPECT_DOUBLE_EQ(col.caliper[0].valueMm, 0.123);
  EXPECT_DOUBLE_EQ(col.caliper[1].valueMm, -12.5);
  EXPECT_DOUBLE_EQ(col.caliper[2].valueMm, 3.25);
  EXPECT_EQ(line.settings()->baud, 9600);  // the gauge's documented rate, 8N1
  EXPECT_EQ(line.settings()->dataBits, 8);
}

TEST(MemoryLine, SylvacIsSetUpAndPolledAt4800_7E2) {
  dev::MemorySerialLine line;
  line.respond(sylvacAnswering("+012.345\r"));
  dev::CaliperConfig c;
  c.kind = dev::CaliperKind::Sylvac;
  c.port = "/dev/memory-sylvac";
  c.openPort = line.opener();
  Collector col;
  dev::DriverOptions o;
  o.pollEvery = 60ms;
  dev::Driver driver(dev::makeCaliperLink(c), col.callbacks(), o);
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() >= 2; })) << col.statusLog();
  driver.stop();
  std::lock_guard lock(col.mutex);
  EXPECT_DOUBLE_EQ(col.caliper[0].valueMm, 12.345);
  const auto s = *line.settings();
  EXPECT_EQ(s.baud, 4800);
  EXPECT_EQ(s.dataBits, 7);
  EXPECT_EQ(s.parity, dev::Parity::Even);
  EXPECT_EQ(s.stopBits, 2);
  // Millimetres first, identification, then the data requests.
  const std::string w = line.written();
  EXPECT_EQ(w.rfind("MM\rID?\r?\r", 0), 0u) << w;
}

TEST(MemoryLine, ASilentSylvacIsAnErrorThatNamesTheCableAndTheSettings) {
  dev::MemorySerialLine line;  // nobody answers
  dev::CaliperConfig c;
  c.kind = dev::CaliperKind::Sylvac;
  c.port = "/dev/memory-sylvac";
  c.openPort = line.opener();
  Collector col;
  dev::Driver driver(dev::makeCaliperLink(c), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.sawState(dev::LinkState::Error, "no answer"); }))
      << col.statusLog();
  driver.stop();
  std::lock_guard lock(col.mutex);
  bool named = false;
  for (const auto& s : col.statuses)
    named = named || (s.state == dev::LinkState::Error && s.remedy.find("duplex") != std::string::npos &&
                      s.remedy.find("4800 7E2") != std::string::npos);
  EXPECT_TRUE(named) << col.statusLog();
}

TEST(MemoryLine, AnUnpluggedAdapterIsReportedAndTheDriverReconnectsAndReadsAgain) {
  dev::MemorySerialLine line;
  Collector col;
  dev::DriverOptions o;
  o.retryMin = 20ms;
  o.retryMax = 40ms;
  dev::Driver driver(dev::makeCaliperLink(mitutoyoOn(line)), col.callbacks(), o);
  driver.start();
  ASSERT_TRUE(col.waitFor([&](Collector&) { return line.opens() == 1; }));
  line.feed("01A+0001.000\r");
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() == 1; }));
  // The adapter is pulled: the read fails, and while it is out the port cannot be opened.
  line.refuseOpen(dev::DeviceErrorKind::NotFound, "/dev/memory-mitutoyo does not exist", "plug the cable in");
  line.failNextRead();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.sawState(dev::LinkState::Disconnected, "does not exist"); }))
      << col.statusLog();
  EXPECT_EQ(line.opens(), 1);
  // Plugged back in: the driver reconnects by itself and readings arrive again.
  line.allowOpen();
  ASSERT_TRUE(col.waitFor([&](Collector&) { return line.opens() == 2; })) << col.statusLog();
  line.feed("01A+0002.000\r");
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() == 2; })) << col.statusLog();
  driver.stop();
  EXPECT_GE(driver.status().reconnects, 1);
  std::lock_guard lock(col.mutex);
  EXPECT_DOUBLE_EQ(col.caliper[1].valueMm, 2.0);
  EXPECT_TRUE(col.sawState(dev::LinkState::Disconnected, "Input/output error")) << col.statusLog();
}

TEST(MemoryLine, ABusyPortIsAnErrorWithTheRemedyAndNothingIsRead) {
  dev::MemorySerialLine line;
  line.refuseOpen(dev::DeviceErrorKind::Busy, "/dev/memory-mitutoyo is busy",
                  "close the other program that uses it (e.g. a terminal or another leafdig)");
  line.feed("01A+0001.000\r");
  Collector col;
  dev::Driver driver(dev::makeCaliperLink(mitutoyoOn(line)), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.sawState(dev::LinkState::Error, "busy"); })) << col.statusLog();
  driver.stop();
  EXPECT_EQ(line.opens(), 0);
  std::lock_guard lock(col.mutex);
  EXPECT_TRUE(col.caliper.empty());
  bool remedy = false;
  for (const auto& st : col.statuses) remedy = remedy || st.remedy.find("close the other program") != std::string::npos;
  EXPECT_TRUE(remedy) << col.statusLog();
}
