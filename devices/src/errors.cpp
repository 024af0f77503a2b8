// Device errors: their kinds' names and the error of a failed system call (errors.hpp).
#include "leafdig/devices/errors.hpp"

#include <cerrno>
#include <cstring>
#include <string>

namespace leafdig::devices {

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

}  // namespace leafdig::devices
