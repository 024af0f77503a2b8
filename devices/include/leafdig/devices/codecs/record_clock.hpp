// The device's clock for a streaming digitizer (issue 26): a FASTRAK in continuous mode sends
// a record every 1/120 s whatever the host is doing, but the host reads them in bursts — a busy
// machine, a USB-serial adapter's latency timer — so the instant the bytes arrive says little
// about when the stylus switch moved. Records are timed by their count instead: record k is at
// anchor + k·T, T the stream's period, the anchor the earliest the stream has ever shown
// (the smallest arrival − k·T: the least-delayed record). After a second without records
// the stream shows within another second whether records were lost (an unplug, a stall, a
// re-initialised device: none comes as early as before again, and the count is moved on by
// the records missing) or only read late (a starved host reading them all at once: they keep
// their count, and a press among them its length). T starts at the rate
// the device is set to and is checked against the stream in blocks of 2.5 s (the least
// delay of each block: bursts only add delay, so the least-delayed records show the rate): a
// stream more than 2 % off, alike in two blocks running — a serial line too slow for the
// rate — is timed at the rate it really has (a busy host's delays come and go: one block off
// is not enough). Where nothing better exists (polled devices, unknown line
// digitizers) samples keep their arrival time.
//
// Thread contract: one stream, one thread (the driver's).
#pragma once

#include <cstdint>
#include <optional>

#include "leafdig/devices/sample.hpp"

namespace leafdig::devices {

class RecordClock {
 public:
  explicit RecordClock(double periodSeconds);
  // The device time of the next record, which arrived at `arrival` (records in order).
  [[nodiscard]] Clock::time_point stamp(Clock::time_point arrival);
  // The stream was re-initialised: the next record starts a new count.
  void restart() { count_ = -1; }
  [[nodiscard]] double periodSeconds() const { return periodNs_ * 1e-9; }

 private:
  double periodNs_;
  std::int64_t count_ = -1;   // records since the count began (-1: none yet)
  Clock::time_point base_{};  // arrival of record 0 of this count
  Clock::time_point last_{};  // arrival of the last record
  double minOffsetNs_ = 0;    // the least delay seen: arrival − base − k·T
  // After a second without records: when they came again, and their least delay since.
  std::optional<Clock::time_point> gapEnded_;
  double sinceGapMinNs_ = 0;
  // The rate check, over blocks of records.
  std::int64_t blockStart_ = 0;
  Clock::time_point blockBegan_{};
  double blockMinNs_ = 0;
  std::optional<double> previousBlockMinNs_;
  std::optional<double> previousDriftNs_;  // the last block's drift, when it was off
};

}  // namespace leafdig::devices
