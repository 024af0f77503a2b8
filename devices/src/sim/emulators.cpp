// Device emulators: FASTRAK, Patriot, Liberty, MicroScribe, Sylvac, Mitutoyo ASCII; the
// keyboard-wedge gauge and the USB-ITN vendor mode.
#include <algorithm>
#include <array>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "leafdig/devices/codecs/calipers.hpp"
#include "leafdig/devices/codecs/fastrak.hpp"
#include "leafdig/devices/codecs/microscribe.hpp"
#include "leafdig/devices/codecs/polhemus.hpp"
#include "leafdig/devices/errors.hpp"
#include "leafdig/devices/pose.hpp"
#include "leafdig/devices/sim/sim.hpp"

namespace leafdig::devices::sim {
namespace {

std::vector<int> parseInts(const std::string& s, std::size_t from) {
  std::vector<int> v;
  std::size_t i = from;
  while (i < s.size()) {
    std::size_t j = s.find(',', i);
    if (j == std::string::npos) j = s.size();
    try {
      v.push_back(std::stoi(s.substr(i, j - i)));
    } catch (const std::exception&) {
      v.push_back(-9999);
    }
    i = j + 1;
  }
  return v;
}

StylusSample sampleFrom(const StylusMotion::State& st, char status) {
  StylusSample s;
  s.station = 1;
  s.positionMm = st.positionMm;
  s.orientationDeg = st.orientationDeg;
  s.button = st.button;
  s.status = status ? std::string(1, status) : "ok";
  return s;
}

// ---- FASTRAK ------------------------------------------------------------------------------
// Receiver 1 is the stylus; with a reference motion a second receiver is plugged into socket 2
// (issue 29). Each active receiver has its own output list ('O<st>,…'); one output cycle sends
// the active receivers' records in number order, and the 120 Hz update rate is shared by them.
class FastrakEmulator final : public Emulator {
 public:
  FastrakEmulator(std::shared_ptr<const StylusMotion> stylus, EmulatorOptions o,
                  std::shared_ptr<const StylusMotion> reference)
      : Emulator(std::move(o)), stylus_(std::move(stylus)), reference_(std::move(reference)) {}
  ~FastrakEmulator() override { stop(); }
  std::string kind() const override { return "fastrak"; }

 protected:
  void powerOn() override {
    format_ = fastrak::Format{};  // inches, ASCII, list 2,4,1
    items_.fill(format_.items);
    active_ = {false, true, reference_ != nullptr, false, false};  // receivers found at power-up
    continuous_ = false;
    buttonMode_ = 1;
    cmd_.clear();
    lastButton_ = false;
  }
  double nativeRateHz() const override { return reference_ ? 60.0 : 120.0; }
  bool streaming() const override { return continuous_ || (buttonMode_ == 1 && !bursting()); }
  void onInput(const std::string& bytes) override {
    for (char c : bytes) {
      if (!cmd_.empty()) {
        if (c == '\r') {
          execute(cmd_);
          cmd_.clear();
        } else if (cmd_.size() < 300) {
          cmd_ += c;
        }
        continue;
      }
      switch (c) {
        case 'c': continuous_ = false; break;
        case 'C': continuous_ = true; break;
        case 'P': cycle(now(), k_++); break;
        case 'F': format_.binary = false; break;
        case 'f': format_.binary = true; break;
        case 'U': format_.centimetres = false; break;
        case 'u': format_.centimetres = true; break;
        case 'S': sendReply(fastrak::encodeStatus({1, format_.binary, format_.centimetres, false, continuous_})); break;
        case 'W': powerOn(); break;  // factory defaults (we never send it; a user might)
        case 0x19:                   // ^Y: re-initialise
          sendReply("\r\n*** fastrak power-up: self-test passed ***\r\n");
          powerOn();
          break;
        case 'D':
        case 'd':
        case 0x0B:
        case '\r':
        case '\n':
        case ' ': break;
        default:
          if (std::string("eOHlNAIRBbxvXoTG").find(c) != std::string::npos)
            cmd_ = std::string(1, c);
          else
            error(std::string(1, c), -99);
      }
    }
  }
  void produce(double t, std::uint64_t k) override {
    const auto st = stylus_->at(t, k);
    if (buttonMode_ == 1 && st.button && !lastButton_) {
      // The default button mode: a press toggles continuous output, or sends one record.
      if (continuous_)
        continuous_ = false;
      else
        cycle(t, k, &st);
    }
    lastButton_ = st.button;
    if (continuous_) cycle(t, k, &st);
  }

 private:
  // One output cycle: every active receiver's record, in number order.
  void cycle(double t, std::uint64_t k, const StylusMotion::State* stylus = nullptr) {
    if (active_[1]) record(stylus ? *stylus : stylus_->at(t, k), 1);
    if (reference_ && active_[2]) record(reference_->at(t, k), 2);
  }
  void record(const StylusMotion::State& st, int station) {
    const RecordFaults f = beginRecord();
    if (f.skip) return;
    fastrak::Format fmt = format_;
    fmt.items = items_[static_cast<std::size_t>(station)];
    StylusSample s = sampleFrom(st, f.status);
    s.station = station;
    if (std::find(fmt.items.begin(), fmt.items.end(), 11) != fmt.items.end())  // the same angles as a quaternion
      s.quaternion = quaternionFromRotation(rotationFromEulerDeg(st.orientationDeg));
    sendRecord(fastrak::encode(fmt, s), st.positionMm, st.button);
  }
  void error(const std::string& cmd, int code) {
    sendReply("2 E*ERROR* " + cmd.substr(0, 1) + " *ERROR* EC " + std::to_string(code) + "\r\n");
  }
  void execute(const std::string& cmd) {
    const char c = cmd[0];
    const auto args = parseInts(cmd, 1);
    const bool station = !args.empty() && args[0] >= 1 && args[0] <= 4;
    if (c == 'e') {
      if (args.size() != 2 || args[0] != 1 || (args[1] != 0 && args[1] != 1)) return error(cmd, -3);
      buttonMode_ = args[1];
    } else if (c == 'O') {
      if (args.size() < 2 || !station) return error(cmd, -3);
      fastrak::Format f = format_;
      f.items.assign(args.begin() + 1, args.end());
      try {
        (void)fastrak::recordLength(f);
      } catch (const std::invalid_argument&) {
        return error(cmd, -3);
      }
      items_[static_cast<std::size_t>(args[0])] = f.items;
    } else if (c == 'l') {  // active station state: on only where a receiver is plugged in
      if (args.size() != 2 || !station || (args[1] != 0 && args[1] != 1)) return error(cmd, -3);
      const bool plugged = args[0] == 1 || (args[0] == 2 && reference_);
      active_[static_cast<std::size_t>(args[0])] = args[1] == 1 && plugged;
    } else if (c == 'N' && args.size() == 1) {
      sendReply("21N  2.523  0.004  0.030\r\n");
    }
    // H, A, I, R, B, b, x, v, X, o, T, G: accepted; they do not change what we emulate.
  }
  std::shared_ptr<const StylusMotion> stylus_, reference_;
  fastrak::Format format_;
  std::array<std::vector<int>, 5> items_;  // output list per receiver (1-4)
  std::array<bool, 5> active_{};
  bool continuous_ = false, lastButton_ = false;
  int buttonMode_ = 1;
  std::string cmd_;
  std::uint64_t k_ = 1u << 30;
};

// ---- Patriot / Liberty --------------------------------------------------------------------
// With a reference motion a second sensor is plugged into port 2: every frame then carries sensor
// 1's record and sensor 2's, in that order, each at the tracker's rate.
class PolhemusEmulator final : public Emulator {
 public:
  PolhemusEmulator(std::shared_ptr<const StylusMotion> stylus, EmulatorOptions o, polhemus::Model m,
                   std::shared_ptr<const StylusMotion> reference)
      : Emulator(std::move(o)), stylus_(std::move(stylus)), reference_(std::move(reference)), model_(m) {}
  ~PolhemusEmulator() override { stop(); }
  std::string kind() const override { return polhemus::toString(model_); }

 protected:
  void powerOn() override {
    format_ = polhemus::Format{};
    format_.model = model_;
    format_.items = {2, 5, 1};
    format_.centimetres = false;
    format_.stations = model_ == polhemus::Model::Patriot ? 2 : 16;
    continuous_ = false;
    buttonMode_ = 1;
    line_.clear();
    lastButton_ = false;
    frame_ = 0;
  }
  double nativeRateHz() const override { return model_ == polhemus::Model::Patriot ? 60.0 : 240.0; }
  bool streaming() const override { return continuous_ || (buttonMode_ == 1 && !bursting()); }
  void onInput(const std::string& bytes) override {
    for (char c : bytes) {
      if (line_.empty() && (c == 'P' || c == 'p')) {  // single record; ends continuous output
        continuous_ = false;
        const std::uint64_t k = k_++;
        const double t = now();
        frame(t, k, stylus_->at(t, k), 'P');
        continue;
      }
      if (c == '\n') continue;
      if (c != '\r') {
        if (line_.size() < 300) line_ += c;
        continue;
      }
      execute(line_);
      line_.clear();
    }
  }
  void produce(double t, std::uint64_t k) override {
    const auto st = stylus_->at(t, k);
    if (buttonMode_ == 1 && st.button && !lastButton_) {
      if (continuous_)
        continuous_ = false;
      else
        frame(t, k, st, 'P');
    }
    lastButton_ = st.button;
    if (continuous_) frame(t, k, st, 'C');
  }

 private:
  // One frame: sensor 1's record, then the reference sensor's.
  void frame(double t, std::uint64_t k, const StylusMotion::State& stylus, char command) {
    record(stylus, command);
    if (reference_) record(reference_->at(t, k), command, 2);
  }
  void record(const StylusMotion::State& st, char command, int station = 1) {
    const RecordFaults f = beginRecord();
    if (f.skip) return;
    const auto ms = static_cast<std::uint32_t>(now() * 1000.0);
    StylusSample s = sampleFrom(st, f.status);
    s.station = station;
    if (std::find(format_.items.begin(), format_.items.end(), 7) != format_.items.end())
      s.quaternion = quaternionFromRotation(rotationFromEulerDeg(st.orientationDeg));
    sendRecord(polhemus::encode(format_, s, frame_++, ms, command), st.positionMm, st.button);
  }
  void execute(const std::string& l) {
    if (l.empty()) return;
    if (l == "C")
      continuous_ = true;
    else if (l == "U1")
      format_.centimetres = true;
    else if (l == "U0")
      format_.centimetres = false;
    else if (l == "F1")
      format_.binary = true;
    else if (l == "F0")
      format_.binary = false;
    else if (l[0] == '\x16') {
      const std::string name = model_ == polhemus::Model::Patriot ? "Patriot" : "Liberty";
      sendReply("\r\nPolhemus " + name +
                " (leafdig emulator)\r\nFirmware 1.0.0  IO Rev 1\r\nStations: " + (reference_ ? "2" : "1") + "\r\n");
    } else if (l.rfind("O*,", 0) == 0 || l.rfind("O1,", 0) == 0) {
      polhemus::Format f = format_;
      f.items.clear();
      for (int i : parseInts(l, 3)) f.items.push_back(i);
      try {
        (void)polhemus::payloadLength(f);
        format_.items = f.items;
      } catch (const std::invalid_argument&) {
        sendReply("*ERROR* invalid output item\r\n");
      }
    } else if (l.rfind("L1,", 0) == 0) {
      buttonMode_ = l == "L1,0" ? 0 : 1;
    } else if (l[0] == 'H' || l[0] == 'h' || l[0] == 'X' || l[0] == 'Y' || l[0] == 'b' || l[0] == '\x02') {
      // hemisphere, filters, boresight: accepted
    } else {
      sendReply("*ERROR* unknown command\r\n");
    }
  }
  std::shared_ptr<const StylusMotion> stylus_, reference_;
  polhemus::Model model_;
  polhemus::Format format_;
  bool continuous_ = false, lastButton_ = false;
  int buttonMode_ = 1;
  std::string line_;
  std::uint32_t frame_ = 0;
  std::uint64_t k_ = 1u << 30;
};

// ---- MicroScribe --------------------------------------------------------------------------
class MicroScribeEmulator final : public Emulator {
 public:
  MicroScribeEmulator(std::shared_ptr<const StylusMotion> stylus, EmulatorOptions o)
      : Emulator(std::move(o)), stylus_(std::move(stylus)), arm_(microscribe::referenceArm()) {}
  ~MicroScribeEmulator() override { stop(); }
  std::string kind() const override { return "microscribe"; }

 protected:
  void powerOn() override {
    phase_ = Phase::Detect;
    buf_.clear();
    joints_ = {0, -30, 60, 0, 60, 0};
  }
  double nativeRateHz() const override { return 100.0; }
  bool streaming() const override { return false; }  // answers requests only
  void produce(double, std::uint64_t) override {}
  void onInput(const std::string& bytes) override {
    for (char ch : bytes) {
      const auto c = static_cast<std::uint8_t>(ch);
      if (phase_ != Phase::Ready) {
        buf_ += ch;
        if (buf_.size() > 16) buf_.erase(0, buf_.size() - 16);
        if (buf_.find("IMMC") != std::string::npos) {
          sendReply("IMMC");
          phase_ = Phase::Locked;
          buf_.clear();
        } else if (phase_ == Phase::Locked && buf_.find("BEGIN") != std::string::npos) {
          sendReply(std::string("MSCR\0", 5));
          phase_ = Phase::Ready;
          buf_.clear();
        }
        continue;
      }
      switch (c) {
        case microscribe::kCmdDhParams: reply(c, microscribe::encodeDhParams(arm_)); break;
        case microscribe::kCmdMaxCounts: reply(c, microscribe::encodeMaxCounts(arm_)); break;
        case microscribe::kCmdProductName: text(c, "MicroScribe3D"); break;
        case 0xC9: text(c, "MSCR"); break;
        case microscribe::kCmdModel: text(c, "DX"); break;
        case microscribe::kCmdSerial: text(c, "LD-0001"); break;
        case 0xCC: text(c, "Standard"); break;
        case 0xCD: text(c, "Format DH0.5"); break;
        case microscribe::kCmdFirmware: text(c, "HCI 2.0"); break;
        case microscribe::kCmdEnd: powerOn(); break;
        case microscribe::kCmdAngles6: packet(); break;
        default: break;  // other commands: not emulated, no answer (as the arm times out)
      }
    }
  }

 private:
  enum class Phase { Detect, Locked, Ready };
  void reply(std::uint8_t cmd, const std::vector<std::uint8_t>& data) {
    std::string s(1, static_cast<char>(cmd));
    s.append(data.begin(), data.end());
    sendReply(s);
  }
  void text(std::uint8_t cmd, const std::string& t) {
    sendReply(std::string(1, static_cast<char>(cmd)) + t + std::string(1, '\0'));
  }
  void packet() {
    const RecordFaults f = beginRecord();
    if (f.skip) return;
    const auto st = stylus_->at(now(), k_++);
    (void)microscribe::inverseKinematics(arm_, st.positionMm, joints_);
    microscribe::Packet p;
    p.buttons = st.button ? 1 : 0;
    std::array<double, 6> quantised{};
    for (std::size_t i = 0; i < 6; ++i) {
      double a = std::fmod(joints_[i], 360.0);
      if (a < 0) a += 360.0;
      p.counts[i] = static_cast<int>(std::lround(a / 360.0 * arm_.countsPerRev[i])) % arm_.countsPerRev[i];
      quantised[i] = 360.0 * p.counts[i] / arm_.countsPerRev[i];
    }
    const auto bytes = microscribe::encodePacket(p);
    sendRecord(std::string(bytes.begin(), bytes.end()), microscribe::forwardKinematics(arm_, quantised), st.button);
  }
  std::shared_ptr<const StylusMotion> stylus_;
  microscribe::Arm arm_;
  Phase phase_ = Phase::Detect;
  std::string buf_;
  std::array<double, 6> joints_{};
  std::uint64_t k_ = 0;
};

// ---- serial gauges ------------------------------------------------------------------------
class GaugeEmulator : public Emulator {
 public:
  GaugeEmulator(std::shared_ptr<VirtualCaliper> c, EmulatorOptions o)
      : Emulator(o), caliper_(std::move(c)), pressEvery_(o.pressEveryS), nextPress_(o.pressEveryS) {}

 protected:
  bool streaming() const override { return false; }
  double nativeRateHz() const override { return 1.0; }
  void produce(double, std::uint64_t) override {}
  void onTick(double t) override {
    if (pressEvery_ > 0 && t >= nextPress_) {
      nextPress_ = t + pressEvery_;
      reading();
    }
    for (int n = dataPresses_.exchange(0); n > 0; --n) reading();
  }
  void onInput(const std::string& bytes) override {
    for (char c : bytes) {
      if (c == '\n') continue;
      if (c != '\r') {
        if (line_.size() < 64) line_ += c;
        continue;
      }
      command(line_);
      line_.clear();
    }
  }
  virtual void command(const std::string& l) = 0;
  virtual std::string format(double mm) = 0;
  void reading() {
    const RecordFaults f = beginRecord();
    if (f.skip) return;
    const double v = caliper_->next();
    sendRecord(format(v), {v, 0, 0}, false);
  }
  std::shared_ptr<VirtualCaliper> caliper_;
  std::string line_;
  double pressEvery_ = 0, nextPress_ = 0;
};

class SylvacEmulator final : public GaugeEmulator {
 public:
  SylvacEmulator(std::shared_ptr<VirtualCaliper> c, EmulatorOptions o) : GaugeEmulator(std::move(c), std::move(o)) {}
  ~SylvacEmulator() override { stop(); }
  std::string kind() const override { return "sylvac"; }

 protected:
  int defaultBaud() const override { return 4800; }
  void powerOn() override {
    inch_ = false;
    line_.clear();
    sendReply("SY304.0\r");  // identification at power-on
  }
  void command(const std::string& raw) override {
    std::string l;
    for (char c : raw) l += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (l.empty()) return;
    sendReply(raw + "\r");  // the instrument echoes commands
    if (l == "?" || l == "PRI")
      reading();
    else if (l == "MM")
      inch_ = false;
    else if (l == "IN")
      inch_ = true;
    else if (l == "UNI?")
      sendReply(inch_ ? "IN\r" : "MM\r");
    else if (l == "ID?")
      sendReply("SY304.0 leafdig-emulator\r");
    else if (l == "SET?")
      sendReply(std::string(inch_ ? "IN" : "MM") + " RES3 REF1 B1\r");
    else if (l == "BAT?")
      sendReply("B1\r");
    else if (l == "OUT0" || l == "OUT1" || l == "KEY0" || l == "KEY1" || l == "RES2" || l == "RES3" || l == "OFF") {
    } else
      sendReply("ERR1\r");
  }
  std::string format(double mm) override {
    return inch_ ? calipers::encodeSylvac(mm / kMmPerInch, 5) : calipers::encodeSylvac(mm, 3);
  }

 private:
  bool inch_ = false;
};

class MitutoyoEmulator final : public GaugeEmulator {
 public:
  MitutoyoEmulator(std::shared_ptr<VirtualCaliper> c, EmulatorOptions o) : GaugeEmulator(std::move(c), std::move(o)) {}
  ~MitutoyoEmulator() override { stop(); }
  std::string kind() const override { return "mitutoyo"; }

 protected:
  void powerOn() override { line_.clear(); }
  void command(const std::string& l) override {
    if (l == "1")
      reading();
    else if (l == "V")
      sendReply("1USB-ITN leafdig-emulator\r");
    else
      sendReply("912\r");  // format error
  }
  std::string format(double mm) override { return calipers::encodeMitutoyo(mm, 3); }
};

// U-WAVE-R receiver: measurement lines arrive when a transmitter's DATA is pressed; the
// info dialogue answers IR requests (docs/devices.md).
class UWaveEmulator final : public GaugeEmulator {
 public:
  UWaveEmulator(std::shared_ptr<VirtualCaliper> c, EmulatorOptions o) : GaugeEmulator(std::move(c), std::move(o)) {}
  ~UWaveEmulator() override { stop(); }
  std::string kind() const override { return "uwave"; }

 protected:
  void powerOn() override { line_.clear(); }
  void command(const std::string& l) override {
    if (l.rfind("IR1", 0) == 0)
      sendReply("RI1" + l.substr(3) + "00\r");
    else
      sendReply("ST1000051\r");
  }
  std::string format(double mm) override { return calipers::encodeUWave(mm, "mm"); }
};

}  // namespace

std::unique_ptr<Emulator> makeUWave(std::shared_ptr<VirtualCaliper> c, EmulatorOptions o) {
  return std::make_unique<UWaveEmulator>(std::move(c), std::move(o));
}

std::unique_ptr<Emulator> makeFastrak(std::shared_ptr<const StylusMotion> s, EmulatorOptions o,
                                      std::shared_ptr<const StylusMotion> reference) {
  return std::make_unique<FastrakEmulator>(std::move(s), std::move(o), std::move(reference));
}
std::unique_ptr<Emulator> makePatriot(std::shared_ptr<const StylusMotion> s, EmulatorOptions o,
                                      std::shared_ptr<const StylusMotion> reference) {
  return std::make_unique<PolhemusEmulator>(std::move(s), std::move(o), polhemus::Model::Patriot, std::move(reference));
}
std::unique_ptr<Emulator> makeLiberty(std::shared_ptr<const StylusMotion> s, EmulatorOptions o,
                                      std::shared_ptr<const StylusMotion> reference) {
  return std::make_unique<PolhemusEmulator>(std::move(s), std::move(o), polhemus::Model::Liberty, std::move(reference));
}
std::unique_ptr<Emulator> makeMicroScribe(std::shared_ptr<const StylusMotion> s, EmulatorOptions o) {
  return std::make_unique<MicroScribeEmulator>(std::move(s), std::move(o));
}
std::unique_ptr<Emulator> makeFastrak(VirtualStylus s, EmulatorOptions o) {
  return makeFastrak(std::make_shared<const VirtualStylus>(std::move(s)), std::move(o));
}
std::unique_ptr<Emulator> makePatriot(VirtualStylus s, EmulatorOptions o) {
  return makePatriot(std::make_shared<const VirtualStylus>(std::move(s)), std::move(o));
}
std::unique_ptr<Emulator> makeLiberty(VirtualStylus s, EmulatorOptions o) {
  return makeLiberty(std::make_shared<const VirtualStylus>(std::move(s)), std::move(o));
}
std::unique_ptr<Emulator> makeMicroScribe(VirtualStylus s, EmulatorOptions o) {
  return makeMicroScribe(std::make_shared<const VirtualStylus>(std::move(s)), std::move(o));
}
std::unique_ptr<Emulator> makeSylvac(std::shared_ptr<VirtualCaliper> c, EmulatorOptions o) {
  return std::make_unique<SylvacEmulator>(std::move(c), std::move(o));
}
std::unique_ptr<Emulator> makeMitutoyo(std::shared_ptr<VirtualCaliper> c, EmulatorOptions o) {
  return std::make_unique<MitutoyoEmulator>(std::move(c), std::move(o));
}

// ---- HID gauge ----------------------------------------------------------------------------
HidGaugeSimulator::HidGaugeSimulator(std::shared_ptr<MemoryHidDevice> d, std::shared_ptr<VirtualCaliper> c,
                                     HidGaugeOptions o)
    : device_(std::move(d)), caliper_(std::move(c)), o_(o) {}

std::string HidGaugeSimulator::press() {
  const double v = caliper_->next();
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", o_.decimals, v);
  std::string text = buf;
  if (o_.comma)
    for (char& ch : text)
      if (ch == '.') ch = ',';
  text += o_.tab ? '\t' : '\n';
  for (auto& r : calipers::encodeHidText(text, o_.keypad, o_.reportId)) device_->push(std::move(r));
  return text;
}

HidInfo HidGaugeSimulator::usbItnInfo() {
  HidInfo i;
  i.path = "sim:hid:0fe7:4001";
  i.vid = 0x0fe7;
  i.pid = 0x4001;
  i.manufacturer = "Mitutoyo (simulated)";
  i.product = "USB-ITN";
  i.usagePage = 1;
  i.usage = 6;
  return i;
}

// ---- USB-ITN vendor mode ------------------------------------------------------------------
UsbItnSimulator::UsbItnSimulator(std::shared_ptr<VirtualCaliper> c) : caliper_(std::move(c)) {}

namespace {
void checkPlugged(const std::shared_ptr<UsbItnSimulator::Cable>& c) {
  std::lock_guard lock(c->mutex);
  if (!c->plugged)
    throw DeviceError(DeviceErrorKind::Io, "usb:0fe7:4001: LIBUSB_ERROR_NO_DEVICE", "plug the USB-ITN cable back in");
}
}  // namespace

void UsbItnSimulator::controlOut(std::uint8_t rt, std::uint8_t req, std::uint16_t value, std::uint16_t,
                                 const std::vector<std::uint8_t>& data) {
  checkPlugged(cable_);
  if (rt != 0x40) throw DeviceError(DeviceErrorKind::Protocol, "USB-ITN: request type stalled", "");
  if (req == 0x01 && value == 0xA5A5) {
    vendorMode_ = true;
  } else if (req == 0x03) {
    if (!vendorMode_) throw DeviceError(DeviceErrorKind::Protocol, "USB-ITN: not in vendor mode", "");
    const std::string cmd(data.begin(), data.end());
    bool noGauge = false;
    {
      std::lock_guard lock(cable_->mutex);
      noGauge = cable_->noGauge;
    }
    if (cmd == "1\r")
      replies_.push_back(noGauge ? "911\r" : calipers::encodeMitutoyo(caliper_->next(), 3));
    else if (cmd == "V\r")
      replies_.push_back("1USB-ITN leafdig-emulator\r");
    else
      replies_.push_back("912\r");
  }
}

std::vector<std::uint8_t> UsbItnSimulator::controlIn(std::uint8_t rt, std::uint8_t req, std::uint16_t, std::uint16_t,
                                                     std::uint16_t length) {
  checkPlugged(cable_);
  if (rt == 0xC0 && req == 0x02 && length >= 1) return {0x01};
  throw DeviceError(DeviceErrorKind::Protocol, "USB-ITN: request stalled", "");
}

std::vector<std::uint8_t> UsbItnSimulator::interruptIn(std::uint8_t ep, std::chrono::milliseconds timeout) {
  checkPlugged(cable_);
  if (ep != 0x81) throw DeviceError(DeviceErrorKind::Protocol, "USB-ITN: no such endpoint", "");
  if (replies_.empty()) {
    std::this_thread::sleep_for(std::min(timeout, std::chrono::milliseconds(20)));
    return {};
  }
  std::string r = std::move(replies_.front());
  replies_.pop_front();
  return {r.begin(), r.end()};
}

}  // namespace leafdig::devices::sim
