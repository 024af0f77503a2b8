// Digitizer links: FASTRAK, Patriot, Liberty, MicroScribe, generic line.
#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <stdexcept>

#include "leafdig/devices/codecs/fastrak.hpp"
#include "leafdig/devices/codecs/microscribe.hpp"
#include "leafdig/devices/codecs/polhemus.hpp"
#include "leafdig/devices/codecs/record_clock.hpp"
#include "leafdig/devices/links/links.hpp"
#include "leafdig/devices/links/reference.hpp"
#include "leafdig/names/name_table.hpp"
#include "links/serial_link.hpp"

namespace leafdig::devices {
namespace {

using namespace std::chrono_literals;
using detail::drain;
using detail::readFor;
using detail::readUntil;

std::vector<int> baudsToTry(int first, bool autobaud) {
  std::vector<int> b{first};
  if (autobaud)
    for (int r : {9600, 115200, 57600, 38400, 19200})  // 9600 is the other common setting
      if (r != first) b.push_back(r);
  return b;
}

std::string list(const std::vector<int>& v) {
  std::string s;
  for (int x : v) s += (s.empty() ? "" : ", ") + std::to_string(x);
  return s;
}

const char* bitMeaning(char c) {
  switch (c) {
    case 'j': return "signal saturation (a receiver too close to the source?)";
    case 'k': return "low signal (receiver far from the source)";
    case 'x': return "receiver out of the motion box";
    case 'y': return "Euler angles outside their envelope";
    default: return "built-in test reported an error";
  }
}

const char* bitRemedy(char c) {
  switch (c) {
    case 'j': return "keep the stylus at least 10 cm from the source; points taken now are flagged";
    case 'k': return "bring the leaf closer to the source (FASTRAK: within about 75 cm)";
    case 'x': return "keep the stylus inside the tracked volume";
    case 'y': return "hold the stylus less steeply";
    default: return "check for metal near the source and receiver; power-cycle the tracker if it persists";
  }
}

// Common state of the serial digitizer links.
class SerialDigitizer : public DeviceLink {
 public:
  explicit SerialDigitizer(DigitizerConfig c) : cfg_(std::move(c)), open_(detail::orDefault(cfg_.openPort)) {}
  [[nodiscard]] std::string where() const override {
    return cfg_.referenceStation > 0 ? cfg_.port + " (reference receiver " + std::to_string(cfg_.referenceStation) + ")"
                                     : cfg_.port;
  }
  void close() noexcept override {
    if (port_) {
      try {
        sayGoodbye();
      } catch (...) {  // the device may be gone already
      }
    }
    port_.reset();
  }
  // A bad status stays reported for a second after the last record that carried it, so the
  // operator sees a steady warning rather than a flicker.
  [[nodiscard]] std::string warning() const override {
    if (reference_ && !reference_->problem().empty()) return reference_->problem();
    if (!badStatus_.empty() && Clock::now() - badStatusAt_ < std::chrono::seconds(1))
      return name() + " status '" + badStatus_ +
             "': " + (badStatus_.size() == 1 ? bitMeaning(badStatus_[0]) : "device warning");
    return baudNote_;
  }
  [[nodiscard]] std::string warningRemedy() const override {
    if (reference_ && !reference_->problem().empty()) return reference_->remedy();
    if (!badStatus_.empty() && Clock::now() - badStatusAt_ < std::chrono::seconds(1))
      return badStatus_.size() == 1 ? bitRemedy(badStatus_[0]) : bitRemedy('?');
    return baudNote_.empty() ? std::string() : "set the rate in the station's settings or with --baud";
  }

 protected:
  virtual void sayGoodbye() {}
  void send(const std::string& s) { port_->write(s); }
  // Opens at each rate in turn until `probe` says the device answered.
  template <class Probe>
  void openProbing(SerialSettings settings, const char* model, const std::string& hint, Probe probe) {
    const auto bauds = baudsToTry(cfg_.baud > 0 ? cfg_.baud : settings.baud, cfg_.autobaud);
    baudNote_.clear();
    for (int baud : bauds) {
      settings.baud = baud;
      port_ = open_(cfg_.port, settings);  // NotFound / Busy / Permission propagate at once
      if (probe(*port_)) {
        if (baud != bauds.front())
          baudNote_ = std::string(model) + " answered at " + std::to_string(baud) + " baud, not " +
                      std::to_string(bauds.front()) + ": pass --baud " + std::to_string(baud);
        return;
      }
      port_.reset();
    }
    throw DeviceError(
        DeviceErrorKind::Protocol,
        std::string("no answer from a ") + model + " on " + cfg_.port + " (tried " + list(bauds) + " baud)", hint);
  }
  void noteStatus(const std::vector<DeviceEvent>& out, std::size_t from) {
    for (std::size_t i = from; i < out.size(); ++i)
      if (auto* s = std::get_if<StylusSample>(&out[i]); s && s->status != "ok") {
        badStatus_ = s->status;
        badStatusAt_ = s->t;
      }
  }
  template <class DecodeFn>
  void pumpStream(std::chrono::milliseconds timeout, std::vector<DeviceEvent>& out, DecodeFn decode) {
    const auto bytes = port_->read(4096, timeout);
    if (bytes.empty()) return;
    const auto t = Clock::now();
    samples_.clear();
    decode(std::span<const std::uint8_t>(bytes), samples_);
    const std::size_t from = out.size();
    for (auto& s : samples_) {
      s.t = t;
      // A streaming device's records by their count, per receiver (issue 26).
      if (recordPeriodS_) s.deviceTime = clocks_.try_emplace(s.station, *recordPeriodS_).first->second.stamp(t);
      if (cfg_.tipOffsetMm && s.station == 1 && !toTip(s)) continue;
      if (!reference_) {
        out.emplace_back(std::move(s));
        continue;
      }
      paired_.clear();
      reference_->push(s, paired_);
      for (auto& p : paired_) out.emplace_back(std::move(p));
    }
    noteStatus(out, from);
  }

  // The stylus' sample at its tip (cfg_.tipOffsetMm): p + R·t. False for a record without an
  // orientation (withheld: the links' output lists always ask for one, so only a record the
  // decoder could not read whole lacks it).
  bool toTip(StylusSample& s) const {
    const auto pose = poseOf(s);
    if (!pose) return false;
    const Vec3& t = *cfg_.tipOffsetMm;
    const Rotation& r = pose->rotation;
    for (std::size_t a = 0; a < 3; ++a) s.positionMm[a] += r[3 * a] * t[0] + r[3 * a + 1] * t[1] + r[3 * a + 2] * t[2];
    return true;
  }

  // With a reference receiver (cfg_.referenceStation): checks its number against the tracker's
  // receivers and starts pairing afresh; returns the number of stations to accept.
  int useReference(const char* model, int stations) {
    if (cfg_.referenceStation == 0) {
      reference_.reset();
      return 1;
    }
    if (cfg_.referenceStation < 2 || cfg_.referenceStation > stations)
      throw DeviceError(DeviceErrorKind::Config,
                        std::string("a ") + model + " has no reference receiver " +
                            std::to_string(cfg_.referenceStation) + " (the stylus is receiver 1; receivers 2-" +
                            std::to_string(stations) + " can be the reference)",
                        "plug the reference receiver into socket 2 and say reference=2");
    ReferenceOptions o;
    o.referenceStation = cfg_.referenceStation;
    o.jumpMm = cfg_.referenceJumpMm;
    o.jumpDeg = cfg_.referenceJumpDeg;
    reference_.emplace(o);
    return cfg_.referenceStation;
  }

  // Streaming links time their records by count at this period (a new count on every open).
  void streamAt(double nativeRateHz) {
    recordPeriodS_ = 1.0 / (cfg_.recordRateHz > 0 ? cfg_.recordRateHz : nativeRateHz);
    clocks_.clear();
  }

  DigitizerConfig cfg_;
  detail::PortOpener open_;
  std::unique_ptr<SerialPort> port_;
  std::optional<double> recordPeriodS_;
  std::map<int, RecordClock> clocks_;
  std::string badStatus_, baudNote_;
  Clock::time_point badStatusAt_{};
  std::vector<StylusSample> samples_, paired_;
  std::optional<ReferenceFrame> reference_;
};

// ---- FASTRAK ------------------------------------------------------------------------------
class FastrakLink final : public SerialDigitizer {
 public:
  using SerialDigitizer::SerialDigitizer;
  [[nodiscard]] std::string name() const override { return "FASTRAK"; }
  void open() override {
    badStatus_.clear();
    openProbing(defaultSettings(DigitizerKind::Fastrak), "FASTRAK",
                "check the baud rate (rear-panel I/O switches), the null-modem cable, that the "
                "system is on and finished its self-test, and that it is a FASTRAK (else try "
                "--digitizer patriot or liberty)",
                [&](SerialPort& p) {
                  p.write("c");  // continuous off (never W or ^K: they wipe the user's setup)
                  drain(p, 40ms, 300ms);
                  p.write("S");
                  fastrak::Status st;
                  return hasStatus(readUntil(p, 400ms, [&](const std::string& b) { return hasStatus(b, &st); }), &st);
                });
    fastrak::Format f;
    f.items = {2, 4, 16, 1};
    f.binary = cfg_.binary;
    f.centimetres = true;
    f.stations = useReference("FASTRAK", 4);
    send("e1,0\r");  // mouse mode: the button is reported in item 16, the stream never stops
    send("u");       // centimetres
    send(fastrak::outputListCommand(f));
    if (reference_) {  // the reference receiver on, with the same list (its angles: item 4)
      send("l" + std::to_string(f.stations) + ",1\r");
      send(fastrak::outputListCommand(f, f.stations));
    }
    if (!cfg_.hemisphere.empty()) send("H1," + cfg_.hemisphere + "\r");
    send(f.binary ? "f" : "F");
    send("S");
    fastrak::Status st;
    const std::string reply = readUntil(*port_, 800ms, [&](const std::string& b) { return hasStatus(b, &st); });
    if (!hasStatus(reply, &st))
      throw DeviceError(DeviceErrorKind::Protocol, "FASTRAK on " + cfg_.port + " stopped answering during set-up",
                        "power-cycle the FASTRAK and check the cable");
    if (!st.centimetres || st.binary != f.binary)
      throw DeviceError(DeviceErrorKind::Protocol,
                        "FASTRAK on " + cfg_.port + " did not take the settings (status reports " +
                            (st.centimetres ? "cm" : "inches") + ", " + (st.binary ? "binary" : "ASCII") + ")",
                        "power-cycle the FASTRAK; if it persists, its firmware may not support these commands");
    dec_ = fastrak::DecoderState{};
    dec_.format = f;
    // Continuous output: 120 records a second for one receiver, shared by the active ones.
    streamAt(reference_ ? 60.0 : 120.0);
    send("C");
  }
  void pump(std::chrono::milliseconds timeout, std::vector<DeviceEvent>& out) override {
    pumpStream(timeout, out,
               [&](std::span<const std::uint8_t> b, std::vector<StylusSample>& s) { fastrak::decode(dec_, b, s); });
  }
  [[nodiscard]] DecodeStats stats() const override { return dec_.stats; }

 private:
  void sayGoodbye() override { send("c"); }
  static bool hasStatus(const std::string& b, fastrak::Status* st) {
    for (std::size_t i = b.find('S'); i != std::string::npos; i = b.find('S', i + 1)) {
      if (i < 2 || b[i - 2] != '2') continue;
      const std::size_t nl = b.find('\n', i);
      if (nl == std::string::npos) continue;
      if (fastrak::parseStatus(std::string_view(b).substr(i - 2, nl - i + 3), *st)) return true;
    }
    return false;
  }
  fastrak::DecoderState dec_;
};

// ---- Patriot / Liberty --------------------------------------------------------------------
class PolhemusLink final : public SerialDigitizer {
 public:
  PolhemusLink(DigitizerConfig c, polhemus::Model m) : SerialDigitizer(std::move(c)), model_(m) {}
  [[nodiscard]] std::string name() const override { return model_ == polhemus::Model::Patriot ? "Patriot" : "Liberty"; }
  void open() override {
    badStatus_.clear();
    const std::string me = name();
    const std::string other = model_ == polhemus::Model::Patriot ? "Liberty" : "Patriot";
    std::string who;
    openProbing(defaultSettings(cfg_.kind), me.c_str(),
                "check the baud rate, the cable and that the tracker is on and finished booting", [&](SerialPort& p) {
                  p.write("P");  // a single record also ends continuous output
                  drain(p, 40ms, 300ms);
                  p.write("\x16\r");  // ^V: WhoAmI
                  who =
                      readUntil(p, 400ms, [&](const std::string& b) { return contains(b, me) || contains(b, other); });
                  return contains(who, me) || contains(who, other);
                });
    if (!contains(who, me))
      throw DeviceError(DeviceErrorKind::Config, "the tracker on " + cfg_.port + " is a " + other + ", not a " + me,
                        "use --digitizer " + std::string(model_ == polhemus::Model::Patriot ? "liberty" : "patriot"));
    polhemus::Format f;
    f.model = model_;
    f.binary = cfg_.binary;
    f.centimetres = true;
    f.items = {2, 5, 10, 1};
    f.stations = model_ == polhemus::Model::Patriot ? 2 : 16;
    (void)useReference(me.c_str(), f.stations);  // every sensor reports at the tracker's rate
    send("U1\r");
    send(f.binary ? "F1\r" : "F0\r");
    send(polhemus::outputListCommand(f));
    send("L1,0\r");  // stylus button reported in item 10; records keep flowing
    if (!cfg_.hemisphere.empty()) send("H*," + cfg_.hemisphere + "\r");
    drain(*port_, 40ms, 300ms);
    dec_ = polhemus::DecoderState{};
    dec_.format = f;
    streamAt(model_ == polhemus::Model::Patriot ? 60.0 : 240.0);
    send("C\r");
  }
  void pump(std::chrono::milliseconds timeout, std::vector<DeviceEvent>& out) override {
    pumpStream(timeout, out,
               [&](std::span<const std::uint8_t> b, std::vector<StylusSample>& s) { polhemus::decode(dec_, b, s); });
  }
  [[nodiscard]] DecodeStats stats() const override { return dec_.stats; }

 private:
  static bool contains(const std::string& hay, const std::string& needle) {
    std::string h = hay, n = needle;
    for (auto& c : h) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (auto& c : n) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return h.find(n) != std::string::npos;
  }
  void sayGoodbye() override { send("P"); }
  polhemus::Model model_;
  polhemus::DecoderState dec_;
};

// ---- MicroScribe --------------------------------------------------------------------------
class MicroScribeLink final : public SerialDigitizer {
 public:
  using SerialDigitizer::SerialDigitizer;
  [[nodiscard]] std::string name() const override { return "MicroScribe"; }
  void open() override {
    SerialSettings s = defaultSettings(DigitizerKind::MicroScribe);
    if (cfg_.baud > 0) s.baud = cfg_.baud;
    port_ = open_(cfg_.port, s);
    // The arm hunts for our baud rate and echoes IMMC when it has locked on.
    std::string got;
    for (int i = 0; i < 25 && got.find("IMMC") == std::string::npos; ++i) {
      send("IMMC");
      got += readFor(*port_, 80ms);
    }
    if (got.find("IMMC") == std::string::npos)
      throw DeviceError(DeviceErrorKind::Protocol, "no answer from a MicroScribe on " + cfg_.port,
                        "switch the arm on with the stylus in its home holder (it calibrates there), "
                        "check the cable; USB-era arms (G2, MX, i) need the vendor SDK");
    drain(*port_, 40ms, 300ms);
    send("BEGIN");
    const std::string hello = readUntil(
        *port_, 1000ms, [](const std::string& b) { return b.find(std::string("MSCR\0", 5)) != std::string::npos; });
    if (hello.find(std::string("MSCR\0", 5)) == std::string::npos)
      throw DeviceError(DeviceErrorKind::Protocol, "the MicroScribe on " + cfg_.port + " did not answer BEGIN",
                        "power-cycle the arm with the stylus in its home holder");
    dec_ = microscribe::DecoderState{};
    const auto dh = command(microscribe::kCmdDhParams, 36);
    const auto counts = command(microscribe::kCmdMaxCounts, 12);
    if (!microscribe::decodeDhParams(dh, dec_.arm) || !microscribe::decodeMaxCounts(counts, dec_.arm))
      throw DeviceError(DeviceErrorKind::Protocol, "the MicroScribe on " + cfg_.port + " sent unusable arm parameters",
                        "power-cycle the arm; if it persists, the firmware is not the MSCR serial HCI");
    model_ = text(microscribe::kCmdModel);
    outstanding_ = false;
  }
  void pump(std::chrono::milliseconds timeout, std::vector<DeviceEvent>& out) override {
    const auto now = Clock::now();
    if ((!outstanding_ && now - lastRequest_ >= 8ms) || now - lastRequest_ > 200ms) {
      const std::uint8_t cmd = microscribe::kCmdAngles6;
      port_->write(&cmd, 1, 200ms);
      lastRequest_ = now;
      outstanding_ = true;
    }
    const std::size_t before = out.size();
    pumpStream(std::min(timeout, std::chrono::milliseconds(10)), out,
               [&](std::span<const std::uint8_t> b, std::vector<StylusSample>& s) { microscribe::decode(dec_, b, s); });
    if (out.size() > before) outstanding_ = false;
  }
  [[nodiscard]] DecodeStats stats() const override { return dec_.stats; }

 private:
  void sayGoodbye() override {
    const std::uint8_t end = microscribe::kCmdEnd;
    port_->write(&end, 1, 100ms);
  }
  std::vector<std::uint8_t> command(std::uint8_t cmd, std::size_t n) {
    port_->write(&cmd, 1, 200ms);
    const std::string r = readUntil(*port_, 1000ms, [&](const std::string& b) { return b.size() >= n + 1; });
    if (r.size() < n + 1 || static_cast<std::uint8_t>(r[0]) != cmd) return {};
    return {r.begin() + 1, r.begin() + 1 + static_cast<std::ptrdiff_t>(n)};
  }
  std::string text(std::uint8_t cmd) {
    port_->write(&cmd, 1, 200ms);
    const std::string r =
        readUntil(*port_, 500ms, [](const std::string& b) { return b.size() > 1 && b.back() == '\0'; });
    return r.size() > 2 ? r.substr(1, r.size() - 2) : std::string();
  }
  microscribe::DecoderState dec_;
  std::string model_;
  bool outstanding_ = false;
  Clock::time_point lastRequest_{};
};

// ---- Generic line digitizer ---------------------------------------------------------------
class LineLink final : public SerialDigitizer {
 public:
  using SerialDigitizer::SerialDigitizer;
  [[nodiscard]] std::string name() const override { return "line digitizer"; }
  void open() override {
    SerialSettings s = defaultSettings(DigitizerKind::Line);
    s.baud = cfg_.baud > 0 ? cfg_.baud : cfg_.line.baud;
    port_ = open_(cfg_.port, s);
    for (const std::string& l : cfg_.line.init) {
      if (!l.empty() && l[0] == '*') {
        try {
          detail::sleepFor(std::stod(l.substr(1)));
        } catch (const std::exception&) {
          throw DeviceError(DeviceErrorKind::Config, "init line '" + l + "' is not a sleep ('*0.5')",
                            "fix the configuration file");
        }
        continue;
      }
      send(l);
    }
    drain(*port_, 40ms, 300ms);
    dec_ = line::DecoderState{};
    dec_.config = cfg_.line;
    if (!cfg_.line.start.empty()) send(cfg_.line.start);
  }
  void pump(std::chrono::milliseconds timeout, std::vector<DeviceEvent>& out) override {
    if (!cfg_.line.poll.empty() && Clock::now() - lastPoll_ >= 10ms) {
      send(cfg_.line.poll);
      lastPoll_ = Clock::now();
    }
    pumpStream(std::min(timeout, std::chrono::milliseconds(20)), out,
               [&](std::span<const std::uint8_t> b, std::vector<StylusSample>& s) { line::decode(dec_, b, s); });
  }
  [[nodiscard]] DecodeStats stats() const override { return dec_.stats; }
  [[nodiscard]] std::chrono::milliseconds stallTimeout() const override { return std::chrono::milliseconds(2000); }

 private:
  void sayGoodbye() override {
    if (!cfg_.line.stop.empty()) send(cfg_.line.stop);
  }
  line::DecoderState dec_;
  Clock::time_point lastPoll_{};
};

}  // namespace

namespace {
constexpr NameTable<DigitizerKind, 5> kDigitizerKinds{{{DigitizerKind::Fastrak, "fastrak"},
                                                       {DigitizerKind::Patriot, "patriot"},
                                                       {DigitizerKind::Liberty, "liberty"},
                                                       {DigitizerKind::MicroScribe, "microscribe"},
                                                       {DigitizerKind::Line, "line"}}};
}  // namespace

const char* toString(DigitizerKind k) {
  return nameIn(kDigitizerKinds, k);
}

DigitizerKind digitizerKindFromString(const std::string& s) {
  return parseName(kDigitizerKinds, s, "digitizer");
}

SerialSettings defaultSettings(DigitizerKind k) {
  SerialSettings s;
  s.baud = k == DigitizerKind::MicroScribe ? 38400 : k == DigitizerKind::Line ? 9600 : 115200;
  return s;
}

std::unique_ptr<DeviceLink> makeDigitizerLink(DigitizerConfig c) {
  switch (c.kind) {
    case DigitizerKind::Fastrak: return std::make_unique<FastrakLink>(std::move(c));
    case DigitizerKind::Patriot: return std::make_unique<PolhemusLink>(std::move(c), polhemus::Model::Patriot);
    case DigitizerKind::Liberty: return std::make_unique<PolhemusLink>(std::move(c), polhemus::Model::Liberty);
    case DigitizerKind::MicroScribe: return std::make_unique<MicroScribeLink>(std::move(c));
    case DigitizerKind::Line: return std::make_unique<LineLink>(std::move(c));
  }
  throw std::invalid_argument("unknown digitizer kind");
}

}  // namespace leafdig::devices
