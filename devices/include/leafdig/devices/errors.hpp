// Device errors carry a kind an operator can act on and a remedy sentence.
#pragma once

#include <stdexcept>
#include <string>

namespace leafdig::devices {

enum class DeviceErrorKind {
  NotFound,     // no such port / device: unplugged or wrong path
  Busy,         // another program holds it
  Permission,   // the user may not open it
  Io,           // read/write failed (unplugged while open, cable)
  Protocol,     // the device answered, but not as expected (wrong baud, wrong device)
  Timeout,      // no answer in time
  Unsupported,  // the platform or library cannot do this
  Config,       // a bad option from the user
};

[[nodiscard]] const char* toString(DeviceErrorKind kind);

class DeviceError : public std::runtime_error {
 public:
  DeviceError(DeviceErrorKind kind, const std::string& what, std::string remedy = {})
      : std::runtime_error(what), kind_(kind), remedy_(std::move(remedy)) {}
  [[nodiscard]] DeviceErrorKind kind() const noexcept { return kind_; }
  [[nodiscard]] const std::string& remedy() const noexcept { return remedy_; }

 private:
  DeviceErrorKind kind_;
  std::string remedy_;
};

// Builds the error for a failed open(2)/ioctl on `path` from errno, with a remedy.
[[nodiscard]] DeviceError errorFromErrno(int err, const std::string& action, const std::string& path);

}  // namespace leafdig::devices
