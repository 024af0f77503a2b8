// A reference receiver (issue 29; docs/devices.md, "A reference receiver"): one receiver is the
// stylus, another is fixed to the pot or the board, and every stylus sample is expressed in the
// reference receiver's frame at that instant, so turning or nudging the pot changes nothing.
//
// Pairing: a tracker sends the stations of one output cycle in number order, so the stylus'
// record (station 1) is paired with the reference's record that follows it in the same cycle,
// before the next stylus record. A cycle whose reference record is missing (dropped, corrupt)
// has its stylus record withheld — never paired with another cycle's reference. A reference
// that misses `silentAfter` cycles in a row has stopped reporting; one that moves more than
// `jumpMm` or turns more than `jumpDeg` between two of its records has jumped (knocked, or
// slipped on the pot). Either pauses the stylus (nothing is delivered) with words until the
// reference has reported `steadyRecords` steady records again.
//
// Thread contract: one owner (the link's I/O thread).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/devices/pose.hpp"
#include "leafdig/devices/sample.hpp"

namespace leafdig::devices {

struct ReferenceOptions {
  int stylusStation = 1;
  int referenceStation = 2;
  double jumpMm = 10.0;  // between two records (1/60 s at a FASTRAK's two stations)
  double jumpDeg = 5.0;
  int silentAfter = 6;     // stylus cycles in a row without a reference record
  int steadyRecords = 30;  // steady reference records before the stylus flows again
};

class ReferenceFrame {
 public:
  struct Stats {
    std::uint64_t paired = 0;    // stylus samples delivered in the reference's frame
    std::uint64_t withheld = 0;  // stylus samples without a usable reference record
    std::uint64_t jumps = 0;     // the reference jumped
    std::uint64_t silences = 0;  // the reference stopped reporting
    std::uint64_t others = 0;    // records of other stations, ignored
  };
  explicit ReferenceFrame(ReferenceOptions options = {});
  // Takes every decoded record in arrival order; appends the stylus' samples, each in the
  // frame of the reference record of its cycle (its raw: both records), to `out`.
  void push(const StylusSample& s, std::vector<StylusSample>& out);
  // A new connection: nothing from before pairs with what comes.
  void reset();
  // Empty while the stylus flows; otherwise what is wrong in words, and what to do.
  [[nodiscard]] const std::string& problem() const { return problem_; }
  [[nodiscard]] const std::string& remedy() const { return remedy_; }
  [[nodiscard]] Stats stats() const { return stats_; }
  [[nodiscard]] const ReferenceOptions& options() const { return o_; }

 private:
  void onReference(const StylusSample& s, std::vector<StylusSample>& out);
  void pause(std::string problem, std::string remedy);
  ReferenceOptions o_;
  std::optional<StylusSample> pending_;  // this cycle's stylus record, waiting for its reference
  std::optional<ReceiverPose> last_;     // the reference's previous record
  int missed_ = 0, steady_ = 0;
  bool paused_ = false;
  std::string problem_, remedy_;
  Stats stats_;
};

}  // namespace leafdig::devices
