// SerialPort over termios: any tty path, pseudo-terminals included.
#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>

#include "leafdig/devices/errors.hpp"
#include "leafdig/devices/transports/serial_port.hpp"
#include "transports/termios_speed.hpp"

namespace leafdig::devices {
namespace {

speed_t speedFor(int baud) {
  if (const auto sp = detail::termiosSpeed(baud)) return *sp;
  throw DeviceError(DeviceErrorKind::Config, "unsupported baud rate " + std::to_string(baud),
                    "use one of 1200 2400 4800 9600 19200 38400 57600 115200 230400 460800 921600");
}

class TtyPort final : public SerialPort {
 public:
  TtyPort(std::string path, const SerialSettings& settings) : path_(std::move(path)) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) throw errorFromErrno(errno, "cannot open", path_);
    if (!::isatty(fd_)) {
      ::close(fd_);
      throw DeviceError(DeviceErrorKind::Config, path_ + " is not a serial port (not a tty)",
                        "give the device's tty, e.g. /dev/ttyUSB0 ('leafdig devices list')");
    }
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      ::close(fd_);
      throw errorFromErrno(err == EWOULDBLOCK ? EBUSY : err, "cannot lock", path_);
    }
    (void)::ioctl(fd_, TIOCEXCL);  // other opens fail with EBUSY (root excepted)
    try {
      setSettings(settings);
    } catch (...) {
      ::close(fd_);
      throw;
    }
  }
  ~TtyPort() override {
    if (fd_ >= 0) {
      (void)::ioctl(fd_, TIOCNXCL);
      ::close(fd_);
    }
  }

  std::vector<std::uint8_t> read(std::size_t max, std::chrono::milliseconds timeout) override {
    pollfd p{fd_, POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(timeout.count()));
    if (r < 0) {
      if (errno == EINTR) return {};
      throw errorFromErrno(errno, "cannot read", path_);
    }
    if (r == 0) return {};
    std::vector<std::uint8_t> buf(max);
    const ssize_t n = ::read(fd_, buf.data(), max);
    if (n > 0) {
      buf.resize(static_cast<std::size_t>(n));
      return buf;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) return {};
    // POLLHUP with nothing to read, EOF or EIO: the other end is gone (unplug).
    throw DeviceError(
        DeviceErrorKind::Io,
        path_ + ": the device went away (read " + (n == 0 ? std::string("end of file") : std::string("failed")) + ")",
        "check the cable and the device's power; leafdig reconnects by itself");
  }

  void write(const std::uint8_t* data, std::size_t size, std::chrono::milliseconds timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (size > 0) {
      const ssize_t n = ::write(fd_, data, size);
      if (n > 0) {
        data += n;
        size -= static_cast<std::size_t>(n);
        continue;
      }
      if (n < 0 && errno != EAGAIN && errno != EINTR) throw errorFromErrno(errno, "cannot write to", path_);
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0)
        throw DeviceError(DeviceErrorKind::Timeout, path_ + ": write timed out",
                          "the device is not reading: check flow control and the cable");
      pollfd p{fd_, POLLOUT, 0};
      (void)::poll(&p, 1, static_cast<int>(left.count()));
    }
  }

  void setSettings(const SerialSettings& s) override {
    termios t{};
    if (::tcgetattr(fd_, &t) != 0) throw errorFromErrno(errno, "cannot read settings of", path_);
    ::cfmakeraw(&t);
    const speed_t sp = speedFor(s.baud);
    ::cfsetispeed(&t, sp);
    ::cfsetospeed(&t, sp);
    t.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARENB | PARODD | CSTOPB | CRTSCTS);
    if (s.dataBits == 7)
      t.c_cflag |= CS7;
    else if (s.dataBits == 8)
      t.c_cflag |= CS8;
    else
      throw DeviceError(DeviceErrorKind::Config, "unsupported data bits " + std::to_string(s.dataBits), "use 7 or 8");
    if (s.parity != Parity::None) t.c_cflag |= PARENB;
    if (s.parity == Parity::Odd) t.c_cflag |= PARODD;
    if (s.stopBits == 2) t.c_cflag |= CSTOPB;
    if (s.rtsCts) t.c_cflag |= CRTSCTS;
    t.c_cflag |= CLOCAL | CREAD;
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    if (::tcsetattr(fd_, TCSANOW, &t) != 0) {
      const int err = errno;
      if (err != EINVAL || !ptyAlreadyAsAsked(t)) throw errorFromErrno(err, "cannot configure", path_);
    }
    settings_ = s;
  }
  SerialSettings settings() const override { return settings_; }
  void flushInput() override { (void)::tcflush(fd_, TCIFLUSH); }
  void setDtr(bool on) override {
    int bit = TIOCM_DTR;
    (void)::ioctl(fd_, on ? TIOCMBIS : TIOCMBIC, &bit);  // ptys have no modem lines: ignored
  }
  std::string path() const override { return path_; }

 private:
  // A pseudo-terminal carries characters, not bits: the kernel keeps it at 8 data bits
  // without parity whatever is asked. Debian's glibc then fails tcsetattr with EINVAL when
  // the call changed nothing, which is what happens when a pty is opened a second time with
  // 7E2 (the Sylvac's framing): everything else is already as asked. That is success.
  bool ptyAlreadyAsAsked(const termios& asked) const {
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISCHR(st.st_mode)) return false;
    const unsigned maj = major(st.st_rdev);
    if (maj < kPtySlaveMajorFirst || maj > kPtySlaveMajorLast) return false;
    termios now{};
    if (::tcgetattr(fd_, &now) != 0) return false;
    const auto ignored = static_cast<tcflag_t>(CSIZE | PARENB | PARODD);
    return (now.c_cflag & ~ignored) == (asked.c_cflag & ~ignored) && now.c_iflag == asked.c_iflag &&
           now.c_oflag == asked.c_oflag && now.c_lflag == asked.c_lflag &&
           ::cfgetospeed(&now) == ::cfgetospeed(&asked) && now.c_cc[VMIN] == asked.c_cc[VMIN] &&
           now.c_cc[VTIME] == asked.c_cc[VTIME];
  }
  static constexpr unsigned kPtySlaveMajorFirst = 136;  // UNIX98_PTY_SLAVE_MAJOR … +7
  static constexpr unsigned kPtySlaveMajorLast = 143;

  std::string path_;
  int fd_ = -1;
  SerialSettings settings_;
};

}  // namespace

std::unique_ptr<SerialPort> openTtyPort(const std::string& path, const SerialSettings& settings) {
  return std::make_unique<TtyPort>(path, settings);
}

}  // namespace leafdig::devices
