// USB through libusb: device listing, hotplug as a "rescan" signal, and the vendor
// control/interrupt transfers Mitutoyo's USB-ITN uses for PC-triggered reads.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace leafdig::devices {

struct UsbDeviceInfo {
  std::uint16_t vid = 0, pid = 0;
  int bus = 0, address = 0;
  std::string manufacturer, product, serial;  // empty when the descriptor is unreadable
};

// Every USB device libusb sees (empty on a machine without USB, which is normal).
[[nodiscard]] std::vector<UsbDeviceInfo> listUsbDevices();
[[nodiscard]] bool usbHotplugSupported();

// The vendor-request seam: what the USB-ITN driver needs from a USB device.
// Thread contract: one thread (the driver's I/O thread).
class UsbVendorDevice {
 public:
  UsbVendorDevice() = default;
  UsbVendorDevice(const UsbVendorDevice&) = delete;
  UsbVendorDevice& operator=(const UsbVendorDevice&) = delete;
  virtual ~UsbVendorDevice() = default;
  // Control transfer OUT (host to device). Throws DeviceError on failure.
  virtual void controlOut(std::uint8_t requestType, std::uint8_t request, std::uint16_t value, std::uint16_t index,
                          const std::vector<std::uint8_t>& data) = 0;
  // Control transfer IN; returns the bytes received.
  [[nodiscard]] virtual std::vector<std::uint8_t> controlIn(std::uint8_t requestType, std::uint8_t request,
                                                            std::uint16_t value, std::uint16_t index,
                                                            std::uint16_t length) = 0;
  // Interrupt IN; empty on timeout.
  [[nodiscard]] virtual std::vector<std::uint8_t> interruptIn(std::uint8_t endpoint,
                                                              std::chrono::milliseconds timeout) = 0;
  [[nodiscard]] virtual std::string describe() const = 0;
};

// Opens vid:pid with libusb: detaches the kernel driver of interface 0 (re-attached on close
// via auto-detach), sets configuration 1, claims interface 0.
[[nodiscard]] std::unique_ptr<UsbVendorDevice> openUsbVendorDevice(std::uint16_t vid, std::uint16_t pid);

// Calls `rescan` (from its own thread) when a USB device arrives or leaves. Uses libusb
// hotplug where the platform has it, otherwise compares listings every `pollInterval`.
// Thread contract: construct and destroy on one thread; `rescan` runs on the watcher thread.
class UsbHotplugWatcher {
 public:
  explicit UsbHotplugWatcher(std::function<void()> rescan,
                             std::chrono::milliseconds pollInterval = std::chrono::seconds(2));
  UsbHotplugWatcher(const UsbHotplugWatcher&) = delete;
  UsbHotplugWatcher& operator=(const UsbHotplugWatcher&) = delete;
  ~UsbHotplugWatcher();
  [[nodiscard]] bool usingHotplug() const { return hotplug_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool hotplug_ = false;
};

}  // namespace leafdig::devices
