// What a curator's work checks before it reads or writes a session (review.cpp, correction.cpp,
// leaf_export.cpp and plant_export.cpp share them, so the words are the same everywhere).
#pragma once

#include <cstdint>
#include <string>

#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/event_store.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/files.hpp"

namespace leafdig::acquisition::detail {

// The session `id` names, or SessionError pointing to the list.
inline db::SessionInfo infoOrThrow(const db::EventStore& store, std::int64_t id) {
  const auto info = store.session(id);
  if (!info)
    throw SessionError("there is no session " + std::to_string(id) + " in " + store.describe() +
                       ": 'leafdig sessions list' shows them");
  return *info;
}

// An export never writes over the station's file it reads (nor its WAL): named as inputs of
// this process, model::writeFileAtomically refuses them by name.
inline void noteStoreAsInput(const db::EventStore& store) {
  if (const auto* file = dynamic_cast<const db::Store*>(&store))
    for (const char* suffix : {"", "-wal", "-shm"}) model::noteInput(file->path() + suffix);
}

// Text of only white space (a reason, a curator's name) is none.
inline bool isBlank(const std::string& text) {
  return text.find_first_not_of(" \t\r\n") == std::string::npos;
}

}  // namespace leafdig::acquisition::detail
