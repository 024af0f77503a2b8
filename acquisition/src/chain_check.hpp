// The one check before a stored session is trusted: its chain recomputed (review, export and
// capture into it share it, so the words are the same everywhere).
#pragma once

#include <cstdint>
#include <string>

#include "leafdig/acquisition/session.hpp"
#include "leafdig/db/event_store.hpp"

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

}  // namespace leafdig::acquisition::detail
