#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "leafdig/devices/errors.hpp"
#include "leafdig/devices/record_clock.hpp"
#include "leafdig/devices/sample.hpp"
#include "leafdig/devices/serial_port.hpp"

namespace leafdig::devices {

std::string printableRaw(std::string_view raw, bool keepLineEnds) {
  std::string out;
  out.reserve(raw.size() + 8);
  for (char c : raw) {
    const auto u = static_cast<unsigned char>(c);
    if (keepLineEnds && (c == '\r' || c == '\n' || c == '\t')) {
      out += c;
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\\') {
      out += "\\\\";
    } else if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    }
  }
  return out;
}

const char* toString(DeviceErrorKind kind) {
  switch (kind) {
    case DeviceErrorKind::NotFound: return "not found";
    case DeviceErrorKind::Busy: return "busy";
    case DeviceErrorKind::Permission: return "permission denied";
    case DeviceErrorKind::Io: return "I/O error";
    case DeviceErrorKind::Protocol: return "protocol error";
    case DeviceErrorKind::Timeout: return "timeout";
    case DeviceErrorKind::Unsupported: return "unsupported";
    case DeviceErrorKind::Config: return "bad configuration";
  }
  return "error";
}

DeviceError errorFromErrno(int err, const std::string& action, const std::string& path) {
  const std::string what = action + " " + path + ": " + std::strerror(err);
  switch (err) {
    case ENOENT:
    case ENODEV:
    case ENXIO:
      return {DeviceErrorKind::NotFound, what,
              "check that the device is plugged in and the path is right ('leafdig devices "
              "list' shows the ports this machine has)"};
    case EBUSY:
    case EWOULDBLOCK:
      return {DeviceErrorKind::Busy, what,
              "another program holds " + path +
                  ": close it (vendor tools such as PiMgr, a terminal program, another leafdig) "
                  "and try again"};
    case EACCES:
    case EPERM:
      return {DeviceErrorKind::Permission, what,
              "install the udev rule (sudo cmake --install build/release && sudo udevadm "
              "control --reload && sudo udevadm trigger) or add yourself to the 'dialout' "
              "group (sudo usermod -aG dialout $USER, then log in again); 'leafdig doctor' "
              "checks both"};
    case EIO: return {DeviceErrorKind::Io, what, "the device went away: check the cable and power"};
    default: return {DeviceErrorKind::Io, what, "check the cable and the device's power"};
  }
}

std::string describe(const SerialSettings& s) {
  const char parity = s.parity == Parity::None ? 'N' : s.parity == Parity::Even ? 'E' : 'O';
  return std::to_string(s.baud) + " " + std::to_string(s.dataBits) + parity + std::to_string(s.stopBits) +
         (s.rtsCts ? " RTS/CTS" : "");
}

}  // namespace leafdig::devices

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
