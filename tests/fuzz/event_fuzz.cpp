// libFuzzer target for the one definition of a valid event (issue 47): the input's first line
// is the kind, the rest the payload (and after a NUL byte, the raw text). db::eventProblem and
// db::settingsProblem must answer — a problem in words, or none — for any bytes; a crash,
// another exception or a hang is a finding. An event they pass holds only numbers a double
// carries within ±1e15 (checked again here with nlohmann's own reading).
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

#include "leafdig/db/event_rules.hpp"

namespace {

void require(bool ok) {
  if (!ok) std::abort();
}

void numbersWithin(const nlohmann::json& j) {
  if (j.is_number()) require(std::isfinite(j.get<double>()) && std::abs(j.get<double>()) <= 1e15);
  if (j.is_structured())
    for (const auto& x : j) numbersWithin(x);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::size_t line = input.find('\n');
  const std::string kind = input.substr(0, line);
  std::string payload = line == std::string::npos ? std::string() : input.substr(line + 1);
  std::string raw;
  if (const std::size_t nul = payload.find('\0'); nul != std::string::npos) {
    raw = payload.substr(nul + 1);
    payload.resize(nul);
  }
  if (!leafdig::db::eventProblem(kind, payload, raw)) numbersWithin(nlohmann::json::parse(payload));
  if (!leafdig::db::settingsProblem(payload)) numbersWithin(nlohmann::json::parse(payload));
  return 0;
}
