// The `leafdig.plant/1` plan reader (schema: data/schema/leafdig.plant-1.schema.json).
#include <cmath>
#include <set>

#include "json_reader.hpp"
#include "json_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/model/plant/plant.hpp"

namespace leafdig::model {

namespace {

using json = nlohmann::json;

class PlanReader {
 public:
  explicit PlanReader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(source_ + ": " + where + ": " + what);
  }

  const json& required(const json& object, const std::string& key, const std::string& where) const {
    if (!object.is_object() || !object.contains(key) || object.at(key).is_null())
      fail(where.empty() ? key : where + "." + key, "missing; this key is required (see docs/plants.md)");
    return object.at(key);
  }

  // Every number of a plan is a length, an angle, a time or a factor: none is beyond a
  // million (a plant is at most 10 m, a time at most 100 000 days or degree-days).
  double number(const json& value, const std::string& where) const {
    if (!value.is_number()) fail(where, "expected a number, found " + std::string(value.type_name()));
    const double v = value.get<double>();
    if (!std::isfinite(v)) fail(where, "not a finite number");
    if (std::abs(v) > kMaxPlanNumber)
      fail(where, detail::formatNumber(v) + " is beyond any length, angle or time of a plant (at most " +
                      detail::formatNumber(kMaxPlanNumber) + "); check the number and the plan's units");
    return v;
  }

  double positive(const json& value, const std::string& where) const {
    const double v = number(value, where);
    if (!(v > 0.0)) fail(where, detail::formatNumber(v) + " must be greater than zero");
    return v;
  }

  // A positive number at most `high` (`what` says what bounds it).
  double within(const json& value, const std::string& where, double high, const std::string& what) const {
    const double v = positive(value, where);
    if (v > high) fail(where, detail::formatNumber(v) + " is more than " + what);
    return v;
  }

  std::optional<double> optionalNumber(const json& object, const std::string& key, const std::string& where) const {
    if (!object.contains(key) || object.at(key).is_null()) return std::nullopt;
    return number(object.at(key), where + "." + key);
  }

  std::string text(const json& value, const std::string& where) const {
    if (!value.is_string()) fail(where, "expected a string, found " + std::string(value.type_name()));
    return value.get<std::string>();
  }

  Range range(const json& object, const std::string& key, const std::string& where, Range fallback) const {
    if (!object.contains(key) || object.at(key).is_null()) return fallback;
    const json& v = object.at(key);
    const std::string at = where + "." + key;
    if (!v.is_array() || v.size() != 2) fail(at, "expected a range [low, high]");
    const Range r{number(v[0], at + "[0]"), number(v[1], at + "[1]")};
    if (r.lo > r.hi) fail(at, "low " + detail::formatNumber(r.lo) + " is above high " + detail::formatNumber(r.hi));
    return r;
  }

 private:
  std::string source_;
};

double unitScale(const PlanReader& reader, const json& units) {
  const std::string u = reader.text(units, "units");
  if (u == "mm") return 1.0;
  if (u == "cm") return 10.0;
  if (u == "in") return 25.4;
  reader.fail("units", "\"" + u + "\" is not a unit leafdig knows; use \"mm\", \"cm\" or \"in\"");
}

}  // namespace

PlantPlan parsePlantPlan(std::string_view text, const std::string& source, const std::filesystem::path& baseDir) {
  const json doc = detail::parseJsonLeniently(text, source);
  const PlanReader r(source);
  if (!doc.is_object()) r.fail("document", "expected a JSON object");
  const std::string format = r.text(r.required(doc, "format", ""), "format");
  if (format != kPlantPlanFormat)
    r.fail("format", "\"" + format + "\" is not a plant plan; expected \"" + kPlantPlanFormat + "\"");
  const double mm = unitScale(r, r.required(doc, "units", ""));

  PlantPlan plan;
  plan.id = r.text(r.required(doc, "id", ""), "id");
  if (plan.id.empty()) r.fail("id", "empty; name the plant (e.g. \"P-07\")");
  if (doc.contains("seed") && !doc.at("seed").is_null()) {
    if (!doc.at("seed").is_number_unsigned()) r.fail("seed", "expected a whole number ≥ 0");
    plan.seed = doc.at("seed").get<std::uint64_t>();
  }

  const json& stem = r.required(doc, "stem", "");
  if (stem.contains("points") && !stem.at("points").is_null()) {
    const json& points = stem.at("points");
    if (!points.is_array() || points.size() < 2)
      r.fail("stem.points", "expected at least two digitized points [x, y, z, diameter], base first");
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::string at = "stem.points[" + std::to_string(i) + "]";
      if (!points[i].is_array() || points[i].size() != 4) r.fail(at, "expected [x, y, z, diameter]");
      Eigen::Vector4d p;
      for (int k = 0; k < 4; ++k) p[k] = mm * r.number(points[i][static_cast<std::size_t>(k)], at);
      if (!(p[3] > 0.0)) r.fail(at, "the diameter must be greater than zero");
      if (p.head<3>().cwiseAbs().maxCoeff() > kMaxCoordinateMm || p[3] > kMaxStemDiameterMm)
        r.fail(at, "beyond a plant's 10 m or a stem's 1 m diameter; check the numbers and the plan's units");
      if (!plan.stem.points.empty() && (p.head<3>() - plan.stem.points.back().head<3>()).norm() < 1e-6)
        r.fail(at, "coincides with the point before it; remove one");
      plan.stem.points.push_back(p);
    }
    for (std::size_t i = 1; i < plan.stem.points.size(); ++i)
      plan.stem.heightMm += (plan.stem.points[i].head<3>() - plan.stem.points[i - 1].head<3>()).norm();
    plan.stem.baseDiameterMm = plan.stem.points.front()[3];
    plan.stem.topDiameterMm = plan.stem.points.back()[3];
  } else {
    plan.stem.heightMm = mm * r.within(r.required(stem, "height", "stem"), "stem.height", kMaxCoordinateMm / mm,
                                       "a plant's height (10 m)");
    plan.stem.baseDiameterMm = mm * r.within(r.required(stem, "base_diameter", "stem"), "stem.base_diameter",
                                             kMaxStemDiameterMm / mm, "a stem's diameter (1 m)");
    plan.stem.topDiameterMm = mm * r.within(r.required(stem, "top_diameter", "stem"), "stem.top_diameter",
                                            kMaxStemDiameterMm / mm, "a stem's diameter (1 m)");
  }

  if (doc.contains("phyllotaxis") && !doc.at("phyllotaxis").is_null()) {
    const json& p = doc.at("phyllotaxis");
    plan.divergenceDeg = r.optionalNumber(p, "divergence_deg", "phyllotaxis").value_or(kGoldenAngleDeg);
    plan.jitterDeg = r.optionalNumber(p, "jitter_deg", "phyllotaxis").value_or(0.0);
    if (plan.jitterDeg < 0.0) r.fail("phyllotaxis.jitter_deg", "must be zero or more degrees");
  }

  bool anyLibrary = false;
  const json& leaves = r.required(doc, "leaves", "");
  if (!leaves.is_array() || leaves.empty()) r.fail("leaves", "expected a non-empty array of leaves");
  std::set<int> ranks;
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    const json& l = leaves[i];
    const std::string at = "leaves[" + std::to_string(i) + "]";
    if (!l.is_object()) r.fail(at, "expected an object");
    LeafPlan leaf;
    const json& rank = r.required(l, "rank", at);
    if (!rank.is_number_integer() || rank.get<int>() < 1 || rank.get<int>() > 999)
      r.fail(at + ".rank", "expected a whole number from 1 (the lowest leaf) to 999");
    leaf.rank = rank.get<int>();
    if (!ranks.insert(leaf.rank).second)
      r.fail(at + ".rank", "rank " + std::to_string(leaf.rank) + " is given twice; each leaf has its own rank");
    const bool hasMarkers = l.contains("markers") && !l.at("markers").is_null();
    const bool hasLibrary = l.contains("library") && !l.at("library").is_null();
    if (hasMarkers == hasLibrary)
      r.fail(at, "give exactly one of \"markers\" (a leafdig.markers/1 file) or \"library\" (a draw from the store)");
    if (hasMarkers) {
      std::filesystem::path p = r.text(l.at("markers"), at + ".markers");
      leaf.markers = p.is_relative() ? baseDir / p : p;
    } else {
      const json& lib = l.at("library");
      if (!lib.is_object()) r.fail(at + ".library", "expected an object such as {\"type\": \"lower\"}");
      LibraryRequest req;
      if (lib.contains("type") && !lib.at("type").is_null()) req.type = r.text(lib.at("type"), at + ".library.type");
      if (lib.contains("position") && !lib.at("position").is_null()) {
        if (!lib.at("position").is_number_integer()) r.fail(at + ".library.position", "expected a whole number");
        req.position = lib.at("position").get<int>();
      }
      leaf.library = req;
      anyLibrary = true;
    }
    leaf.insertionHeightMm = mm * r.number(r.required(l, "insertion_height", at), at + ".insertion_height");
    if (leaf.insertionHeightMm < 0.0 || leaf.insertionHeightMm > plan.stem.heightMm)
      r.fail(at + ".insertion_height", detail::formatNumber(leaf.insertionHeightMm) + " mm is outside the stem (0 to " +
                                           detail::formatNumber(plan.stem.heightMm) +
                                           " mm): lower the insertion or raise stem.height");
    leaf.azimuthDeg = r.optionalNumber(l, "azimuth_deg", at);
    leaf.inclinationDeg = r.optionalNumber(l, "inclination_deg", at);
    if (leaf.inclinationDeg && (*leaf.inclinationDeg < 0.0 || *leaf.inclinationDeg > 180.0))
      r.fail(at + ".inclination_deg", "must be from 0 (upright) through 90 (flat) to 180 (hanging)");
    leaf.rollDeg = r.optionalNumber(l, "roll_deg", at).value_or(0.0);
    if (l.contains("scale") && !l.at("scale").is_null())
      leaf.scale = r.within(l.at("scale"), at + ".scale", 100.0, "a hundred times the leaf's size");
    leaf.bendDeg = r.optionalNumber(l, "bend_deg", at);
    plan.leaves.push_back(std::move(leaf));
  }
  std::sort(plan.leaves.begin(), plan.leaves.end(), [](const auto& a, const auto& b) { return a.rank < b.rank; });

  if (doc.contains("library") && !doc.at("library").is_null()) {
    const json& lib = doc.at("library");
    if (!lib.is_object()) r.fail("library", "expected an object with \"db\" and \"ranges\"");
    if (lib.contains("db") && !lib.at("db").is_null()) {
      std::filesystem::path p = r.text(lib.at("db"), "library.db");
      plan.libraryDb = (p.is_relative() ? baseDir / p : p).string();
    }
    if (lib.contains("ranges") && !lib.at("ranges").is_null()) {
      const json& rg = lib.at("ranges");
      plan.ranges.scale = r.range(rg, "scale", "library.ranges", plan.ranges.scale);
      if (!(plan.ranges.scale.lo > 0.0)) r.fail("library.ranges.scale", "scales must be greater than zero");
      plan.ranges.bendDeg = r.range(rg, "bend_deg", "library.ranges", plan.ranges.bendDeg);
      plan.ranges.azimuthJitterDeg = r.range(rg, "azimuth_jitter_deg", "library.ranges", plan.ranges.azimuthJitterDeg);
      if (rg.contains("inclination_deg") && !rg.at("inclination_deg").is_null())
        plan.ranges.inclinationDeg = r.range(rg, "inclination_deg", "library.ranges", {});
    }
  }
  if (anyLibrary && !plan.libraryDb)
    r.fail("library.db",
           "a leaf draws from the organ library, so the plan must name the store (\"library\": "
           "{\"db\": \"station.sqlite\"})");

  if (doc.contains("growth") && !doc.at("growth").is_null()) {
    const json& g = doc.at("growth");
    GrowthPlan growth;
    if (g.contains("time_unit") && !g.at("time_unit").is_null()) {
      growth.timeUnit = r.text(g.at("time_unit"), "growth.time_unit");
      if (growth.timeUnit != "days" && growth.timeUnit != "degree_days")
        r.fail("growth.time_unit", "\"" + growth.timeUnit + "\": use \"days\" or \"degree_days\" (thermal time)");
    }
    growth.plastochron = r.positive(r.required(g, "plastochron", "growth"), "growth.plastochron");
    const json& leaf = r.required(g, "leaf", "growth");
    growth.leafRate = r.within(r.required(leaf, "rate", "growth.leaf"), "growth.leaf.rate", kMaxGrowthRate,
                               "any growth rate (1 000 per time unit)");
    growth.leafMidpoint = r.positive(r.required(leaf, "midpoint", "growth.leaf"), "growth.leaf.midpoint");
    const json& stemGrowth = r.required(g, "stem", "growth");
    growth.stemRate = r.within(r.required(stemGrowth, "rate", "growth.stem"), "growth.stem.rate", kMaxGrowthRate,
                               "any growth rate (1 000 per time unit)");
    growth.stemMidpoint = r.positive(r.required(stemGrowth, "midpoint", "growth.stem"), "growth.stem.midpoint");
    growth.widthAtEmergence = r.optionalNumber(g, "width_at_emergence", "growth").value_or(0.4);
    if (!(growth.widthAtEmergence > 0.0 && growth.widthAtEmergence < 1.0))
      r.fail("growth.width_at_emergence", "must be between 0 and 1 (width grows less than length)");
    plan.growth = growth;
  }
  return plan;
}

PlantPlan readPlantPlan(const std::filesystem::path& path) {
  return parsePlantPlan(detail::readInputText(path), path.string(), path.parent_path());
}

}  // namespace leafdig::model
