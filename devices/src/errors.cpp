// Device errors: their kinds' names and the error of a failed system call (errors.hpp).
#include "leafdig/devices/errors.hpp"

#include <cerrno>
#include <cstring>
#include <string>

#include "leafdig/names/name_table.hpp"

namespace leafdig::devices {

namespace {
constexpr NameTable<DeviceErrorKind, 8> kErrorKinds{{{DeviceErrorKind::NotFound, "not found"},
                                                     {DeviceErrorKind::Busy, "busy"},
                                                     {DeviceErrorKind::Permission, "permission denied"},
                                                     {DeviceErrorKind::Io, "I/O error"},
                                                     {DeviceErrorKind::Protocol, "protocol error"},
                                                     {DeviceErrorKind::Timeout, "timeout"},
                                                     {DeviceErrorKind::Unsupported, "unsupported"},
                                                     {DeviceErrorKind::Config, "bad configuration"}}};
}  // namespace

const char* toString(DeviceErrorKind kind) {
  return nameIn(kErrorKinds, kind);
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
