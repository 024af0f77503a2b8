#include "leafdig/model/plant/plant.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include "draws.hpp"
#include "leaf_shaping.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/model/plant/plant_frame.hpp"

namespace leafdig::model {

namespace {

constexpr double kPi = 3.14159265358979323846;
double radians(double deg) {
  return deg * kPi / 180.0;
}

// One generator per leaf, seeded by the plan seed and the leaf's rank (draws.hpp).
class Draws {
 public:
  Draws(std::uint64_t seed, int rank) : draws_(seed, static_cast<std::uint64_t>(rank)) {}
  double uniform() { return draws_.uniform(); }
  double in(const Range& r) { return draws_.in(r.lo, r.hi); }

 private:
  detail::Draws draws_;
};

void forEachPoint(MarkerSet& m, const std::function<void(Eigen::Vector3d&)>& f) {
  f(m.tipMm);
  for (auto& row : m.rows)
    for (auto& p : row.pointsMm) f(p);
}

void scaleThickness(MarkerSet& m, double factor) {
  const auto scale = [factor](std::optional<double>& v) {
    if (v) *v *= factor;
  };
  scale(m.edgeThicknessMm);
  for (auto& row : m.rows) {
    scale(row.midribThicknessMm);
    scale(row.veinOriginThicknessMm);
    scale(row.edgeThicknessMm);
    for (auto& t : row.measuredThicknessMm) scale(t);
  }
}

StemPoint stemAt(const Vein& stem, double fraction) {
  // Arc length through 512 samples, then the parameter at `fraction` of it.
  constexpr int kSamples = 512;
  std::vector<double> length{0.0};
  Eigen::Vector3d previous = stem.curve.center(0.0);
  for (int i = 1; i <= kSamples; ++i) {
    const Eigen::Vector3d p = stem.curve.center(static_cast<double>(i) / kSamples);
    length.push_back(length.back() + (p - previous).norm());
    previous = p;
  }
  const double want = std::clamp(fraction, 0.0, 1.0) * length.back();
  const auto it = std::lower_bound(length.begin(), length.end(), want);
  const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - length.begin()));
  const double span = length[i] - length[i - 1];
  const double t = (static_cast<double>(i - 1) + (span > 0 ? (want - length[i - 1]) / span : 0.0)) / kSamples;
  const BallBSplineCurve::Jet jet = stem.curve.jet(std::clamp(t, 0.0, 1.0));
  return {jet.c, jet.dc.normalized(), jet.r};
}

// The rigid motion from the shaped leaf frame to the plant: the base-to-tip chord at
// `inclination` from the stem's local axis, in the plane of that axis and the `azimuth`
// direction (horizontal, made perpendicular to the axis), the leaf's width across that
// plane (adaxial side up when flat on an upright stem), then `roll` about the chord. The
// base sits on the stem's surface on the azimuth's side.
Eigen::Isometry3d placeLeaf(const Eigen::Vector3d& tipInLeafFrame, const StemPoint& at, double azimuthDeg,
                            double inclinationDeg, double rollDeg, Eigen::Vector3d& base) {
  const Eigen::Vector3d a = tipInLeafFrame.normalized();
  Eigen::Vector3d b = Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX().dot(a) * a;
  b.normalize();
  Eigen::Matrix3d leaf;
  leaf << a, b, b.cross(a);

  const double phi = radians(azimuthDeg);
  const double theta = radians(inclinationDeg);
  const Eigen::Vector3d& axis = at.tangent;
  Eigen::Vector3d u(std::cos(phi), std::sin(phi), 0.0);
  u = (u - u.dot(axis) * axis).normalized();
  const Eigen::Vector3d aw = std::cos(theta) * axis + std::sin(theta) * u;
  const Eigen::Vector3d bw0 = u.cross(axis).normalized();
  const Eigen::Vector3d bw = Eigen::AngleAxisd(radians(rollDeg), aw) * bw0;
  Eigen::Matrix3d world;
  world << aw, bw, bw.cross(aw);

  base = at.center + at.radius * u;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = world * leaf.transpose();
  t.translation() = base;
  return t;
}

// The stem's balls: digitized points moved to the origin, or a straight taper up +Z; both
// stretched about the base by the growth factor.
std::vector<Ball> stemBalls(const StemPlan& stem, double heightFactor) {
  std::vector<Ball> balls;
  if (!stem.points.empty()) {
    const Eigen::Vector3d origin = stem.points.front().head<3>();
    for (const auto& p : stem.points) balls.push_back({(p.head<3>() - origin) * heightFactor, p[3] / 2});
    return balls;
  }
  for (int i = 0; i <= 2; ++i) {
    const double f = i / 2.0;
    const double radius = (stem.baseDiameterMm + (stem.topDiameterMm - stem.baseDiameterMm) * f) / 2;
    balls.push_back({Eigen::Vector3d(0, 0, stem.heightMm * heightFactor * f), radius});
  }
  return balls;
}

bool matches(const LibraryLeaf& leaf, const LibraryRequest& request) {
  if (!request.type.empty() && leaf.markers.leaf.type != request.type) return false;
  if (request.position && leaf.markers.leaf.position != request.position) return false;
  return true;
}

}  // namespace

namespace detail {

MarkerSet toLeafFrame(const MarkerSet& markers) {
  const LeafModel model = buildLeafModel(markers);
  const Eigen::Isometry3d toLeaf = leafFrameFromDigitizer(model);
  MarkerSet out = markers;
  forEachPoint(out, [&](Eigen::Vector3d& p) { p = toLeaf * p; });
  return out;
}

MarkerSet shapeLeaf(const MarkerSet& leafFrame, double scale, double lengthFactor, double widthFactor, double bendDeg) {
  MarkerSet m = leafFrame;
  const double sy = scale * lengthFactor;
  const double sx = scale * widthFactor;
  forEachPoint(m, [&](Eigen::Vector3d& p) { p = Eigen::Vector3d(p.x() * sx, p.y() * sy, p.z() * sy); });
  scaleThickness(m, sy);
  const double yTip = m.tipMm.y();
  if (bendDeg != 0.0 && yTip > 0.0) {
    forEachPoint(m, [&](Eigen::Vector3d& p) {
      if (p.y() <= 0.0) return;
      const double s = p.y() / yTip;
      const double a = -radians(bendDeg) * s * s;
      p = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()) * p;
    });
  }
  return m;
}

}  // namespace detail

StemPoint stemPointAt(const Plant& plant, double fraction) {
  if (!plant.stem) return {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.0};
  return stemAt(*plant.stem, fraction);
}

double logistic(double rate, double midpoint, double tau) {
  return 1.0 / (1.0 + std::exp(-rate * (tau - midpoint)));
}

double midribLengthMm(const LeafModel& leaf) {
  for (const Vein& v : leaf.veins) {
    if (v.name != "midrib") continue;
    double length = 0.0;
    Eigen::Vector3d previous = v.curve.center(0.0);
    constexpr int kSteps = 256;
    for (int i = 1; i <= kSteps; ++i) {
      const Eigen::Vector3d p = v.curve.center(static_cast<double>(i) / kSteps);
      length += (p - previous).norm();
      previous = p;
    }
    return length;
  }
  return 0.0;
}

double bladeWidthMm(const MarkerSet& markers) {
  double width = 0.0;
  for (const auto& row : markers.rows) width = std::max(width, (row.pointsMm[0] - row.pointsMm[6]).norm());
  return width;
}

PlantBuilder::PlantBuilder(PlantPlan plan, std::vector<LibraryLeaf> library) : plan_(std::move(plan)) {
  for (const LeafPlan& lp : plan_.leaves) {
    // One generator per leaf; always the same draws in the same order, used or not.
    Draws draws(plan_.seed, lp.rank);
    const double jitter = plan_.jitterDeg * (2.0 * draws.uniform() - 1.0);
    const double pick = draws.uniform();
    const double scale = draws.in(plan_.ranges.scale);
    const double bend = draws.in(plan_.ranges.bendDeg);
    const double azimuthJitter = draws.in(plan_.ranges.azimuthJitterDeg);
    const double inclination = plan_.ranges.inclinationDeg ? draws.in(*plan_.ranges.inclinationDeg) : 0.0;
    if (!plan_.ranges.inclinationDeg) (void)draws.uniform();

    Resolved r{lp, {}, {}, 0, 0, 1, 0};
    const bool fromLibrary = !lp.markers.has_value();
    MarkerSet markers;
    if (fromLibrary) {
      std::vector<const LibraryLeaf*> candidates;
      for (const LibraryLeaf& l : library)
        if (matches(l, *lp.library)) candidates.push_back(&l);
      if (candidates.empty()) {
        std::string what = lp.library->type.empty() ? std::string("any") : "a \"" + lp.library->type + "\"";
        if (lp.library->position) what += " position-" + std::to_string(*lp.library->position);
        throw InputError("leaf rank " + std::to_string(lp.rank) + " asks the organ library for " + what +
                         " leaf, but the library (" + std::to_string(library.size()) +
                         " approved leaves) has none: approve a matching session (leafdig sessions approve) or "
                         "change the leaf's \"library\" request");
      }
      const auto index = std::min(candidates.size() - 1, static_cast<std::size_t>(pick * candidates.size()));
      markers = candidates[index]->markers;
      r.source = candidates[index]->source;
    } else {
      markers = readMarkersFile(*lp.markers);
      r.source = lp.markers->filename().string();
    }
    r.leafFrameMarkers = detail::toLeafFrame(markers);
    const double phyllotaxis = std::fmod(lp.rank * plan_.divergenceDeg + jitter, 360.0);
    r.azimuthDeg = lp.azimuthDeg ? *lp.azimuthDeg : phyllotaxis + (fromLibrary ? azimuthJitter : 0.0);
    r.azimuthDeg = std::fmod(r.azimuthDeg + 360.0, 360.0);
    r.inclinationDeg = lp.inclinationDeg             ? *lp.inclinationDeg
                       : plan_.ranges.inclinationDeg ? inclination
                                                     : kDefaultInclinationDeg;
    r.scale = lp.scale ? *lp.scale : (fromLibrary ? scale : 1.0);
    r.bendDeg = lp.bendDeg ? *lp.bendDeg : (fromLibrary ? bend : 0.0);
    leaves_.push_back(std::move(r));
  }
}

Plant PlantBuilder::build(std::optional<double> time) const {
  if (time && !plan_.growth) {
    throw InputError("plant " + plan_.id + " has no \"growth\" in its plan: a time needs growth parameters");
  }
  double heightFactor = 1.0;
  if (time) {
    if (!std::isfinite(*time))
      throw InputError("the time " + std::to_string(*time) + " is not a finite number: give a time in " +
                       (plan_.growth->timeUnit.empty() ? std::string("days") : plan_.growth->timeUnit));
    heightFactor = logistic(plan_.growth->stemRate, plan_.growth->stemMidpoint, *time);
    if (!(heightFactor >= kMinGrowthFactor)) {
      std::ostringstream out;
      out << "plant " << plan_.id << " at time " << *time << " has a stem " << heightFactor
          << " of its final height: it has not emerged yet (its stem's growth midpoint is "
          << plan_.growth->stemMidpoint << "). Choose a later time";
      throw InputError(out.str());
    }
  }
  const double stemHeight = plan_.stem.heightMm * heightFactor;
  Plant plant{plan_.id,
              time,
              plan_.growth ? plan_.growth->timeUnit : "",
              stemHeight,
              plan_.stem.baseDiameterMm,
              plan_.stem.topDiameterMm,
              Vein{"stem", BallBSplineCurve::interpolate(stemBalls(plan_.stem, heightFactor))},
              {},
              {}};

  for (const Resolved& r : leaves_) {
    double lengthFactor = 1.0;
    double widthFactor = 1.0;
    if (time) {
      const GrowthPlan& g = *plan_.growth;
      const double tau = *time - (r.plan.rank - 1) * g.plastochron;
      if (tau < 0.0) continue;  // not yet appeared
      lengthFactor = logistic(g.leafRate, g.leafMidpoint, tau);
      if (!(lengthFactor >= kMinGrowthFactor)) continue;  // not yet visible: a leaf of no size
      widthFactor = g.widthAtEmergence + (1.0 - g.widthAtEmergence) * lengthFactor;
    }
    PlacedLeaf leaf;
    leaf.rank = r.plan.rank;
    leaf.source = r.source;
    leaf.insertionHeightMm = r.plan.insertionHeightMm * heightFactor;
    leaf.azimuthDeg = r.azimuthDeg;
    leaf.inclinationDeg = r.inclinationDeg;
    leaf.rollDeg = r.plan.rollDeg;
    leaf.scale = r.scale;
    leaf.bendDeg = r.bendDeg;
    leaf.lengthFactor = lengthFactor;
    leaf.widthFactor = widthFactor;
    const MarkerSet shaped = detail::shapeLeaf(r.leafFrameMarkers, r.scale, lengthFactor, widthFactor, r.bendDeg);
    const double fraction = plan_.stem.heightMm > 0 ? r.plan.insertionHeightMm / plan_.stem.heightMm : 0.0;
    Eigen::Vector3d base;
    leaf.placement =
        placeLeaf(shaped.tipMm, stemAt(*plant.stem, fraction), r.azimuthDeg, r.inclinationDeg, r.plan.rollDeg, base);
    leaf.model = transformed(buildLeafModel(shaped), leaf.placement);
    leaf.base = base;
    leaf.tip = leaf.placement * shaped.tipMm;
    leaf.lengthMm = midribLengthMm(leaf.model);
    leaf.widthMm = bladeWidthMm(shaped);
    plant.leaves.push_back(std::move(leaf));
  }
  return plant;
}

Plant singleLeafPlant(const LeafModel& leaf, int rank, std::string source) {
  Plant plant{leaf.markers.leaf.id.empty() ? "leaf" : leaf.markers.leaf.id,
              std::nullopt,
              "",
              0.0,
              0.0,
              0.0,
              std::nullopt,
              {},
              {}};
  PlacedLeaf l;
  l.rank = rank;
  l.source = std::move(source);
  l.model = leaf;
  l.base = leaf.markers.rows.back().pointsMm[kMidribColumn];
  l.tip = leaf.markers.tipMm;
  l.insertionHeightMm = 0.0;  // not on a stem
  const Eigen::Vector3d chord = l.tip - l.base;
  l.azimuthDeg = azimuthDeg(chord);
  l.inclinationDeg = inclinationDeg(chord);
  l.lengthMm = midribLengthMm(leaf);
  l.widthMm = bladeWidthMm(leaf.markers);
  plant.leaves.push_back(std::move(l));
  return plant;
}

LeafMesh meshPlant(const Plant& plant, const MeshResolution& resolution) {
  MeshOptions options;
  options.resolution = resolution;
  return meshPlant(plant, options);
}

LeafMesh meshPlant(const Plant& plant, const MeshOptions& options) {
  LeafMesh out;
  const auto axisMesh = [&](const Vein& axis) {
    switch (options.method) {
      case MeshMethod::Uniform:
        return meshVein(axis, subdivideSpans(axis.curve.dataParameters(), 24),
                        std::max(12, options.resolution.ringVertices), CapStyle::None, 0, out.warnings);
      case MeshMethod::Seed: return meshVeinSeed(axis, options.seed, CapStyle::None, out.warnings);
      case MeshMethod::Adaptive: return meshVeinAdaptive(axis, options.maxErrorMm, CapStyle::None, out.warnings);
    }
    return Mesh{};
  };
  if (plant.stem) out.organs.push_back({"plant/stem", OrganKind::Vein, axisMesh(*plant.stem), 0});
  for (const Vein& branch : plant.branches)
    out.organs.push_back({"plant/" + branch.name, OrganKind::Vein, axisMesh(branch), 0});
  for (const PlacedLeaf& leaf : plant.leaves) {
    LeafMesh m = meshLeaf(leaf.model, options);
    const std::string prefix = "plant/leaf-" + std::to_string(leaf.rank) + "/";
    for (Organ& o : m.organs) {
      o.name = prefix + o.name;
      o.leafRank = leaf.rank;
      out.organs.push_back(std::move(o));
    }
    for (Warning& w : m.warnings) {
      w.organ = prefix + w.organ;
      out.warnings.push_back(std::move(w));
    }
  }
  return out;
}

}  // namespace leafdig::model
