#include "leafdig/devices/transports/memory_serial_port.hpp"

#include <algorithm>
#include <deque>

namespace leafdig::devices {

struct MemorySerialLine::State {
  mutable std::mutex mutex;
  std::condition_variable cv;
  std::deque<std::uint8_t> incoming;
  std::string written;
  Responder responder;
  bool stalled = false;
  std::string failRead, failWrite;
  std::optional<DeviceError> refuse;
  int opens = 0;
  int generation = 0;  // a port of an older open is dead once the line broke
  bool broken = false;
  std::optional<SerialSettings> settings;
  bool dtr = true;
};

class MemorySerialPort final : public SerialPort {
 public:
  MemorySerialPort(std::shared_ptr<MemorySerialLine::State> state, std::string path, int generation)
      : state_(std::move(state)), path_(std::move(path)), generation_(generation) {}

  std::vector<std::uint8_t> read(std::size_t max, std::chrono::milliseconds timeout) override {
    std::unique_lock lock(state_->mutex);
    checkAlive(state_->failRead);
    state_->cv.wait_for(lock, timeout, [&] {
      return !state_->failRead.empty() || state_->generation != generation_ ||
             (!state_->stalled && !state_->incoming.empty());
    });
    checkAlive(state_->failRead);
    std::vector<std::uint8_t> out;
    if (state_->stalled) return out;
    const std::size_t n = std::min(max, state_->incoming.size());
    out.assign(state_->incoming.begin(), state_->incoming.begin() + static_cast<std::ptrdiff_t>(n));
    state_->incoming.erase(state_->incoming.begin(), state_->incoming.begin() + static_cast<std::ptrdiff_t>(n));
    return out;
  }

  void write(const std::uint8_t* data, std::size_t size, std::chrono::milliseconds) override {
    std::string reply;
    MemorySerialLine::Responder responder;
    std::string text(reinterpret_cast<const char*>(data), size);
    {
      std::lock_guard lock(state_->mutex);
      checkAlive(state_->failWrite);
      if (state_->stalled) return;
      state_->written += text;
      responder = state_->responder;
    }
    if (responder) reply = responder(text);  // outside the lock: it may call feed()
    if (!reply.empty()) {
      std::lock_guard lock(state_->mutex);
      state_->incoming.insert(state_->incoming.end(), reply.begin(), reply.end());
    }
    state_->cv.notify_all();
  }

  void setSettings(const SerialSettings& settings) override {
    std::lock_guard lock(state_->mutex);
    state_->settings = settings;
  }
  [[nodiscard]] SerialSettings settings() const override {
    std::lock_guard lock(state_->mutex);
    return state_->settings.value_or(SerialSettings{});
  }
  void flushInput() override {
    std::lock_guard lock(state_->mutex);
    state_->incoming.clear();
  }
  void setDtr(bool on) override {
    std::lock_guard lock(state_->mutex);
    state_->dtr = on;
  }
  [[nodiscard]] std::string path() const override { return path_; }

 private:
  // Throws (with the lock held by the caller) when the line broke or this port is stale.
  void checkAlive(std::string& failure) {
    if (!failure.empty()) {
      const std::string message = path_ + ": " + failure;
      failure.clear();
      state_->broken = true;
      throw DeviceError(DeviceErrorKind::Io, message, "reconnect the cable; leafdig reconnects by itself");
    }
    if (state_->broken || state_->generation != generation_)
      throw DeviceError(DeviceErrorKind::Io, path_ + ": the device went away", "reconnect the cable");
  }

  std::shared_ptr<MemorySerialLine::State> state_;
  std::string path_;
  int generation_;
};

MemorySerialLine::MemorySerialLine() : state_(std::make_shared<State>()) {}

void MemorySerialLine::feed(const std::string& bytes) {
  {
    std::lock_guard lock(state_->mutex);
    state_->incoming.insert(state_->incoming.end(), bytes.begin(), bytes.end());
  }
  state_->cv.notify_all();
}

void MemorySerialLine::respond(Responder responder) {
  std::lock_guard lock(state_->mutex);
  state_->responder = std::move(responder);
}

void MemorySerialLine::stall(bool on) {
  {
    std::lock_guard lock(state_->mutex);
    state_->stalled = on;
  }
  state_->cv.notify_all();
}

void MemorySerialLine::failNextRead(const std::string& message) {
  {
    std::lock_guard lock(state_->mutex);
    state_->failRead = message;
  }
  state_->cv.notify_all();
}

void MemorySerialLine::failNextWrite(const std::string& message) {
  std::lock_guard lock(state_->mutex);
  state_->failWrite = message;
}

void MemorySerialLine::refuseOpen(DeviceErrorKind kind, const std::string& message, const std::string& remedy) {
  std::lock_guard lock(state_->mutex);
  state_->refuse = DeviceError(kind, message, remedy);
}

void MemorySerialLine::allowOpen() {
  std::lock_guard lock(state_->mutex);
  state_->refuse.reset();
}

std::string MemorySerialLine::written() const {
  std::lock_guard lock(state_->mutex);
  return state_->written;
}

int MemorySerialLine::opens() const {
  std::lock_guard lock(state_->mutex);
  return state_->opens;
}

std::optional<SerialSettings> MemorySerialLine::settings() const {
  std::lock_guard lock(state_->mutex);
  return state_->settings;
}

bool MemorySerialLine::dtr() const {
  std::lock_guard lock(state_->mutex);
  return state_->dtr;
}

MemorySerialLine::Opener MemorySerialLine::opener() {
  std::shared_ptr<State> state = state_;
  return [state](const std::string& path, const SerialSettings& settings) -> std::unique_ptr<SerialPort> {
    std::lock_guard lock(state->mutex);
    if (state->refuse) throw *state->refuse;
    // A reopen loses what the device sent to the old port, as a real replug does; bytes fed
    // before the first open wait for it.
    if (state->opens > 0) state->incoming.clear();
    ++state->opens;
    ++state->generation;  // ports of earlier opens are dead
    state->broken = false;
    state->failRead.clear();
    state->failWrite.clear();
    state->settings = settings;
    return std::make_unique<MemorySerialPort>(state, path, state->generation);
  };
}

}  // namespace leafdig::devices
