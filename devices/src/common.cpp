#include <cerrno>
#include <cstdio>
#include <cstring>

#include "leafdig/devices/errors.hpp"
#include "leafdig/devices/sample.hpp"
#include "leafdig/devices/serial_port.hpp"

namespace leafdig::devices {

std::string printableRaw(std::string_view raw, bool keepLineEnds) {
  std::string out;
  out.reserve(raw.size() + 8);
  for (char c : raw) {
    const auto u = static_cast<unsigned char>(c);
    if (keepLineEnds && (c == '\r' || c == '\n' || c == '\t')) {
      out += c;
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\\') {
      out += "\\\\";
    } else if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    }
  }
  return out;
}

const char* toString(DeviceErrorKind kind) {
  switch (kind) {
    case DeviceErrorKind::NotFound: return "not found";
    case DeviceErrorKind::Busy: return "busy";
    case DeviceErrorKind::Permission: return "permission denied";
    case DeviceErrorKind::Io: return "I/O error";
    case DeviceErrorKind::Protocol: return "protocol error";
    case DeviceErrorKind::Timeout: return "timeout";
    case DeviceErrorKind::Unsupported: return "unsupported";
    case DeviceErrorKind::Config: return "bad configuration";
  }
  return "error";
}

DeviceError errorFromErrno(int err, const std::string& action, const std::string& path) {
  const std::string what = action + " " + path + ": " + std::strerror(err);
  switch (err) {
    case ENOENT:
    case ENODEV:
    case ENXIO:
      return {DeviceErrorKind::NotFound, what,
              "check that the device is plugged in and the path is right ('leafdig devices "
              "list' shows the ports this machine has)"};
    case EBUSY:
    case EWOULDBLOCK:
      return {DeviceErrorKind::Busy, what,
              "another program holds " + path +
                  ": close it (vendor tools such as PiMgr, a terminal program, another leafdig) "
                  "and try again"};
    case EACCES:
    case EPERM:
      return {DeviceErrorKind::Permission, what,
              "install the udev rule (sudo cmake --install build/release && sudo udevadm "
              "control --reload && sudo udevadm trigger) or add yourself to the 'dialout' "
              "group (sudo usermod -aG dialout $USER, then log in again); 'leafdig doctor' "
              "checks both"};
    case EIO: return {DeviceErrorKind::Io, what, "the device went away: check the cable and power"};
    default: return {DeviceErrorKind::Io, what, "check the cable and the device's power"};
  }
}

std::string describe(const SerialSettings& s) {
  const char parity = s.parity == Parity::None ? 'N' : s.parity == Parity::Even ? 'E' : 'O';
  return std::to_string(s.baud) + " " + std::to_string(s.dataBits) + parity + std::to_string(s.stopBits) +
         (s.rtsCts ? " RTS/CTS" : "");
}

}  // namespace leafdig::devices
