// HID devices: hidapi (hidraw backend) for real gauges, an in-memory device for tests and
// simulators, and the evdev grab that keeps keyboard-wedge readings out of other windows.
//
// Thread contract: a HidDevice is owned by one thread (the driver's I/O thread).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace leafdig::devices {

struct HidInfo {
  std::string path;  // /dev/hidrawN
  std::uint16_t vid = 0, pid = 0;
  std::string manufacturer, product, serial;
  int interfaceNumber = -1;
  std::uint16_t usagePage = 0, usage = 0;
};

class HidDevice {
 public:
  HidDevice() = default;
  HidDevice(const HidDevice&) = delete;
  HidDevice& operator=(const HidDevice&) = delete;
  virtual ~HidDevice() = default;
  // One input report (without a report-ID byte unless the device numbers its reports), or
  // an empty vector on timeout. Throws DeviceError(Io) when the device went away.
  [[nodiscard]] virtual std::vector<std::uint8_t> readReport(std::chrono::milliseconds timeout) = 0;
  [[nodiscard]] virtual HidInfo info() const = 0;
};

[[nodiscard]] std::vector<HidInfo> enumerateHid(std::uint16_t vid = 0, std::uint16_t pid = 0);
// Opens the first device matching vid:pid (and serial when given) with hidapi.
[[nodiscard]] std::unique_ptr<HidDevice> openHidapi(std::uint16_t vid, std::uint16_t pid,
                                                    const std::string& serial = {});
[[nodiscard]] std::unique_ptr<HidDevice> openHidapiPath(const std::string& path);

// An in-memory HID device: reports are pushed by a producer thread (a simulator) and read
// by the driver. unplug() makes reads fail as a real unplug does; replug() restores it.
// Thread contract: push/unplug/replug from any thread; readReport from one thread.
class MemoryHidDevice final : public HidDevice {
 public:
  explicit MemoryHidDevice(HidInfo info) : info_(std::move(info)) {}
  std::vector<std::uint8_t> readReport(std::chrono::milliseconds timeout) override;
  [[nodiscard]] HidInfo info() const override { return info_; }
  void push(std::vector<std::uint8_t> report);
  void unplug();
  void replug();
  [[nodiscard]] bool plugged() const;

 private:
  HidInfo info_;
  mutable std::mutex mutex_;
  std::condition_variable_any cv_;
  std::deque<std::vector<std::uint8_t>> queue_;
  bool plugged_ = true;
};

// Exclusive grab (EVIOCGRAB) of the evdev nodes of one HID device, so its keystrokes reach
// leafdig only. Released on destruction. `grabbed()` lists the nodes held; `problems()`
// says why a node could not be grabbed (permission: needs the udev rule or the input group).
class EvdevGrab {
 public:
  explicit EvdevGrab(const std::string& hidrawPath);
  EvdevGrab(const EvdevGrab&) = delete;
  EvdevGrab& operator=(const EvdevGrab&) = delete;
  ~EvdevGrab();
  [[nodiscard]] const std::vector<std::string>& grabbed() const { return grabbed_; }
  [[nodiscard]] const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<int> fds_;
  std::vector<std::string> grabbed_, problems_;
};

// The /dev/input/eventN nodes that belong to a hidraw node (via sysfs).
[[nodiscard]] std::vector<std::string> evdevNodesFor(const std::string& hidrawPath,
                                                     const std::string& sysRoot = "/sys");

}  // namespace leafdig::devices
