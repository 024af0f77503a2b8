// How the command line reports a store's failure (a station file or the lab server): the
// message, what to do, and the exit code of the README — 2 for what the user must fix (a
// foreign, damaged or newer file, bad input, a refusal by the server), 1 for the rest.
#pragma once

#include <iostream>

#include "leafdig/db/event_store.hpp"

namespace leafdig::cli {

inline int reportStoreError(const db::StoreError& e) {
  std::cerr << "leafdig: " << e.what() << "\n";
  if (!e.remedy().empty()) std::cerr << "  what to do: " << e.remedy() << "\n";
  switch (e.kind()) {
    case db::StoreErrorKind::NotLeafdig:
    case db::StoreErrorKind::TooNew:
    case db::StoreErrorKind::Corrupt:
    case db::StoreErrorKind::Input:
    case db::StoreErrorKind::Refused: return 2;
    default: return 1;
  }
}

}  // namespace leafdig::cli
