// The one check before a stored session is trusted: its chain recomputed (review, export and
// capture into it share it, so the words are the same everywhere).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

#include "leafdig/acquisition/review.hpp"
#include "leafdig/acquisition/session.hpp"
#include "leafdig/db/event_store.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/files.hpp"

namespace leafdig::acquisition::detail {

// What a session that does not verify cannot be when a capture would go on with it.
inline constexpr const char* kCapturedInto =
    "captured into: nothing is added to it; 'leafdig sessions verify' shows it to a curator";

// SessionError "session N fails 'sessions verify' (event K: what): it cannot be <doing>".
inline void requireChain(const db::EventStore& store, std::int64_t id, const std::string& doing) {
  const db::ChainReport chain = store.verify(id);
  if (!chain.ok)
    throw SessionError("session " + std::to_string(id) + " fails 'sessions verify' (event " +
                       std::to_string(chain.firstBadSeq.value_or(0)) + ": " + chain.problem + "): it cannot be " +
                       doing);
}

// An export never writes over the station's file it reads (nor its WAL): named as inputs of
// this process, model::writeFileAtomically refuses them by name.
inline void noteStoreAsInput(const db::EventStore& store) {
  if (const auto* file = dynamic_cast<const db::Store*>(&store))
    for (const char* suffix : {"", "-wal", "-shm"}) model::noteInput(file->path() + suffix);
}

// What a curator's correction of session `id` needs before anything is read (a leaf's and a
// plant's alike): a complete session (approved and rejected are final, open is still being
// captured), a reason, a name, and a chain that verifies. std::invalid_argument / SessionError.
// Text of only white space (a reason, a curator's name) is none.
inline bool isBlank(const std::string& text) {
  return text.find_first_not_of(" \t\r\n") == std::string::npos;
}

inline void requireCorrectable(const db::EventStore& store, std::int64_t id, const std::string& status,
                               const std::string& reason, const std::string& who) {
  if (status != "complete")
    throw std::invalid_argument("session " + std::to_string(id) + " is " + status +
                                ": only a complete session (awaiting review) can be corrected");
  if (isBlank(reason)) throw std::invalid_argument("a correction needs a reason: say what was wrong");
  if (isBlank(who)) throw std::invalid_argument("a correction needs the curator's name");
  requireChain(store, id, "corrected");
}

// A corrected point that would move further than `limitMm` from where it was (both in the frame
// `sessions show` gives) is refused until the curator confirms the move (issue 49).
inline void requireConfirmedMove(const std::array<double, 3>& from, const std::array<double, 3>& to, double limitMm,
                                 const std::string& item) {
  double s = 0;
  for (std::size_t i = 0; i < 3; ++i) s += (to[i] - from[i]) * (to[i] - from[i]);
  const double d = std::sqrt(s);
  if (d <= limitMm) return;
  std::ostringstream t;
  t << std::fixed << std::setprecision(1) << "the " << item << " would move " << d << " mm, more than the " << limitMm
    << " mm a correction moves unconfirmed: check the position (x, y, z in mm, as sessions show gives it), then "
       "confirm the move (--confirm); nothing was written";
  throw UnconfirmedMove(t.str(), d);
}

}  // namespace leafdig::acquisition::detail
