// The lab server's schema (docs/server-schema.md), one migration per version:
// db/migrations/lab/NNNN_what.sql, embedded byte for byte at build time (cmake/embed_sql.cmake).
// `leafdig server init` applies the missing ones, each in its own transaction. Never edit a
// released migration: add the next file (LabMigrations.EveryReleasedMigrationIsUnchanged holds
// each one's SHA-256), and raise kLabSchemaVersion — a count of files that differs from it
// does not compile.
#pragma once

#include <array>

#include "leafdig/db/lab.hpp"

namespace leafdig::db::detail {

// The three group roles are cluster-wide and created (if missing) before the migrations.
inline constexpr const char* kLabRoles[] = {"leafdig_technicians", "leafdig_curators", "leafdig_readers"};

// The migrations' SQL, version 1 first (NUL-terminated).
extern const std::array<const char*, kLabSchemaVersion> kLabMigrations;

}  // namespace leafdig::db::detail
