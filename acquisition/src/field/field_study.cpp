#include "leafdig/acquisition/field/field_study.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <sstream>

#include "field/numbers.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/field/correction.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/marker_points.hpp"
#include "leafdig/model/plant/plant_survey.hpp"

namespace leafdig::acquisition {
namespace {

namespace m = leafdig::model;
using Eigen::Vector3d;
using PointMap = std::function<Vector3d(const Vector3d&)>;

// A leaf's markers or a plant with every position through `f` (model::forEachPoint's order).
template <class Set>
Set mapped(Set s, const PointMap& f) {
  m::forEachPoint(s, [&](Vector3d& p) { p = f(p); });
  return s;
}

std::vector<Vector3d> pointsOf(const m::MarkerSet& s) {
  std::vector<Vector3d> out;
  m::forEachPoint(s, [&](const Vector3d& p) { out.push_back(p); });
  return out;
}

double rms(const std::vector<Vector3d>& got, const std::vector<Vector3d>& truth) {
  double sum = 0;
  for (std::size_t i = 0; i < got.size(); ++i) sum += (got[i] - truth[i]).squaredNorm();
  return got.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(got.size()));
}

// After the rigid motion that fits `got` to `truth` best: the shape's error, not its place.
double shapeRms(const std::vector<Vector3d>& got, const std::vector<Vector3d>& truth) {
  const auto n = static_cast<Eigen::Index>(got.size());
  Eigen::Matrix3Xd a(3, n), b(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    a.col(i) = got[static_cast<std::size_t>(i)];
    b.col(i) = truth[static_cast<std::size_t>(i)];
  }
  const Eigen::Matrix4d t = Eigen::umeyama(a, b, false);
  double sum = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    sum += ((t.topLeftCorner<3, 3>() * a.col(i) + t.topRightCorner<3, 1>()) - b.col(i)).squaredNorm();
  return std::sqrt(sum / static_cast<double>(n));
}

double bladeArea(const m::MarkerSet& s) {
  return m::convergedBladeArea(m::buildLeafModel(s).blade, Vector3d::UnitZ()).areaMm2;
}

double percentOff(double got, double truth) {
  return truth > 0 ? 100.0 * std::abs(got - truth) / truth : 0.0;
}

double angleOff(double a, double b) {
  return std::abs(std::remainder(a - b, 360.0));
}

struct Noise {
  std::mt19937_64 rng;
  double sigma = 0;
  Vector3d operator()() {
    if (sigma <= 0) return Vector3d::Zero();
    std::normal_distribution<double> n(0.0, sigma);
    const double x = n(rng), y = n(rng), z = n(rng);
    return {x, y, z};
  }
};

Vector3d reported(const devices::sim::FieldDistortion& field, const Vector3d& p) {
  const devices::Vec3 r = field.reportedPosition({p.x(), p.y(), p.z()});
  return {r[0], r[1], r[2]};
}

// The jig's divots where `pose` puts it, as the bent field reports them, with noise.
std::vector<Vector3d> jigReport(const FieldStudyInput& in, const m::Jig& jig, const Eigen::Isometry3d& pose,
                                Noise* noise, bool bent = true) {
  std::vector<Vector3d> out;
  for (const m::JigPoint& p : jig.points) {
    const Vector3d truth = pose * p.pointMm;
    out.push_back((bent ? reported(in.field, truth) : truth) + (noise ? (*noise)() : Vector3d::Zero()));
  }
  return out;
}

// `n` divots spread over the jig: every (N/n)-th in its order, so the levels stay in.
m::Jig spread(const m::Jig& jig, int n) {
  const auto total = static_cast<int>(jig.points.size());
  if (n < 4 || n > total)
    throw m::InputError("a jig count of " + std::to_string(n) + " divots: the jig has " + std::to_string(total) +
                        " and a fit needs at least 4");
  m::Jig out;
  out.name = jig.name;
  for (int k = 0; k < n; ++k)
    out.points.push_back(jig.points[static_cast<std::size_t>((static_cast<long>(k) * total) / n)]);
  return out;
}

void accumulate(CaptureError& into, const CaptureError& e, double share) {
  into.markerRmsMm += e.markerRmsMm * share;
  into.shapeRmsMm += e.shapeRmsMm * share;
  into.areaErrorPercent += e.areaErrorPercent * share;
}

// `truth`: the true leaf's points (pointsOf) and its blade's area.
CaptureError leafError(const m::MarkerSet& got, const std::vector<Vector3d>& truth, double truthArea) {
  const auto g = pointsOf(got);
  return {rms(g, truth), shapeRms(g, truth), percentOff(bladeArea(got), truthArea)};
}

struct PlantTruth {
  std::vector<Vector3d> nodes;
  std::map<int, m::LeafPose> poses;
  double area = 0;
};

PlantTruth plantMeasures(const m::PlantMarkers& p) {
  const m::PlantSurvey s = m::surveyPlant(p);
  PlantTruth t;
  for (const m::SurveyedNode& n : s.nodes) t.nodes.push_back(n.pointMm);
  for (const m::SurveyedLeaf& l : s.leaves) {
    if (l.pose) t.poses[l.node] = *l.pose;
    if (l.areaMm2) t.area += *l.areaMm2;
  }
  return t;
}

PlantError plantError(const m::PlantMarkers& got, const PlantTruth& truth) {
  const PlantTruth g = plantMeasures(got);
  PlantError e;
  e.nodeRmsMm = rms(g.nodes, truth.nodes);
  double sum = 0;
  int count = 0;
  for (const auto& [node, pose] : truth.poses) {
    const auto at = g.poses.find(node);
    if (at == g.poses.end()) continue;
    sum += angleOff(at->second.azimuthDeg, pose.azimuthDeg) + angleOff(at->second.inclinationDeg, pose.inclinationDeg);
    count += 2;
  }
  e.leafAngleDeg = count ? sum / count : 0.0;
  e.areaErrorPercent = percentOff(g.area, truth.area);
  return e;
}

void accumulate(PlantError& into, const PlantError& e, double share) {
  into.nodeRmsMm += e.nodeRmsMm * share;
  into.leafAngleDeg += e.leafAngleDeg * share;
  into.areaErrorPercent += e.areaErrorPercent * share;
}

std::string mostOften(const std::map<std::string, int>& votes) {
  std::string best;
  int n = -1;
  for (const auto& [model, count] : votes)
    if (count > n) {
      best = model;
      n = count;
    }
  return best;
}

}  // namespace

FieldStudyResult runFieldStudy(const FieldStudyInput& in) {
  if (in.repeats < 1) throw m::InputError("a study needs at least one repeat");
  FieldStudyResult r;
  r.fieldName = in.fieldName;
  r.jigName = in.jig.name;
  r.jigPoints = static_cast<int>(in.jig.points.size());
  r.repeats = in.repeats;
  r.noiseMm = in.noiseMm;
  r.seed = in.seed;
  std::vector<int> counts = in.jigCounts;
  if (counts.empty()) {
    for (int n : {6, 8, 12, 16})
      if (n < r.jigPoints) counts.push_back(n);
    counts.push_back(r.jigPoints);
  }
  const double share = 1.0 / in.repeats;
  const PointMap bent = [&](const Vector3d& p) { return reported(in.field, p); };

  // The truths, once.
  std::vector<double> truthAreas;
  std::vector<std::vector<Vector3d>> truthPoints;
  for (const auto& [name, leaf] : in.leaves) {
    truthAreas.push_back(bladeArea(leaf));
    truthPoints.push_back(pointsOf(leaf));
    r.leaves.push_back({name, static_cast<int>(truthPoints.back().size()), {}, {}, {}});
  }
  std::optional<PlantTruth> plantTruth;
  if (in.plant) {
    plantTruth = plantMeasures(in.plant->second);
    r.plant = PlantStudyRow{in.plant->first,
                            static_cast<int>(plantTruth->nodes.size()),
                            static_cast<int>(plantTruth->poses.size()),
                            {},
                            {},
                            {}};
  }
  r.fieldRmsMm = m::fitJig(in.jig, jigReport(in, in.jig, in.leafJigPose, nullptr)).rmsMm;
  std::vector<std::map<std::string, int>> countVotes(counts.size());
  std::map<std::string, int> votes;
  r.counts.resize(counts.size());

  for (int rep = 0; rep < in.repeats; ++rep) {
    Noise noise{std::mt19937_64(in.seed * 1000003ULL + static_cast<std::uint64_t>(rep)), in.noiseMm};
    // Vector3d named: `p + noise()` alone is an Eigen expression holding the temporary.
    const PointMap noisy = [&](const Vector3d& p) -> Vector3d { return p + noise(); };
    // The check where the leaves lie: what it reports and the correction it chooses.
    const std::vector<Vector3d> divots = jigReport(in, in.jig, in.leafJigPose, &noise);
    r.checkRmsMm += m::fitJig(in.jig, divots).rmsMm * share;
    r.cleanCheckRmsMm += m::fitJig(in.jig, jigReport(in, in.jig, in.leafJigPose, &noise, false)).rmsMm * share;
    const m::CorrectionChoice choice = m::chooseCorrection(in.jig, divots);
    ++votes[choice.correction.name()];
    r.holdoutRmsMm += choice.holdoutRmsMm * share;
    const PointMap correct = [&](const Vector3d& p) { return choice.correction.apply(p); };

    std::vector<std::vector<Vector3d>> bentLeaves;  // each leaf as the bent field reports it, with noise
    for (std::size_t i = 0; i < in.leaves.size(); ++i) {
      const m::MarkerSet& truth = in.leaves[i].second;
      const m::MarkerSet clean = mapped(truth, noisy);
      const m::MarkerSet uncorrected = mapped(mapped(truth, bent), noisy);
      const m::MarkerSet corrected = mapped(uncorrected, correct);
      accumulate(r.leaves[i].clean, leafError(clean, truthPoints[i], truthAreas[i]), share);
      accumulate(r.leaves[i].uncorrected, leafError(uncorrected, truthPoints[i], truthAreas[i]), share);
      accumulate(r.leaves[i].corrected, leafError(corrected, truthPoints[i], truthAreas[i]), share);
      bentLeaves.push_back(pointsOf(uncorrected));
    }

    // Fewer divots: the model chosen, its held-out error, and what it leaves on the leaves.
    for (std::size_t c = 0; c < counts.size(); ++c) {
      const m::Jig few = spread(in.jig, counts[c]);
      const m::CorrectionChoice fewChoice = m::chooseCorrection(few, jigReport(in, few, in.leafJigPose, &noise));
      ++countVotes[c][fewChoice.correction.name()];
      r.counts[c].points = counts[c];
      r.counts[c].holdoutRmsMm += fewChoice.holdoutRmsMm * share;
      r.counts[c].holdoutMaxMm += fewChoice.holdoutMaxMm * share;
      double sum = 0, n = 0;  // the leaves' shape errors, pooled
      for (std::size_t i = 0; i < in.leaves.size(); ++i) {
        std::vector<Vector3d> got;
        for (const Vector3d& p : bentLeaves[i]) got.push_back(fewChoice.correction.apply(p));
        const double e = shapeRms(got, truthPoints[i]);
        sum += e * e * static_cast<double>(got.size());
        n += static_cast<double>(got.size());
      }
      r.counts[c].leafShapeRmsMm += (n > 0 ? std::sqrt(sum / n) : 0.0) * share;
    }

    if (in.plant) {
      const std::vector<Vector3d> plantDivots = jigReport(in, in.jig, in.plantJigPose, &noise);
      const m::CorrectionChoice plantChoice = m::chooseCorrection(in.jig, plantDivots);
      const PointMap correctPlant = [&](const Vector3d& p) { return plantChoice.correction.apply(p); };
      const m::PlantMarkers& truth = in.plant->second;
      const m::PlantMarkers uncorrected = mapped(mapped(truth, bent), noisy);
      accumulate(r.plant->clean, plantError(mapped(truth, noisy), *plantTruth), share);
      accumulate(r.plant->uncorrected, plantError(uncorrected, *plantTruth), share);
      accumulate(r.plant->corrected, plantError(mapped(uncorrected, correctPlant), *plantTruth), share);
      int outside = 0, all = 0;
      m::forEachPoint(uncorrected, [&](const Vector3d& p) {
        outside += plantChoice.correction.inside(p) ? 0 : 1;
        ++all;
      });
      r.plant->outsidePercent += 100.0 * outside / std::max(all, 1) * share;
    }
  }
  r.model = mostOften(votes);
  for (std::size_t c = 0; c < counts.size(); ++c) r.counts[c].model = mostOften(countVotes[c]);
  return r;
}

namespace {

// The leaves' table's rows: each leaf clean, uncorrected and corrected.
void leafRows(std::ostream& o, const FieldStudyResult& r) {
  for (const LeafStudyRow& l : r.leaves) {
    const std::pair<const char*, const CaptureError*> rows[] = {
        {"clean", &l.clean}, {"uncorrected", &l.uncorrected}, {"corrected", &l.corrected}};
    for (const auto& [name, e] : rows)
      o << "| " << l.leaf << " | " << l.markers << " | " << name << " | " << detail::fixed(e->markerRmsMm, 2) << " | "
        << detail::fixed(e->shapeRmsMm, 2) << " | " << detail::fixed(e->areaErrorPercent, 3) << " |\n";
  }
}

}  // namespace

std::string fieldStudyAccuracySection(const FieldStudyResult& r, const std::string& command) {
  std::ostringstream o;
  o << "\n## Through a bent field\n\n"
    << "Everything above assumes a clean magnetic field. Metal near the transmitter bends it, and every point is "
       "then off by a static error no noise model holds (docs/devices.md, \"The field\"). The sample leaves "
       "through "
    << r.fieldName << ", captured in a clean field, through the bent one uncorrected, and through the correction a "
    << "check of the " << r.jigPoints << "-divot jig chose (" << r.model << ", held out "
    << detail::fixed(r.holdoutRmsMm, 2) << " mm RMS); σ = " << detail::fixed(r.noiseMm, 2) << " mm, the mean of "
    << r.repeats << " noise draws (`" << command << "`: [field-study.md](field-study.md) has the plant and the "
    << "jig's count too). The shape RMS is after the best rigid fit, what a leaf's model feels.\n\n"
    << "| leaf | markers | capture | marker RMS (mm) | shape RMS (mm) | area error (%) |\n|---|---|---|---|---|---|\n";
  leafRows(o, r);
  o << "\nA capture through a check states it: its area interval widens by the correction's held-out error in "
       "quadrature with the digitizer's noise (docs/devices.md, \"Captures through a checked field\").\n";
  return o.str();
}

std::string fieldStudyMarkdown(const FieldStudyResult& r, const std::string& command) {
  std::ostringstream o;
  o << "# Captures through a bent field\n\n"
    << "Generated by `" << command << "`; do not edit by hand (docs/devices.md, \"Checking the field\", says how a "
    << "lab checks its own).\n"
    << "The field: " << r.fieldName << ". The jig: " << r.jigName << ", " << r.jigPoints
    << " divots, laid where the leaves lie (and again where the plant stands). Every position the digitizer "
    << "reports is the field's report of the truth plus noise of σ = " << detail::fixed(r.noiseMm, 2)
    << " mm per coordinate; each number is the mean of " << r.repeats << " noise draws (seed " << r.seed
    << "). *Clean*: the truth plus noise. *Uncorrected*: the bent field's report. *Corrected*: that report "
    << "through the correction the simulated check chose. The marker is the sensor: a stylus's tip offset "
    << "turned by the field is in the captures the tests make, not here.\n\n";

  o << "## The check\n\n"
    << "| | RMS of the jig's rigid fit |\n|---|---|\n"
    << "| the check reports (bent field, noise) | " << detail::fixed(r.checkRmsMm, 2) << " mm |\n"
    << "| the bent field's truth at the divots (no noise) | " << detail::fixed(r.fieldRmsMm, 2) << " mm |\n"
    << "| reported ÷ truth | " << detail::fixed(r.fieldRmsMm > 0 ? r.checkRmsMm / r.fieldRmsMm : 0.0, 2)
    << " (target: within 0.8–1.2) |\n"
    << "| the same check in a clean field | " << detail::fixed(r.cleanCheckRmsMm, 2) << " mm |\n\n"
    << "The correction chosen: " << r.model << ", held-out error " << detail::fixed(r.holdoutRmsMm, 2)
    << " mm RMS.\n\n";

  o << "## Leaves\n\n"
    << "Target: corrected within the clean field's error (markers ≤ 1 mm RMS, area ≤ 0.5 %) where the "
       "uncorrected capture is several millimetres off. The marker RMS is absolute, in the transmitter's frame: a "
       "jig's rigid fit cannot tell a field that shifts every point alike from the jig lying elsewhere, so the "
       "corrected points keep that common shift (the corrected marker RMS); a leaf's model and measures are made in "
       "its own frame and do not feel it. The shape RMS (after the best rigid fit) is the error they feel.\n\n"
    << "| leaf | markers | capture | marker RMS (mm) | shape RMS (mm) | area error (%) |\n|---|---|---|---|---|---|\n";
  leafRows(o, r);
  if (r.plant) {
    o << "\n## The plant\n\n"
      << "In the plant frame (made from its landmarks, bent with the rest): the nodes' positions, the leaves' "
         "azimuth and inclination (mean |Δ|), the full leaves' total area.\n\n"
      << "| plant | nodes | leaves | capture | node RMS (mm) | leaf angles (°) | area error (%) |\n"
      << "|---|---|---|---|---|---|---|\n";
    const std::pair<const char*, const PlantError*> rows[] = {
        {"clean", &r.plant->clean}, {"uncorrected", &r.plant->uncorrected}, {"corrected", &r.plant->corrected}};
    for (const auto& [name, e] : rows)
      o << "| " << r.plant->plant << " | " << r.plant->nodes << " | " << r.plant->leaves << " | " << name << " | "
        << detail::fixed(e->nodeRmsMm, 2) << " | " << detail::fixed(e->leafAngleDeg, 2) << " | "
        << detail::fixed(e->areaErrorPercent, 3) << " |\n";
    o << "\n"
      << detail::fixed(r.plant->outsidePercent, 0)
      << " % of the plant's points lay outside the box of the jig's divots, where the correction is held at its "
         "edge (clamped, as `field check` documents): a jig laid over the whole plant's volume corrects them too.\n";
  }
  o << "\n## How many divots\n\n"
    << "The jig's divots spread over it (every k-th in its order, so each level stays in), checked as above: the "
       "model chosen most often, its held-out error (five-fold, as `field check` reports it), and the error left "
       "on the leaves' shape by that correction (against their truth, after the best rigid fit).\n\n"
    << "| divots | model | held-out RMS (mm) | held-out largest (mm) | leaves' shape after it (mm RMS) |\n"
    << "|---|---|---|---|---|\n";
  for (const JigCountRow& c : r.counts)
    o << "| " << c.points << " | " << c.model << " | " << detail::fixed(c.holdoutRmsMm, 2) << " | "
      << detail::fixed(c.holdoutMaxMm, 2) << " | " << detail::fixed(c.leafShapeRmsMm, 2) << " |\n";
  return o.str();
}

}  // namespace leafdig::acquisition
