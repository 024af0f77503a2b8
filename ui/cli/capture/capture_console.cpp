#include "capture/capture_console.hpp"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "leafdig/acquisition/field/field_applied.hpp"
#include "leafdig/acquisition/protocol/point_rules.hpp"
#include "leafdig/acquisition/session/session_log.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::cli {

namespace acq = leafdig::acquisition;
using nlohmann::json;

std::string stationDbPath(const std::string& db) {
  return db.empty() ? db::Store::defaultPath() : db;
}

json nullable(int v) {
  return v > 0 ? json(v) : json(nullptr);
}

json stepJson(const acq::Step& s, const std::string& prompt) {
  return {{"what", acq::toString(s.what)}, {"row", nullable(s.row)}, {"col", nullable(s.col)}, {"prompt", prompt}};
}

std::shared_ptr<const devices::sim::FieldDistortion> distortionOf(const std::string& path) {
  if (path.empty()) return nullptr;
  return std::make_shared<const devices::sim::FieldDistortion>(devices::sim::readFieldDistortion(path));
}

devices::Vec3 vec3Option(const std::string& text, const std::string& option, double limitMm, const char* example) {
  std::istringstream in(text);
  devices::Vec3 v{};
  char c1 = 0, c2 = 0;
  std::string rest;
  if (!(in >> v[0] >> c1 >> v[1] >> c2 >> v[2]) || c1 != ',' || c2 != ',' || (in >> rest) ||
      !(std::abs(v[0]) <= limitMm && std::abs(v[1]) <= limitMm && std::abs(v[2]) <= limitMm)) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%.0f", limitMm);
    throw model::InputError(option + " is x,y,z in mm, each within " + limit + ", e.g. " + example + "; got '" +
                            text.substr(0, 60) + "'");
  }
  return v;
}

devices::Vec3 simTipOf(const std::string& text) {
  if (text.empty()) return {0, 0, 0};
  return vec3Option(text, "--sim-tip", 500, "0,0,120");
}

double fieldCheckMaxAge(const std::optional<double>& flag) {
  const auto inRange = [](double h) { return h >= 1 && h <= acq::kFieldCheckMaxAgeLimitHours; };
  if (flag) {
    if (!inRange(*flag))
      throw model::InputError("--field-check-max-age-hours " + std::to_string(*flag) +
                              ": give the hours a field check holds, from 1 to 8760");
    return *flag;
  }
  const auto text = acq::stationSetting("field", "max_check_age_hours");
  if (!text) return acq::kFieldCheckMaxAgeHours;
  double hours = 0;
  std::size_t used = 0;
  try {
    hours = std::stod(*text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text->size() || !inRange(hours))
    throw model::InputError(acq::stationSettingsFile() + ": [field] max_check_age_hours = " + *text +
                            " is not a number of hours from 1 to 8760: correct it in the station's settings or "
                            "remove the line");
  return hours;
}

int sentinelCount(const std::optional<int>& flag) {
  const auto allowed = [](int n) { return n == 0 || (n >= acq::kMinSentinels && n <= acq::kMaxSentinels); };
  if (flag) {
    if (!allowed(*flag))
      throw model::InputError("--sentinels " + std::to_string(*flag) +
                              ": take 3 to 5 of the field check's divots again, or 0 for none");
    return *flag;
  }
  const auto text = acq::stationSetting("field", "sentinels");
  if (!text) return 0;
  if (*text == "0" || *text == "3" || *text == "4" || *text == "5") return std::stoi(*text);
  throw model::InputError(acq::stationSettingsFile() + ": [field] sentinels = " + *text +
                          " is not 0, 3, 4 or 5: correct it in the station's settings or remove the line");
}

std::string describe(const acq::Item& i) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1);
  if (i.what == acq::What::Tip)
    s << "tip";
  else if (i.what == acq::What::Board)
    s << "board point " << i.col;
  else if (i.what == acq::What::BoardAgain)
    s << "board point " << i.col << " again (transmitter position " << i.row + 1 << ")";
  else if (i.what == acq::What::Marker)
    s << "row " << i.row << " point " << i.col;
  else if (i.what == acq::What::EdgeThickness)
    s << "margin thickness";
  else
    s << "row " << i.row << " " << acq::toString(i.what)
      << (i.what == acq::What::PointThickness ? " at point " + std::to_string(i.col) : "");
  if (acq::isStylusItem(i.what))
    s << " (" << i.positionMm[0] << ", " << i.positionMm[1] << ", " << i.positionMm[2] << ") mm";
  else
    s << std::setprecision(3) << " " << i.valueMm << " mm";
  if (!i.flag.empty()) s << " [" << i.flag << "]";
  return s.str();
}

GiveUpWatch::GiveUpWatch(double seconds) : seconds_(seconds), lastProgress_(std::chrono::steady_clock::now()) {}

void GiveUpWatch::progressed() {
  std::lock_guard lock(mutex_);
  lastProgress_ = std::chrono::steady_clock::now();
  refusedSince_ = 0;
}

void GiveUpWatch::refused(const std::string& reason) {
  std::lock_guard lock(mutex_);
  lastRefusal_ = reason;
  ++refusedSince_;
}

void GiveUpWatch::at(const std::string& prompt, bool paused) {
  std::lock_guard lock(mutex_);
  if (paused != paused_) lastProgress_ = std::chrono::steady_clock::now();  // a pause is no lack of progress
  paused_ = paused;
  where_ = prompt;
}

std::string GiveUpWatch::overdue(const std::string& capture, std::int64_t id, const std::string& db) const {
  std::lock_guard lock(mutex_);
  if (paused_ || std::chrono::steady_clock::now() - lastProgress_ <= std::chrono::duration<double>(seconds_)) return {};
  std::ostringstream why;
  why << std::fixed << std::setprecision(0) << "leafdig: the simulated technician got nowhere for " << seconds_ << " s "
      << (where_.empty() ? "before its first input was taken" : "at '" + where_ + "'") << " (" << refusedSince_
      << " inputs refused since the last accepted one"
      << (lastRefusal_.empty() ? "" : "; the last: '" + lastRefusal_ + "'") << "): the " << capture
      << " was stopped and kept. This is a fault of the simulation or of the station: report it with 'leafdig "
         "sessions show "
      << id << " --db " << db << "'\n";
  return why.str();
}

void checkRelocationTolerance(const std::optional<double>& mm, bool resuming) {
  if (!mm) return;
  if (!(*mm >= 0.1 && *mm <= 10.0))
    throw std::invalid_argument("--relocation-tolerance must be a residual in mm, 0.1 to 10 (default 1.5)");
  if (resuming)
    throw std::invalid_argument(
        "--relocation-tolerance is set when a capture begins: a resumed session keeps its own (leave it out)");
}

}  // namespace leafdig::cli
