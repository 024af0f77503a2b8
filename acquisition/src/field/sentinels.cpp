#include "leafdig/acquisition/field/sentinels.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "field/numbers.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::acquisition {

namespace {
using nlohmann::json;

double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}
}  // namespace

const SentinelDivot& FieldSentinels::worst() const {
  if (divots.empty()) throw std::logic_error("sentinels without divots");
  return *std::max_element(divots.begin(), divots.end(),
                           [](const SentinelDivot& a, const SentinelDivot& b) { return a.movedMm < b.movedMm; });
}

std::string FieldSentinels::words() const {
  const SentinelDivot& w = worst();
  const std::string head = std::to_string(divots.size()) + " sentinel divots of field check " +
                           std::to_string(checkId) + " taken again: the largest move " + detail::fixed(w.movedMm) +
                           " mm (" + w.id + ")";
  if (!moved()) return head + ", within its " + detail::fixed(toleranceMm) + " mm";
  return head + ", beyond its " + detail::fixed(toleranceMm) + " mm: the field moved since the check (metal " +
         "brought near, the transmitter or the jig knocked) and its correction no longer describes it. Check the " +
         "field again (leafdig field check) and capture through the new check, or capture with " +
         "--field-calibration none";
}

model::Jig sentinelJig(const model::Jig& jig, int count) {
  if (count < kMinSentinels || count > kMaxSentinels)
    throw std::invalid_argument("sentinel divots are " + std::to_string(kMinSentinels) + " to " +
                                std::to_string(kMaxSentinels) + " (0: none); got " + std::to_string(count));
  const std::size_t n = jig.points.size();
  const std::size_t want = std::min<std::size_t>(static_cast<std::size_t>(count), n);
  Eigen::Vector3d middle = Eigen::Vector3d::Zero();
  for (const auto& p : jig.points) middle += p.pointMm;
  middle /= static_cast<double>(std::max<std::size_t>(n, 1));
  std::vector<std::size_t> chosen;
  std::vector<double> nearest(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) nearest[i] = (jig.points[i].pointMm - middle).norm();
  while (chosen.size() < want) {
    // The divot farthest from every one chosen so far (from the middle, for the first); the
    // first in the jig's order on a tie, so the choice is the same on every station.
    std::size_t best = n;
    for (std::size_t i = 0; i < n; ++i)
      if (std::find(chosen.begin(), chosen.end(), i) == chosen.end() && (best == n || nearest[i] > nearest[best]))
        best = i;
    chosen.push_back(best);
    for (std::size_t i = 0; i < n; ++i)
      nearest[i] = chosen.size() == 1 ? (jig.points[i].pointMm - jig.points[best].pointMm).norm()
                                      : std::min(nearest[i], (jig.points[i].pointMm - jig.points[best].pointMm).norm());
  }
  std::sort(chosen.begin(), chosen.end());
  model::Jig sub;
  sub.name = jig.name + " (sentinel divots)";
  for (const std::size_t i : chosen) sub.points.push_back(jig.points[i]);
  return sub;
}

FieldSentinels compareSentinels(const FieldCalibration& check, const model::Jig& sentinels,
                                const std::vector<JigPress>& presses, std::string takenUtc) {
  if (presses.size() != sentinels.points.size() || presses.empty())
    throw std::invalid_argument("the sentinel divots are not all taken");
  FieldSentinels s;
  s.checkId = check.id;
  s.takenUtc = std::move(takenUtc);
  s.toleranceMm = check.result.toleranceMm;
  for (std::size_t i = 0; i < presses.size(); ++i) {
    const std::string& id = sentinels.points[i].id;
    const auto at = std::find_if(check.jig.points.begin(), check.jig.points.end(),
                                 [&](const model::JigPoint& p) { return p.id == id; });
    if (at == check.jig.points.end())
      throw std::invalid_argument("divot " + id + " is not field check " + std::to_string(check.id) + "'s");
    const JigPress& then = check.presses.at(static_cast<std::size_t>(at - check.jig.points.begin()));
    s.divots.push_back({id, presses[i].positionMm, distance(presses[i].positionMm, then.positionMm)});
  }
  return s;
}

json sentinelsJson(const FieldSentinels& s) {
  json divots = json::array();
  for (const SentinelDivot& d : s.divots)
    divots.push_back(
        {{"id", d.id}, {"position_mm", {d.positionMm[0], d.positionMm[1], d.positionMm[2]}}, {"moved_mm", d.movedMm}});
  return {{"taken_utc", s.takenUtc},     {"tolerance_mm", s.toleranceMm}, {"divots", divots},
          {"max_mm", s.worst().movedMm}, {"worst_point", s.worst().id},   {"verdict", s.moved() ? "moved" : "held"}};
}

FieldSentinels sentinelsFromJson(const json& doc, std::int64_t checkId, const std::string& where) {
  const auto fail = [&](const std::string& what) { throw model::InputError(where + ": " + what); };
  const auto number = [&](const json& v, const std::string& key, double most) {
    if (!v.is_number() || !(v.get<double>() >= 0 && v.get<double>() <= most))
      fail(key + " is not a number from 0 to " + detail::fixed(most, 0));
    return v.get<double>();
  };
  if (!doc.is_object()) fail("is not an object");
  for (const auto& [key, value] : doc.items())
    if (key != "taken_utc" && key != "tolerance_mm" && key != "divots" && key != "max_mm" && key != "worst_point" &&
        key != "verdict")
      fail("has a key leafdig does not read: " + key.substr(0, 40));
  FieldSentinels s;
  s.checkId = checkId;
  if (!doc.value("taken_utc", json()).is_string() || doc["taken_utc"].get_ref<const std::string&>().size() > 100)
    fail("taken_utc is not a time");
  s.takenUtc = doc["taken_utc"].get<std::string>();
  s.toleranceMm = number(doc.value("tolerance_mm", json()), "tolerance_mm", 100);
  const json& divots = doc.value("divots", json());
  if (!divots.is_array() || divots.size() < static_cast<std::size_t>(kMinSentinels) ||
      divots.size() > static_cast<std::size_t>(kMaxSentinels))
    fail("divots is not a list of " + std::to_string(kMinSentinels) + " to " + std::to_string(kMaxSentinels));
  for (std::size_t i = 0; i < divots.size(); ++i) {
    const json& d = divots[i];
    const std::string at = "divots[" + std::to_string(i) + "]";
    if (!d.is_object() || !d.value("id", json()).is_string() || d["id"].get_ref<const std::string&>().empty() ||
        d["id"].get_ref<const std::string&>().size() > 40)
      fail(at + ".id is not a divot's name");
    const json& p = d.value("position_mm", json());
    if (!p.is_array() || p.size() != 3) fail(at + ".position_mm is not three numbers");
    SentinelDivot one;
    one.id = d["id"].get<std::string>();
    for (std::size_t k = 0; k < 3; ++k) {
      if (!p[k].is_number() || !(std::abs(p[k].get<double>()) <= 1e5)) fail(at + ".position_mm is not three numbers");
      one.positionMm[k] = p[k].get<double>();
    }
    one.movedMm = number(d.value("moved_mm", json()), at + ".moved_mm", 1e5);
    s.divots.push_back(one);
  }
  if (!detail::sameNumber(number(doc.value("max_mm", json()), "max_mm", 1e5), s.worst().movedMm) ||
      doc.value("worst_point", json()) != s.worst().id)
    fail("max_mm and worst_point are not the divots' own");
  if (doc.value("verdict", json()) != (s.moved() ? "moved" : "held")) fail("the verdict is not the divots' own");
  return s;
}

}  // namespace leafdig::acquisition
