// Schema migrations (private). Migration N takes a database from user_version N-1 to N.
// docs/schema.md documents the result for people who open the file in other tools.
#pragma once

#include <array>

namespace leafdig::db::detail {

inline constexpr std::array<const char*, 5> kMigrations = {
    // ---- 1: the entities of docs/schema.md ----------------------------------------------------
    R"SQL(
CREATE TABLE operators (
  id      INTEGER PRIMARY KEY,
  name    TEXT NOT NULL UNIQUE,
  role    TEXT NOT NULL CHECK (role IN ('technician', 'curator'))
);
CREATE TABLE projects (
  id      INTEGER PRIMARY KEY,
  name    TEXT NOT NULL UNIQUE
);
CREATE TABLE plants (
  id         INTEGER PRIMARY KEY,
  project_id INTEGER NOT NULL REFERENCES projects(id),
  name       TEXT NOT NULL,
  UNIQUE (project_id, name)
);
CREATE TABLE leaves (
  id                INTEGER PRIMARY KEY,
  plant_id          INTEGER NOT NULL REFERENCES plants(id),
  position          INTEGER NOT NULL CHECK (position >= 1),
  type              TEXT NOT NULL DEFAULT '',
  measured_area_mm2 REAL CHECK (measured_area_mm2 IS NULL OR measured_area_mm2 > 0),
  UNIQUE (plant_id, position)
);
CREATE TABLE devices (
  id          INTEGER PRIMARY KEY,
  kind        TEXT NOT NULL,
  port        TEXT NOT NULL,
  description TEXT NOT NULL DEFAULT '',
  UNIQUE (kind, port)
);
CREATE TABLE sessions (
  id            INTEGER PRIMARY KEY,
  leaf_id       INTEGER NOT NULL REFERENCES leaves(id),
  operator_id   INTEGER NOT NULL REFERENCES operators(id),
  station       TEXT NOT NULL,
  status        TEXT NOT NULL DEFAULT 'open'
                CHECK (status IN ('open', 'complete', 'approved', 'rejected', 'abandoned')),
  mode          TEXT NOT NULL CHECK (mode IN ('standard', 'full', 'small')),
  capture_order TEXT NOT NULL CHECK (capture_order IN ('sequential', 'interleaved')),
  settings_json TEXT NOT NULL DEFAULT '{}',
  created_utc   TEXT NOT NULL,
  genesis_hash  TEXT NOT NULL,
  head_seq      INTEGER NOT NULL DEFAULT 0,
  head_hash     TEXT NOT NULL
);
CREATE TABLE events (
  session_id   INTEGER NOT NULL REFERENCES sessions(id),
  seq          INTEGER NOT NULL CHECK (seq >= 1),
  utc          TEXT NOT NULL,
  mono_ns      INTEGER NOT NULL,
  kind         TEXT NOT NULL,
  payload_json TEXT NOT NULL,
  raw          TEXT NOT NULL DEFAULT '',
  prev_hash    TEXT NOT NULL,
  hash         TEXT NOT NULL,
  PRIMARY KEY (session_id, seq)
) WITHOUT ROWID;
CREATE TRIGGER events_no_update BEFORE UPDATE ON events
  BEGIN SELECT RAISE(ABORT, 'events are append-only: record a correction event instead'); END;
CREATE TRIGGER events_no_delete BEFORE DELETE ON events
  BEGIN SELECT RAISE(ABORT, 'events are append-only: record a correction event instead'); END;
CREATE TABLE markers (
  session_id INTEGER NOT NULL REFERENCES sessions(id),
  seq        INTEGER NOT NULL,
  what       TEXT NOT NULL,
  row        INTEGER,
  col        INTEGER,
  x_mm REAL NOT NULL, y_mm REAL NOT NULL, z_mm REAL NOT NULL,
  PRIMARY KEY (session_id, seq),
  FOREIGN KEY (session_id, seq) REFERENCES events(session_id, seq)
);
CREATE TABLE thickness_readings (
  session_id INTEGER NOT NULL REFERENCES sessions(id),
  seq        INTEGER NOT NULL,
  what       TEXT NOT NULL,
  row        INTEGER,
  col        INTEGER,
  value_mm   REAL NOT NULL CHECK (value_mm > 0),
  raw        TEXT NOT NULL DEFAULT '',
  PRIMARY KEY (session_id, seq),
  FOREIGN KEY (session_id, seq) REFERENCES events(session_id, seq)
);
CREATE TABLE exports (
  id         INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions(id),
  path       TEXT NOT NULL,
  format     TEXT NOT NULL,
  utc        TEXT NOT NULL
);
CREATE INDEX sessions_by_leaf ON sessions(leaf_id);
CREATE INDEX leaves_by_plant ON leaves(plant_id);
)SQL",
    // ---- 2: plant sessions (docs/plants.md): a session captures one leaf or a whole plant -----
    // The sessions table is made again (SQLite cannot drop a NOT NULL): `kind`, the plant of
    // every session, and a leaf only for leaf sessions. Run with foreign keys off; the store
    // checks them before it commits (the procedure of SQLite's "ALTER TABLE" page).
    R"SQL(
CREATE TABLE sessions_2 (
  id            INTEGER PRIMARY KEY,
  kind          TEXT NOT NULL DEFAULT 'leaf' CHECK (kind IN ('leaf', 'plant')),
  plant_id      INTEGER NOT NULL REFERENCES plants(id),
  leaf_id       INTEGER REFERENCES leaves(id),
  operator_id   INTEGER NOT NULL REFERENCES operators(id),
  station       TEXT NOT NULL,
  status        TEXT NOT NULL DEFAULT 'open'
                CHECK (status IN ('open', 'complete', 'approved', 'rejected', 'abandoned')),
  mode          TEXT NOT NULL CHECK (mode IN ('standard', 'full', 'small')),
  capture_order TEXT NOT NULL CHECK (capture_order IN ('sequential', 'interleaved')),
  settings_json TEXT NOT NULL DEFAULT '{}',
  created_utc   TEXT NOT NULL,
  genesis_hash  TEXT NOT NULL,
  head_seq      INTEGER NOT NULL DEFAULT 0,
  head_hash     TEXT NOT NULL,
  CHECK ((kind = 'leaf') = (leaf_id IS NOT NULL))
);
INSERT INTO sessions_2 (id, kind, plant_id, leaf_id, operator_id, station, status, mode, capture_order, settings_json,
                        created_utc, genesis_hash, head_seq, head_hash)
  SELECT s.id, 'leaf', l.plant_id, s.leaf_id, s.operator_id, s.station, s.status, s.mode, s.capture_order,
         s.settings_json, s.created_utc, s.genesis_hash, s.head_seq, s.head_hash
  FROM sessions s JOIN leaves l ON l.id = s.leaf_id;
DROP TABLE sessions;
ALTER TABLE sessions_2 RENAME TO sessions;
CREATE INDEX sessions_by_leaf ON sessions(leaf_id);
CREATE INDEX sessions_by_plant ON sessions(plant_id);
)SQL",
    // ---- 3: the station in the chain (issue 47) -------------------------------------------------
    // A session's genesis hash now covers its station and kind (form 2, docs/schema.md, "The event
    // log"): a copy of another station's file with its station column edited no longer verifies.
    // Sessions written before keep form 1 (their genesis covers id, time and settings only) and
    // still verify; `sessions verify` and `show` say which form a session has.
    R"SQL(
ALTER TABLE sessions ADD COLUMN genesis_form INTEGER NOT NULL DEFAULT 1 CHECK (genesis_form IN (1, 2));
)SQL",
    // ---- 4: the field the stylus lives in (issue 50) -------------------------------------------
    // Each check of the digitizer's field against a jig, append-only and chained: a check's hash
    // covers the one before it, its station, operator, device, time, verdict and record (the jig,
    // every press, the fit, the correction chosen and its held-out error: docs/devices.md).
    R"SQL(
CREATE TABLE field_checks (
  id           INTEGER PRIMARY KEY,
  station      TEXT NOT NULL,
  operator_id  INTEGER NOT NULL REFERENCES operators(id),
  device_id    INTEGER NOT NULL REFERENCES devices(id),
  created_utc  TEXT NOT NULL,
  verdict      TEXT NOT NULL CHECK (verdict IN ('pass', 'correctable', 'fail')),
  record_json  TEXT NOT NULL,
  prev_hash    TEXT NOT NULL,
  hash         TEXT NOT NULL
);
CREATE TRIGGER field_checks_no_update BEFORE UPDATE ON field_checks
  BEGIN SELECT RAISE(ABORT, 'field checks are append-only: run a new check'); END;
CREATE TRIGGER field_checks_no_delete BEFORE DELETE ON field_checks
  BEGIN SELECT RAISE(ABORT, 'field checks are append-only: run a new check'); END;
)SQL",
    // ---- 5: the stylus' tip (issue 50) ---------------------------------------------------------
    // Each tip (pivot) calibration of a digitizer's stylus, append-only and chained as the field
    // checks are: its record holds every sample of the pivot, the fit and its residuals.
    R"SQL(
CREATE TABLE tip_calibrations (
  id           INTEGER PRIMARY KEY,
  station      TEXT NOT NULL,
  operator_id  INTEGER NOT NULL REFERENCES operators(id),
  device_id    INTEGER NOT NULL REFERENCES devices(id),
  created_utc  TEXT NOT NULL,
  verdict      TEXT NOT NULL CHECK (verdict IN ('pass', 'fail')),
  record_json  TEXT NOT NULL,
  prev_hash    TEXT NOT NULL,
  hash         TEXT NOT NULL
);
CREATE TRIGGER tip_calibrations_no_update BEFORE UPDATE ON tip_calibrations
  BEGIN SELECT RAISE(ABORT, 'tip calibrations are append-only: calibrate again'); END;
CREATE TRIGGER tip_calibrations_no_delete BEFORE DELETE ON tip_calibrations
  BEGIN SELECT RAISE(ABORT, 'tip calibrations are append-only: calibrate again'); END;
)SQL",
};

}  // namespace leafdig::db::detail
