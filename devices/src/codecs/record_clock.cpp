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
    previousDriftNs_.reset();
    gapEnded_.reset();
    return arrival;
  };
  // The stamp of record `count_`: the count at the rate from the least-delayed record.
  const auto counted = [&] {
    return base_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::nano>(
                       minOffsetNs_ + static_cast<double>(count_) * periodNs_));
  };
  if (count_ < 0) return newCount();
  // Nothing for more than a second: records lost (an unplug, a stall, a reset) — or a host that
  // did not read for that long (a starved PC) and now reads them all at once. Which one, the
  // stream shows within a second: records that were only late soon come as early as ever;
  // after a loss none does. Until then the count goes on, so a delivery burst keeps its timing.
  const bool gap = arrival - last_ > std::chrono::duration<double, std::nano>(std::max(1e9, 120.0 * periodNs_));
  last_ = arrival;
  ++count_;
  double offset = since(arrival) - static_cast<double>(count_) * periodNs_;
  if (gap) {
    gapEnded_ = arrival;
    sinceGapMinNs_ = offset;
  }
  if (gapEnded_) {
    sinceGapMinNs_ = std::min(sinceGapMinNs_, offset);
    if (sinceGapMinNs_ - minOffsetNs_ < 0.5e9) {
      gapEnded_.reset();  // the records were all there, late
    } else if (arrival - *gapEnded_ >= std::chrono::seconds(1)) {
      // Lost: the count takes up the stream where it now is (the least-delayed record since
      // the gap as late as the least-delayed before it).
      const auto lost = static_cast<std::int64_t>(std::llround((sinceGapMinNs_ - minOffsetNs_) / periodNs_));
      count_ += lost;
      offset -= static_cast<double>(lost) * periodNs_;
      gapEnded_.reset();
      blockStart_ = count_;
      blockBegan_ = arrival;
      previousBlockMinNs_.reset();
      previousDriftNs_.reset();
    } else {
      return counted();  // not yet known: timed by the count as it was
    }
  }
  minOffsetNs_ = std::min(minOffsetNs_, offset);  // the least-delayed record sets the anchor
  // The rate check: the least delay of each block (2.5 s and 256 records at least, longer than
  // any burst); two blocks whose least delays drift apart by more than 2 % of a period per
  // record mean the stream runs at another rate.
  blockMinNs_ = count_ - blockStart_ == 1 ? offset : std::min(blockMinNs_, offset);
  if (count_ - blockStart_ >= 256 && arrival - blockBegan_ >= std::chrono::milliseconds(2500)) {
    if (previousBlockMinNs_) {
      const double drift = (blockMinNs_ - *previousBlockMinNs_) / static_cast<double>(count_ - blockStart_);
      // Taken up when two blocks in a row agree (within a quarter): a busy host's delays come
      // and go, a rate is the same in every block.
      const bool off = std::abs(drift) > 0.02 * periodNs_;
      if (off && previousDriftNs_ && std::abs(drift - *previousDriftNs_) <= 0.25 * std::abs(drift)) {
        periodNs_ += (drift + *previousDriftNs_) / 2;
        return newCount();
      }
      if (off)
        previousDriftNs_ = drift;
      else
        previousDriftNs_.reset();
    }
    previousBlockMinNs_ = blockMinNs_;
    blockStart_ = count_;
    blockBegan_ = arrival;
  }
  return counted();
}

}  // namespace leafdig::devices
