// The emulator base: a pseudo-terminal, its stable symlink, the device loop, and fault
// injection on the way out.
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include "leafdig/devices/errors.hpp"
#include "leafdig/devices/sim/sim.hpp"
#include "transports/termios_speed.hpp"

namespace leafdig::devices::sim {
namespace {

double monotonicSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::atomic<int> counter{0};

}  // namespace

Emulator::Emulator(EmulatorOptions options) : options_(std::move(options)), rng_(options_.faults.seed) {}

Emulator::~Emulator() {
  // Subclasses stop the thread in their destructors (it calls their virtuals); this is a
  // last resort for a subclass that forgot.
  stop();
}

void Emulator::start() {
  if (thread_.joinable()) return;
  linkPath_ = options_.linkPath;
  if (linkPath_.empty())
    linkPath_ = "/tmp/leafdig-sim-" + kind() + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  if (!openPty()) {
    const int err = errno;
    // The stable link is made in a folder the user may have named (--link): say so when it
    // is that folder, not the pseudo-terminal, that failed.
    const std::string folder = linkPath_.find('/') == std::string::npos
                                   ? std::string(".")
                                   : linkPath_.substr(0, std::max<std::size_t>(1, linkPath_.rfind('/')));
    if (::access(folder.c_str(), W_OK) != 0)
      throw DeviceError(options_.linkPath.empty() ? DeviceErrorKind::Io : DeviceErrorKind::Config,
                        "cannot make the link " + linkPath_ +
                            " to the simulator's pseudo-terminal: " + std::string(std::strerror(err)),
                        "give --link a path in a folder that exists and that you may write to");
    throw DeviceError(DeviceErrorKind::Unsupported,
                      "cannot create a pseudo-terminal: " + std::string(std::strerror(err)),
                      "check that /dev/ptmx exists and /dev/pts is mounted");
  }
  powerOn();
  start_ = monotonicSeconds();
  stop_ = false;
  thread_ = std::thread([this] { run(); });
}

void Emulator::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  std::lock_guard lock(mutex_);
  if (master_ >= 0) {
    ::close(master_);
    master_ = -1;
    ::unlink(linkPath_.c_str());
  }
}

std::string Emulator::path() const {
  return linkPath_;
}
std::string Emulator::ptyPath() const {
  std::lock_guard lock(mutex_);
  return ptyPath_;
}
FaultLog Emulator::faultLog() const {
  std::lock_guard lock(mutex_);
  return log_;
}
std::vector<SentRecord> Emulator::sentRecords() const {
  std::lock_guard lock(mutex_);
  return sent_;
}
std::uint64_t Emulator::recordsSent() const {
  std::lock_guard lock(mutex_);
  return log_.records;
}
void Emulator::unplugFor(double seconds) {
  unplugRequest_ = seconds;
}
double Emulator::now() const {
  return monotonicSeconds() - start_;
}

bool Emulator::openPty() {
  const int m = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (m < 0) return false;
  char name[128];
  if (::grantpt(m) != 0 || ::unlockpt(m) != 0 || ::ptsname_r(m, name, sizeof name) != 0) {
    ::close(m);
    return false;
  }
  termios t{};
  if (::tcgetattr(m, &t) == 0) {  // raw from the start: no echo, no line editing
    ::cfmakeraw(&t);
    (void)::tcsetattr(m, TCSANOW, &t);
  }
  const std::string tmp = linkPath_ + ".new";
  ::unlink(tmp.c_str());
  if (::symlink(name, tmp.c_str()) != 0 || ::rename(tmp.c_str(), linkPath_.c_str()) != 0) {
    ::close(m);
    return false;
  }
  std::lock_guard lock(mutex_);
  master_ = m;
  ptyPath_ = name;
  return true;
}

void Emulator::closePty() {
  std::lock_guard lock(mutex_);
  if (master_ >= 0) ::close(master_);
  master_ = -1;
  ::unlink(linkPath_.c_str());
}

bool Emulator::baudMismatch() const {
  const int want = options_.faults.deviceBaud > 0 ? options_.faults.deviceBaud : defaultBaud();
  if (want <= 0 || master_ < 0) return false;
  termios t{};
  if (::tcgetattr(master_, &t) != 0) return false;  // on Linux this is the slave's termios
  return ::cfgetospeed(&t) != detail::termiosSpeed(want).value_or(B0);
}

std::string Emulator::garble(const std::string& bytes) {
  // What a UART at the wrong rate delivers: framing errors, bytes that mean nothing.
  std::string out;
  std::uniform_int_distribution<int> b(0x80, 0xff);
  for (std::size_t i = 0; i < bytes.size(); i += 2) out += static_cast<char>(b(rng_));
  std::lock_guard lock(mutex_);
  log_.garbledBytes += out.size();
  return out;
}

void Emulator::writeAll(const std::string& raw) {
  const std::string bytes = baudMismatch() ? garble(raw) : raw;
  std::size_t off = 0;
  while (off < bytes.size() && !stop_) {
    const ssize_t n = ::write(master_, bytes.data() + off, bytes.size() - off);
    if (n > 0) {
      off += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) return;
    pollfd p{master_, POLLOUT, 0};
    const int r = ::poll(&p, 1, 100);
    if (r > 0 && (p.revents & POLLHUP) && !(p.revents & POLLOUT)) return;  // nobody listening
  }
}

void Emulator::sendReply(const std::string& bytes) {
  if (master_ >= 0) writeAll(bytes);
}

Emulator::RecordFaults Emulator::beginRecord() {
  RecordFaults r;
  const FaultPlan& f = options_.faults;
  const double t = now();
  if (t < stalledUntil_) {
    r.skip = true;
    return r;
  }
  std::uniform_real_distribution<double> u(0.0, 1.0);
  if (f.unplug > 0 && u(rng_) < f.unplug) {
    {
      std::lock_guard lock(mutex_);
      ++log_.unplugs;
    }
    unplugRequest_ = f.unplugSeconds;
    r.skip = true;
    return r;
  }
  if (f.reset > 0 && u(rng_) < f.reset) {
    {
      std::lock_guard lock(mutex_);
      ++log_.resets;
    }
    sendReply("\r\n*** " + kind() + " power-up: self-test passed ***\r\n");
    powerOn();
    r.skip = true;
    return r;
  }
  if (f.stall > 0 && u(rng_) < f.stall) {
    std::lock_guard lock(mutex_);
    ++log_.stalls;
    stalledUntil_ = t + f.stallSeconds;
    r.skip = true;
    return r;
  }
  if (f.status > 0 && u(rng_) < f.status) {
    std::lock_guard lock(mutex_);
    ++log_.statusLetters;
    r.status = f.statusLetter;
  }
  return r;
}

void Emulator::sendRecord(const std::string& bytes, const Vec3& truth, bool button) {
  const FaultPlan& f = options_.faults;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::string out = bytes;
  bool garbage = false, flip = false, cut = false;
  if (f.garbage > 0 && u(rng_) < f.garbage) {
    std::uniform_int_distribution<int> len(1, 24), any(0, 255);
    std::string g;
    for (int i = len(rng_); i > 0; --i) g += static_cast<char>(any(rng_));
    out = g + out;
    garbage = true;
  }
  if (f.bitflip > 0 && u(rng_) < f.bitflip && !bytes.empty()) {
    std::uniform_int_distribution<std::size_t> pos(out.size() - bytes.size(), out.size() - 1);
    std::uniform_int_distribution<int> bit(0, 7);
    out[pos(rng_)] ^= static_cast<char>(1 << bit(rng_));
    flip = true;
  }
  if (f.truncate > 0 && u(rng_) < f.truncate && bytes.size() > 1) {
    std::uniform_int_distribution<std::size_t> keep(1, bytes.size() - 1);
    out.resize(out.size() - bytes.size() + keep(rng_));
    cut = true;
  }
  {
    std::lock_guard lock(mutex_);
    ++log_.records;
    log_.garbage += garbage;
    log_.bitflips += flip;
    log_.truncated += cut;
    if (logRecords_) sent_.push_back({bytes, out, truth, button});
  }
  // A delay: the records keep being made on time but reach the host later, all at once.
  const double t = now();
  if (f.delay > 0 && heldUntil_ < t && u(rng_) < f.delay) {
    std::lock_guard lock(mutex_);
    ++log_.delays;
    heldUntil_ = t + f.delaySeconds;
  }
  if (t < heldUntil_) {
    held_ += out;
    return;
  }
  if (!held_.empty()) {
    out = held_ + out;
    held_.clear();
  }
  sendReply(out);
}

void Emulator::run() {
  double nextTick = 0;
  std::uint64_t k = 0;
  const double rate = options_.rateHz > 0 ? options_.rateHz : nativeRateHz();
  char buf[4096];
  while (!stop_) {
    if (const double s = unplugRequest_.exchange(0); s > 0) {
      closePty();
      const double until = now() + s;
      while (!stop_ && now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      if (stop_ || !openPty()) break;
      powerOn();
      nextTick = now();  // the device was off: no records are owed for that time
      continue;
    }
    // Wait for the host's bytes until the next record is due, to the nanosecond: at the
    // simulations' rates (up to 960 Hz) a record is due in less than a millisecond, and a
    // poll() timeout in whole milliseconds would spin the thread on a zero timeout.
    const double t = now();
    double waitS = 0.020;
    if (streaming()) waitS = options_.burst ? 0.0 : std::clamp(nextTick - t, 0.0, 0.020);
    const auto waitNs = static_cast<long>(waitS * 1e9);
    const timespec timeout{0, waitNs};
    const int timeoutMs = static_cast<int>(waitNs / 1000000);
    pollfd p{master_, POLLIN, 0};
    const int r = ::ppoll(&p, 1, &timeout, nullptr);
    if (r > 0 && (p.revents & POLLIN)) {
      const ssize_t n = ::read(master_, buf, sizeof buf);
      if (n > 0) {
        if (baudMismatch()) {
          std::lock_guard lock(mutex_);
          log_.garbledBytes += static_cast<std::uint64_t>(n);
        } else if (now() >= stalledUntil_) {
          onInput(std::string(buf, static_cast<std::size_t>(n)));
        }
      }
    } else if (r > 0 && (p.revents & POLLHUP)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(timeoutMs > 0 ? timeoutMs : 2));  // no host yet
    }
    onTick(now());
    if (!held_.empty() && now() >= heldUntil_) {  // a delay is over: the burst goes out
      std::string burst;
      burst.swap(held_);
      sendReply(burst);
    }
    if (!streaming()) {
      nextTick = now();  // records only while streaming: none are owed for a quiet spell
      continue;
    }
    if (options_.burst) {
      if (options_.burstRecords > 0 && recordsSent() >= options_.burstRecords) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        continue;
      }
      for (int i = 0; i < 32; ++i, ++k) {
        if (options_.burstRecords > 0 && recordsSent() >= options_.burstRecords) break;
        produce(static_cast<double>(k) / rate, k);
      }
      continue;
    }
    // A streaming device makes its records on its own clock, whatever the host does: an
    // emulator woken late (a busy machine) makes every record it owes, each for its own instant
    // (the stylus as it was then), as the device would have made them and its cable delivered
    // them late — the host times them by their count (RecordClock). It never skips: a skip
    // would be a pause of the device's clock, which no digitizer has; only an unplug (above)
    // starts the clock again. At most 256 at a time, so the host's bytes are still read.
    const double tn = now();
    for (int owed = 0; tn >= nextTick && owed < 256; ++owed) {
      produce(nextTick, k);
      ++k;
      nextTick += 1.0 / rate;
    }
  }
}

}  // namespace leafdig::devices::sim
