#include "failure.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <new>
#include <ostream>
#include <stdexcept>
#include <system_error>

#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/event_store.hpp"
#include "leafdig/devices/errors.hpp"
#include "leafdig/model/errors.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {
namespace {

Failure storeFailure(const db::StoreError& e) {
  switch (e.kind()) {
    case db::StoreErrorKind::NotLeafdig:
    case db::StoreErrorKind::TooNew:
    case db::StoreErrorKind::Corrupt:
    case db::StoreErrorKind::Input:
    case db::StoreErrorKind::Refused:
    case db::StoreErrorKind::Tampered: return {2, "refused", e.what(), e.remedy()};
    case db::StoreErrorKind::Interrupted: return {130, "interrupted", e.what(), e.remedy()};
    case db::StoreErrorKind::DiskFull:
    case db::StoreErrorKind::Busy:
    case db::StoreErrorKind::Io:
    case db::StoreErrorKind::Conflict:
    case db::StoreErrorKind::Unreachable: break;
  }
  return {1, "io", e.what(), e.remedy()};
}

}  // namespace

Failure describeFailure(const std::exception_ptr& error, const std::string& inputContext) {
  try {
    std::rethrow_exception(error);
  } catch (const CLI::ParseError& e) {
    return {2, "input", e.what(), "run 'leafdig --help' for usage"};
  } catch (const db::StoreError& e) {
    return storeFailure(e);
  } catch (const devices::DeviceError& e) {
    if (e.kind() == devices::DeviceErrorKind::Config) return {2, "input", inputContext + e.what(), e.remedy()};
    return {1, "io", e.what(), e.remedy()};
  } catch (const model::InputError& e) {
    return {2, "input", inputContext + e.what(), {}};
  } catch (const acquisition::SessionError& e) {
    return {2, "input", inputContext + e.what(), {}};
  } catch (const std::invalid_argument& e) {
    return {2, "input", inputContext + e.what(), {}};
  } catch (const model::IoError& e) {
    return {1, "io", e.what(), {}};
  } catch (const std::filesystem::filesystem_error& e) {
    return {1, "io", e.what(), {}};
  } catch (const std::system_error& e) {
    return {1, "io", e.what(), {}};
  } catch (const std::bad_alloc&) {
    return {1, "io", "out of memory", "close other programs, or give a smaller input"};
  } catch (const std::exception& e) {
    return {1, "internal", std::string("internal error: ") + e.what(),
            "please report it with the command and its input"};
  } catch (...) {
    return {1, "internal", "internal error of an unknown kind", "please report it with the command and its input"};
  }
}

int reportFailure(const std::exception_ptr& error, std::ostream& out, const std::string& inputContext) {
  const Failure f = describeFailure(error, inputContext);
  out << "leafdig: " << terminalMessage(f.message) << "\n";
  if (!f.remedy.empty()) out << "  what to do: " << terminalMessage(f.remedy) << "\n";
  return f.exitCode;
}

}  // namespace leafdig::cli
