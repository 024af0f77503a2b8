// Byte transports for serial devices.
//
// Thread contract: a SerialPort is owned by one thread (the driver's I/O thread); its
// methods are not safe to call concurrently. Reads block at most their timeout, so the
// owner can check a stop flag between reads. Ports are not copyable.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace leafdig::devices {

enum class Parity { None, Even, Odd };

struct SerialSettings {
  int baud = 115200;
  int dataBits = 8;
  Parity parity = Parity::None;
  int stopBits = 1;
  bool rtsCts = false;
};

[[nodiscard]] std::string describe(const SerialSettings& s);  // "115200 8N1"

class SerialPort {
 public:
  SerialPort() = default;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;
  virtual ~SerialPort() = default;

  // Waits up to `timeout` for bytes and returns what is available (at most `max`); an empty
  // result means the timeout expired. Throws DeviceError(Io) when the device went away.
  [[nodiscard]] virtual std::vector<std::uint8_t> read(std::size_t max, std::chrono::milliseconds timeout) = 0;
  // Writes everything (blocking up to `timeout`); throws DeviceError on failure.
  virtual void write(const std::uint8_t* data, std::size_t size, std::chrono::milliseconds timeout) = 0;
  void write(const std::string& text, std::chrono::milliseconds timeout = std::chrono::milliseconds(500)) {
    write(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), timeout);
  }
  virtual void setSettings(const SerialSettings& settings) = 0;
  [[nodiscard]] virtual SerialSettings settings() const = 0;
  // Discards unread input.
  virtual void flushInput() = 0;
  // Sets the DTR line (Sylvac simplex cables request a reading by dropping DTR).
  virtual void setDtr(bool on) = 0;
  [[nodiscard]] virtual std::string path() const = 0;
};

// A tty by path (any /dev/tty*, pseudo-terminals included), through termios. Takes an
// exclusive advisory lock (flock) and TIOCEXCL so a second program gets "busy".
[[nodiscard]] std::unique_ptr<SerialPort> openTtyPort(const std::string& path, const SerialSettings& settings);

// A real serial port through libserialport (USB-serial adapters, on-board UARTs). Cannot
// open pseudo-terminals (libserialport looks the name up in /sys/class/tty).
[[nodiscard]] std::unique_ptr<SerialPort> openLibSerialPort(const std::string& name, const SerialSettings& settings);

// Opens with libserialport when it knows the port, with termios otherwise (ptys, symlinks).
[[nodiscard]] std::unique_ptr<SerialPort> openSerialPort(const std::string& path, const SerialSettings& settings);

struct SerialPortInfo {
  std::string path;         // /dev/ttyUSB0
  std::string description;  // libserialport's description
  std::string transport;    // "usb", "native", "bluetooth"
  std::optional<std::uint16_t> vid, pid;
  std::string manufacturer, product, serial;
  int usbBus = -1, usbAddress = -1;
};

// Every serial port libserialport sees (pseudo-terminals are never listed).
[[nodiscard]] std::vector<SerialPortInfo> listSerialPorts();

}  // namespace leafdig::devices
