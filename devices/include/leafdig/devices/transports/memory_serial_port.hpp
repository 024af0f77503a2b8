// A scriptable serial line in memory, for driver tests that need no pseudo-terminal (the
// idea of QGroundControl's MockLink): the test plays the device — feeds the bytes it sends,
// answers what the driver writes — and injects the failures of real cables: a stall (reads
// time out, writes vanish), an I/O error on read or write (the adapter unplugged), a port
// that cannot be opened (busy, missing, no permission). `opener()` is the `openPort` of
// DigitizerConfig / CaliperConfig; every open gets a port on the same line.
//
// Thread contract: the test's calls (feed, respond, stall, fail…, written, opens) from any
// thread; each port it opens is used by one thread (the driver's I/O thread).
#pragma once

#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "leafdig/devices/errors.hpp"
#include "leafdig/devices/transports/serial_port.hpp"

namespace leafdig::devices {

class MemorySerialLine {
 public:
  using Opener = std::function<std::unique_ptr<SerialPort>(const std::string&, const SerialSettings&)>;
  // Answers one complete write with the bytes the device sends back ("" for none).
  using Responder = std::function<std::string(const std::string& written)>;

  MemorySerialLine();

  void feed(const std::string& bytes);  // bytes the device sends now
  void respond(Responder responder);    // answer every write from now on
  void stall(bool on);                  // reads time out, writes are swallowed
  // The next read (or write) throws DeviceError(Io) with `message`, as an unplugged
  // adapter does, once; the port stays broken until it is opened again.
  void failNextRead(const std::string& message = "Input/output error");
  void failNextWrite(const std::string& message = "Input/output error");
  // Opening fails with this error until allowOpen().
  void refuseOpen(DeviceErrorKind kind, const std::string& message, const std::string& remedy);
  void allowOpen();

  [[nodiscard]] std::string written() const;                     // everything the driver wrote, in order
  [[nodiscard]] int opens() const;                               // successful opens so far
  [[nodiscard]] std::optional<SerialSettings> settings() const;  // of the latest open
  [[nodiscard]] bool dtr() const;
  [[nodiscard]] Opener opener();

 private:
  friend class MemorySerialPort;
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace leafdig::devices
