// What the store's two sources share (store.cpp opens and checks a file, store_records.cpp
// reads and writes its records): the implementation, SQLite's failures in an operator's words,
// and the time budget of an operation.
#pragma once

#include <SQLiteCpp/SQLiteCpp.h>
#include <sqlite3.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include "leafdig/db/store.hpp"
#include "schema.hpp"

namespace leafdig::db {
namespace detail {

// Why the progress handler stopped a statement (SQLITE_INTERRUPT).
enum class Stop { None, Signal, TimeLimit };
inline thread_local Stop lastStop = Stop::None;
inline thread_local double lastLimitSeconds = 0;

// Maps SQLite failures to what an operator can act on.
[[noreturn]] inline void rethrow(const SQLite::Exception& e, const std::string& path, const std::string& doing) {
  const int code = e.getErrorCode() & 0xff;
  const std::string what = doing + " " + path + ": " + e.what();
  switch (code) {
    case SQLITE_INTERRUPT:
      if (lastStop == Stop::TimeLimit)
        throw StoreError(StoreErrorKind::Tampered,
                         doing + " " + path + ": a statement ran longer than " +
                             std::to_string(static_cast<int>(lastLimitSeconds)) + " s and was stopped",
                         "a leafdig file answers every question in well under a second; this one does not: check it "
                         "with 'leafdig sessions verify --all'; nothing was changed");
      throw StoreError(StoreErrorKind::Interrupted, doing + " " + path + ": interrupted",
                       "nothing acknowledged was lost; run the command again");
    case SQLITE_FULL:
      throw StoreError(StoreErrorKind::DiskFull, what,
                       "the disk holding " + path +
                           " is full: free some space; nothing acknowledged was lost and "
                           "capture continues when space returns");
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      throw StoreError(StoreErrorKind::Busy, what, "another program is writing to the database; try again in a moment");
    case SQLITE_NOTADB:
      throw StoreError(StoreErrorKind::NotLeafdig, what,
                       "this file is not a SQLite database; give a leafdig database path");
    case SQLITE_CORRUPT:
      throw StoreError(
          StoreErrorKind::Corrupt, what,
          "the database is damaged; it was not modified. Restore it from a backup, or give another --db path");
    case SQLITE_CONSTRAINT:
      throw StoreError(StoreErrorKind::Input, what, "the change breaks a rule of the database (see docs/schema.md)");
    default: throw StoreError(StoreErrorKind::Io, what, "check that the folder exists and is writable");
  }
}

// The progress handler's state: statements stop on a signal, or past the time limit of the
// operation that runs them (OperationClock). A Store is shared between threads (the capture
// thread appends while the window reads), and SQLite runs the handler in the thread that runs
// the statement: the deadline is that thread's, the limit the Store's.
struct Budget {
  std::atomic<double> limitSeconds{Store::kDefaultTimeLimitSeconds};
};
inline thread_local std::chrono::steady_clock::time_point operationDeadline =
    std::chrono::steady_clock::time_point::max();

// Sets the deadline of one operation of a Store (all its statements together) on this thread;
// nested operations keep the outer one's.
class OperationClock {
 public:
  explicit OperationClock(const Budget& budget) : outer_(operationDeadline) {
    if (outer_ == std::chrono::steady_clock::time_point::max())
      operationDeadline =
          std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                 std::chrono::duration<double>(budget.limitSeconds.load()));
  }
  OperationClock(const OperationClock&) = delete;
  OperationClock& operator=(const OperationClock&) = delete;
  ~OperationClock() { operationDeadline = outer_; }

 private:
  std::chrono::steady_clock::time_point outer_;
};
}  // namespace detail

struct Store::Impl {
  std::unique_ptr<SQLite::Database> db;
  detail::Budget budget;
  int version = kSchemaVersion;  // a reader may hold an older file, read as it is
};

}  // namespace leafdig::db
