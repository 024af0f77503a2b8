// Where a session's exported file came from (issue 49): a file that leaves the lab still says
// which session it is, the station that captured it, its status, who captured it and which
// curator decided it when. One list, written into every session export's header or metadata:
// MTG and CSV `#` comment lines, OBJ and PLY comments, GLB `asset.extras.provenance`, a
// `provenance` object in the model and survey JSON (docs/decisions.md, "Corrections that cannot
// slip, and files that say where they came from").
//
// Thread contract: like the Store it takes, one thread at a time.
#pragma once

#include <string>

#include "leafdig/db/event_store.hpp"
#include "leafdig/model/io/mesh_export.hpp"

namespace leafdig::acquisition {

// session, station, station_session, status, operator, decision (approved, rejected or
// "none"), curator and decided_utc (of the last decision, when there is one), corrections (how
// many), in that order; every value one line of printable text (control characters as spaces).
[[nodiscard]] model::Provenance sessionProvenance(const db::EventStore& store, const db::SessionInfo& info);
// As comment lines: `<prefix>KEY: VALUE\n` each ("# " for MTG and CSV); commas, semicolons and
// quotes in a value become spaces, so a spreadsheet keeps each line one cell beginning with '#'.
[[nodiscard]] std::string provenanceComments(const model::Provenance& p, const std::string& prefix = "# ");
// As a JSON object's text: {"session": "3", …} (every value a string, as in the other formats).
[[nodiscard]] std::string provenanceJson(const model::Provenance& p);

}  // namespace leafdig::acquisition
