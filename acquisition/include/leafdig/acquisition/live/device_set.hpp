// The two devices of a capture: parsing the operator's device specs and running one driver
// for the digitizer and one for the caliper, both delivering into a capture loop.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include "leafdig/devices/links/driver.hpp"
#include "leafdig/devices/links/links.hpp"

namespace leafdig::acquisition {

// "fastrak:/dev/ttyUSB0" (also patriot, liberty, microscribe). Throws std::invalid_argument
// naming the accepted form.
[[nodiscard]] devices::DigitizerConfig parseDigitizerSpec(const std::string& spec);
// "sylvac:/dev/ttyUSB1", "mitutoyo:PORT", "uwave:PORT", "hid:0fe7:4001", "hid:/dev/hidraw3",
// "usbitn" or "usbitn:VID:PID".
[[nodiscard]] devices::CaliperConfig parseCaliperSpec(const std::string& spec);

// A digitizer alone, started, delivering into `sinks` (a field check, a tip calibration):
// `spec` as parseDigitizerSpec reads it, `rateHz` its record rate when not the device's own.
[[nodiscard]] std::unique_ptr<devices::Driver> startDigitizer(const std::string& spec, double rateHz,
                                                              const devices::Driver::Callbacks& sinks);

// The two drivers of a capture, delivering into a capture loop (or any sinks).
// Thread contract: construct, start, stop, connect and disconnect from one owner thread;
// connected(), status() and spec() from any thread.
class DeviceSet {
 public:
  enum class Role { Digitizer, Caliper };
  // Throws std::invalid_argument for a spec that does not parse (nothing is opened then).
  // digitizerRateHz: the digitizer's record rate when it is not the device's own (a simulator).
  // The drivers deliver into `sinks` (their events and status changes, on the drivers'
  // threads): a capture loop's (capture_loop.hpp's CaptureLoop::sinks).
  DeviceSet(const std::string& digitizerSpec, const std::string& caliperSpec, const devices::Driver::Callbacks& sinks,
            double digitizerRateHz = 0);
  DeviceSet(const DeviceSet&) = delete;
  DeviceSet& operator=(const DeviceSet&) = delete;
  ~DeviceSet();
  void start();
  void stop();
  // The operator takes a device off line (to swap a cable, lend the caliper) and back: the
  // capture records both as device events and keeps its step.
  void disconnect(Role role);
  void connect(Role role);
  [[nodiscard]] bool connected(Role role) const;
  // Each driver's status now: state, rate, last-sample age, message and remedy.
  [[nodiscard]] devices::DeviceStatus status(Role role) const;
  [[nodiscard]] const std::string& spec(Role role) const;

 private:
  [[nodiscard]] devices::Driver& driver(Role role) const;
  std::function<void(const devices::DeviceStatus&)> onStatus_;  // also told of disconnect()
  std::string digitizerSpec_, caliperSpec_;
  std::unique_ptr<devices::Driver> digitizer_, caliper_;
  std::atomic<bool> digitizerOn_{false}, caliperOn_{false};
};

}  // namespace leafdig::acquisition
