// Drivers: a DeviceLink (codec + transport + init for one device) run by a Driver, which
// owns the I/O thread, reconnects after unplugs and stalls, filters stylus streams and
// reports a status an operator understands.
#pragma once

#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "leafdig/devices/errors.hpp"
#include "leafdig/devices/sample.hpp"

namespace leafdig::devices {

using DeviceEvent = std::variant<StylusSample, CaliperReading>;

enum class LinkState { Disconnected, Connecting, Streaming, Warning, Error };
[[nodiscard]] const char* toString(LinkState s);

struct DeviceStatus {
  LinkState state = LinkState::Disconnected;
  std::string device;          // "FASTRAK", "Sylvac"
  std::string where;           // port path or USB id
  std::string message;         // what is happening, in words
  std::string remedy;          // what to do (errors and warnings)
  double rateHz = 0;           // delivered samples per second (recent)
  double lastSampleAgeS = -1;  // seconds since the last sample, -1 before the first
  DecodeStats stats;           // the codec's counters (this connection + earlier ones)
  std::uint64_t filtered = 0;  // stylus samples withheld by the spike filter
  int reconnects = 0;
};

// One device's I/O for one connection. Thread contract: all methods are called from the
// Driver's I/O thread only (or from a single test thread without a Driver).
class DeviceLink {
 public:
  DeviceLink() = default;
  DeviceLink(const DeviceLink&) = delete;
  DeviceLink& operator=(const DeviceLink&) = delete;
  virtual ~DeviceLink() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  [[nodiscard]] virtual std::string where() const = 0;
  // Opens the transport and initialises the device. Throws DeviceError with a remedy.
  virtual void open() = 0;
  virtual void close() noexcept = 0;
  // Waits up to `timeout` for input, decodes it, appends events (time-stamped on arrival).
  // Throws DeviceError when the link is lost.
  virtual void pump(std::chrono::milliseconds timeout, std::vector<DeviceEvent>& out) = 0;
  // A PC-triggered reading (caliper request); no-op where the device pushes readings.
  virtual void trigger() {}
  [[nodiscard]] virtual DecodeStats stats() const = 0;
  // A streaming device that is silent this long is re-initialised (reset, wrong mode).
  [[nodiscard]] virtual bool streams() const { return true; }
  [[nodiscard]] virtual std::chrono::milliseconds stallTimeout() const { return std::chrono::milliseconds(1000); }
  // The latest device-side warning (status letter, gauge error), empty when none.
  [[nodiscard]] virtual std::string warning() const { return {}; }
  [[nodiscard]] virtual std::string warningRemedy() const { return {}; }  // what to do about it
};

// Withholds stylus samples that cannot be right: a sample further than `spikeMm` from the
// midpoint of its two raw neighbours (a bit flip that still parses, a glitch) is dropped;
// the button changes only when two consecutive kept samples agree. Delays by one sample.
class StylusFilter {
 public:
  explicit StylusFilter(double spikeMm = 2.0) : spikeMm_(spikeMm) {}
  void push(StylusSample s, std::vector<StylusSample>& out);
  void reset();  // after a reconnect: neighbours from before do not count
  [[nodiscard]] std::uint64_t rejected() const { return rejected_; }

 private:
  double spikeMm_;
  std::deque<StylusSample> window_;
  bool button_ = false, candidate_ = false;
  int agree_ = 0;
  std::uint64_t rejected_ = 0;
};

struct DriverOptions {
  bool filterStylus = true;
  double spikeMm = 2.0;
  std::chrono::milliseconds pollEvery{0};  // > 0: trigger() the link at this interval
  std::chrono::milliseconds retryMin{100}, retryMax{2000};
};

// Runs a link on its own thread. Thread contract: construct, start, stop and destroy from
// one owner thread; trigger() and status() from any thread; callbacks run on the I/O thread
// and must not block (hand events to a queue).
class Driver {
 public:
  struct Callbacks {
    std::function<void(const DeviceEvent&)> onEvent;
    std::function<void(const DeviceStatus&)> onStatus;  // every state or message change
  };
  Driver(std::unique_ptr<DeviceLink> link, Callbacks callbacks, DriverOptions options = {});
  Driver(const Driver&) = delete;
  Driver& operator=(const Driver&) = delete;
  ~Driver();
  void start();
  void stop();
  void trigger();
  [[nodiscard]] DeviceStatus status() const;

 private:
  // The I/O thread's steps (driver.cpp).
  void run();
  [[nodiscard]] bool connect();
  void waitBeforeRetry();
  void pollIfDue();
  [[nodiscard]] std::size_t deliver();
  void recordDelivery(std::size_t delivered, Clock::time_point now);
  void reportWarningChange();
  void reinitialiseIfStalled(Clock::time_point now);
  void dropConnection();
  void setState(LinkState s, std::string message, std::string remedy = {});
  std::unique_ptr<DeviceLink> link_;
  Callbacks callbacks_;
  DriverOptions options_;
  std::thread thread_;
  std::atomic<bool> stop_{false}, trigger_{false};
  mutable std::mutex mutex_;
  DeviceStatus status_;
  DecodeStats previousStats_;
  StylusFilter filter_;
  Clock::time_point lastEvent_{};
  std::deque<Clock::time_point> recent_;
  // I/O thread only:
  // When the device last sent a valid record, delivered or not (a stylus sample withheld while
  // a reference receiver is silent is still the device talking): the stall watchdog's clock.
  Clock::time_point lastHeard_{};
  std::uint64_t recordsHeard_ = 0;
  bool connected_ = false;
  bool streamBegins_ = false;  // the next stylus sample delivered is the first of a connection
  std::chrono::milliseconds retry_{0};
  Clock::time_point lastPoll_{};
  std::string lastWarning_;
  std::vector<DeviceEvent> events_;
  std::vector<StylusSample> kept_;
};

}  // namespace leafdig::devices
