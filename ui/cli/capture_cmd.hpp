// leafdig capture, leafdig sessions list|show|verify|resume|approve|reject|correct|export, leafdig demo.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace leafdig::cli {

struct CaptureOptions {
  std::string db;       // a station's SQLite file, or (sessions list/show/…) a postgresql:// URL
  std::string station;  // --station: this station's id (default: settings file, else host name)
  bool json = false;
  // capture
  std::string project = "default", plant = "plant-1", digitizer, caliper, mode = "standard", order = "sequential",
              operatorName = "technician";
  int leafPosition = 1;
  std::string leafType;
  std::string serration;               // the leaf's declared margin teeth ("" : not declared)
  std::optional<double> toothDepthMm;  // their depth
  bool board = false;
  bool referenceReceiver = false;               // receiver 2 on the leaf's board: the digitizer spec's ",reference=2"
  double potTurnDeg = 0;                        // simulation: the board turns by this under the reference receiver
  std::optional<double> relocationToleranceMm;  // --relocation-tolerance: a new session's
  int relocateSourceAfter = 0;                  // simulation: the transmitter moves after this many points (0: never)
  // simulation
  bool simulate = false, noMistakes = false;
  std::string markers, faults, caliperFaults;
  std::string synth;                    // a synthetic leaf (synth_cmd.hpp: parseSynthSpec)
  std::optional<double> stylusNoiseMm;  // the simulated stylus's noise per axis
  std::uint64_t seed = 1;
  std::optional<double> speed;  // not given: 1 for a new capture, a resumed one's own, 8 for the demo
  double giveUpAfterS = 180;    // a simulated technician that gets nowhere this long is stopped
  // sessions
  std::int64_t id = 0;
  bool all = false;
  std::string who, why, out;
  std::vector<std::string> formats;
  int node = 0;  // sessions export --node: a plant session's full leaf alone
  std::string frame = "leaf", blade = "interp";
  // sessions correct
  std::string what;
  int row = 0, col = 0;
  std::vector<double> position;
  std::optional<double> value;
  // demo
  std::string samples;
  int synthLeaves = 2;
};

// How far a simulated capture got, for --give-up-after: anything the station took (but a device
// message) is progress, a refusal is not, and a pause is no lack of it. Thread-safe: the
// capture's thread tells it, a watcher asks it.
class GiveUpWatch {
 public:
  explicit GiveUpWatch(double seconds);
  void progressed();
  void refused(const std::string& reason);
  void at(const std::string& prompt, bool paused);  // the station's state now
  // The words to print once the technician got nowhere for the limit; empty before.
  [[nodiscard]] std::string overdue(const std::string& capture, std::int64_t id, const std::string& db) const;

 private:
  double seconds_;
  mutable std::mutex mutex_;
  std::chrono::steady_clock::time_point lastProgress_;
  std::string where_, lastRefusal_;
  int refusedSince_ = 0;
  bool paused_ = false;
};

class CommandTable;
// --relocation-tolerance (leaf and plant capture): 0.1–10 mm, given when a capture begins (a
// resumed one keeps its session's). Throws std::invalid_argument in words.
void checkRelocationTolerance(const std::optional<double>& mm, bool resuming);
// Registers `capture`, `demo` and `sessions list|show|verify|resume|approve|reject|correct|export`.
void addCaptureCommands(CLI::App& app, CommandTable& table);

}  // namespace leafdig::cli
