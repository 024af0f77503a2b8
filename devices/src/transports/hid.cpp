// HID transports: hidapi (hidraw backend), the in-memory device, the evdev grab.
#include "leafdig/devices/transports/hid.hpp"

#include <fcntl.h>
#include <hidapi/hidapi.h>
#include <linux/input.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "leafdig/devices/errors.hpp"

namespace leafdig::devices {
namespace {

std::string narrow(const wchar_t* w) {
  std::string s;
  if (!w) return s;
  for (; *w; ++w) s += (*w < 0x80) ? static_cast<char>(*w) : '?';
  return s;
}

void ensureInit() {
  static std::once_flag once;
  std::call_once(once, [] { (void)hid_init(); });
}

HidInfo toInfo(const hid_device_info* d) {
  HidInfo i;
  i.path = d->path ? d->path : "";
  i.vid = d->vendor_id;
  i.pid = d->product_id;
  i.manufacturer = narrow(d->manufacturer_string);
  i.product = narrow(d->product_string);
  i.serial = narrow(d->serial_number);
  i.interfaceNumber = d->interface_number;
  i.usagePage = d->usage_page;
  i.usage = d->usage;
  return i;
}

class HidapiDevice final : public HidDevice {
 public:
  HidapiDevice(hid_device* dev, HidInfo info) : dev_(dev), info_(std::move(info)) {}
  ~HidapiDevice() override { hid_close(dev_); }
  std::vector<std::uint8_t> readReport(std::chrono::milliseconds timeout) override {
    std::vector<std::uint8_t> buf(64);
    const int n = hid_read_timeout(dev_, buf.data(), buf.size(), static_cast<int>(timeout.count()));
    if (n < 0)
      throw DeviceError(DeviceErrorKind::Io, info_.path + ": " + narrow(hid_error(dev_)),
                        "the gauge was unplugged or its cable failed; leafdig reconnects by itself");
    buf.resize(static_cast<std::size_t>(n));
    return buf;
  }
  HidInfo info() const override { return info_; }

 private:
  hid_device* dev_;
  HidInfo info_;
};

DeviceError openFailure(const std::string& what) {
  const int err = errno;
  if (err == EACCES || err == EPERM) return errorFromErrno(err, "cannot open", what);
  return {DeviceErrorKind::NotFound, "cannot open HID device " + what,
          "check that the gauge is plugged in ('leafdig devices list' shows HID devices); if it "
          "is listed, install the udev rule ('leafdig doctor')"};
}

}  // namespace

std::vector<HidInfo> enumerateHid(std::uint16_t vid, std::uint16_t pid) {
  ensureInit();
  std::vector<HidInfo> out;
  hid_device_info* list = hid_enumerate(vid, pid);
  for (hid_device_info* d = list; d; d = d->next) out.push_back(toInfo(d));
  hid_free_enumeration(list);
  return out;
}

std::unique_ptr<HidDevice> openHidapi(std::uint16_t vid, std::uint16_t pid, const std::string& serial) {
  for (const HidInfo& i : enumerateHid(vid, pid))
    if (serial.empty() || i.serial == serial) return openHidapiPath(i.path);
  char id[16];
  std::snprintf(id, sizeof id, "%04x:%04x", vid, pid);
  throw DeviceError(DeviceErrorKind::NotFound,
                    std::string("no HID device ") + id + (serial.empty() ? "" : " serial " + serial),
                    "plug the gauge in, or check the id with 'leafdig devices list'");
}

std::unique_ptr<HidDevice> openHidapiPath(const std::string& path) {
  ensureInit();
  HidInfo info;
  info.path = path;
  for (const HidInfo& i : enumerateHid())
    if (i.path == path) info = i;
  errno = 0;
  hid_device* dev = hid_open_path(path.c_str());
  if (!dev) throw openFailure(path);
  return std::make_unique<HidapiDevice>(dev, info);
}

// ---- MemoryHidDevice ----------------------------------------------------------------------
std::vector<std::uint8_t> MemoryHidDevice::readReport(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, timeout, [&] { return !queue_.empty() || !plugged_; });
  if (!plugged_)
    throw DeviceError(DeviceErrorKind::Io, info_.path + ": device unplugged",
                      "plug the gauge back in; leafdig reconnects by itself");
  if (queue_.empty()) return {};
  auto r = std::move(queue_.front());
  queue_.pop_front();
  return r;
}
void MemoryHidDevice::push(std::vector<std::uint8_t> report) {
  {
    std::lock_guard lock(mutex_);
    if (!plugged_) return;
    queue_.push_back(std::move(report));
  }
  cv_.notify_all();
}
void MemoryHidDevice::unplug() {
  {
    std::lock_guard lock(mutex_);
    plugged_ = false;
    queue_.clear();
  }
  cv_.notify_all();
}
void MemoryHidDevice::replug() {
  std::lock_guard lock(mutex_);
  plugged_ = true;
}
bool MemoryHidDevice::plugged() const {
  std::lock_guard lock(mutex_);
  return plugged_;
}

// ---- evdev grab ---------------------------------------------------------------------------
std::vector<std::string> evdevNodesFor(const std::string& hidrawPath, const std::string& sysRoot) {
  namespace fs = std::filesystem;
  std::vector<std::string> nodes;
  const std::string name = fs::path(hidrawPath).filename().string();
  std::error_code ec;
  const fs::path inputs = fs::path(sysRoot) / "class/hidraw" / name / "device/input";
  for (const auto& input : fs::directory_iterator(inputs, ec)) {
    for (const auto& e : fs::directory_iterator(input.path(), ec)) {
      const std::string n = e.path().filename().string();
      if (n.rfind("event", 0) == 0) nodes.push_back("/dev/input/" + n);
    }
  }
  return nodes;
}

EvdevGrab::EvdevGrab(const std::string& hidrawPath) {
  const auto nodes = evdevNodesFor(hidrawPath);
  if (nodes.empty())
    problems_.push_back("no keyboard (evdev) node found for " + hidrawPath +
                        ": readings may also be typed into the focused window");
  for (const std::string& n : nodes) {
    const int fd = ::open(n.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      problems_.push_back(n + ": " + std::strerror(errno) +
                          " (install the udev rule or join the 'input' group so leafdig can keep "
                          "gauge keystrokes out of other windows)");
      continue;
    }
    if (::ioctl(fd, EVIOCGRAB, 1) != 0) {
      problems_.push_back(n + ": cannot grab (" + std::string(std::strerror(errno)) + "); another program holds it");
      ::close(fd);
      continue;
    }
    fds_.push_back(fd);
    grabbed_.push_back(n);
  }
}

EvdevGrab::~EvdevGrab() {
  for (int fd : fds_) {
    (void)::ioctl(fd, EVIOCGRAB, 0);
    ::close(fd);
  }
}

}  // namespace leafdig::devices
