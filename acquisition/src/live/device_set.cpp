#include "leafdig/acquisition/live/device_set.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "leafdig/devices/links/driver.hpp"

namespace leafdig::acquisition {
namespace {

namespace dev = leafdig::devices;

std::pair<std::string, std::string> splitSpec(const std::string& spec, const char* what, const char* example) {
  const auto colon = spec.find(':');
  if (spec.empty() || colon == 0)
    throw std::invalid_argument(std::string(what) + " '" + spec + "': expected KIND:PORT, e.g. " + example);
  if (colon == std::string::npos) return {spec, ""};
  return {spec.substr(0, colon), spec.substr(colon + 1)};
}

}  // namespace

dev::DigitizerConfig parseDigitizerSpec(const std::string& spec) {
  const auto [kind, port] = splitSpec(spec, "--digitizer", "fastrak:/dev/ttyUSB0");
  dev::DigitizerConfig c;
  c.kind = dev::digitizerKindFromString(kind);
  if (c.kind == dev::DigitizerKind::Line)
    throw std::invalid_argument(
        "--digitizer line needs a JSON description: use 'leafdig devices listen' to try it; "
        "capture supports fastrak, patriot, liberty and microscribe");
  if (port.empty())
    throw std::invalid_argument("--digitizer " + kind + " needs a port: " + kind +
                                ":/dev/ttyUSB0 ('leafdig devices list')");
  c.port = port;
  // Options after the port, each ",key=value": ",reference=N" (receiver N is a reference receiver
  // fixed to the pot or the board) and ",tip=x:y:z" (the stylus' tip in its sensor's frame, mm:
  // a tip calibration, tip_calibration.hpp's withTip).
  for (std::size_t comma = c.port.rfind(','); comma != std::string::npos; comma = c.port.rfind(',')) {
    const std::string option = c.port.substr(comma + 1);
    c.port = c.port.substr(0, comma);
    if (option.rfind("reference=", 0) == 0) {
      const std::string n = option.substr(10);
      if (n.size() != 1 || n[0] < '2' || n[0] > '9' || c.port.empty())
        throw std::invalid_argument(std::string("--digitizer ")
                                        .append(spec)
                                        .append(": the reference receiver is a number from 2 (")
                                        .append(kind)
                                        .append(":/dev/ttyUSB0,reference=2); the stylus is receiver 1"));
      if (c.kind == dev::DigitizerKind::MicroScribe)
        throw std::invalid_argument("--digitizer " + spec +
                                    ": a MicroScribe arm has no receivers; a reference "
                                    "receiver needs a FASTRAK, Patriot or Liberty");
      c.referenceStation = n[0] - '0';
    } else if (option.rfind("tip=", 0) == 0) {
      if (c.tipOffsetMm)
        throw std::invalid_argument("--digitizer " + spec +
                                    ": the tip is given twice (a tip calibration applies one: leave tip= out, or "
                                    "--tip-calibration none)");
      std::istringstream in(option.substr(4));
      dev::Vec3 tip{};
      char colon1 = 0, colon2 = 0;
      std::string rest;
      if (!(in >> tip[0] >> colon1 >> tip[1] >> colon2 >> tip[2]) || colon1 != ':' || colon2 != ':' || (in >> rest) ||
          !(std::abs(tip[0]) <= 500 && std::abs(tip[1]) <= 500 && std::abs(tip[2]) <= 500))
        throw std::invalid_argument("--digitizer " + spec +
                                    ": the tip is x:y:z in mm, each within 500, in the stylus sensor's frame "
                                    "(leafdig field tip finds it)");
      if (c.kind == dev::DigitizerKind::MicroScribe)
        throw std::invalid_argument("--digitizer " + spec +
                                    ": a MicroScribe's tip is its arm's (its tip length); a tip calibration is a "
                                    "FASTRAK's, Patriot's or Liberty's");
      c.tipOffsetMm = tip;
    } else {
      throw std::invalid_argument("--digitizer " + spec + ": '" + option.substr(0, 40) +
                                  "' is no option of a digitizer (reference=N, tip=x:y:z)");
    }
  }
  if (c.port.empty())
    throw std::invalid_argument("--digitizer " + kind + " needs a port: " + kind +
                                ":/dev/ttyUSB0 ('leafdig devices list')");
  return c;
}

std::unique_ptr<dev::Driver> startDigitizer(const std::string& spec, double rateHz,
                                            const dev::Driver::Callbacks& sinks) {
  dev::DigitizerConfig config = parseDigitizerSpec(spec);
  config.recordRateHz = rateHz;
  auto driver = std::make_unique<dev::Driver>(dev::makeDigitizerLink(std::move(config)), sinks);
  driver->start();
  return driver;
}

dev::CaliperConfig parseCaliperSpec(const std::string& spec) {
  const auto [kind, rest] = splitSpec(spec, "--caliper", "sylvac:/dev/ttyUSB1 or hid:0fe7:4001");
  dev::CaliperConfig c;
  c.kind = dev::caliperKindFromString(kind);
  if (c.kind == dev::CaliperKind::Hid || c.kind == dev::CaliperKind::UsbItn) {
    if (rest.rfind("/dev/", 0) == 0)
      c.hidPath = rest;
    else if (!rest.empty() && !dev::parseVidPid(rest, c.vid, c.pid))
      throw std::invalid_argument("--caliper " + kind + ":" + rest +
                                  ": expected VID:PID in hex (e.g. 0fe7:4001) or a /dev/hidraw path");
    return c;
  }
  if (rest.empty()) throw std::invalid_argument("--caliper " + kind + " needs a port: " + kind + ":/dev/ttyUSB1");
  c.port = rest;
  return c;
}

DeviceSet::DeviceSet(const std::string& digitizerSpec, const std::string& caliperSpec,
                     const dev::Driver::Callbacks& sinks, double digitizerRateHz)
    : onStatus_(sinks.onStatus), digitizerSpec_(digitizerSpec), caliperSpec_(caliperSpec) {
  dev::DigitizerConfig digitizer = parseDigitizerSpec(digitizerSpec);
  digitizer.recordRateHz = digitizerRateHz;
  digitizer_ = std::make_unique<dev::Driver>(dev::makeDigitizerLink(std::move(digitizer)), sinks);
  caliper_ = std::make_unique<dev::Driver>(dev::makeCaliperLink(parseCaliperSpec(caliperSpec)), sinks);
}
DeviceSet::~DeviceSet() {
  stop();
}
void DeviceSet::start() {
  connect(Role::Digitizer);
  connect(Role::Caliper);
}
void DeviceSet::stop() {
  if (digitizer_) digitizer_->stop();
  if (caliper_) caliper_->stop();
  digitizerOn_ = caliperOn_ = false;
}
dev::Driver& DeviceSet::driver(Role role) const {
  return role == Role::Digitizer ? *digitizer_ : *caliper_;
}
const std::string& DeviceSet::spec(Role role) const {
  return role == Role::Digitizer ? digitizerSpec_ : caliperSpec_;
}
bool DeviceSet::connected(Role role) const {
  return role == Role::Digitizer ? digitizerOn_.load() : caliperOn_.load();
}
void DeviceSet::connect(Role role) {
  driver(role).start();
  (role == Role::Digitizer ? digitizerOn_ : caliperOn_) = true;
}
void DeviceSet::disconnect(Role role) {
  dev::Driver& d = driver(role);
  d.stop();
  (role == Role::Digitizer ? digitizerOn_ : caliperOn_) = false;
  dev::DeviceStatus s = d.status();
  s.state = dev::LinkState::Disconnected;
  s.message = "disconnected at the station";
  s.remedy = "connect it again to go on";
  s.rateHz = 0;
  if (onStatus_) onStatus_(s);
}
dev::DeviceStatus DeviceSet::status(Role role) const {
  dev::DeviceStatus s = driver(role).status();
  if (!connected(role)) {
    s.state = dev::LinkState::Disconnected;
    s.rateHz = 0;
    s.message = "disconnected at the station";
    s.remedy = "connect it again to go on";
  }
  return s;
}

}  // namespace leafdig::acquisition
