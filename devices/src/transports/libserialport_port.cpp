// SerialPort over libserialport, and port enumeration.
#include <libserialport.h>
#include <sys/file.h>

#include <cerrno>

#include "leafdig/devices/errors.hpp"
#include "leafdig/devices/transports/serial_port.hpp"

namespace leafdig::devices {
namespace {

DeviceError lastError(const std::string& action, const std::string& path) {
  const int err = sp_last_error_code();
  if (err != 0) return errorFromErrno(err, action, path);
  char* msg = sp_last_error_message();
  std::string text = msg ? msg : "unknown error";
  sp_free_error_message(msg);
  return {DeviceErrorKind::Io, action + " " + path + ": " + text, "check the cable and the device's power"};
}

class LibSerialPort final : public SerialPort {
 public:
  LibSerialPort(const std::string& name, const SerialSettings& s) : name_(name) {
    if (sp_get_port_by_name(name.c_str(), &port_) != SP_OK)
      throw DeviceError(DeviceErrorKind::NotFound, "no serial port named " + name,
                        "check that the device is plugged in ('leafdig devices list')");
    if (sp_open(port_, SP_MODE_READ_WRITE) != SP_OK) {
      auto e = lastError("cannot open", name);
      sp_free_port(port_);
      throw e;
    }
    int fd = -1;
    if (sp_get_port_handle(port_, &fd) == SP_OK && fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      sp_close(port_);
      sp_free_port(port_);
      throw errorFromErrno(EBUSY, "cannot lock", name);
    }
    try {
      setSettings(s);
    } catch (...) {
      sp_close(port_);
      sp_free_port(port_);
      throw;
    }
  }
  ~LibSerialPort() override {
    sp_close(port_);
    sp_free_port(port_);
  }
  std::vector<std::uint8_t> read(std::size_t max, std::chrono::milliseconds timeout) override {
    std::vector<std::uint8_t> buf(max);
    const sp_return r = sp_blocking_read_next(port_, buf.data(), max, static_cast<unsigned>(timeout.count()));
    if (r < 0) throw lastError("cannot read from", name_);
    buf.resize(static_cast<std::size_t>(r));
    return buf;
  }
  void write(const std::uint8_t* data, std::size_t size, std::chrono::milliseconds timeout) override {
    const sp_return r = sp_blocking_write(port_, data, size, static_cast<unsigned>(timeout.count()));
    if (r < 0) throw lastError("cannot write to", name_);
    if (static_cast<std::size_t>(r) != size)
      throw DeviceError(DeviceErrorKind::Timeout, name_ + ": write timed out",
                        "the device is not reading: check flow control and the cable");
  }
  void setSettings(const SerialSettings& s) override {
    const bool ok = sp_set_baudrate(port_, s.baud) == SP_OK && sp_set_bits(port_, s.dataBits) == SP_OK &&
                    sp_set_parity(port_, s.parity == Parity::None   ? SP_PARITY_NONE
                                         : s.parity == Parity::Even ? SP_PARITY_EVEN
                                                                    : SP_PARITY_ODD) == SP_OK &&
                    sp_set_stopbits(port_, s.stopBits) == SP_OK &&
                    sp_set_flowcontrol(port_, s.rtsCts ? SP_FLOWCONTROL_RTSCTS : SP_FLOWCONTROL_NONE) == SP_OK;
    if (!ok)
      throw DeviceError(DeviceErrorKind::Config, name_ + ": cannot set " + describe(s),
                        "the adapter does not support these settings");
    settings_ = s;
  }
  SerialSettings settings() const override { return settings_; }
  void flushInput() override { (void)sp_flush(port_, SP_BUF_INPUT); }
  void setDtr(bool on) override { (void)sp_set_dtr(port_, on ? SP_DTR_ON : SP_DTR_OFF); }
  std::string path() const override { return name_; }

 private:
  std::string name_;
  sp_port* port_ = nullptr;
  SerialSettings settings_;
};

}  // namespace

std::unique_ptr<SerialPort> openLibSerialPort(const std::string& name, const SerialSettings& s) {
  return std::make_unique<LibSerialPort>(name, s);
}

std::unique_ptr<SerialPort> openSerialPort(const std::string& path, const SerialSettings& s) {
  sp_port* probe = nullptr;
  if (sp_get_port_by_name(path.c_str(), &probe) == SP_OK) {
    const bool real =
        sp_get_port_transport(probe) == SP_TRANSPORT_USB || sp_get_port_transport(probe) == SP_TRANSPORT_BLUETOOTH;
    sp_free_port(probe);
    if (real) return openLibSerialPort(path, s);
  }
  return openTtyPort(path, s);  // ptys, symlinks, on-board UARTs: termios does it all
}

std::vector<SerialPortInfo> listSerialPorts() {
  std::vector<SerialPortInfo> out;
  sp_port** ports = nullptr;
  if (sp_list_ports(&ports) != SP_OK) return out;
  for (sp_port** p = ports; *p; ++p) {
    SerialPortInfo info;
    info.path = sp_get_port_name(*p);
    if (const char* d = sp_get_port_description(*p)) info.description = d;
    const sp_transport t = sp_get_port_transport(*p);
    info.transport = t == SP_TRANSPORT_USB ? "usb" : t == SP_TRANSPORT_BLUETOOTH ? "bluetooth" : "native";
    if (t == SP_TRANSPORT_USB) {
      int vid = 0, pid = 0, bus = 0, addr = 0;
      if (sp_get_port_usb_vid_pid(*p, &vid, &pid) == SP_OK) {
        info.vid = static_cast<std::uint16_t>(vid);
        info.pid = static_cast<std::uint16_t>(pid);
      }
      if (sp_get_port_usb_bus_address(*p, &bus, &addr) == SP_OK) {
        info.usbBus = bus;
        info.usbAddress = addr;
      }
      if (const char* s = sp_get_port_usb_manufacturer(*p)) info.manufacturer = s;
      if (const char* s = sp_get_port_usb_product(*p)) info.product = s;
      if (const char* s = sp_get_port_usb_serial(*p)) info.serial = s;
    }
    out.push_back(std::move(info));
  }
  sp_free_port_list(ports);
  return out;
}

}  // namespace leafdig::devices
