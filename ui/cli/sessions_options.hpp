// What `leafdig sessions …` parses (sessions_cmd.cpp declares the options, sessions_show.cpp
// and sessions_cmd.cpp read them).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/acquisition/review/correction.hpp"

namespace leafdig::cli {

struct SessionsOptions {
  std::string db;  // a station's SQLite file, or a postgresql:// URL
  bool json = false;
  std::int64_t id = 0;
  bool all = false;                                 // verify
  std::string status, kind, plant, station, since;  // list: its filters
  std::string who, why;                             // approve, reject, correct
  std::string out;                                  // export
  std::vector<std::string> formats;
  int node = 0;  // export --node: a plant session's full leaf alone; correct: its node
  std::string frame = "leaf", blade = "interp";
  std::string resolution = "export", organs = "all";  // export: how the meshes are made
  bool warnUnapproved = true;  // export: warn on stderr that the session is not approved (not the demo's)
  // correct
  std::string what;
  int row = 0, col = 0;
  std::vector<double> position;
  std::optional<double> value;
  bool confirm = false;                                      // a move above confirmAboveMm is meant
  bool dryRun = false;                                       // correct: show the effect, write nothing
  double confirmAboveMm = acquisition::kConfirmMoveAboveMm;  // mm
  std::string positionFrame;  // correct: "plant" or "digitizer" (empty: plant for a plant session)
};

}  // namespace leafdig::cli
