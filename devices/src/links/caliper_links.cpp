// Caliper links: serial gauges (Mitutoyo ASCII, U-WAVE, Sylvac), HID keyboard wedges,
// Mitutoyo USB-ITN vendor mode.
#include <cstdio>
#include <stdexcept>

#include "leafdig/devices/codecs/calipers.hpp"
#include "leafdig/devices/links/links.hpp"
#include "leafdig/names/name_table.hpp"
#include "links/serial_link.hpp"

namespace leafdig::devices {
namespace {

using namespace std::chrono_literals;

std::string hexId(std::uint16_t vid, std::uint16_t pid) {
  char b[16];
  std::snprintf(b, sizeof b, "%04x:%04x", vid, pid);
  return b;
}

class CaliperLinkBase : public DeviceLink {
 public:
  explicit CaliperLinkBase(CaliperConfig c) : cfg_(std::move(c)) {}
  bool streams() const override { return false; }  // gauges are silent until asked or pressed
  std::string warning() const override { return warning_; }

 protected:
  void emit(std::vector<CaliperReading>& readings, std::vector<DeviceEvent>& out) {
    const auto t = Clock::now();
    for (auto& r : readings) {
      r.t = t;
      out.emplace_back(std::move(r));
    }
    if (!readings.empty()) warning_.clear();
    readings.clear();
  }
  CaliperConfig cfg_;
  std::string warning_;
  std::vector<CaliperReading> readings_;
};

// ---- serial gauges ------------------------------------------------------------------------
class SerialCaliperLink final : public CaliperLinkBase {
 public:
  explicit SerialCaliperLink(CaliperConfig c)
      : CaliperLinkBase(std::move(c)), open_(detail::orDefault(cfg_.openPort)) {}
  std::string name() const override {
    return cfg_.kind == CaliperKind::Sylvac ? "Sylvac" : cfg_.kind == CaliperKind::UWave ? "U-WAVE" : "Mitutoyo";
  }
  std::string where() const override { return cfg_.port; }
  void open() override {
    SerialSettings s = defaultSettings(cfg_.kind);
    if (cfg_.baud > 0) s.baud = cfg_.baud;
    port_ = open_(cfg_.port, s);
    sylvac_ = calipers::SylvacState{};
    mitutoyo_ = calipers::MitutoyoState{};
    mitutoyo_.unit = cfg_.unit;
    uwave_ = calipers::UWaveState{};
    warning_.clear();
    if (cfg_.kind == CaliperKind::Sylvac && !cfg_.dtrTrigger) {
      port_->write("MM\r");   // readings in millimetres from here on
      port_->write("ID?\r");  // identification (kept for the record)
      const std::string r = detail::readUntil(
          *port_, 500ms, [](const std::string& b) { return b.find("SY") != std::string::npos && b.back() == '\r'; });
      feed(std::vector<std::uint8_t>(r.begin(), r.end()), nullptr);
      if (sylvac_.identification.empty() && r.find("MM") == std::string::npos)
        throw DeviceError(DeviceErrorKind::Protocol, "no answer from a Sylvac gauge on " + cfg_.port,
                          "check the gauge is on and its cable is a duplex (RS/USB) cable; the port "
                          "must be 4800 7E2 (leafdig sets it); for a simplex cable pass --dtr-trigger");
    }
  }
  void close() noexcept override { port_.reset(); }
  void trigger() override {
    if (!port_) return;
    if (cfg_.kind == CaliperKind::Sylvac) {
      if (cfg_.dtrTrigger) {
        port_->setDtr(false);
        detail::sleepFor(0.12);  // >= 110 ms
        port_->setDtr(true);
      } else {
        port_->write("?\r");
      }
    } else if (cfg_.kind == CaliperKind::Mitutoyo) {
      port_->write("1\r");
    }
  }
  void pump(std::chrono::milliseconds timeout, std::vector<DeviceEvent>& out) override {
    const auto b = port_->read(1024, timeout);
    if (!b.empty()) feed(b, &out);
  }
  DecodeStats stats() const override {
    return cfg_.kind == CaliperKind::Sylvac  ? sylvac_.stats
           : cfg_.kind == CaliperKind::UWave ? uwave_.stats
                                             : mitutoyo_.stats;
  }

 private:
  void feed(const std::vector<std::uint8_t>& b, std::vector<DeviceEvent>* out) {
    const std::span<const std::uint8_t> s(b);
    if (cfg_.kind == CaliperKind::Sylvac) {
      const std::size_t errs = sylvac_.errors.size();
      calipers::decodeSylvac(sylvac_, s, readings_);
      if (sylvac_.errors.size() > errs) {
        const std::string& e = sylvac_.errors.back();
        warning_ = "Sylvac reports " + e + ": " + calipers::sylvacErrorMeaning(e.size() > 3 ? e[3] : '?');
      }
    } else if (cfg_.kind == CaliperKind::UWave) {
      calipers::decodeUWave(uwave_, s, readings_);
    } else {
      const std::size_t errs = mitutoyo_.errors.size();
      calipers::decodeMitutoyo(mitutoyo_, s, readings_);
      if (mitutoyo_.errors.size() > errs) {
        const std::string& e = mitutoyo_.errors.back();
        warning_ = "Mitutoyo reports error " + e +
                   (e.size() >= 3 && e[2] == '1' ? " (no data: is the gauge connected and on?)" : "");
      }
    }
    if (out)
      emit(readings_, *out);
    else
      readings_.clear();
  }
  detail::PortOpener open_;
  std::unique_ptr<SerialPort> port_;
  calipers::SylvacState sylvac_;
  calipers::MitutoyoState mitutoyo_;
  calipers::UWaveState uwave_;
};

// ---- HID keyboard wedge ------------------------------------------------------------------
class HidCaliperLink final : public CaliperLinkBase {
 public:
  using CaliperLinkBase::CaliperLinkBase;
  std::string name() const override { return "HID gauge"; }
  std::string where() const override { return cfg_.hidPath.empty() ? hexId(cfg_.vid, cfg_.pid) : cfg_.hidPath; }
  void open() override {
    dev_ = cfg_.openHid           ? cfg_.openHid()
           : cfg_.hidPath.empty() ? openHidapi(cfg_.vid, cfg_.pid)
                                  : openHidapiPath(cfg_.hidPath);
    state_ = calipers::HidKeyboardState{};
    state_.defaultUnit = cfg_.unit == "in" ? "in" : "mm";
    warning_.clear();
    grab_.reset();
    if (cfg_.grabKeyboard && !cfg_.openHid) {
      grab_ = std::make_unique<EvdevGrab>(dev_->info().path);
      if (!grab_->problems().empty()) warning_ = grab_->problems().front();
    }
  }
  void close() noexcept override {
    grab_.reset();  // releases the keyboard first
    dev_.reset();
  }
  void pump(std::chrono::milliseconds timeout, std::vector<DeviceEvent>& out) override {
    const auto end = Clock::now() + timeout;
    do {
      const auto r = dev_->readReport(std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()));
      if (r.empty()) break;
      calipers::decodeHidReport(state_, r, readings_);
      emit(readings_, out);
    } while (Clock::now() < end);
  }
  DecodeStats stats() const override { return state_.stats; }

 private:
  std::unique_ptr<HidDevice> dev_;
  std::unique_ptr<EvdevGrab> grab_;
  calipers::HidKeyboardState state_;
};

// ---- Mitutoyo USB-ITN vendor mode ---------------------------------------------------------
class UsbItnLink final : public CaliperLinkBase {
 public:
  using CaliperLinkBase::CaliperLinkBase;
  std::string name() const override { return "Mitutoyo USB-ITN"; }
  std::string where() const override { return "usb:" + hexId(cfg_.vid, cfg_.pid); }
  void open() override {
    dev_ = cfg_.openUsb ? cfg_.openUsb() : openUsbVendorDevice(cfg_.vid, cfg_.pid);
    dev_->controlOut(0x40, 0x01, 0xA5A5, 0, {});  // enable the vendor (VCP) mode
    const auto ack = dev_->controlIn(0xC0, 0x02, 0, 0, 1);
    if (ack.size() != 1 || ack[0] != 0x01)
      throw DeviceError(DeviceErrorKind::Protocol, "the USB-ITN did not acknowledge vendor mode",
                        "unplug and replug the cable; the keyboard (DATA button) mode returns on replug");
    state_ = calipers::MitutoyoState{};
    state_.unit = cfg_.unit;
    warning_.clear();
  }
  void close() noexcept override { dev_.reset(); }
  void trigger() override {
    if (dev_) dev_->controlOut(0x40, 0x03, 0, 0, {'1', '\r'});
  }
  void pump(std::chrono::milliseconds timeout, std::vector<DeviceEvent>& out) override {
    const auto b = dev_->interruptIn(0x81, timeout);
    if (b.empty()) return;
    const std::size_t errs = state_.errors.size();
    calipers::decodeMitutoyo(state_, b, readings_);
    if (state_.errors.size() > errs) {
      const std::string& e = state_.errors.back();
      warning_ = "USB-ITN reports " + e +
                 (e == "911"   ? ": gauge timeout (is a gauge plugged into the cable?)"
                  : e == "918" ? ": busy, retrying"
                               : "");
    }
    emit(readings_, out);
  }
  DecodeStats stats() const override { return state_.stats; }

 private:
  std::unique_ptr<UsbVendorDevice> dev_;
  calipers::MitutoyoState state_;
};

}  // namespace

namespace {
constexpr NameTable<CaliperKind, 5> kCaliperKinds{{{CaliperKind::Hid, "hid"},
                                                   {CaliperKind::UsbItn, "usb-itn"},
                                                   {CaliperKind::Mitutoyo, "mitutoyo"},
                                                   {CaliperKind::UWave, "uwave"},
                                                   {CaliperKind::Sylvac, "sylvac"}}};
}  // namespace

const char* toString(CaliperKind k) {
  return nameIn(kCaliperKinds, k);
}

bool parseVidPid(const std::string& s, std::uint16_t& vid, std::uint16_t& pid) {
  unsigned v = 0, p = 0;
  char tail = 0;
  if (std::sscanf(s.c_str(), "%x:%x%c", &v, &p, &tail) != 2 || v > 0xffff || p > 0xffff) return false;
  vid = static_cast<std::uint16_t>(v);
  pid = static_cast<std::uint16_t>(p);
  return true;
}

CaliperKind caliperKindFromString(const std::string& s) {
  return parseName(kCaliperKinds, s, "caliper");
}

SerialSettings defaultSettings(CaliperKind k) {
  SerialSettings s;
  s.baud = 9600;
  if (k == CaliperKind::Sylvac) {
    s.baud = 4800;
    s.dataBits = 7;
    s.parity = Parity::Even;
    s.stopBits = 2;
  } else if (k == CaliperKind::UWave) {
    s.baud = 57600;
  }
  return s;
}

std::unique_ptr<DeviceLink> makeCaliperLink(CaliperConfig c) {
  if ((c.kind == CaliperKind::Hid || c.kind == CaliperKind::UsbItn) && c.vid == 0 && c.pid == 0) {
    c.vid = 0x0fe7;  // Mitutoyo USB-ITN
    c.pid = 0x4001;
  }
  switch (c.kind) {
    case CaliperKind::Hid: return std::make_unique<HidCaliperLink>(std::move(c));
    case CaliperKind::UsbItn: return std::make_unique<UsbItnLink>(std::move(c));
    default:
      if (c.port.empty()) throw std::invalid_argument(std::string(toString(c.kind)) + " needs --port PATH");
      return std::make_unique<SerialCaliperLink>(std::move(c));
  }
}

}  // namespace leafdig::devices
