// Drivers against the emulators, over real pseudo-terminals (and the HID/USB seams).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "device_test_support.hpp"
#include "leafdig/devices/codecs/fastrak.hpp"
#include "leafdig/devices/links/links.hpp"

namespace dev = leafdig::devices;
using dev::testing::Collector;
using dev::testing::dist;
using dev::testing::quickStylus;
using namespace std::chrono_literals;

namespace {

std::map<std::string, dev::sim::SentRecord> byOriginal(const dev::sim::Emulator& e) {
  std::map<std::string, dev::sim::SentRecord> m;
  for (auto& r : e.sentRecords()) m[r.original] = r;
  return m;
}

// Every delivered sample is a record the emulator sent, at the position it measured.
void expectSamplesMatchSentRecords(const std::vector<dev::StylusSample>& got, const dev::sim::Emulator& e,
                                   double toleranceMm) {
  const auto sent = byOriginal(e);
  ASSERT_FALSE(got.empty());
  for (const auto& s : got) {
    const auto it = sent.find(s.raw);
    ASSERT_NE(it, sent.end()) << "delivered a record the device never sent: " << dev::printableRaw(s.raw);
    EXPECT_LT(dist(s.positionMm, it->second.truthMm), toleranceMm) << dev::printableRaw(s.raw);
  }
}

struct DigitizerCase {
  const char* name;
  dev::DigitizerKind kind;
  bool binary;
  double toleranceMm;
};

void PrintTo(const DigitizerCase& c, std::ostream* os) {
  *os << c.name;
}

class DigitizerAgainstEmulator : public ::testing::TestWithParam<DigitizerCase> {};

TEST_P(DigitizerAgainstEmulator, DeliversEveryRecordWithButtonPresses) {
  const auto c = GetParam();
  dev::sim::EmulatorOptions eo;
  std::unique_ptr<dev::sim::Emulator> emu;
  switch (c.kind) {
    case dev::DigitizerKind::Fastrak: emu = dev::sim::makeFastrak(quickStylus(), eo); break;
    case dev::DigitizerKind::Patriot: emu = dev::sim::makePatriot(quickStylus(), eo); break;
    case dev::DigitizerKind::Liberty: emu = dev::sim::makeLiberty(quickStylus(), eo); break;
    default: emu = dev::sim::makeMicroScribe(quickStylus(1, dev::sim::kMicroScribeLeafOffset), eo);
  }
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.kind = c.kind;
  cfg.port = emu->path();
  cfg.binary = c.binary;
  Collector col;
  dev::Driver driver(dev::makeDigitizerLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor(
      [](Collector& k) {
        int presses = 0;
        for (std::size_t i = 1; i < k.stylus.size(); ++i) presses += k.stylus[i].button && !k.stylus[i - 1].button;
        return presses >= 2;
      },
      15s))
      << col.statusLog();
  driver.stop();
  emu->stop();
  std::lock_guard lock(col.mutex);
  expectSamplesMatchSentRecords(col.stylus, *emu, c.toleranceMm);
  EXPECT_TRUE(col.sawState(dev::LinkState::Connecting));
  EXPECT_TRUE(col.sawState(dev::LinkState::Streaming));
  const auto st = driver.status();
  EXPECT_EQ(st.stats.dropped, 0u);
  EXPECT_GT(st.stats.records, 0u);
  // Timestamps are monotonic and taken once per arrival.
  for (std::size_t i = 1; i < col.stylus.size(); ++i) EXPECT_LE(col.stylus[i - 1].t, col.stylus[i].t);
}

INSTANTIATE_TEST_SUITE_P(Devices, DigitizerAgainstEmulator,
                         ::testing::Values(DigitizerCase{"FastrakAscii", dev::DigitizerKind::Fastrak, false, 0.087},
                                           DigitizerCase{"FastrakBinary", dev::DigitizerKind::Fastrak, true, 1e-3},
                                           DigitizerCase{"PatriotAscii", dev::DigitizerKind::Patriot, false, 0.0087},
                                           DigitizerCase{"PatriotBinary", dev::DigitizerKind::Patriot, true, 1e-3},
                                           DigitizerCase{"LibertyAscii", dev::DigitizerKind::Liberty, false, 0.0087},
                                           DigitizerCase{"LibertyBinary", dev::DigitizerKind::Liberty, true, 1e-3},
                                           DigitizerCase{"MicroScribe", dev::DigitizerKind::MicroScribe, false, 1e-5}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(LineDigitizer, DrivesAFastrakThroughItsJsonDescription) {
  auto emu = dev::sim::makeFastrak(quickStylus(), {});
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.kind = dev::DigitizerKind::Line;
  cfg.port = emu->path();
  cfg.line = dev::line::parseConfig(R"({"init": ["c", "*0.05", "u", "e1,0\r", "O1,2,16,1\r"], "start": "C", "stop": "c",
      "baud": 115200, "fields": {"mode": "columns", "x": [3,7], "y": [10,7], "z": [17,7], "button": [25,1]},
      "unit": "cm"})");
  Collector col;
  dev::Driver driver(dev::makeDigitizerLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.stylus.size() >= 60; }));
  driver.stop();
  emu->stop();
  std::lock_guard lock(col.mutex);
  expectSamplesMatchSentRecords(col.stylus, *emu, 0.087);
}

TEST(Fastrak, DefaultButtonModeStopsTheStreamAsUsersReport) {
  // Without e1,0 a press toggles continuous output off (InVesalius #106): the emulator does it.
  auto emu = dev::sim::makeFastrak(quickStylus(), {});
  emu->start();
  auto port = dev::openTtyPort(emu->path(), {});
  port->write("C");
  std::string got;
  const auto end = std::chrono::steady_clock::now() + 1500ms;
  while (std::chrono::steady_clock::now() < end) {
    const auto b = port->read(4096, 50ms);
    got.append(b.begin(), b.end());
  }
  const auto lines = static_cast<double>(std::count(got.begin(), got.end(), '\n'));
  // The first press comes at 0.25 s: about 30 records, then silence.
  EXPECT_GT(lines, 10);
  EXPECT_LT(lines, 60);
  emu->stop();
}

TEST(Fastrak, FindsTheBaudRateAndSaysWhichToConfigure) {
  dev::sim::EmulatorOptions eo;
  eo.faults.deviceBaud = 9600;
  auto emu = dev::sim::makeFastrak(quickStylus(), eo);
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.port = emu->path();
  cfg.baud = 115200;
  Collector col;
  dev::Driver driver(dev::makeDigitizerLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.stylus.size() >= 20; }, 10s)) << col.statusLog();
  driver.stop();
  EXPECT_TRUE(col.sawState(dev::LinkState::Warning, "--baud 9600")) << col.statusLog();
  std::lock_guard lock(col.mutex);
  expectSamplesMatchSentRecords(col.stylus, *emu, 0.087);
}

TEST(Fastrak, AWrongBaudWithoutProbingIsAnErrorThatNamesTheFix) {
  dev::sim::EmulatorOptions eo;
  eo.faults.deviceBaud = 9600;
  auto emu = dev::sim::makeFastrak(quickStylus(), eo);
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.port = emu->path();
  cfg.autobaud = false;
  auto link = dev::makeDigitizerLink(cfg);
  try {
    link->open();
    FAIL() << "opened at the wrong baud";
  } catch (const dev::DeviceError& e) {
    EXPECT_EQ(e.kind(), dev::DeviceErrorKind::Protocol);
    EXPECT_NE(std::string(e.what()).find("115200"), std::string::npos);
    EXPECT_NE(e.remedy().find("baud"), std::string::npos);
  }
}

TEST(Fastrak, ReconnectsAfterAnUnplugWithoutARestart) {
  auto emu = dev::sim::makeFastrak(quickStylus(), {});
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.port = emu->path();
  Collector col;
  dev::Driver driver(dev::makeDigitizerLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.stylus.size() >= 20; }));
  emu->unplugFor(0.4);
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.sawState(dev::LinkState::Disconnected); }, 5s));
  const std::size_t atUnplug = col.stylusCount();
  ASSERT_TRUE(col.waitFor([&](Collector& k) { return k.stylus.size() >= atUnplug + 40; }, 10s)) << col.statusLog();
  EXPECT_GE(driver.status().reconnects, 1);
  driver.stop();
  // The first sample of each connection says the stream began there (a press under way before
  // it was cut); no other sample does.
  std::lock_guard lock(col.mutex);
  ASSERT_FALSE(col.stylus.empty());
  EXPECT_TRUE(col.stylus.front().streamBegins);
  std::vector<std::size_t> begins;
  for (std::size_t i = 0; i < col.stylus.size(); ++i)
    if (col.stylus[i].streamBegins) begins.push_back(i);
  EXPECT_EQ(begins.size(), static_cast<std::size_t>(1 + driver.status().reconnects));
  ASSERT_GE(begins.size(), 2U);
  EXPECT_GE(begins[1], atUnplug);
}

TEST(SerialPorts, ABusyPortSaysWhoToClose) {
  auto emu = dev::sim::makeFastrak(quickStylus(), {});
  emu->start();
  auto first = dev::openTtyPort(emu->path(), {});
  try {
    (void)dev::openTtyPort(emu->path(), {});
    FAIL() << "a second open succeeded";
  } catch (const dev::DeviceError& e) {
    EXPECT_EQ(e.kind(), dev::DeviceErrorKind::Busy);
    EXPECT_NE(e.remedy().find("another program"), std::string::npos);
  }
}

TEST(SerialPorts, MissingPortsAndNonTtysAreNamed) {
  try {
    (void)dev::openSerialPort("/dev/ttyLEAFDIG-nope", {});
    FAIL();
  } catch (const dev::DeviceError& e) {
    EXPECT_EQ(e.kind(), dev::DeviceErrorKind::NotFound);
    EXPECT_NE(std::string(e.what()).find("/dev/ttyLEAFDIG-nope"), std::string::npos);
    EXPECT_NE(e.remedy().find("devices list"), std::string::npos);
  }
  const std::string file = ::testing::TempDir() + "/not-a-tty";
  std::ofstream(file) << "x";
  try {
    (void)dev::openTtyPort(file, {});
    FAIL();
  } catch (const dev::DeviceError& e) {
    EXPECT_EQ(e.kind(), dev::DeviceErrorKind::Config);
  }
  try {
    dev::SerialSettings s;
    s.baud = 12345;
    auto emu = dev::sim::makeFastrak(quickStylus(), {});
    emu->start();
    (void)dev::openTtyPort(emu->path(), s);
    FAIL();
  } catch (const dev::DeviceError& e) {
    EXPECT_EQ(e.kind(), dev::DeviceErrorKind::Config);
  }
}

TEST(SerialPorts, LibSerialPortListsPortsAndRefusesPtysCleanly) {
  for (const auto& p : dev::listSerialPorts()) EXPECT_FALSE(p.path.empty());
  auto emu = dev::sim::makeFastrak(quickStylus(), {});
  emu->start();
  EXPECT_THROW((void)dev::openLibSerialPort(emu->ptyPath(), {}), dev::DeviceError);
  // openSerialPort falls back to termios for a pty.
  EXPECT_NO_THROW((void)dev::openSerialPort(emu->ptyPath(), {}));
}

TEST(Polhemus, APatriotDriverOnALibertySaysWhichToChoose) {
  auto emu = dev::sim::makeLiberty(quickStylus(), {});
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.kind = dev::DigitizerKind::Patriot;
  cfg.port = emu->path();
  auto link = dev::makeDigitizerLink(cfg);
  try {
    link->open();
    FAIL();
  } catch (const dev::DeviceError& e) {
    EXPECT_EQ(e.kind(), dev::DeviceErrorKind::Config);
    EXPECT_NE(e.remedy().find("--digitizer liberty"), std::string::npos);
  }
}

// ---- calipers -----------------------------------------------------------------------------
std::shared_ptr<dev::sim::VirtualCaliper> caliper() {
  return std::make_shared<dev::sim::VirtualCaliper>(std::vector<double>{0.512, 0.231, 0.087, 1.25},
                                                    dev::sim::CaliperOptions{});
}

// Every reading is a line the emulator sent, with the value it measured.
void expectReadingsWereSent(const std::vector<dev::CaliperReading>& got, const dev::sim::Emulator& e,
                            double toleranceMm) {
  const auto sent = e.sentRecords();
  ASSERT_GE(sent.size(), got.size());
  for (const auto& r : got) {
    bool found = false;
    for (const auto& s : sent) found |= s.original == r.raw && std::abs(s.truthMm[0] - r.valueMm) < toleranceMm;
    EXPECT_TRUE(found) << r.raw;
  }
}

void expectReadingsNearTruth(const std::vector<dev::CaliperReading>& got, const std::vector<double>& truth) {
  ASSERT_GE(got.size(), truth.size());
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i].valueMm, truth[i % truth.size()], 0.02) << i;
}

dev::CaliperConfig sylvacOn(const dev::sim::Emulator& emu) {
  dev::CaliperConfig cfg;
  cfg.kind = dev::CaliperKind::Sylvac;
  cfg.port = emu.path();
  return cfg;
}

TEST(Sylvac, PcTriggeredReadingsAt4800_7E2) {
  auto cal = caliper();
  auto emu = dev::sim::makeSylvac(cal, {});
  emu->start();
  const dev::CaliperConfig cfg = sylvacOn(*emu);
  Collector col;
  dev::DriverOptions o;
  o.pollEvery = 40ms;
  dev::Driver driver(dev::makeCaliperLink(cfg), col.callbacks(), o);
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() >= 6; })) << col.statusLog();
  driver.stop();
  std::lock_guard lock(col.mutex);
  expectReadingsNearTruth(col.caliper, cal->truth());
  EXPECT_EQ(col.caliper[0].unit, "mm");
}

TEST(Sylvac, ReconnectingToTheSamePortWorks) {
  // The station's disconnect → connect opens the port a second time with 7E2 at 4800; on a
  // pseudo-terminal that request changes nothing, which glibc reports as EINVAL.
  auto cal = caliper();
  auto emu = dev::sim::makeSylvac(cal, {});
  emu->start();
  const dev::CaliperConfig cfg = sylvacOn(*emu);
  for (int round = 0; round < 3; ++round) {
    Collector col;
    dev::DriverOptions o;
    o.pollEvery = 40ms;
    dev::Driver driver(dev::makeCaliperLink(cfg), col.callbacks(), o);
    driver.start();
    ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() >= 2; })) << "round " << round << "\n"
                                                                                 << col.statusLog();
    driver.stop();
  }
  auto port = dev::openTtyPort(emu->path(), {4800, 7, dev::Parity::Even, 2, false});
  EXPECT_EQ(dev::describe(port->settings()), "4800 7E2");
}

TEST(Sylvac, AHostAtTheWrongSettingsGetsAClearError) {
  auto emu = dev::sim::makeSylvac(caliper(), {});
  emu->start();
  dev::CaliperConfig cfg = sylvacOn(*emu);
  cfg.baud = 9600;
  auto link = dev::makeCaliperLink(cfg);
  try {
    link->open();
    FAIL();
  } catch (const dev::DeviceError& e) {
    EXPECT_NE(e.remedy().find("4800 7E2"), std::string::npos);
  }
}

TEST(MitutoyoAscii, DataButtonPressesArriveUnasked) {
  auto cal = caliper();
  dev::sim::EmulatorOptions eo;
  eo.pressEveryS = 0.05;
  auto emu = dev::sim::makeMitutoyo(cal, eo);
  emu->start();
  dev::CaliperConfig cfg;
  cfg.kind = dev::CaliperKind::Mitutoyo;
  cfg.port = emu->path();
  Collector col;
  dev::Driver driver(dev::makeCaliperLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() >= 5; })) << col.statusLog();
  driver.stop();
  emu->stop();
  std::lock_guard lock(col.mutex);
  // Readings pushed before the driver connected went nowhere; what arrives was sent.
  expectReadingsWereSent(col.caliper, *emu, 1e-9);
}

TEST(UWave, TransmitterPressesArriveThroughTheReceiver) {
  auto cal = caliper();
  dev::sim::EmulatorOptions eo;
  eo.pressEveryS = 0.05;
  auto emu = dev::sim::makeUWave(cal, eo);
  emu->start();
  dev::CaliperConfig cfg;
  cfg.kind = dev::CaliperKind::UWave;
  cfg.port = emu->path();
  Collector col;
  dev::Driver driver(dev::makeCaliperLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() >= 4; })) << col.statusLog();
  driver.stop();
  emu->stop();
  std::lock_guard lock(col.mutex);
  expectReadingsWereSent(col.caliper, *emu, 0.006);
}

TEST(DeviceErrors, PermissionProblemsSayHowToGetAccess) {
  const auto e = dev::errorFromErrno(EACCES, "cannot open", "/dev/ttyUSB0");
  EXPECT_EQ(e.kind(), dev::DeviceErrorKind::Permission);
  EXPECT_NE(std::string(e.what()).find("/dev/ttyUSB0"), std::string::npos);
  EXPECT_NE(e.remedy().find("udev rule"), std::string::npos);
  EXPECT_NE(e.remedy().find("dialout"), std::string::npos);
  EXPECT_EQ(dev::errorFromErrno(EBUSY, "cannot open", "/dev/ttyUSB0").kind(), dev::DeviceErrorKind::Busy);
  EXPECT_EQ(dev::errorFromErrno(ENOENT, "cannot open", "/dev/ttyUSB0").kind(), dev::DeviceErrorKind::NotFound);
}

class HidProxy final : public dev::HidDevice {
 public:
  explicit HidProxy(std::shared_ptr<dev::MemoryHidDevice> d) : d_(std::move(d)) {}
  std::vector<std::uint8_t> readReport(std::chrono::milliseconds t) override { return d_->readReport(t); }
  dev::HidInfo info() const override { return d_->info(); }

 private:
  std::shared_ptr<dev::MemoryHidDevice> d_;
};

TEST(HidGauge, KeyboardWedgeReadingsSurviveAnUnplug) {
  auto cal = caliper();
  auto hid = std::make_shared<dev::MemoryHidDevice>(dev::sim::HidGaugeSimulator::usbItnInfo());
  dev::sim::HidGaugeOptions ho;
  ho.keypad = true;
  ho.comma = true;
  dev::sim::HidGaugeSimulator gauge(hid, cal, ho);
  dev::CaliperConfig cfg;
  cfg.kind = dev::CaliperKind::Hid;
  cfg.openHid = [hid]() -> std::unique_ptr<dev::HidDevice> {
    if (!hid->plugged())
      throw dev::DeviceError(dev::DeviceErrorKind::NotFound, "no HID device 0fe7:4001", "plug it in");
    return std::make_unique<HidProxy>(hid);
  };
  Collector col;
  dev::Driver driver(dev::makeCaliperLink(cfg), col.callbacks());
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.sawState(dev::LinkState::Streaming); }));
  std::vector<std::string> typed;
  for (int i = 0; i < 3; ++i) typed.push_back(gauge.press());
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() >= 3; })) << col.statusLog();
  hid->unplug();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.sawState(dev::LinkState::Disconnected); }));
  hid->replug();
  ASSERT_TRUE(col.waitFor([](Collector& k) {
    return std::count_if(k.statuses.begin(), k.statuses.end(),
                         [](auto& s) { return s.state == dev::LinkState::Streaming; }) >= 2;
  })) << col.statusLog();
  typed.push_back(gauge.press());
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() >= 4; })) << col.statusLog();
  driver.stop();
  std::lock_guard lock(col.mutex);
  for (std::size_t i = 0; i < 4; ++i) {
    std::string t = typed[i];
    t.pop_back();
    std::replace(t.begin(), t.end(), ',', '.');
    EXPECT_DOUBLE_EQ(col.caliper[i].valueMm, std::stod(t));
  }
}

TEST(UsbItn, VendorModeReadsOnRequestAndReportsAMissingGauge) {
  auto cal = caliper();
  auto cable = std::make_shared<dev::sim::UsbItnSimulator::Cable>();
  dev::CaliperConfig cfg;
  cfg.kind = dev::CaliperKind::UsbItn;
  cfg.openUsb = [cal, cable]() -> std::unique_ptr<dev::UsbVendorDevice> {
    auto d = std::make_unique<dev::sim::UsbItnSimulator>(cal);
    d->setCable(cable);
    return d;
  };
  Collector col;
  dev::DriverOptions o;
  o.pollEvery = 30ms;
  dev::Driver driver(dev::makeCaliperLink(cfg), col.callbacks(), o);
  driver.start();
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.caliper.size() >= 5; })) << col.statusLog();
  {
    std::lock_guard lock(cable->mutex);
    cable->noGauge = true;
  }
  ASSERT_TRUE(col.waitFor([](Collector& k) { return k.sawState(dev::LinkState::Warning, "911"); })) << col.statusLog();
  driver.stop();
  std::lock_guard lock(col.mutex);
  expectReadingsNearTruth(std::vector<dev::CaliperReading>(col.caliper.begin(), col.caliper.begin() + 4), cal->truth());
}

TEST(UsbAndHid, EnumerationOnAMachineWithoutDevicesIsEmptyNotAnError) {
  EXPECT_NO_THROW((void)dev::listUsbDevices());
  EXPECT_NO_THROW((void)dev::enumerateHid());
  EXPECT_THROW((void)dev::openHidapi(0x0fe7, 0x4001), dev::DeviceError);
  EXPECT_THROW((void)dev::openUsbVendorDevice(0x0fe7, 0x4001), dev::DeviceError);
  EXPECT_TRUE(dev::evdevNodesFor("/dev/hidraw-none").empty());
  dev::EvdevGrab grab("/dev/hidraw-none");
  EXPECT_TRUE(grab.grabbed().empty());
  ASSERT_FALSE(grab.problems().empty());
  EXPECT_NE(grab.problems()[0].find("focused window"), std::string::npos);
}

TEST(UsbHotplug, WatcherStartsAndStopsCleanly) {
  int calls = 0;
  {
    dev::UsbHotplugWatcher w([&] { ++calls; }, 100ms);
    EXPECT_EQ(w.usingHotplug(), dev::usbHotplugSupported());  // libusb hotplug where it exists, else polling
    std::this_thread::sleep_for(250ms);
  }
  EXPECT_EQ(calls, 0);  // nothing was plugged in
}

// ---- the spike filter ---------------------------------------------------------------------
dev::StylusSample at(double x, bool button = false) {
  dev::StylusSample s;
  s.positionMm = {x, 0, 0};
  s.button = button;
  return s;
}

TEST(StylusFilter, DropsAnIsolatedSpikeAndKeepsSmoothMotion) {
  dev::StylusFilter f(2.0);
  std::vector<dev::StylusSample> out;
  for (double x : {0.0, 1.0, 2.0, 30.0, 4.0, 5.0, 6.0, 7.0}) f.push(at(x), out);
  for (const auto& s : out) EXPECT_LT(std::abs(s.positionMm[0]), 10.0);
  EXPECT_GE(f.rejected(), 1u);
  EXPECT_GE(out.size(), 3u);
}

TEST(StylusFilter, AcceptsARealStepAfterOneSample) {
  dev::StylusFilter f(2.0);
  std::vector<dev::StylusSample> out;
  for (double x : {0.0, 0.0, 0.0, 50.0, 50.0, 50.0, 50.0}) f.push(at(x), out);
  ASSERT_FALSE(out.empty());
  EXPECT_DOUBLE_EQ(out.back().positionMm[0], 50.0);
}

TEST(StylusFilter, ASingleFlippedButtonRecordIsNoPress) {
  dev::StylusFilter f(2.0);
  std::vector<dev::StylusSample> out;
  for (int i = 0; i < 10; ++i) f.push(at(0.0, i == 4), out);
  for (const auto& s : out) EXPECT_FALSE(s.button);
  out.clear();
  for (int i = 0; i < 10; ++i) f.push(at(0.0, i >= 3 && i < 8), out);
  EXPECT_TRUE(std::any_of(out.begin(), out.end(), [](auto& s) { return s.button; }));
}

// The simulated hand moves on the device's clock (the emulator's record times), not the
// host's: an emulator woken late makes the records it owes in a burst, and each shows the
// hand as it was at its own instant — the press as long as the hand held it, the stylus still
// on its target throughout. The technician waits until the device has made every record of
// the gesture (idle), however late that is.
TEST(OperatorHand, AGestureIsInTheDevicesRecordsHoweverLateTheyAreMade) {
  dev::sim::StylusOptions o;
  o.sigmaMm = 0.1;
  o.tremorMm = 0.0;
  dev::sim::OperatorHand hand(o, 1.0);
  const dev::Vec3 target{120.0, -40.0, 15.0};
  hand.perform({target, 0.35, 0.45, 0.6});
  EXPECT_FALSE(hand.idle());
  // 3 s of records at 120 Hz, all made at once (the host did not run the emulator meanwhile).
  int pressed = 0;
  bool idleBeforeTheEnd = false;
  for (std::uint64_t k = 0; k < 360; ++k) {
    const double t = static_cast<double>(k) / 120.0;
    const auto st = hand.at(t, k);
    if (st.button) {
      ++pressed;
      EXPECT_LT(dist(st.positionMm, target), 1.0) << "record " << k << " moved during the press";
    }
    if (t < 1.4 && hand.idle()) idleBeforeTheEnd = true;
  }
  EXPECT_NEAR(pressed, 42, 1) << "0.35 s at 120 Hz";
  EXPECT_FALSE(idleBeforeTheEnd);
  EXPECT_TRUE(hand.idle());
  // The next gesture starts after the records made so far, not back in the device's past.
  hand.perform({{0.0, 0.0, 0.0}, 0.35, 0.45, 0.6});
  EXPECT_FALSE(hand.at(3.0, 360).button);
  EXPECT_FALSE(hand.idle());
}

}  // namespace
