// Records stamped by the device's own clock where the protocol gives one (record_clock.hpp).
#include "leafdig/devices/codecs/record_clock.hpp"

#include <chrono>
#include <cmath>

namespace leafdig::devices {

RecordClock::RecordClock(double periodSeconds) : periodNs_(periodSeconds * 1e9) {}

Clock::time_point RecordClock::stamp(Clock::time_point arrival) {
  // Offsets in ns from the arrival of record 0 of this count.
  const auto since = [&](Clock::time_point t) { return std::chrono::duration<double, std::nano>(t - base_).count(); };
  const auto newCount = [&] {
    count_ = 0;
    base_ = arrival;
    last_ = arrival;
    minOffsetNs_ = 0.0;
    blockStart_ = 0;
    blockBegan_ = arrival;
    blockMinNs_ = 0.0;
    previousBlockMinNs_.reset();
    return arrival;
  };
  // Records missing: nothing for more than a second (an unplug, a stall, a reset). A delivery
  // burst is shorter: its records are all there, only late.
  if (count_ < 0 || arrival - last_ > std::chrono::duration<double, std::nano>(std::max(1e9, 120.0 * periodNs_)))
    return newCount();
  last_ = arrival;
  ++count_;
  const double offset = since(arrival) - static_cast<double>(count_) * periodNs_;
  minOffsetNs_ = std::min(minOffsetNs_, offset);  // the least-delayed record sets the anchor
  // The rate check: the least delay of each block (2.5 s and 256 records at least, longer than
  // any burst); two blocks whose least delays drift apart by more than 2 % of a period per
  // record mean the stream runs at another rate.
  blockMinNs_ = count_ - blockStart_ == 1 ? offset : std::min(blockMinNs_, offset);
  if (count_ - blockStart_ >= 256 && arrival - blockBegan_ >= std::chrono::milliseconds(2500)) {
    if (previousBlockMinNs_) {
      const double drift = (blockMinNs_ - *previousBlockMinNs_) / static_cast<double>(count_ - blockStart_);
      if (std::abs(drift) > 0.02 * periodNs_) {
        periodNs_ += drift;
        return newCount();
      }
    }
    previousBlockMinNs_ = blockMinNs_;
    blockStart_ = count_;
    blockBegan_ = arrival;
  }
  return base_ + std::chrono::duration_cast<Clock::duration>(
                     std::chrono::duration<double, std::nano>(minOffsetNs_ + static_cast<double>(count_) * periodNs_));
}

}  // namespace leafdig::devices
