// How the command line reports a store's failure (a station file or the lab server): the
// message, what to do, and the exit code of the README — 2 for what the user must fix (a
// foreign, damaged or newer file, bad input, a refusal by the server), 1 for the rest.
#pragma once

#include <iostream>

#include "leafdig/db/event_store.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {

inline int reportStoreError(const db::StoreError& e) {
  std::cerr << "leafdig: " << terminalMessage(e.what()) << "\n";
  if (!e.remedy().empty()) std::cerr << "  what to do: " << terminalMessage(e.remedy()) << "\n";
  switch (e.kind()) {
    case db::StoreErrorKind::NotLeafdig:
    case db::StoreErrorKind::TooNew:
    case db::StoreErrorKind::Corrupt:
    case db::StoreErrorKind::Input:
    case db::StoreErrorKind::Refused:
    case db::StoreErrorKind::Tampered: return 2;
    case db::StoreErrorKind::Interrupted: return 130;
    default: return 1;
  }
}

}  // namespace leafdig::cli
