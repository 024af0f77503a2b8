// Simulated devices (shipped, first-class): emulators that speak the real wire protocols on
// pseudo-terminals, HID report generators behind HidDevice, the USB-ITN vendor mode behind
// UsbVendorDevice, a virtual stylus and caliper to drive them, and scriptable faults.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "leafdig/devices/sample.hpp"
#include "leafdig/devices/transports/hid.hpp"
#include "leafdig/devices/transports/usb.hpp"

namespace leafdig::devices::sim {

// ---- faults -------------------------------------------------------------------------------
// Per-record probabilities, plus durations. Spec: comma-separated key=value, e.g.
//   "garbage=0.01,bitflip=0.005,truncate=0.01,stall=0.002:1.5,reset=0.001,unplug=0.001:0.5,
//    status=0.01:x,baud=9600,seed=7"
// stall=P:S stalls S seconds; unplug=P:S stays unplugged S seconds; delay=P:S holds its
// output back S seconds (records go on being made on time) and then delivers them in one
// burst, as a busy host or a USB-serial adapter's latency does; status=P:L sets the
// status letter L; baud=N makes the device run at N baud (a host at another rate sees
// garbage and is not understood).
struct FaultPlan {
  double garbage = 0, bitflip = 0, truncate = 0, stall = 0, reset = 0, unplug = 0, status = 0, delay = 0;
  double stallSeconds = 1.5, unplugSeconds = 0.5, delaySeconds = 0.5;
  char statusLetter = 'x';
  int deviceBaud = 0;
  std::uint64_t seed = 1;
  [[nodiscard]] static FaultPlan parse(const std::string& spec);  // throws invalid_argument
  [[nodiscard]] bool any() const;
};

struct FaultLog {
  std::uint64_t records = 0, garbage = 0, bitflips = 0, truncated = 0, stalls = 0, resets = 0, unplugs = 0,
                statusLetters = 0, garbledBytes = 0, delays = 0;
};

// ---- virtual stylus and caliper -----------------------------------------------------------
// How the virtual hand holds the stylus (azimuth, elevation, roll in degrees), before its tremor.
inline constexpr Vec3 kHandOrientationDeg{10.0, -45.0, 0.0};

struct StylusOptions {
  double sigmaMm = 0.3;       // Gaussian noise per axis
  double tremorMm = 0.15;     // hand tremor amplitude (8-12 Hz)
  double travelS = 0.6;       // moving from one marker to the next
  double dwellS = 0.7;        // resting on a marker
  double pressAfterS = 0.15;  // the button goes down this long after arriving
  double pressS = 0.35;       // and stays down this long (FASTRAK switch cycle: 40 frames)
  std::uint64_t seed = 1;
  Vec3 offsetMm{0, 0, 0};  // where the leaf sits in the device frame
};

// Where the stylus is at emulator time t (seconds) for record k. Emulators ask this for
// every record they produce. Thread contract: at() is called from the emulator's thread.
class StylusMotion {
 public:
  struct State {
    Vec3 positionMm{};  // with noise and tremor
    Vec3 truthMm{};     // without
    Vec3 orientationDeg{};
    bool button = false;
    int target = -1;  // marker being pressed, -1 while moving
  };
  StylusMotion() = default;
  StylusMotion(const StylusMotion&) = default;
  StylusMotion& operator=(const StylusMotion&) = default;
  virtual ~StylusMotion() = default;
  [[nodiscard]] virtual State at(double t, std::uint64_t k) const = 0;
};

// Walks `targets` (marker positions, mm) in order, then starts over. Deterministic: the
// state at time t with noise index k is always the same.
class VirtualStylus final : public StylusMotion {
 public:
  explicit VirtualStylus(std::vector<Vec3> targetsMm, StylusOptions options = {});
  [[nodiscard]] State at(double t, std::uint64_t k) const override;
  [[nodiscard]] double period() const;  // one walk over all markers
  [[nodiscard]] const std::vector<Vec3>& targets() const { return targets_; }

 private:
  std::vector<Vec3> targets_;
  StylusOptions o_;
};

// A hand that the program moves: gestures are queued (from any thread) and performed one
// after the other on the device's clock — the emulator's record time `t`, scaled by `speed`
// (2 = twice as fast) — so a device whose records reach the host late, or in a burst, still
// reports each gesture as the hand made it; between gestures the stylus rests where it is,
// button up. Noise and tremor as VirtualStylus. Used by the virtual operator, which reacts to
// what the station says. One device samples it (its record times never go back).
class OperatorHand final : public StylusMotion {
 public:
  struct Gesture {
    Vec3 targetMm{};        // where to go (device frame, before the offset)
    double pressS = 0.35;   // button held this long once there (0: no press)
    double settleS = 0.45;  // still on the target before the press
    double travelS = 0.6;   // moving there (lifted off the leaf)
    // A pivot (a tip calibration, docs/devices.md, "The stylus tip"): while the button is held
    // the tip stays in the divot and the stylus tilts up to this many degrees (at least 60 % of
    // it), twice round; 0: held still.
    double pivotDeg = 0;
  };
  explicit OperatorHand(StylusOptions options = {}, double speed = 1.0);
  // Queues a gesture; it starts after the last one, and not before the latest record made.
  void perform(const Gesture& g);
  // True when the device has made the records of every queued gesture (the button is up
  // again in them).
  [[nodiscard]] bool idle() const;
  [[nodiscard]] State at(double t, std::uint64_t k) const override;

 private:
  StylusOptions o_;
  double speed_;
  mutable std::mutex mutex_;
  mutable std::deque<std::pair<double, Gesture>> queue_;  // start time, gesture (at() drops finished ones)
  mutable Vec3 restMm_{};
  mutable double seenUntil_ = 0;  // the latest record's time (scaled)
  double busyUntil_ = 0;
};

// A stylus whose sensor is not at its tip (a receiver in a pen, or a stylus whose factory offset
// the digitizer does not apply): the wrapped motion says where the tip is and how the stylus is
// turned, and the digitizer reports the sensor, at tip − R·tipMm (R: the stylus' orientation,
// tipMm: the tip in the sensor's frame). A hand beside the leaf tilts the stylus towards where it
// presses: with `tiltDegPerMm`, the azimuth turns by that much per mm of the tip's x and the
// elevation per mm of its y (each at most 30°), so a tip offset left uncorrected bends a leaf
// instead of only moving it. A zero tipMm reports the tip (the wrapped motion as it is).
class StylusSensor final : public StylusMotion {
 public:
  StylusSensor(std::shared_ptr<const StylusMotion> tip, Vec3 tipMm, double tiltDegPerMm = 0.1);
  [[nodiscard]] State at(double t, std::uint64_t k) const override;
  // Where the sensor is from a tip at `tipTruthMm` held as the hand holds it (kHandOrientationDeg,
  // leaning): −R·tipMm, what a station without the tip calibration sees the tip moved by.
  [[nodiscard]] Vec3 sensorFromTip(const Vec3& tipTruthMm) const;
  [[nodiscard]] const Vec3& tipMm() const { return tipMm_; }
  // R·v for the stylus held at `tipTruthMm` (the hand's orientation, leaning).
  [[nodiscard]] Vec3 turned(const Vec3& tipTruthMm, const Vec3& v) const;

 private:
  std::shared_ptr<const StylusMotion> tip_;
  Vec3 tipMm_;
  double tiltDegPerMm_;
};

struct CaliperOptions {
  double sigmaMm = 0.003;
  double resolutionMm = 0.001;  // Mitutoyo/Sylvac digital calipers
  std::uint64_t seed = 1;
};

// Returns the file's thicknesses in order (then starts over) with noise, rounded to the
// gauge's resolution. Thread-safe.
class VirtualCaliper {
 public:
  explicit VirtualCaliper(std::vector<double> thicknessMm, CaliperOptions options = {});
  double next();
  // The jaws now hold this thickness: next() returns it (with noise) until release().
  void hold(double thicknessMm);
  void release();
  [[nodiscard]] std::size_t count() const;
  [[nodiscard]] const std::vector<double>& truth() const { return values_; }

 private:
  std::vector<double> values_;
  CaliperOptions o_;
  mutable std::mutex mutex_;
  std::size_t index_ = 0;
  std::optional<double> held_;
  std::mt19937_64 rng_;
};

// ---- pseudo-terminal emulators ------------------------------------------------------------
struct EmulatorOptions {
  double rateHz = 0;               // records per second when streaming; 0: the device's own rate
  bool burst = false;              // as fast as the pty allows (long-stream tests)
  std::uint64_t burstRecords = 0;  // in burst mode: stop streaming after this many
  std::string linkPath;            // stable symlink to the current pty; default /tmp/leafdig-sim-*
  FaultPlan faults;
  double pressEveryS = 0;  // calipers: the operator presses DATA this often (0: never)
};

// One record as sent: the bytes before and after fault injection. For the tests.
struct SentRecord {
  std::string original, sent;
  Vec3 truthMm{};
  bool button = false;
};

// Runs a device on a pseudo-terminal, in its own thread. Unplug closes the pty and opens a
// new one after a pause; the symlink `path()` always points at the current one.
// Thread contract: start/stop/destroy from the owner; the accessors from any thread.
class Emulator {
 public:
  explicit Emulator(EmulatorOptions options);
  Emulator(const Emulator&) = delete;
  Emulator& operator=(const Emulator&) = delete;
  virtual ~Emulator();
  void start();
  void stop();
  [[nodiscard]] std::string path() const;     // the stable symlink
  [[nodiscard]] std::string ptyPath() const;  // the current /dev/pts/N
  [[nodiscard]] FaultLog faultLog() const;
  [[nodiscard]] std::vector<SentRecord> sentRecords() const;
  [[nodiscard]] std::uint64_t recordsSent() const;
  void unplugFor(double seconds);  // scripted unplug (any thread)
  // The operator presses the gauge's DATA button (any thread); digitizers ignore it.
  void pressData() { dataPresses_.fetch_add(1); }
  [[nodiscard]] virtual std::string kind() const = 0;

 protected:
  // Device behaviour, called on the emulator thread.
  virtual void onInput(const std::string& bytes) = 0;
  virtual bool streaming() const = 0;
  virtual double nativeRateHz() const = 0;
  virtual void produce(double t, std::uint64_t k) = 0;  // one streaming tick
  virtual void powerOn() = 0;                           // state after power-up / replug
  virtual void onTick(double /*t*/) {}                  // every loop (caliper button presses)
  [[nodiscard]] virtual int defaultBaud() const { return 0; }

  struct RecordFaults {
    bool skip = false;  // the device is stalled / unplugged / just reset
    char status = 0;    // status letter to report in this record (0: fine)
  };
  RecordFaults beginRecord();
  void sendRecord(const std::string& bytes, const Vec3& truth, bool button);
  void sendReply(const std::string& bytes);
  [[nodiscard]] double now() const;  // seconds since start
  [[nodiscard]] bool bursting() const { return options_.burst; }
  bool logRecords_ = true;

 private:
  void run();
  bool openPty();
  void closePty();
  void writeAll(const std::string& bytes);
  bool baudMismatch() const;
  std::string garble(const std::string& bytes);

  EmulatorOptions options_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<double> unplugRequest_{0};

 protected:
  std::atomic<int> dataPresses_{0};

 private:
  mutable std::mutex mutex_;
  int master_ = -1;
  std::string ptyPath_, linkPath_;
  FaultLog log_;
  std::vector<SentRecord> sent_;
  std::mt19937_64 rng_;
  double stalledUntil_ = -1;
  double heldUntil_ = -1;  // a delay fault: output held back until then, then sent at once
  std::string held_;
  double start_ = 0;
};

[[nodiscard]] std::unique_ptr<Emulator> makeFastrak(VirtualStylus stylus, EmulatorOptions options);
// With `reference`, a second receiver in socket 2 reports that motion's position and angles
// (a reference receiver fixed to the pot): both are active at power-up and share the 120 Hz.
[[nodiscard]] std::unique_ptr<Emulator> makeFastrak(std::shared_ptr<const StylusMotion> stylus, EmulatorOptions options,
                                                    std::shared_ptr<const StylusMotion> reference = nullptr);
[[nodiscard]] std::unique_ptr<Emulator> makePatriot(VirtualStylus stylus, EmulatorOptions options);
// With `reference`, a second sensor (port 2) reports that motion after sensor 1 in every frame.
[[nodiscard]] std::unique_ptr<Emulator> makePatriot(std::shared_ptr<const StylusMotion> stylus, EmulatorOptions options,
                                                    std::shared_ptr<const StylusMotion> reference = nullptr);
[[nodiscard]] std::unique_ptr<Emulator> makeLiberty(VirtualStylus stylus, EmulatorOptions options);
[[nodiscard]] std::unique_ptr<Emulator> makeLiberty(std::shared_ptr<const StylusMotion> stylus, EmulatorOptions options,
                                                    std::shared_ptr<const StylusMotion> reference = nullptr);
// The arm's base is the device origin; put the leaf within reach with StylusOptions::offsetMm
// (kMicroScribeLeafOffset is a good place).
[[nodiscard]] std::unique_ptr<Emulator> makeMicroScribe(VirtualStylus stylus, EmulatorOptions options);
[[nodiscard]] std::unique_ptr<Emulator> makeMicroScribe(std::shared_ptr<const StylusMotion> stylus,
                                                        EmulatorOptions options);
[[nodiscard]] std::unique_ptr<Emulator> makeSylvac(std::shared_ptr<VirtualCaliper> caliper, EmulatorOptions options);
[[nodiscard]] std::unique_ptr<Emulator> makeMitutoyo(std::shared_ptr<VirtualCaliper> caliper, EmulatorOptions options);
[[nodiscard]] std::unique_ptr<Emulator> makeUWave(std::shared_ptr<VirtualCaliper> caliper, EmulatorOptions options);
constexpr Vec3 kMicroScribeLeafOffset{380.0, 0.0, 0.0};

// ---- HID and USB back ends ----------------------------------------------------------------
struct HidGaugeOptions {
  bool keypad = false;    // digits from the numeric keypad
  bool comma = false;     // ',' as the decimal mark
  bool tab = false;       // Tab instead of Enter
  bool reportId = false;  // a report-ID byte before each report
  int decimals = 3;
};

// Types readings into a MemoryHidDevice as a keyboard-wedge gauge does.
class HidGaugeSimulator {
 public:
  HidGaugeSimulator(std::shared_ptr<MemoryHidDevice> device, std::shared_ptr<VirtualCaliper> caliper,
                    HidGaugeOptions options = {});
  // Types the next reading (press DATA); returns the text typed.
  std::string press();
  [[nodiscard]] static HidInfo usbItnInfo();  // 0fe7:4001 "USB-ITN"

 private:
  std::shared_ptr<MemoryHidDevice> device_;
  std::shared_ptr<VirtualCaliper> caliper_;
  HidGaugeOptions o_;
};

// Mitutoyo USB-ITN in vendor mode behind the libusb seam. Thread contract: the driver's
// thread calls the transfers; unplug/replug from any thread.
class UsbItnSimulator final : public UsbVendorDevice {
 public:
  explicit UsbItnSimulator(std::shared_ptr<VirtualCaliper> caliper);
  void controlOut(std::uint8_t rt, std::uint8_t req, std::uint16_t value, std::uint16_t index,
                  const std::vector<std::uint8_t>& data) override;
  std::vector<std::uint8_t> controlIn(std::uint8_t rt, std::uint8_t req, std::uint16_t value, std::uint16_t index,
                                      std::uint16_t length) override;
  std::vector<std::uint8_t> interruptIn(std::uint8_t endpoint, std::chrono::milliseconds timeout) override;
  [[nodiscard]] std::string describe() const override { return "usb:0fe7:4001 (simulated)"; }
  // Shared state, so a test can unplug "the cable" behind an open handle.
  struct Cable {
    std::mutex mutex;
    bool plugged = true;
    bool noGauge = false;  // the cable without a gauge: replies "911"
  };
  [[nodiscard]] std::shared_ptr<Cable> cable() const { return cable_; }
  void setCable(std::shared_ptr<Cable> c) { cable_ = std::move(c); }

 private:
  std::shared_ptr<VirtualCaliper> caliper_;
  std::shared_ptr<Cable> cable_ = std::make_shared<Cable>();
  bool vendorMode_ = false;
  std::deque<std::string> replies_;
};

}  // namespace leafdig::devices::sim
