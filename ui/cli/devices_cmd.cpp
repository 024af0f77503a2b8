#include "devices_cmd.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "commands.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/event_store.hpp"
#include "leafdig/devices/links/links.hpp"
#include "leafdig/devices/sim/field_distortion.hpp"
#include "leafdig/devices/sim/sim.hpp"
#include "leafdig/devices/transports/registry.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "signals.hpp"

namespace leafdig::cli {
namespace {

namespace dev = leafdig::devices;
using nlohmann::json;

std::string hex4(std::uint16_t v) {
  char b[8];
  std::snprintf(b, sizeof b, "%04x", v);
  return b;
}

// ---- devices list --------------------------------------------------------------------------
int runList(const DevicesOptions& o) {
  const dev::Inventory inv = dev::takeInventory();
  const auto profileJson = [](std::optional<std::uint16_t> vid, std::optional<std::uint16_t> pid) -> json {
    if (!vid || !pid) return nullptr;
    const dev::Profile* p = dev::matchProfile(*vid, *pid);
    if (!p) return nullptr;
    return json{{"name", p->name}, {"role", p->role}, {"driver", p->driver}, {"note", p->note}};
  };
  if (o.json) {
    json j{{"serial", json::array()}, {"hid", json::array()}, {"usb", json::array()}};
    for (const auto& s : inv.serial)
      j["serial"].push_back({{"path", s.path},
                             {"description", s.description},
                             {"transport", s.transport},
                             {"vid", s.vid ? json(hex4(*s.vid)) : json(nullptr)},
                             {"pid", s.pid ? json(hex4(*s.pid)) : json(nullptr)},
                             {"serial", s.serial},
                             {"profile", profileJson(s.vid, s.pid)}});
    for (const auto& h : inv.hid)
      j["hid"].push_back({{"path", h.path},
                          {"vid", hex4(h.vid)},
                          {"pid", hex4(h.pid)},
                          {"product", h.product},
                          {"manufacturer", h.manufacturer},
                          {"serial", h.serial},
                          {"interface", h.interfaceNumber},
                          {"profile", profileJson(h.vid, h.pid)}});
    for (const auto& u : inv.usb)
      j["usb"].push_back({{"bus", u.bus},
                          {"address", u.address},
                          {"vid", hex4(u.vid)},
                          {"pid", hex4(u.pid)},
                          {"product", u.product},
                          {"manufacturer", u.manufacturer},
                          {"serial", u.serial},
                          {"profile", profileJson(u.vid, u.pid)}});
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  const auto profileText = [](std::optional<std::uint16_t> vid, std::optional<std::uint16_t> pid) -> std::string {
    if (!vid || !pid) return "";
    const dev::Profile* p = dev::matchProfile(*vid, *pid);
    return p ? std::string("  → ") + p->name + " (" + p->driver + ")" : "";
  };
  std::cout << "Serial ports (" << inv.serial.size() << "):\n";
  for (const auto& s : inv.serial)
    std::cout << "  " << s.path << "  " << s.description
              << (s.vid ? "  [" + hex4(*s.vid) + ":" + hex4(*s.pid) + "]" : std::string()) << profileText(s.vid, s.pid)
              << "\n";
  if (inv.serial.empty()) std::cout << "  none. A digitizer on a USB-serial adapter appears as /dev/ttyUSB*.\n";
  std::cout << "HID devices (" << inv.hid.size() << "):\n";
  for (const auto& h : inv.hid)
    std::cout << "  " << h.path << "  " << hex4(h.vid) << ":" << hex4(h.pid) << "  " << h.manufacturer << " "
              << h.product << profileText(h.vid, h.pid) << "\n";
  if (inv.hid.empty()) std::cout << "  none. A USB-ITN or keyboard-wedge gauge appears here when plugged in.\n";
  std::cout << "USB devices (" << inv.usb.size() << "):\n";
  for (const auto& u : inv.usb)
    std::cout << "  bus " << u.bus << " address " << u.address << "  " << hex4(u.vid) << ":" << hex4(u.pid) << "  "
              << u.manufacturer << " " << u.product << profileText(u.vid, u.pid) << "\n";
  if (inv.usb.empty()) std::cout << "  none.\n";
  if (inv.serial.empty() && inv.hid.empty() && inv.usb.empty())
    std::cout << "\nNo devices found. That is normal on a machine without them: try the simulators,\n"
                 "e.g. 'leafdig sim fastrak --markers data/samples/lower-leaf-n10.markers.json' and\n"
                 "'leafdig devices listen --digitizer fastrak --port <the path it prints>'.\n";
  return 0;
}

// ---- devices listen ------------------------------------------------------------------------
json sampleJson(const dev::DeviceEvent& e, dev::Clock::time_point t0) {
  if (const auto* s = std::get_if<dev::StylusSample>(&e)) {
    json o = s->orientationDeg
                 ? json::array({(*s->orientationDeg)[0], (*s->orientationDeg)[1], (*s->orientationDeg)[2]})
                 : json(nullptr);
    return {{"t", std::chrono::duration<double>(s->t - t0).count()},
            {"station", s->station},
            {"position_mm", {s->positionMm[0], s->positionMm[1], s->positionMm[2]}},
            {"orientation_deg", o},
            {"button", s->button},
            {"status", s->status},
            {"raw", dev::printableRaw(s->raw, true)}};
  }
  const auto& c = std::get<dev::CaliperReading>(e);
  return {{"t", std::chrono::duration<double>(c.t - t0).count()},
          {"value_mm", c.valueMm},
          {"unit", c.unit},
          {"raw", dev::printableRaw(c.raw, true)}};
}

std::string sampleText(const dev::DeviceEvent& e, dev::Clock::time_point t0) {
  char buf[256];
  if (const auto* s = std::get_if<dev::StylusSample>(&e)) {
    std::snprintf(buf, sizeof buf, "%9.3f s  station %d  x %9.2f  y %9.2f  z %9.2f mm  %s  %s",
                  std::chrono::duration<double>(s->t - t0).count(), s->station, s->positionMm[0], s->positionMm[1],
                  s->positionMm[2], s->button ? "BUTTON" : "      ", s->status.c_str());
    return buf;
  }
  const auto& c = std::get<dev::CaliperReading>(e);
  std::snprintf(buf, sizeof buf, "%9.3f s  %8.3f mm  (gauge: %s %s)%s%s",
                std::chrono::duration<double>(c.t - t0).count(), c.valueMm, dev::printableRaw(c.raw).c_str(),
                c.unit.c_str(), c.flag.empty() ? "" : "  flag ", c.flag.c_str());
  return buf;
}

int runListen(const DevicesOptions& o) {
  if (o.digitizer.empty() == o.caliper.empty()) {
    throw model::InputError("give either --digitizer KIND or --caliper KIND");
  }
  std::unique_ptr<dev::DeviceLink> link;
  dev::DriverOptions dopts;
  dopts.filterStylus = !o.noFilter;
  if (o.pollMs > 0) dopts.pollEvery = std::chrono::milliseconds(o.pollMs);
  if (!o.digitizer.empty()) {
    dev::DigitizerConfig c;
    c.kind = dev::digitizerKindFromString(o.digitizer);
    if (o.port.empty()) {
      throw model::InputError("--digitizer needs --port PATH (see 'leafdig devices list', or start 'leafdig sim')");
    }
    c.port = o.port;
    c.baud = o.baud;
    c.binary = o.binary;
    if (c.kind == dev::DigitizerKind::Line) {
      if (o.lineConfig.empty()) {
        throw model::InputError("--digitizer line needs --line-config FILE (a JSON description; docs/devices.md)");
      }
      std::ifstream in(o.lineConfig);
      if (!in) {
        throw model::InputError("cannot read " + o.lineConfig);
      }
      std::stringstream ss;
      ss << in.rdbuf();
      c.line = dev::line::parseConfig(ss.str());
    }
    link = dev::makeDigitizerLink(std::move(c));
  } else {
    dev::CaliperConfig c;
    c.kind = dev::caliperKindFromString(o.caliper);
    c.port = o.port;
    c.baud = o.baud;
    c.unit = o.unit;
    c.dtrTrigger = o.dtrTrigger;
    c.grabKeyboard = !o.noGrab;
    if (!o.hid.empty()) {
      if (o.hid.rfind("/dev/", 0) == 0)
        c.hidPath = o.hid;
      else if (!dev::parseVidPid(o.hid, c.vid, c.pid)) {
        throw model::InputError("--hid must be VID:PID in hex (e.g. 0fe7:4001) or a /dev/hidraw path");
      }
    }
    link = dev::makeCaliperLink(std::move(c));
  }
  installSignalHandlers();
  const auto t0 = dev::Clock::now();
  std::mutex m;
  std::vector<dev::DeviceEvent> queue;
  dev::DeviceStatus last;
  std::mutex sm;
  dev::Driver driver(std::move(link),
                     {[&](const dev::DeviceEvent& e) {
                        std::lock_guard lock(m);
                        queue.push_back(e);
                      },
                      [&](const dev::DeviceStatus& s) {
                        {
                          std::lock_guard lock(sm);
                          last = s;
                        }
                        std::cerr << "[" << dev::toString(s.state) << "] " << s.message
                                  << (s.remedy.empty() ? "" : " — " + s.remedy) << std::endl;
                      }},
                     dopts);
  driver.start();
  int printed = 0;
  while (!interrupted()) {
    std::vector<dev::DeviceEvent> batch;
    {
      std::lock_guard lock(m);
      batch.swap(queue);
    }
    for (const auto& e : batch) {
      if (o.json)
        std::cout << sampleJson(e, t0).dump() << "\n";
      else
        std::cout << sampleText(e, t0) << "\n";
      ++printed;
      if (o.count > 0 && printed >= o.count) break;
    }
    std::cout.flush();
    if (o.count > 0 && printed >= o.count) break;
    if (o.seconds > 0 && std::chrono::duration<double>(dev::Clock::now() - t0).count() >= o.seconds) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  dev::DeviceStatus lastBeforeStop;
  {
    std::lock_guard lock(sm);
    lastBeforeStop = last;
  }
  driver.stop();
  const dev::DeviceStatus st = driver.status();
  std::cerr << "leafdig: " << printed << " samples; " << st.stats.records << " records decoded, " << st.stats.dropped
            << " corrupt records dropped, " << st.stats.discardedBytes << " stray bytes skipped, " << st.filtered
            << " samples withheld by the spike filter, " << st.reconnects << " reconnects\n";
  if (printed == 0 && !interrupted()) {
    std::cerr << "leafdig: no samples received. Last state: " << lastBeforeStop.message
              << (lastBeforeStop.remedy.empty() ? "" : "\n  what to do: " + lastBeforeStop.remedy) << "\n";
    return 1;
  }
  return 0;
}

// ---- sim -----------------------------------------------------------------------------------
int runSim(const DevicesOptions& o) {
  dev::sim::EmulatorOptions eo;
  try {
    eo.faults = dev::sim::FaultPlan::parse(o.faults);
  } catch (const std::invalid_argument& e) {
    throw model::InputError(std::string("--faults: ") + e.what());
  }
  if (o.faults.find("seed=") == std::string::npos) eo.faults.seed = o.seed;
  eo.rateHz = o.rate;
  eo.linkPath = o.link;
  eo.pressEveryS = o.pressEvery;
  const model::MarkerSet markers = model::readMarkersFile(o.markers);
  // Protocol order: the tip, then every row right to left; thicknesses row by row.
  std::vector<dev::Vec3> targets{{markers.tipMm.x(), markers.tipMm.y(), markers.tipMm.z()}};
  std::vector<double> thickness;
  for (const auto& r : markers.rows) {
    for (const auto& p : r.pointsMm) targets.push_back({p.x(), p.y(), p.z()});
    if (r.midribThicknessMm) thickness.push_back(*r.midribThicknessMm);
    if (r.veinOriginThicknessMm) thickness.push_back(*r.veinOriginThicknessMm);
    if (r.edgeThicknessMm) thickness.push_back(*r.edgeThicknessMm);
  }
  if (markers.edgeThicknessMm) thickness.push_back(*markers.edgeThicknessMm);
  dev::sim::StylusOptions so;
  so.sigmaMm = o.sigma;
  so.seed = o.seed;
  if (o.simKind == "microscribe") so.offsetMm = dev::sim::kMicroScribeLeafOffset;
  std::unique_ptr<dev::sim::Emulator> emu;
  auto caliper = std::make_shared<dev::sim::VirtualCaliper>(thickness, dev::sim::CaliperOptions{0.003, 0.001, o.seed});
  const dev::sim::VirtualStylus stylus(targets, so);
  // The magnetic trackers through a distorted field (issue 50), when a file is given.
  std::shared_ptr<const dev::sim::StylusMotion> sensor = std::make_shared<dev::sim::VirtualStylus>(stylus);
  if (!o.distortion.empty()) {
    if (o.simKind != "fastrak" && o.simKind != "patriot" && o.simKind != "liberty")
      throw model::InputError("--distortion bends a magnetic tracker's field (fastrak, patriot, liberty), not a " +
                              o.simKind + "'s");
    sensor = std::make_shared<dev::sim::DistortedMotion>(
        sensor, std::make_shared<const dev::sim::FieldDistortion>(dev::sim::readFieldDistortion(o.distortion)));
  }
  if (o.simKind == "fastrak")
    emu = dev::sim::makeFastrak(sensor, eo);
  else if (o.simKind == "patriot")
    emu = dev::sim::makePatriot(sensor, eo);
  else if (o.simKind == "liberty")
    emu = dev::sim::makeLiberty(sensor, eo);
  else if (o.simKind == "microscribe")
    emu = dev::sim::makeMicroScribe(stylus, eo);
  else if (o.simKind == "sylvac")
    emu = dev::sim::makeSylvac(caliper, eo);
  else if (o.simKind == "mitutoyo")
    emu = dev::sim::makeMitutoyo(caliper, eo);
  else if (o.simKind == "uwave")
    emu = dev::sim::makeUWave(caliper, eo);
  else {
    throw model::InputError("unknown simulator '" + o.simKind +
                            "': use fastrak, patriot, liberty, microscribe, sylvac, mitutoyo or uwave");
  }
  emu->start();
  installSignalHandlers();
  std::cout << emu->path() << std::endl;
  std::cerr << "leafdig: " << o.simKind << " emulator on " << emu->path() << " (now " << emu->ptyPath() << "), "
            << targets.size() << " markers, " << thickness.size() << " thicknesses"
            << (eo.faults.any() ? ", faults: " + o.faults : std::string()) << ". Stop with Ctrl-C.\n";
  const auto t0 = std::chrono::steady_clock::now();
  while (!interrupted()) {
    if (o.simSeconds > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >= o.simSeconds)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const auto log = emu->faultLog();
  emu->stop();
  std::cerr << "leafdig: sent " << log.records << " records; faults: " << log.garbage << " garbage, " << log.bitflips
            << " bit flips, " << log.truncated << " truncated, " << log.stalls << " stalls, " << log.resets
            << " resets, " << log.unplugs << " unplugs, " << log.statusLetters << " status letters, "
            << log.garbledBytes << " bytes garbled by a baud mismatch\n";
  return 0;
}

// ---- doctor --------------------------------------------------------------------------------
int runDoctor(const DevicesOptions& o) {
  auto checks = dev::doctorChecks();
  // The id this station's sessions carry (and the lab server knows it by).
  {
    const std::string id = acquisition::thisStation();
    const bool fromFile = std::filesystem::exists(acquisition::stationSettingsFile());
    dev::Check station;
    station.what = "station id";
    station.detail = "'" + id + "'";
    station.ok = true;
    try {
      db::checkStationId(id);
      station.detail += fromFile ? " ([station] id in " + acquisition::stationSettingsFile() + ", or the host name)"
                                 : " (the host name; set [station] id= in " + acquisition::stationSettingsFile() + ")";
    } catch (const db::StoreError& e) {
      station.ok = false;
      station.remedy = e.remedy();
    }
    checks.insert(checks.begin(), station);
  }
  int problems = 0;
  json j = json::array();
  for (const auto& c : checks) {
    problems += c.ok ? 0 : 1;
    if (o.json) {
      j.push_back({{"check", c.what}, {"ok", c.ok}, {"detail", c.detail}, {"remedy", c.remedy}});
      continue;
    }
    std::cout << (c.ok ? "  ok    " : "  FIX   ") << c.what << ": " << c.detail << "\n";
    if (!c.ok) std::cout << "        → " << c.remedy << "\n";
  }
  if (o.json)
    std::cout << j.dump(2) << "\n";
  else
    std::cout << (problems ? std::to_string(problems) + " item(s) to look at; the simulators work regardless.\n"
                           : "Everything looks ready.\n");
  return 0;
}

void declareDevicesCommands(CLI::App& app, DevicesOptions& o) {
  CLI::App* devices = app.add_subcommand("devices", "List, test and listen to digitizers and calipers");
  devices->require_subcommand(1);
  CLI::App* list = devices->add_subcommand("list", "Serial ports, HID and USB devices, with known profiles");
  list->add_flag("--json", o.json, "Machine-readable output");
  CLI::App* listen = devices->add_subcommand("listen", "Connect to one device and print its samples");
  listen->add_option("--digitizer", o.digitizer, "fastrak, patriot, liberty, microscribe or line");
  listen->add_option("--caliper", o.caliper, "hid, usb-itn, mitutoyo, uwave or sylvac");
  listen->add_option("--port", o.port, "Serial port or pseudo-terminal path");
  listen->add_option("--hid", o.hid, "HID gauge as VID:PID (hex) or /dev/hidrawN (default 0fe7:4001)");
  listen->add_option("--baud", o.baud, "Baud rate (default: the device's usual rate; FASTRAK/Patriot probe others)");
  listen->add_option("--count", o.count, "Stop after N samples");
  listen->add_option("--seconds", o.seconds, "Stop after S seconds");
  listen->add_option("--poll-ms", o.pollMs, "Request a caliper reading every N ms (PC-triggered gauges)");
  listen->add_option("--unit", o.unit, "Caliper unit when the gauge does not say: mm, in, auto (Mitutoyo)");
  listen->add_option("--line-config", o.lineConfig, "JSON description of a generic line digitizer");
  listen->add_flag("--binary", o.binary, "Binary records (FASTRAK, Patriot, Liberty)");
  listen->add_flag("--dtr-trigger", o.dtrTrigger, "Sylvac simplex cable: request readings by dropping DTR");
  listen->add_flag("--no-grab", o.noGrab, "HID: do not grab the gauge's keyboard node");
  listen->add_flag("--no-filter", o.noFilter, "Deliver stylus samples without the spike filter");
  listen->add_flag("--json", o.json, "JSON lines (docs/devices.md)");

  CLI::App* sim = app.add_subcommand("sim", "Run a simulated device on a pseudo-terminal");
  sim->add_option("device", o.simKind, "fastrak, patriot, liberty, microscribe, sylvac, mitutoyo or uwave")->required();
  sim->add_option("--markers", o.markers, "leafdig.markers/1 file the virtual stylus and caliper walk")->required();
  sim->add_option("--faults", o.faults,
                  "Fault script, e.g. garbage=0.01,bitflip=0.005,truncate=0.01,stall=0.002:1.5,reset=0.001,"
                  "unplug=0.001:0.5,status=0.01:x,baud=9600,seed=7");
  sim->add_option("--rate", o.rate, "Records per second (default: the device's own, FASTRAK 120)");
  sim->add_option("--link", o.link, "Stable path to create for the pty (default /tmp/leafdig-sim-*)");
  sim->add_option("--press-every", o.pressEvery, "Calipers: press DATA every S seconds");
  sim->add_option("--seconds", o.simSeconds, "Stop after S seconds (default: run until Ctrl-C)");
  sim->add_option("--sigma", o.sigma, "Stylus noise per axis, mm (default 0.3)");
  sim->add_option("--seed", o.seed, "Random seed")->check(seedText());
  sim->add_option("--distortion", o.distortion,
                  "A leafdig.field-distortion/1 file: the tracker's field bent as by metal nearby (fastrak, patriot, "
                  "liberty; docs/devices.md, \"The field\")");

  CLI::App* doctor = app.add_subcommand("doctor", "Check libraries, ports, permissions and the udev rule");
  doctor->add_flag("--json", o.json, "Machine-readable output");
}

}  // namespace

void addDevicesCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<DevicesOptions>();
  declareDevicesCommands(app, *o);
  CLI::App* devices = app.get_subcommand("devices");
  table.add(devices->get_subcommand("list"), [o] { return runList(*o); });
  table.add(devices->get_subcommand("listen"), [o] { return runListen(*o); });
  table.add(app.get_subcommand("sim"), [o] { return runSim(*o); });
  table.add(app.get_subcommand("doctor"), [o] { return runDoctor(*o); });
}

}  // namespace leafdig::cli
