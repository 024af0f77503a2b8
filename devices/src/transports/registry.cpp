#include "leafdig/devices/transports/registry.hpp"

#include <grp.h>
#include <hidapi/hidapi.h>
#include <libserialport.h>
#include <libusb-1.0/libusb.h>
#include <pwd.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace leafdig::devices {

const std::vector<Profile>& knownProfiles() {
  static const std::vector<Profile> profiles = {
      {0x0fe7, 0x4001, "Mitutoyo USB-ITN", "caliper", "hid (keyboard mode) or usb-itn (PC-triggered)",
       "keyboard mode types readings: leafdig grabs the device so they stay out of other windows"},
      {0x0fe7, 0x2002, "Mitutoyo U-WAVE-R receiver", "caliper", "uwave",
       "needs ftdi_sio bound to 0fe7:2002 (the udev rule does it)"},
      {0x067b, 0x2303, "Prolific PL2303 (Sylvac USB cable)", "caliper", "sylvac", "4800 7E2"},
      {0x0f44, 0xef12, "Polhemus Patriot (USB)", "digitizer", "patriot",
       "leafdig speaks RS-232: use the serial port (USB needs the vendor driver)"},
      {0x0f44, 0xef20, "Polhemus Patriot HS (USB)", "digitizer", "patriot", "use the RS-232 port"},
      {0x0f44, 0xff20, "Polhemus Liberty (USB)", "digitizer", "liberty", "use the RS-232 port"},
      {0x0f44, 0xff21, "Polhemus Liberty HS (USB, no firmware yet)", "digitizer", "liberty",
       "needs a firmware upload (fxload) before it enumerates as ff20; use the RS-232 port"},
      {0x0563, 0x0053, "MicroScribe G2/MX/i (USB)", "digitizer", "-",
       "USB-era arms need the vendor SDK; leafdig speaks the legacy serial HCI only"},
  };
  return profiles;
}

const Profile* matchProfile(std::uint16_t vid, std::uint16_t pid) {
  for (const Profile& p : knownProfiles())
    if (p.vid == vid && p.pid == pid) return &p;
  return nullptr;
}

Inventory takeInventory() {
  return {listSerialPorts(), enumerateHid(), listUsbDevices()};
}

namespace {
bool inGroup(const char* name) {
  const group* g = ::getgrnam(name);
  if (!g) return false;
  if (::getegid() == g->gr_gid || ::geteuid() == 0) return true;
  gid_t groups[256];
  const int n = ::getgroups(256, groups);
  for (int i = 0; i < n; ++i)
    if (groups[i] == g->gr_gid) return true;
  return false;
}
}  // namespace

std::vector<Check> doctorChecks(const std::string& udevRulePath) {
  std::vector<Check> out;
  {
    Check c{"libserialport", true, std::string("version ") + sp_get_lib_version_string(), ""};
    out.push_back(c);
  }
  {
    const libusb_version* v = libusb_get_version();
    libusb_context* ctx = nullptr;
    const int rc = libusb_init(&ctx);
    Check c{"libusb", rc == 0,
            "version " + std::to_string(v->major) + "." + std::to_string(v->minor) + "." + std::to_string(v->micro) +
                (rc == 0 ? std::string(", hotplug ") +
                               (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) ? "yes" : "no (polling)")
                         : std::string(", cannot start: ") + libusb_error_name(rc)),
            rc == 0 ? "" : "USB gauges in vendor mode need libusb; check /dev/bus/usb is present"};
    if (ctx) libusb_exit(ctx);
    out.push_back(c);
  }
  {
    const bool ok = hid_init() == 0;
    out.push_back({"hidapi (hidraw)", ok, ok ? "ready" : "hid_init failed", ok ? "" : "reinstall libhidapi-hidraw0"});
  }
  {
    namespace fs = std::filesystem;
    std::error_code ec;
    const bool pts = fs::exists("/dev/ptmx", ec);
    out.push_back({"pseudo-terminals (simulators)", pts, pts ? "/dev/ptmx present" : "/dev/ptmx missing",
                   pts ? "" : "mount devpts; the simulators need it"});
    const bool usbfs = fs::exists("/dev/bus/usb", ec);
    out.push_back({"USB device nodes", usbfs, usbfs ? "/dev/bus/usb present" : "no /dev/bus/usb (a container?)",
                   usbfs ? "" : "real USB gauges need /dev/bus/usb; simulators work without it"});
  }
  for (const char* g : {"dialout", "plugdev", "input"}) {
    const bool member = inGroup(g);
    out.push_back(
        {std::string("group '") + g + "'", member, member ? "you are a member (or root)" : "you are not a member",
         member
             ? ""
             : std::string("sudo usermod -aG ") + g +
                   " $USER, then log in again (or install the udev rule, which grants access to the logged-in user)"});
  }
  {
    std::ifstream rule(udevRulePath);
    const bool ok = static_cast<bool>(rule);
    out.push_back(
        {"udev rule", ok, ok ? udevRulePath + " installed" : udevRulePath + " not installed",
         ok ? "" : "sudo cmake --install build/release && sudo udevadm control --reload && sudo udevadm trigger"});
  }
  for (const auto& p : listSerialPorts()) {
    const bool rw = ::access(p.path.c_str(), R_OK | W_OK) == 0;
    out.push_back({"serial port " + p.path, rw, rw ? "readable and writable" : "no read/write permission",
                   rw ? "" : "join the 'dialout' group or install the udev rule"});
  }
  for (const auto& h : enumerateHid()) {
    const bool rw = ::access(h.path.c_str(), R_OK | W_OK) == 0;
    out.push_back({"HID device " + h.path, rw, rw ? "readable" : "no permission", rw ? "" : "install the udev rule"});
  }
  return out;
}

}  // namespace leafdig::devices
