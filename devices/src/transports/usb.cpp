// libusb: listing, hotplug watcher, vendor transfers.
#include "leafdig/devices/transports/usb.hpp"

#include <libusb-1.0/libusb.h>

#include <atomic>
#include <cstdio>
#include <set>
#include <tuple>

#include "leafdig/devices/errors.hpp"

namespace leafdig::devices {
namespace {

struct Context {
  libusb_context* ctx = nullptr;
  Context() {
    if (libusb_init(&ctx) != 0) ctx = nullptr;
  }
  ~Context() {
    if (ctx) libusb_exit(ctx);
  }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
};

std::string descriptorString(libusb_device_handle* h, std::uint8_t index) {
  if (!h || index == 0) return {};
  unsigned char buf[256];
  const int n = libusb_get_string_descriptor_ascii(h, index, buf, sizeof buf);
  return n > 0 ? std::string(reinterpret_cast<char*>(buf), static_cast<std::size_t>(n)) : std::string();
}

DeviceError usbError(int rc, const std::string& what) {
  switch (rc) {
    case LIBUSB_ERROR_ACCESS:
      return {DeviceErrorKind::Permission, what + ": permission denied",
              "install the udev rule ('leafdig doctor' shows how) and replug the device"};
    case LIBUSB_ERROR_BUSY:
      return {DeviceErrorKind::Busy, what + ": busy", "another program has claimed the device: close it"};
    case LIBUSB_ERROR_NO_DEVICE:
    case LIBUSB_ERROR_NOT_FOUND: return {DeviceErrorKind::NotFound, what + ": device gone", "plug the device back in"};
    case LIBUSB_ERROR_TIMEOUT:
      return {DeviceErrorKind::Timeout, what + ": timed out", "check the gauge is connected to the interface"};
    default: return {DeviceErrorKind::Io, what + ": " + libusb_error_name(rc), "check the cable"};
  }
}

class LibusbVendorDevice final : public UsbVendorDevice {
 public:
  LibusbVendorDevice(std::uint16_t vid, std::uint16_t pid) {
    char id[16];
    std::snprintf(id, sizeof id, "%04x:%04x", vid, pid);
    name_ = id;
    if (!ctx_.ctx)
      throw DeviceError(DeviceErrorKind::Unsupported, "libusb could not start", "check /dev/bus/usb exists");
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(ctx_.ctx, &list);
    int rc = LIBUSB_ERROR_NOT_FOUND;
    for (ssize_t i = 0; i < n && !handle_; ++i) {
      libusb_device_descriptor d{};
      if (libusb_get_device_descriptor(list[i], &d) == 0 && d.idVendor == vid && d.idProduct == pid)
        rc = libusb_open(list[i], &handle_);
    }
    if (list) libusb_free_device_list(list, 1);
    if (!handle_) {
      if (rc == LIBUSB_ERROR_NOT_FOUND)
        throw DeviceError(DeviceErrorKind::NotFound, "no USB device " + name_,
                          "plug the interface in; 'leafdig devices list' shows what is connected");
      throw usbError(rc, "USB device " + name_);
    }
    (void)libusb_set_auto_detach_kernel_driver(handle_, 1);  // re-attached on release
    (void)libusb_set_configuration(handle_, 1);
    rc = libusb_claim_interface(handle_, 0);
    if (rc != 0) {
      libusb_close(handle_);
      throw usbError(rc, "USB device " + name_ + " interface 0");
    }
  }
  ~LibusbVendorDevice() override {
    (void)libusb_release_interface(handle_, 0);
    libusb_close(handle_);
  }
  void controlOut(std::uint8_t rt, std::uint8_t req, std::uint16_t value, std::uint16_t index,
                  const std::vector<std::uint8_t>& data) override {
    std::vector<std::uint8_t> copy = data;
    const int rc = libusb_control_transfer(handle_, rt, req, value, index, copy.data(),
                                           static_cast<std::uint16_t>(copy.size()), 1000);
    if (rc < 0) throw usbError(rc, name_ + " control OUT");
  }
  std::vector<std::uint8_t> controlIn(std::uint8_t rt, std::uint8_t req, std::uint16_t value, std::uint16_t index,
                                      std::uint16_t length) override {
    std::vector<std::uint8_t> buf(length);
    const int rc = libusb_control_transfer(handle_, rt, req, value, index, buf.data(), length, 1000);
    if (rc < 0) throw usbError(rc, name_ + " control IN");
    buf.resize(static_cast<std::size_t>(rc));
    return buf;
  }
  std::vector<std::uint8_t> interruptIn(std::uint8_t ep, std::chrono::milliseconds timeout) override {
    std::vector<std::uint8_t> buf(64);
    int got = 0;
    const int rc = libusb_interrupt_transfer(handle_, ep, buf.data(), static_cast<int>(buf.size()), &got,
                                             static_cast<unsigned>(timeout.count()));
    if (rc == LIBUSB_ERROR_TIMEOUT) return {};
    if (rc < 0) throw usbError(rc, name_ + " interrupt IN");
    buf.resize(static_cast<std::size_t>(got));
    return buf;
  }
  std::string describe() const override { return "usb:" + name_; }

 private:
  Context ctx_;
  libusb_device_handle* handle_ = nullptr;
  std::string name_;
};

using Key = std::tuple<int, int, int, int>;
std::set<Key> snapshot() {
  std::set<Key> s;
  for (const auto& d : listUsbDevices()) s.insert({d.bus, d.address, d.vid, d.pid});
  return s;
}

}  // namespace

std::vector<UsbDeviceInfo> listUsbDevices() {
  std::vector<UsbDeviceInfo> out;
  Context c;
  if (!c.ctx) return out;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(c.ctx, &list);
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
    UsbDeviceInfo info;
    info.vid = d.idVendor;
    info.pid = d.idProduct;
    info.bus = libusb_get_bus_number(list[i]);
    info.address = libusb_get_device_address(list[i]);
    libusb_device_handle* h = nullptr;
    if (libusb_open(list[i], &h) == 0) {
      info.manufacturer = descriptorString(h, d.iManufacturer);
      info.product = descriptorString(h, d.iProduct);
      info.serial = descriptorString(h, d.iSerialNumber);
      libusb_close(h);
    }
    out.push_back(std::move(info));
  }
  if (list) libusb_free_device_list(list, 1);
  return out;
}

bool usbHotplugSupported() {
  return libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG) != 0;
}

std::unique_ptr<UsbVendorDevice> openUsbVendorDevice(std::uint16_t vid, std::uint16_t pid) {
  return std::make_unique<LibusbVendorDevice>(vid, pid);
}

struct UsbHotplugWatcher::Impl {
  std::function<void()> rescan;
  std::chrono::milliseconds interval;
  std::atomic<bool> stop{false};
  std::atomic<bool> changed{false};
  Context ctx;
  libusb_hotplug_callback_handle handle{};
  bool registered = false;
  std::thread thread;

  static int LIBUSB_CALL callback(libusb_context*, libusb_device*, libusb_hotplug_event, void* user) {
    static_cast<Impl*>(user)->changed = true;  // no I/O in here: the thread calls rescan
    return 0;
  }
};

UsbHotplugWatcher::UsbHotplugWatcher(std::function<void()> rescan, std::chrono::milliseconds poll)
    : impl_(std::make_unique<Impl>()) {
  impl_->rescan = std::move(rescan);
  impl_->interval = poll;
  Impl* im = impl_.get();
  if (im->ctx.ctx && usbHotplugSupported() &&
      libusb_hotplug_register_callback(
          im->ctx.ctx,
          static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED | LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
          static_cast<libusb_hotplug_flag>(0), LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
          LIBUSB_HOTPLUG_MATCH_ANY, &Impl::callback, im, &im->handle) == LIBUSB_SUCCESS) {
    im->registered = true;
    hotplug_ = true;
    im->thread = std::thread([im] {
      while (!im->stop) {
        timeval tv{0, 200000};
        (void)libusb_handle_events_timeout_completed(im->ctx.ctx, &tv, nullptr);
        if (im->changed.exchange(false)) im->rescan();
      }
    });
  } else {
    im->thread = std::thread([im] {
      auto last = snapshot();
      while (!im->stop) {
        for (auto waited = std::chrono::milliseconds(0); waited < im->interval && !im->stop;
             waited += std::chrono::milliseconds(50))
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
        auto now = snapshot();
        if (now != last) {
          last = std::move(now);
          im->rescan();
        }
      }
    });
  }
}

UsbHotplugWatcher::~UsbHotplugWatcher() {
  impl_->stop = true;
  if (impl_->registered) libusb_hotplug_deregister_callback(impl_->ctx.ctx, impl_->handle);  // wakes handle_events
  if (impl_->thread.joinable()) impl_->thread.join();
}

}  // namespace leafdig::devices
