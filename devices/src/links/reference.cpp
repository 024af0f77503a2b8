// The reference receiver's pairing and checks (reference.hpp).
#include "leafdig/devices/links/reference.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

namespace leafdig::devices {
namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

}  // namespace

ReferenceFrame::ReferenceFrame(ReferenceOptions options) : o_(options) {}

void ReferenceFrame::reset() {
  pending_.reset();
  last_.reset();
  missed_ = steady_ = 0;
  paused_ = false;
  problem_.clear();
  remedy_.clear();
}

void ReferenceFrame::pause(std::string problem, std::string remedy) {
  paused_ = true;
  steady_ = 0;
  problem_ = std::move(problem);
  remedy_ = std::move(remedy);
}

void ReferenceFrame::push(const StylusSample& s, std::vector<StylusSample>& out) {
  if (s.station == o_.referenceStation) return onReference(s, out);
  if (s.station != o_.stylusStation) {
    ++stats_.others;
    return;
  }
  if (pending_) {  // the previous cycle's reference never came
    ++stats_.withheld;
    if (++missed_ == o_.silentAfter) {
      ++stats_.silences;
      pause("reference receiver " + std::to_string(o_.referenceStation) + " stopped reporting: the stylus is paused",
            "check that the reference receiver is plugged into receiver socket " + std::to_string(o_.referenceStation) +
                " and fixed to the pot; capture goes on when it reports again");
    }
  }
  pending_ = s;
}

void ReferenceFrame::onReference(const StylusSample& s, std::vector<StylusSample>& out) {
  const std::optional<ReceiverPose> pose = poseOf(s);
  if (!pose) {
    if (pending_) ++stats_.withheld;
    pending_.reset();
    pause("reference receiver " + std::to_string(o_.referenceStation) +
              "'s records carry no orientation: the stylus cannot be put in its frame",
          "the digitizer's output list lacks angles for that receiver: reconnect so the station sets it again");
    return;
  }
  missed_ = 0;
  if (last_) {
    const double moved =
        std::hypot(pose->positionMm[0] - last_->positionMm[0], pose->positionMm[1] - last_->positionMm[1],
                   pose->positionMm[2] - last_->positionMm[2]);
    const double turned = rotationBetweenDeg(last_->rotation, pose->rotation);
    if (moved > o_.jumpMm || turned > o_.jumpDeg) {
      ++stats_.jumps;
      pause("reference receiver " + std::to_string(o_.referenceStation) + " jumped " + number(moved) + " mm and " +
                number(turned) + "° between two records: the stylus is paused until it is still",
            "hold the pot still; if the receiver slipped on the pot, fix it and take the landmarks again "
            "(Move transmitter)");
    } else if (paused_ && ++steady_ >= o_.steadyRecords) {
      paused_ = false;
      problem_.clear();
      remedy_.clear();
    }
  }
  last_ = pose;
  if (!pending_) return;
  if (paused_) {
    ++stats_.withheld;
  } else {
    StylusSample inRef = inFrameOf(*pending_, *pose);
    inRef.raw += s.raw;  // both records of the cycle, as received
    out.push_back(std::move(inRef));
    ++stats_.paired;
  }
  pending_.reset();
}

}  // namespace leafdig::devices
