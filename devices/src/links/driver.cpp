#include "leafdig/devices/links/driver.hpp"

#include <cmath>
#include <utility>

#include "leafdig/names/name_table.hpp"

namespace leafdig::devices {

namespace {
constexpr NameTable<LinkState, 5> kLinkStates{{{LinkState::Disconnected, "disconnected"},
                                               {LinkState::Connecting, "connecting"},
                                               {LinkState::Streaming, "streaming"},
                                               {LinkState::Warning, "warning"},
                                               {LinkState::Error, "error"}}};
}  // namespace

const char* toString(LinkState s) {
  return nameIn(kLinkStates, s);
}

namespace {
double distance(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}
DecodeStats add(const DecodeStats& a, const DecodeStats& b) {
  return {a.records + b.records, a.dropped + b.dropped, a.discardedBytes + b.discardedBytes,
          a.statusWarnings + b.statusWarnings, a.replies + b.replies};
}
}  // namespace

// ---- StylusFilter -------------------------------------------------------------------------
void StylusFilter::push(StylusSample s, std::vector<StylusSample>& out) {
  if (!window_.empty() && window_.back().station != s.station) {
    // Several stations interleave: filter only station by station (keep it simple: pass
    // other stations through unfiltered).
    out.push_back(std::move(s));
    return;
  }
  window_.push_back(std::move(s));
  if (window_.size() < 3) return;  // a sample is judged once both neighbours are known
  StylusSample& prev = window_[0];
  StylusSample& cur = window_[1];
  const StylusSample& next = window_[2];
  Vec3 mid{};
  for (std::size_t k = 0; k < 3; ++k) mid[k] = 0.5 * (prev.positionMm[k] + next.positionMm[k]);
  const bool spike = distance(cur.positionMm, mid) > spikeMm_;
  if (spike) {
    ++rejected_;
  } else {
    // Debounce the button: it changes only when two consecutive kept samples agree.
    if (cur.button != button_) {
      if (agree_ > 0 && candidate_ == cur.button) {
        button_ = cur.button;
        agree_ = 0;
      } else {
        candidate_ = cur.button;
        agree_ = 1;
      }
    } else {
      agree_ = 0;
    }
    StylusSample copy = cur;
    copy.button = button_;
    out.push_back(std::move(copy));
  }
  window_.pop_front();
}

void StylusFilter::reset() {
  window_.clear();
  agree_ = 0;
  // The button is released by a reconnect: a press must be seen again after it.
  button_ = false;
  candidate_ = false;
}

// ---- Driver -------------------------------------------------------------------------------
Driver::Driver(std::unique_ptr<DeviceLink> link, Callbacks callbacks, DriverOptions options)
    : link_(std::move(link)), callbacks_(std::move(callbacks)), options_(options), filter_(options.spikeMm) {
  status_.device = link_->name();
  status_.where = link_->where();
  status_.message = "not started";
}

Driver::~Driver() {
  stop();
}

void Driver::start() {
  if (thread_.joinable()) return;
  stop_ = false;
  thread_ = std::thread([this] { run(); });
}

void Driver::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void Driver::trigger() {
  trigger_ = true;
}

DeviceStatus Driver::status() const {
  std::lock_guard lock(mutex_);
  DeviceStatus s = status_;
  if (lastEvent_ != Clock::time_point{})
    s.lastSampleAgeS = std::chrono::duration<double>(Clock::now() - lastEvent_).count();
  return s;
}

void Driver::setState(LinkState state, std::string message, std::string remedy) {
  DeviceStatus copy;
  {
    std::lock_guard lock(mutex_);
    if (status_.state == state && status_.message == message) return;
    status_.state = state;
    status_.message = std::move(message);
    status_.remedy = std::move(remedy);
    copy = status_;
  }
  if (callbacks_.onStatus) callbacks_.onStatus(copy);
}

// The I/O thread: connect (with back-off), then pump the link — poll, decode, deliver,
// rate, warnings, stall — until stopped. An I/O error drops the connection and the loop
// connects again.
void Driver::run() {
  connected_ = false;
  retry_ = options_.retryMin;
  lastPoll_ = Clock::now();
  while (!stop_) {
    if (!connected_ && !connect()) {
      waitBeforeRetry();
      continue;
    }
    try {
      pollIfDue();
      events_.clear();
      link_->pump(std::chrono::milliseconds(50), events_);
      const auto now = Clock::now();
      if (const std::uint64_t records = link_->stats().records; records != recordsHeard_ || !events_.empty()) {
        recordsHeard_ = records;
        lastHeard_ = now;
      }
      recordDelivery(deliver(), now);
      reportWarningChange();
      reinitialiseIfStalled(now);
    } catch (const DeviceError& e) {
      dropConnection();
      setState(LinkState::Disconnected, e.what(), e.remedy());
    }
  }
  if (connected_) link_->close();
  connected_ = false;
  setState(LinkState::Disconnected, "stopped");
}

bool Driver::connect() {
  setState(LinkState::Connecting, "connecting to " + link_->name() + " on " + link_->where());
  try {
    link_->open();
  } catch (const DeviceError& e) {
    link_->close();
    // Gone or not there yet is a disconnection (it may come back); the rest needs the user.
    const bool absent = e.kind() == DeviceErrorKind::Io || e.kind() == DeviceErrorKind::NotFound;
    setState(absent ? LinkState::Disconnected : LinkState::Error, e.what(), e.remedy());
    return false;
  }
  connected_ = true;
  retry_ = options_.retryMin;
  filter_.reset();
  streamBegins_ = true;
  {
    std::lock_guard lock(mutex_);
    lastEvent_ = Clock::now();
  }
  lastHeard_ = Clock::now();
  recordsHeard_ = link_->stats().records;
  setState(LinkState::Streaming, link_->name() + " ready on " + link_->where());
  return true;
}

void Driver::waitBeforeRetry() {
  using std::chrono::milliseconds;
  for (auto waited = milliseconds(0); waited < retry_ && !stop_; waited += milliseconds(20))
    std::this_thread::sleep_for(milliseconds(20));
  retry_ = std::min(retry_ * 2, options_.retryMax);
}

void Driver::pollIfDue() {
  if (options_.pollEvery.count() > 0 && Clock::now() - lastPoll_ >= options_.pollEvery) {
    lastPoll_ = Clock::now();
    trigger_ = true;
  }
  if (trigger_.exchange(false)) link_->trigger();
}

std::size_t Driver::deliver() {
  std::size_t delivered = 0;
  // The first stylus sample of a connection says so: a press under way before it was cut.
  const auto mark = [&](StylusSample& s) { s.streamBegins = std::exchange(streamBegins_, false); };
  for (auto& ev : events_) {
    if (auto* s = std::get_if<StylusSample>(&ev); s && options_.filterStylus) {
      kept_.clear();
      filter_.push(std::move(*s), kept_);
      for (auto& k : kept_) {
        mark(k);
        if (callbacks_.onEvent) callbacks_.onEvent(DeviceEvent(std::move(k)));
        ++delivered;
      }
    } else {
      if (auto* u = std::get_if<StylusSample>(&ev)) mark(*u);
      if (callbacks_.onEvent) callbacks_.onEvent(ev);
      ++delivered;
    }
  }
  return delivered;
}

void Driver::recordDelivery(std::size_t delivered, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  if (!events_.empty()) lastEvent_ = now;
  for (std::size_t i = 0; i < delivered; ++i) recent_.push_back(now);
  while (!recent_.empty() && now - recent_.front() > std::chrono::seconds(1)) recent_.pop_front();
  status_.rateHz = static_cast<double>(recent_.size());
  status_.stats = add(previousStats_, link_->stats());
  status_.filtered = filter_.rejected();
}

void Driver::reportWarningChange() {
  const std::string warning = link_->warning();
  if (warning == lastWarning_) return;
  lastWarning_ = warning;
  if (!warning.empty())
    setState(LinkState::Warning, warning, link_->warningRemedy());
  else
    setState(LinkState::Streaming, link_->name() + " streaming on " + link_->where());
}

// A streaming device silent too long is re-initialised: that one path recovers resets,
// stalls and a FASTRAK knocked out of continuous mode.
void Driver::reinitialiseIfStalled(Clock::time_point now) {
  if (!link_->streams() || now - lastHeard_ <= link_->stallTimeout()) return;
  const auto silentMs = std::chrono::duration_cast<std::chrono::milliseconds>(now - lastHeard_).count();
  setState(LinkState::Warning, link_->name() + " sent no data for " + std::to_string(silentMs) + " ms: re-initialising",
           "if this repeats, check the cable and that the device is powered");
  dropConnection();
}

// Drops the connection (unplug, stall): keeps the codec's counters, counts a reconnect.
void Driver::dropConnection() {
  previousStats_ = add(previousStats_, link_->stats());
  link_->close();
  connected_ = false;
  lastWarning_.clear();
  std::lock_guard lock(mutex_);
  ++status_.reconnects;
}

}  // namespace leafdig::devices
