#include "leafdig/model/accuracy.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iomanip>
#include <limits>
#include <mutex>
#include <sstream>
#include <thread>

#include "draws.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf_model.hpp"
#include "leafdig/model/metrics.hpp"
#include "segment.hpp"

namespace leafdig::model {

namespace {

const Eigen::Vector3d kUp(0.0, 0.0, 1.0);

// The blade area of a marker set at a fixed resolution (per row span, across).
double bladeAreaAt(const MarkerSet& markers, BladeKind kind, int perRow, int across) {
  return bladeGridArea(buildBlade(markerGrid(markers), kind), perRow, across);
}

// Every other row, the first and the last always kept.
MarkerSet everyOtherRow(const MarkerSet& markers) {
  MarkerSet out = markers;
  out.rows.clear();
  const std::size_t n = markers.rows.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 2 == 0 || i + 1 == n) out.rows.push_back(markers.rows[i]);
  }
  return out;
}

double quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double pos = q * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

double polylineLength(const std::vector<Eigen::Vector3d>& points) {
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

double distanceToPolyline(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& line) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < line.size(); ++i)
    best = std::min(best, std::sqrt(detail::squaredDistanceToSegment(line[i - 1], line[i], p)));
  return best;
}

std::vector<Eigen::Vector3d> centreLine(const BallBSplineCurve& curve, int samples) {
  std::vector<Eigen::Vector3d> out;
  for (int k = 0; k <= samples; ++k) out.push_back(curve.center(static_cast<double>(k) / samples));
  return out;
}

// One noisy capture of one synthetic leaf, measured for each blade kind.
struct Job {
  std::size_t leafIndex;  // into the leaves of the plan
  double sigmaMm;
  std::uint64_t seed;
  std::size_t firstResult;
  bool interpOnly;  // a toothed leaf: the interp blade and its interval alone
};

struct TruthLeaf {
  AccuracyCase base;  // shape, length, rows
  SyntheticLeaf leaf;
  double area;
  std::vector<Eigen::Vector3d> midrib;
  std::vector<TruthVein> veins;
};

void measure(const AccuracyPlan& plan, const TruthLeaf& truth, const Job& job, std::vector<AccuracyResult>& results) {
  const MarkerSet markers = truth.leaf.markers(job.sigmaMm, job.seed);
  AccuracyCase leafCase = truth.base;
  leafCase.sigmaMm = job.sigmaMm;
  leafCase.seed = job.seed;
  // Veins and midrib do not depend on the blade kind: measured once, on the interp model.
  double veinSum = 0.0, veinMax = 0.0, modelMidrib = 0.0;
  std::size_t veinCount = 0;
  const double trueMidrib = polylineLength(truth.midrib);
  const std::vector<BladeKind> blades = job.interpOnly ? std::vector<BladeKind>{BladeKind::Interp} : plan.blades;
  for (std::size_t b = 0; b < blades.size(); ++b) {
    const LeafModel model = buildLeafModel(markers, {blades[b], nullptr});
    if (b == 0) {
      for (const Vein& v : model.veins) {
        const std::vector<Eigen::Vector3d>* target = nullptr;
        if (v.name == "midrib") {
          target = &truth.midrib;
          modelMidrib = polylineLength(centreLine(v.curve, 800));
        } else if (v.name.rfind("lateral-", 0) == 0) {
          const int row = std::stoi(v.name.substr(8));
          const int side = v.name.find("right") != std::string::npos ? +1 : -1;
          for (const TruthVein& t : truth.veins) {
            if (t.row == row && t.side == side) target = &t.points;
          }
        }
        if (!target) continue;
        for (const Eigen::Vector3d& p : centreLine(v.curve, 40)) {
          const double d = distanceToPolyline(p, *target);
          veinSum += d;
          veinMax = std::max(veinMax, d);
          ++veinCount;
        }
      }
    }
    const BladeAreaEstimate est = convergedBladeArea(model.blade, kUp, 2e-4, 8);
    AccuracyResult r;
    r.leaf = leafCase;
    r.blade = blades[b];
    r.trueAreaMm2 = truth.area;
    r.modelAreaMm2 = est.areaMm2;
    r.areaErrorPercent = (est.areaMm2 - truth.area) / truth.area * 100.0;
    r.trueMidribMm = trueMidrib;
    r.modelMidribMm = modelMidrib;
    r.midribErrorPercent = (modelMidrib - trueMidrib) / trueMidrib * 100.0;
    r.veinMeanMm = veinCount ? veinSum / static_cast<double>(veinCount) : 0.0;
    r.veinMaxMm = veinMax;
    if (blades[b] == BladeKind::Interp && plan.coverageDraws > 0 && job.sigmaMm > 0.0) {
      AreaUncertaintyOptions o;
      o.sigmaMm = job.sigmaMm;
      o.draws = plan.coverageDraws;
      o.seed = job.seed + 1000003;
      const AreaUncertainty u = areaUncertainty(markers, o);
      r.intervalChecked = true;
      r.interval = u;
      r.inInterval = truth.area >= u.low95Mm2 && truth.area <= u.high95Mm2;
      // The same capture had its serration not been declared: no margin term.
      const double low = std::max(0.0, u.noiseLowMm2);
      const double high = u.noiseHighMm2 + std::max(u.interpolationMm2, u.systematicMm2);
      r.inIntervalUndeclared = truth.area >= low && truth.area <= high;
    }
    results[job.firstResult + b] = r;
  }
}

}  // namespace

double systematicUnderestimate(int rows) {
  const double n = std::max(2, rows);
  return (0.34 + 62.0 / (n * n)) / 100.0;
}

double interpolationErrorEstimate(const MarkerSet& markers, BladeKind blade) {
  if (markers.rows.size() < 4) return 0.0;
  const LeafModel full = buildLeafModel(markers, {blade, nullptr});
  const BladeAreaEstimate est = convergedBladeArea(full.blade, kUp);
  const MarkerSet half = everyOtherRow(markers);
  // The half-row blade at the same sampling density per millimetre of leaf: twice the
  // segments per (now twice as long) row span.
  const double halfArea = bladeAreaAt(half, blade, 2 * est.segmentsPerRow, est.segmentsAcross);
  return std::abs(est.areaMm2 - halfArea);
}

namespace {

// The margin's length through the markers (tip to each row's end, both sides) and the widest
// row's width.
std::pair<double, double> marginLengthAndWidth(const MarkerSet& markers) {
  double width = 0.0;
  for (const MarkerRow& row : markers.rows)
    width = std::max(width, (row.pointsMm[0] - row.pointsMm[kMarkersPerRow - 1]).norm());
  return {marginSpacingMm(markers) * 2.0 * static_cast<double>(markers.rows.size()), width};
}

std::string millimetres(double v) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(v < 1 ? 2 : 1) << v;
  return out.str();
}

void addMarginTerm(const MarkerSet& markers, AreaUncertainty& u) {
  const auto [length, width] = marginLengthAndWidth(markers);
  const LeafInfo& leaf = markers.leaf;
  if (leaf.marginFromScan && !leaf.marginFromScan->empty()) {
    // Measured: the markers may stand anywhere between the margin's sinuses and its tips.
    const MarginSample at = marginAt(*leaf.marginFromScan, marginSpacingMm(markers));
    u.marginHighMm2 = length * at.insideMm;
    u.marginLowMm2 = length * at.outsideMm;
    u.margin = "a scan of the leaf: its margin runs " + millimetres(at.outsideMm) + " mm outside and " +
               millimetres(at.insideMm) + " mm inside a smooth margin at the markers' spacing (" +
               millimetres(at.spacingMm) + " mm)";
    return;
  }
  if (!leaf.serration) {
    u.margin = "not declared";
    u.note =
        "the leaf's serration was not declared: teeth between the markers are not in this interval (declare it, "
        "none if the margin is entire, or give a scan of the leaf)";
    return;
  }
  if (*leaf.serration == Serration::None) {
    u.margin = "none (an entire margin)";
    return;
  }
  // Declared teeth of depth D along the margin's length: the markers sample the profile at
  // unknown phases, so the model's margin lies anywhere from the sinuses (0) to the tips
  // (max) while the truth holds the profile's mean: the interval reaches up by length × D ×
  // mean and down by length × D × (max − mean) (docs/accuracy.md, "Toothed margins").
  const double depth = leaf.toothDepthMm.value_or(kDefaultToothDepthFraction * width);
  const ToothSpread spread = toothSpread(*leaf.serration);
  u.marginHighMm2 = length * depth * spread.mean;
  u.marginLowMm2 = length * depth * (spread.max - spread.mean);
  u.margin = std::string("declared: ") + toString(*leaf.serration) + " teeth " + millimetres(depth) + " mm deep" +
             (leaf.toothDepthMm ? "" : " (1.5 % of the width: the depth was not given)");
}

}  // namespace

AreaUncertainty areaUncertainty(const MarkerSet& markers, const AreaUncertaintyOptions& options) {
  if (!(options.sigmaMm >= 0.0 && options.sigmaMm <= 20.0)) {
    throw InputError("the digitizer accuracy (sigma) must be between 0 and 20 mm");
  }
  if (options.draws < 8) throw InputError("the area uncertainty needs at least 8 Monte-Carlo draws");
  const LeafModel model = buildLeafModel(markers, {options.blade, nullptr});
  const BladeAreaEstimate est = convergedBladeArea(model.blade, kUp);
  AreaUncertainty u;
  u.areaMm2 = est.areaMm2;
  u.sigmaMm = options.sigmaMm;
  u.draws = options.draws;
  std::vector<double> deltas;
  deltas.reserve(static_cast<std::size_t>(options.draws));
  // The nominal at the draws' resolution, so the interval holds the spread alone.
  const double nominal = bladeAreaAt(markers, options.blade, est.segmentsPerRow, est.segmentsAcross);
  detail::Draws draws(options.seed, 0x75e7);
  for (int k = 0; k < options.draws; ++k) {
    MarkerSet noisy = markers;
    for (MarkerRow& row : noisy.rows) {
      for (Eigen::Vector3d& p : row.pointsMm) {
        for (int c = 0; c < 3; ++c) p[c] += options.sigmaMm * draws.gaussian();
      }
    }
    for (int c = 0; c < 3; ++c) noisy.tipMm[c] += options.sigmaMm * draws.gaussian();
    deltas.push_back(bladeAreaAt(noisy, options.blade, est.segmentsPerRow, est.segmentsAcross) - nominal);
  }
  // The basic (reflected) bootstrap interval: noise on the markers biases the area upwards
  // (a rougher surface is larger), and the draws, noisier still, show by how much; the
  // interval reflects their spread about the captured area and so removes that bias.
  u.noiseLowMm2 = u.areaMm2 - quantile(deltas, 0.975);
  u.noiseHighMm2 = u.areaMm2 - quantile(deltas, 0.025);
  u.interpolationMm2 = interpolationErrorEstimate(markers, options.blade);
  // Rows cost area on one side: the blade's margin is a spline through the row ends, and the
  // lobes below the last row's veins at the base are not sampled at all. For interp the
  // accuracy study measured the 95th percentile of that under-estimate as 0.34 % + 62 % / N²
  // over five shapes and four lengths (docs/accuracy.md); the interval reaches up by the
  // larger of it and the row-drop estimate (every blade kind loses area to its rows, none
  // gains it: the interval is not widened downwards).
  u.systematicMm2 = options.blade == BladeKind::Interp
                        ? systematicUnderestimate(static_cast<int>(markers.rows.size())) * u.areaMm2
                        : 0.0;
  addMarginTerm(markers, u);
  u.low95Mm2 = std::max(0.0, u.noiseLowMm2 - u.marginLowMm2);  // an area is never negative
  u.high95Mm2 = u.noiseHighMm2 + std::max(u.interpolationMm2, u.systematicMm2) + u.marginHighMm2;
  return u;
}

AccuracyPlan AccuracyPlan::full() {
  AccuracyPlan p;
  p.shapes = {LeafShape::Tobacco, LeafShape::Elliptic, LeafShape::Ovate, LeafShape::Obovate, LeafShape::Oblong};
  p.lengthsMm = {100.0, 200.0, 350.0, 500.0};
  p.rows = {6, 8, 10, 12, 15, 18, 21, 25};
  p.sigmasMm = {0.0, 0.25, 0.5, 1.0};
  p.blades = {BladeKind::Interp, BladeKind::Approx, BladeKind::Bezier, BladeKind::Nurbs};
  p.seedsPerNoisyCase = 8;
  p.margins = {Serration::Round, Serration::Sharp, Serration::Straight, Serration::Acuminate};
  p.marginSigmasMm = {0.25, 0.5, 1.0};
  p.marginSeeds = 3;
  return p;
}

AccuracyPlan AccuracyPlan::quick() {
  AccuracyPlan p;
  p.shapes = {LeafShape::Tobacco, LeafShape::Elliptic};
  p.lengthsMm = {300.0};
  p.rows = {6, 12, 20};
  p.sigmasMm = {0.0, 0.5};
  p.blades = {BladeKind::Interp, BladeKind::Approx};
  p.seedsPerNoisyCase = 3;
  p.coverageDraws = 16;
  p.margins = {Serration::Straight};
  p.marginSigmasMm = {0.5};
  p.marginSeeds = 1;
  return p;
}

std::vector<AccuracyResult> runAccuracyStudy(const AccuracyPlan& plan, int threads,
                                             const std::function<void(std::size_t, std::size_t)>& progress) {
  if (plan.shapes.empty() || plan.lengthsMm.empty() || plan.rows.empty() || plan.sigmasMm.empty() ||
      plan.blades.empty() || plan.seedsPerNoisyCase < 1) {
    throw InputError("an accuracy study needs at least one shape, length, row count, noise level, blade kind and seed");
  }
  std::vector<TruthLeaf> leaves;
  for (LeafShape shape : plan.shapes) {
    for (double length : plan.lengthsMm) {
      for (int rows : plan.rows) {
        SyntheticLeafSpec spec = defaultSyntheticSpec(shape);
        spec.outline.lengthMm = length;
        // The bend scales with the leaf: cupping and margin wave are given for a 500 mm leaf.
        spec.bend.cupMm *= length / 500.0;
        spec.bend.waveMm *= length / 500.0;
        spec.bend.wavelengthMm *= length / 500.0;
        spec.rows = rows;
        SyntheticLeaf leaf(spec);
        const double area = leaf.area();
        leaves.push_back({{shape, length, rows, 0.0, 0}, leaf, area, leaf.midrib(2049), leaf.veins(129)});
      }
    }
  }
  // The toothed leaves: the same shapes, lengths and rows with each serration.
  const std::size_t smoothLeaves = leaves.size();
  for (Serration serration : plan.margins) {
    for (std::size_t l = 0; l < smoothLeaves; ++l) {
      SyntheticLeafSpec spec = leaves[l].leaf.spec();
      spec.outline.serration = serration;
      spec.outline.teethPerSide = 20;
      spec.outline.toothDepthMm =
          0.015 * spec.outline.widthMm.value_or(spec.outline.lengthMm / aspectRatio(spec.outline.shape));
      SyntheticLeaf leaf(spec);
      AccuracyCase c = leaves[l].base;
      c.serration = serration;
      const double area = leaf.area();
      leaves.push_back({c, leaf, area, leaf.midrib(2049), leaf.veins(129)});
    }
  }
  std::vector<Job> jobs;
  std::size_t next = 0;
  for (std::size_t l = 0; l < smoothLeaves; ++l) {
    for (double sigma : plan.sigmasMm) {
      const int seeds = sigma > 0.0 ? plan.seedsPerNoisyCase : 1;
      for (int s = 0; s < seeds; ++s) {
        jobs.push_back({l, sigma, static_cast<std::uint64_t>(s + 1), next, false});
        next += plan.blades.size();
      }
    }
  }
  for (std::size_t l = smoothLeaves; l < leaves.size(); ++l) {
    for (double sigma : plan.marginSigmasMm) {
      for (int s = 0; s < plan.marginSeeds; ++s) {
        jobs.push_back({l, sigma, static_cast<std::uint64_t>(s + 1), next, true});
        next += 1;  // interp only
      }
    }
  }
  std::vector<AccuracyResult> results(next);
  std::atomic<std::size_t> cursor{0};
  std::atomic<std::size_t> done{0};
  std::mutex errorMutex;
  std::string error;
  const auto runOne = [&](std::size_t j) {
    try {
      measure(plan, leaves[jobs[j].leafIndex], jobs[j], results);
    } catch (const std::exception& e) {
      const std::lock_guard<std::mutex> lock(errorMutex);
      if (error.empty()) error = e.what();
    }
    ++done;
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t) {
    pool.emplace_back([&] {
      for (std::size_t j = cursor++; j < jobs.size(); j = cursor++) runOne(j);
    });
  }
  // The calling thread works too, and reports progress between its jobs.
  for (std::size_t j = cursor++; j < jobs.size(); j = cursor++) {
    runOne(j);
    if (progress) progress(done.load(), jobs.size());
  }
  for (std::thread& t : pool) t.join();
  if (progress) progress(jobs.size(), jobs.size());
  if (!error.empty()) throw InputError("the accuracy study failed: " + error);
  return results;
}

}  // namespace leafdig::model
