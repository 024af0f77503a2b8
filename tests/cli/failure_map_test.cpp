// The one error map (ui/cli/failure.cpp) on every family it knows, including those no
// command line can reach on purpose (an internal error, memory, the file system).
#include <gtest/gtest.h>

#include <filesystem>
#include <new>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "failure.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/event_store.hpp"
#include "leafdig/devices/errors.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/names/name_table.hpp"

namespace {

using leafdig::cli::describeFailure;
using leafdig::cli::Failure;
namespace db = leafdig::db;
namespace dev = leafdig::devices;

template <class E>
Failure of(const E& e, const std::string& context = {}) {
  return describeFailure(std::make_exception_ptr(e), context);
}

TEST(FailureMap, EveryFamilyHasOneExitCode) {
  struct Row {
    const char* what;
    Failure got;
    int exitCode;
    const char* family;
  };
  const auto store = [](db::StoreErrorKind k) { return of(db::StoreError(k, "store says no", "do this")); };
  const std::vector<Row> rows{
      {"InputError", of(leafdig::model::InputError("row 3: bad")), 2, "input"},
      {"invalid_argument", of(std::invalid_argument("--x bad")), 2, "input"},
      {"UnknownName", of(leafdig::UnknownName("serration", "wavy", "none or round")), 2, "input"},
      {"SessionError", of(leafdig::acquisition::SessionError("no session")), 2, "input"},
      {"DeviceError Config", of(dev::DeviceError(dev::DeviceErrorKind::Config, "bad baud", "use 9600")), 2, "input"},
      {"DeviceError NotFound", of(dev::DeviceError(dev::DeviceErrorKind::NotFound, "no port", "plug it")), 1, "io"},
      {"StoreError NotLeafdig", store(db::StoreErrorKind::NotLeafdig), 2, "refused"},
      {"StoreError TooNew", store(db::StoreErrorKind::TooNew), 2, "refused"},
      {"StoreError Corrupt", store(db::StoreErrorKind::Corrupt), 2, "refused"},
      {"StoreError Input", store(db::StoreErrorKind::Input), 2, "refused"},
      {"StoreError Refused", store(db::StoreErrorKind::Refused), 2, "refused"},
      {"StoreError Tampered", store(db::StoreErrorKind::Tampered), 2, "refused"},
      {"StoreError Interrupted", store(db::StoreErrorKind::Interrupted), 130, "interrupted"},
      {"StoreError DiskFull", store(db::StoreErrorKind::DiskFull), 1, "io"},
      {"StoreError Busy", store(db::StoreErrorKind::Busy), 1, "io"},
      {"StoreError Io", store(db::StoreErrorKind::Io), 1, "io"},
      {"StoreError Conflict", store(db::StoreErrorKind::Conflict), 1, "io"},
      {"StoreError Unreachable", store(db::StoreErrorKind::Unreachable), 1, "io"},
      {"IoError", of(leafdig::model::IoError("out.glb: No space left on device")), 1, "io"},
      {"filesystem_error",
       of(std::filesystem::filesystem_error("mkdir", std::make_error_code(std::errc::permission_denied))), 1, "io"},
      {"system_error", of(std::system_error(std::make_error_code(std::errc::io_error), "read")), 1, "io"},
      {"bad_alloc", of(std::bad_alloc()), 1, "io"},
      {"runtime_error", of(std::runtime_error("banded solve: singular matrix")), 1, "internal"},
      {"logic_error", of(std::logic_error("a broken promise")), 1, "internal"},
  };
  for (const Row& r : rows) {
    SCOPED_TRACE(r.what);
    EXPECT_EQ(r.got.exitCode, r.exitCode);
    EXPECT_EQ(r.got.family, r.family);
    EXPECT_FALSE(r.got.message.empty());
  }
  EXPECT_EQ(describeFailure(std::make_exception_ptr(42)).family, "internal");
}

TEST(FailureMap, TheWordsKeepTheMessageTheRemedyAndTheContext) {
  const Failure input = of(leafdig::model::InputError("row 3, point 2: x is not a number"), "cannot export: ");
  EXPECT_EQ(input.message, "cannot export: row 3, point 2: x is not a number");
  const Failure store = of(db::StoreError(db::StoreErrorKind::Busy, "the file is locked", "close the other station"));
  EXPECT_EQ(store.message, "the file is locked");
  EXPECT_EQ(store.remedy, "close the other station");
  EXPECT_EQ(of(std::runtime_error("singular")).message, "internal error: singular");
  // Printed: who speaks, the message, what to do; control characters from a file escaped.
  std::ostringstream out;
  const int code = leafdig::cli::reportFailure(
      std::make_exception_ptr(db::StoreError(db::StoreErrorKind::Corrupt, "plant \x1b[2J", "restore it")), out);
  EXPECT_EQ(code, 2);
  EXPECT_EQ(out.str(), "leafdig: plant \\x1b[2J\n  what to do: restore it\n");
}

}  // namespace
