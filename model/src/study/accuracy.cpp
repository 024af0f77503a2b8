#include "leafdig/model/study/accuracy.hpp"

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
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "segment.hpp"

namespace leafdig::model {

namespace {

const Eigen::Vector3d kUp(0.0, 0.0, 1.0);

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
