#include "leafdig/model/synth/synthetic_leaf.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <type_traits>

#include "draws.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

namespace {

constexpr double kPi = std::numbers::pi;

double radians(double deg) {
  return deg * kPi / 180.0;
}

using detail::roundTo;

// Gauss–Legendre nodes and weights on [0, 1].
template <int N>
struct GaussLegendre {
  std::array<double, N> x{}, w{};
  GaussLegendre() {
    for (int i = 0; i < N; ++i) {
      // Newton on P_N from Chebyshev's guess.
      double z = std::cos(kPi * (i + 0.75) / (N + 0.5));
      double dp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= N; ++k) {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = N * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      x[static_cast<std::size_t>(i)] = 0.5 * (1.0 - z);
      w[static_cast<std::size_t>(i)] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
  }
};

const GaussLegendre<10>& outerRule() {
  static const GaussLegendre<10> rule;
  return rule;
}
const GaussLegendre<12>& innerRule() {
  static const GaussLegendre<12> rule;
  return rule;
}

// Five-point central difference. The result is evaluated into the function's own value
// type: returning an Eigen expression would keep references to the four temporaries.
template <typename F>
auto derivative(const F& f, double t, double h) {
  using Value = std::decay_t<decltype(f(t))>;
  const Value result = (f(t - 2 * h) - 8.0 * f(t - h) + 8.0 * f(t + h) - f(t + 2 * h)) / (12.0 * h);
  return result;
}

void require(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

struct SurfaceFrame {
  Eigen::Vector3d point, dx, dy;
};

}  // namespace

const char* toString(LeafShape shape) {
  return nameIn(kLeafShapeNames, shape);
}

const char* toString(ToothDirection direction) {
  return nameIn(kToothDirectionNames, direction);
}

LeafShape leafShapeFromString(const std::string& word) {
  return parseName(kLeafShapeNames, word, "leaf shape");
}

ToothDirection toothDirectionFromString(const std::string& word) {
  return parseName(kToothDirectionNames, word, "tooth direction");
}

double aspectRatio(LeafShape shape) {
  switch (shape) {
    case LeafShape::Oblong: return 3.0;
    case LeafShape::Elliptic: return 1.5;
    default: return 2.0;
  }
}

SyntheticLeafSpec defaultSyntheticSpec(LeafShape shape) {
  SyntheticLeafSpec s;
  s.outline.shape = shape;
  s.type = toString(shape);
  // Basal lateral veins spread wider on a rounded base; at 40° they would leave the round
  // lobes below them outside the marked blade (−10 % area on an ellipse).
  switch (shape) {
    case LeafShape::Oblong: s.veinAngleBaseDeg = 70.0; break;
    case LeafShape::Elliptic:
    case LeafShape::Ovate: s.veinAngleBaseDeg = 75.0; break;
    case LeafShape::Obovate: s.veinAngleBaseDeg = 60.0; break;
    case LeafShape::Tobacco: s.veinAngleBaseDeg = 55.0; break;
  }
  if (shape == LeafShape::Tobacco) {
    s.outline.tipNarrowing = 0.6;
    s.outline.tipExtent = 0.25;
    s.outline.baseNarrowing = 0.5;
    s.outline.baseExtent = 0.2;
    s.bend.waveMm = 3.0;
    s.bend.wavelengthMm = 70.0;
  }
  return s;
}

SyntheticLeaf::SyntheticLeaf(SyntheticLeafSpec spec) : spec_(std::move(spec)) {
  const OutlineSpec& o = spec_.outline;
  require(std::isfinite(o.lengthMm) && o.lengthMm > 1.0 && o.lengthMm <= 5000.0,
          "the leaf length must be between 1 and 5000 mm, e.g. 500");
  width_ = o.widthMm.value_or(o.lengthMm / aspectRatio(o.shape));
  require(std::isfinite(width_) && width_ > 0.05 * o.lengthMm && width_ <= 2.0 * o.lengthMm,
          "the leaf width must be between 5 % and 200 % of its length");
  symmetry_ = o.symmetry.value_or(o.shape == LeafShape::Ovate     ? 0.25
                                  : o.shape == LeafShape::Obovate ? -0.25
                                  : o.shape == LeafShape::Tobacco ? 0.1
                                                                  : 0.0);
  require(std::abs(symmetry_) < 0.45, "the symmetry S must be within (-0.45, 0.45): beyond, the outline folds");
  require(o.asymmetry >= 0.0 && o.asymmetry <= 0.5, "the asymmetry must be between 0 and 0.5");
  require(o.tipNarrowing > -1.0 && o.tipNarrowing <= 0.95 && o.baseNarrowing > -1.0 && o.baseNarrowing <= 0.95,
          "tip and base narrowing must be within (-1, 0.95]");
  require(o.tipExtent >= 0.01 && o.tipExtent <= 1.0 && o.baseExtent >= 0.01 && o.baseExtent <= 1.0,
          "tip and base extents must be between 0.01 and 1 (fractions of the length)");
  double terms = 0.0;
  for (const SineTerm& t : o.widthTerms) {
    require(std::isfinite(t.amplitude) && std::isfinite(t.frequency) && std::isfinite(t.phaseRad) &&
                t.frequency >= 0.0 && t.frequency <= 64.0,
            "a width term needs a finite amplitude and phase and a frequency between 0 and 64");
    terms += std::abs(t.amplitude);
  }
  require(terms < 0.8, "the width terms' amplitudes must add up to less than 0.8 (the half-width must stay positive)");
  if (o.serration != Serration::None) {
    require(o.teethPerSide >= 1 && o.teethPerSide <= 400, "a serrated margin needs 1 to 400 teeth per side");
    require(o.toothDepthMm > 0.0 && o.toothDepthMm <= width_ / 16.0,
            "the tooth depth must be positive and at most 1/16 of the width (" + std::to_string(width_ / 16.0) +
                " mm here)");
  }
  const BendSpec& b = spec_.bend;
  require(std::isfinite(b.droopDeg) && std::abs(b.droopDeg) <= 180.0, "the droop must be within ±180°");
  require(std::isfinite(b.twistDeg) && std::abs(b.twistDeg) <= 90.0, "the twist must be within ±90°");
  require(std::isfinite(b.cupMm) && std::abs(b.cupMm) <= width_, "the cupping must be at most the leaf's width");
  require(std::isfinite(b.waveMm) && b.waveMm >= 0.0 && b.waveMm <= width_ / 4.0,
          "the margin wave must be between 0 and a quarter of the width");
  require(std::isfinite(b.wavelengthMm) && b.wavelengthMm > 1.0, "the margin wavelength must be over 1 mm");
  require(spec_.rows >= 2 && spec_.rows <= 60, "a synthetic leaf needs 2 to 60 marker rows");
  require(spec_.veinAngleTipDeg > 5.0 && spec_.veinAngleTipDeg < 85.0 && spec_.veinAngleBaseDeg > 5.0 &&
              spec_.veinAngleBaseDeg < 85.0,
          "lateral vein angles must be between 5° and 85° from the midrib");
  // The exact area, once: markers, the truth file and the study all ask for it.
  const double coarse = greenArea(1, false);
  area_ = greenArea(2, false);
  areaError_ = std::abs(area_ - coarse) / std::abs(area_);
}

// y0(φ) = L/2 (1 − cos φ) − S L/2 sin²φ; half-width (W/2) p(φ) (1 + Σ a sin(kφ + p)) g_tip g_base.
// With `tangent`, also d/dφ of the point, analytically (the product rule through every
// factor; the Gaussians depend on φ through y0).
Eigen::Vector2d SyntheticLeaf::baseOutline(int side, double phi, Eigen::Vector2d* tangent) const {
  const OutlineSpec& o = spec_.outline;
  const double L = o.lengthMm;
  const double s = std::sin(phi);
  const double c = std::cos(phi);
  const double y = 0.5 * L * (1.0 - c) - symmetry_ * 0.5 * L * s * s;
  const double dy = 0.5 * L * s - symmetry_ * L * s * c;
  const bool oblong = o.shape == LeafShape::Oblong;
  const double p = oblong ? (s + std::sin(3.0 * phi) / 9.0) * 9.0 / 8.0 : s;
  const double dp = oblong ? (c + std::cos(3.0 * phi) / 3.0) * 9.0 / 8.0 : c;
  double wave = 1.0, dwave = 0.0;
  for (const SineTerm& t : o.widthTerms) {
    wave += t.amplitude * std::sin(t.frequency * phi + t.phaseRad);
    dwave += t.amplitude * t.frequency * std::cos(t.frequency * phi + t.phaseRad);
  }
  const double tipScale = o.tipExtent * L;
  const double baseScale = o.baseExtent * L;
  const double tipD = (L - y) / tipScale;
  const double baseD = y / baseScale;
  const double tipE = std::exp(-tipD * tipD);
  const double baseE = std::exp(-baseD * baseD);
  const double gTip = 1.0 - o.tipNarrowing * tipE;
  const double gBase = 1.0 - o.baseNarrowing * baseE;
  const double asym = side < 0 ? 1.0 - o.asymmetry : 1.0;
  const double half = side * 0.5 * width_ * asym;
  if (tangent) {
    // d gTip/dφ = −g_t e^{−D²} (−2D) dD/dφ with dD/dφ = −y'/σ_t; likewise at the base with +y'/σ_b.
    const double dgTip = o.tipNarrowing * tipE * 2.0 * tipD * (-dy / tipScale);
    const double dgBase = o.baseNarrowing * baseE * 2.0 * baseD * (dy / baseScale);
    const double dx = half * (dp * wave * gTip * gBase + p * dwave * gTip * gBase + p * wave * dgTip * gBase +
                              p * wave * gTip * dgBase);
    *tangent = Eigen::Vector2d(dx, dy);
  }
  return {half * p * wave * gTip * gBase, y};
}

Eigen::Vector2d SyntheticLeaf::outlinePoint(int side, double phi) const {
  const OutlineSpec& o = spec_.outline;
  if (o.serration == Serration::None) return baseOutline(side, phi);
  const double delta = o.toothDepthMm * toothProfile(o.serration, o.teethPerSide * phi);
  if (o.toothDirection == ToothDirection::Horizontal)
    return baseOutline(side, phi) + Eigen::Vector2d(side * delta, 0.0);
  Eigen::Vector2d t;
  const Eigen::Vector2d base = baseOutline(side, phi, &t);
  const double n = t.norm();
  if (!(n > 0.0)) return base;
  return base + delta * side * Eigen::Vector2d(t.y(), -t.x()) / n;
}

std::vector<Eigen::Vector2d> SyntheticLeaf::outline(int perSide) const {
  std::vector<Eigen::Vector2d> out;
  out.reserve(static_cast<std::size_t>(2 * perSide));
  for (int k = 0; k <= perSide; ++k) out.push_back(outlinePoint(+1, kPi * k / perSide));
  for (int k = perSide - 1; k >= 1; --k) out.push_back(outlinePoint(-1, kPi * k / perSide));
  return out;
}

std::vector<double> SyntheticLeaf::breakpoints() const {
  const int n = spec_.outline.serration == Serration::None ? 0 : spec_.outline.teethPerSide;
  std::vector<double> b;
  if (n == 0) {
    b = {0.0, kPi};
    return b;
  }
  for (int k = 0; k <= 2 * n; ++k) b.push_back(kPi * k / (2.0 * n));
  return b;
}

namespace {

// Φ and its partial derivatives at a flat point (x, y) (docs/synthetic-leaves.md):
// Φ = C(y) + a X + b N(y) with C the drooping midrib (curvature κ, arc length y), N its
// normal, (a, b) the lateral offset and the height h rotated by the twist ω(y).
SurfaceFrame surfaceFrame(const SyntheticLeafSpec& spec, double width, double x, double y) {
  const BendSpec& b = spec.bend;
  const double L = spec.outline.lengthMm;
  const double kappa = radians(b.droopDeg) / L;
  const double psi = kappa * y;
  const double cpsi = std::cos(psi), spsi = std::sin(psi);
  const Eigen::Vector3d X(1.0, 0.0, 0.0);
  const Eigen::Vector3d T(0.0, cpsi, -spsi);
  const Eigen::Vector3d N(0.0, spsi, cpsi);
  Eigen::Vector3d C;
  if (std::abs(kappa) < 1e-12) {
    C = {0.0, y, 0.0};
  } else {
    C = {0.0, spsi / kappa, (cpsi - 1.0) / kappa};
  }
  const double wh = 0.5 * width;
  const double r = x / wh;
  const double theta = 2.0 * kPi * y / b.wavelengthMm + 1.3 * r;
  const double st = std::sin(theta), ct = std::cos(theta);
  const double h = r * r * (b.cupMm + b.waveMm * st);
  const double hx = (2.0 * r * (b.cupMm + b.waveMm * st) + r * r * b.waveMm * ct * 1.3) / wh;
  const double hy = r * r * b.waveMm * ct * 2.0 * kPi / b.wavelengthMm;
  const double dOmega = radians(b.twistDeg) / L;
  const double omega = dOmega * y;
  const double co = std::cos(omega), so = std::sin(omega);
  const double a = x * co - h * so;
  const double bb = x * so + h * co;
  const double ax = co - hx * so, bx = so + hx * co;
  const double ay = -bb * dOmega - hy * so, by = a * dOmega + hy * co;
  SurfaceFrame f;
  f.point = C + a * X + bb * N;
  f.dx = ax * X + bx * N;
  f.dy = (1.0 + kappa * bb) * T + ay * X + by * N;
  return f;
}

}  // namespace

Eigen::Vector3d SyntheticLeaf::surfacePoint(const Eigen::Vector2d& flat) const {
  return surfaceFrame(spec_, width_, flat.x(), flat.y()).point;
}

double SyntheticLeaf::jacobian(double x, double y) const {
  const SurfaceFrame f = surfaceFrame(spec_, width_, x, y);
  return f.dx.cross(f.dy).norm();
}

// Green's theorem: ∬ J dA = ∮ P dy with P(x, y) = ∫₀ˣ J(ξ, y) dξ, the outline run
// counter-clockwise (right half up, left half down). Outer Gauss–Legendre on panels between
// the kinks, inner Gauss–Legendre over ξ.
double SyntheticLeaf::greenArea(int panelsPerInterval, bool flat) const {
  const auto& outer = outerRule();
  const auto& inner = innerRule();
  const std::vector<double> breaks = breakpoints();
  const int minPanels = 16;
  const int intervals = static_cast<int>(breaks.size()) - 1;
  const int perInterval = panelsPerInterval * std::max(1, (minPanels + intervals - 1) / intervals);
  double total = 0.0;
  for (int side : {+1, -1}) {
    double sideSum = 0.0;
    const auto y = [&](double phi) { return outlinePoint(side, phi).y(); };
    for (int i = 0; i < intervals; ++i) {
      const double a = breaks[static_cast<std::size_t>(i)];
      const double span = (breaks[static_cast<std::size_t>(i) + 1] - a) / perInterval;
      const double h = std::min(1e-4, 0.05 * span);
      for (int p = 0; p < perInterval; ++p) {
        const double lo = a + p * span;
        for (std::size_t q = 0; q < outer.x.size(); ++q) {
          const double phi = lo + span * outer.x[q];
          const Eigen::Vector2d pt = outlinePoint(side, phi);
          const double dy = derivative(y, phi, h);
          double P = pt.x();
          if (!flat) {
            double s = 0.0;
            for (std::size_t r = 0; r < inner.x.size(); ++r) s += inner.w[r] * jacobian(inner.x[r] * pt.x(), pt.y());
            P = s * pt.x();
          }
          sideSum += outer.w[q] * span * P * dy;
        }
      }
    }
    total += side > 0 ? sideSum : -sideSum;
  }
  return total;
}

double SyntheticLeaf::flatArea() const {
  return greenArea(2, true);
}

double SyntheticLeaf::area(double* errorEstimate) const {
  if (errorEstimate) *errorEstimate = areaError_;
  return area_;
}

// The half outline of `side` sampled at φ_k = π k / S (k = 0..S; the base point nudged to
// φ = π·1e-6 so that a vein starting at the base does not meet it there), fine enough to
// bracket every crossing of a vein with the margin: 4 000 samples, 64 per tooth when more.
std::vector<Eigen::Vector2d> SyntheticLeaf::marginSamples(int side) const {
  const int n = spec_.outline.serration == Serration::None ? 0 : spec_.outline.teethPerSide;
  const int count = std::max(4000, 64 * n);
  std::vector<Eigen::Vector2d> out;
  out.reserve(static_cast<std::size_t>(count) + 1);
  for (int k = 0; k <= count; ++k) out.push_back(outlinePoint(side, k == 0 ? kPi * 1e-6 : kPi * k / count));
  return out;
}

// Length of the straight flat vein from (0, y0) at `angle` to the midrib until it meets
// the margin of `side`: the first crossing of the ray with the outline, bracketed on the
// sampled margin and bisected on the exact outline.
double SyntheticLeaf::veinLength(int side, double y0, double angleRad,
                                 const std::vector<Eigen::Vector2d>& margin) const {
  const Eigen::Vector2d o(0.0, y0);
  const Eigen::Vector2d d(side * std::sin(angleRad), std::cos(angleRad));
  const auto crossOf = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d v = p - o;
    return side * (v.x() * d.y() - v.y() * d.x());
  };
  const auto cross = [&](double phi) { return crossOf(outlinePoint(side, phi)); };
  const int count = static_cast<int>(margin.size()) - 1;
  double prev = crossOf(margin.front());
  for (int k = 1; k <= count; ++k) {
    const Eigen::Vector2d& p = margin[static_cast<std::size_t>(k)];
    const double c = crossOf(p);
    if (prev > 0.0 && c <= 0.0 && (p - o).dot(d) > 0.0) {
      double lo = k == 1 ? kPi * 1e-6 : kPi * (k - 1) / count, hi = kPi * k / count;
      for (int it = 0; it < 80; ++it) {
        const double mid = 0.5 * (lo + hi);
        (cross(mid) > 0.0 ? lo : hi) = mid;
      }
      return (outlinePoint(side, 0.5 * (lo + hi)) - o).dot(d);
    }
    prev = c;
  }
  throw InputError("a lateral vein at " + std::to_string(y0) +
                   " mm from the base does not meet the margin: use smaller vein angles");
}

namespace {

struct VeinLayout {
  int row;
  int side;
  Eigen::Vector2d start, end;
};

std::vector<VeinLayout> layout(const SyntheticLeaf& leaf,
                               const std::function<double(int, double, double)>& veinLength) {
  const SyntheticLeafSpec& s = leaf.spec();
  std::vector<VeinLayout> out;
  const int n = s.rows;
  for (int i = 1; i <= n; ++i) {
    const double q = static_cast<double>(i - 1) / (n - 1);  // 0 at row 1 (tip side), 1 at the base
    const double y0 = s.outline.lengthMm * (1.0 - static_cast<double>(i) / n);
    const double angle = radians(s.veinAngleTipDeg + (s.veinAngleBaseDeg - s.veinAngleTipDeg) * q);
    for (int side : {+1, -1}) {
      const double len = veinLength(side, y0, angle);
      const Eigen::Vector2d o(0.0, y0);
      const Eigen::Vector2d d(side * std::sin(angle), std::cos(angle));
      out.push_back({i, side, o, o + len * d});
    }
  }
  return out;
}

}  // namespace

MarkerSet SyntheticLeaf::markers(double noiseMm, std::uint64_t seed) const {
  require(std::isfinite(noiseMm) && noiseMm >= 0.0 && noiseMm <= 20.0, "the marker noise must be between 0 and 20 mm");
  detail::Draws draws(seed);
  const auto sample = [&](const Eigen::Vector3d& p) {
    Eigen::Vector3d out;
    for (int k = 0; k < 3; ++k) out[k] = roundTo(p[k] + (noiseMm > 0.0 ? noiseMm * draws.gaussian() : 0.0), 0.01);
    return out;
  };
  MarkerSet set;
  set.leaf.id = spec_.id;
  set.leaf.plant = spec_.plant;
  set.leaf.type = spec_.type;
  set.leaf.measuredAreaMm2 = roundTo(area(), 1.0);
  // A toothed margin is declared as the leaf was made: its serration and tooth depth.
  if (spec_.outline.serration != Serration::None) {
    set.leaf.serration = spec_.outline.serration;
    set.leaf.toothDepthMm = spec_.outline.toothDepthMm;
  }
  set.edgeThicknessMm = 0.3;
  set.tipMm = sample(surfacePoint({0.0, spec_.outline.lengthMm}));
  const std::array<std::vector<Eigen::Vector2d>, 2> margins{marginSamples(+1), marginSamples(-1)};
  const auto veins =
      layout(*this, [&](int side, double y0, double a) { return veinLength(side, y0, a, margins[side > 0 ? 0 : 1]); });
  const double scale = spec_.outline.lengthMm / 500.0;
  for (int i = 1; i <= spec_.rows; ++i) {
    const double q = static_cast<double>(i - 1) / (spec_.rows - 1);
    MarkerRow row;
    for (const VeinLayout& v : veins) {
      if (v.row != i) continue;
      for (int k = v.side > 0 ? 0 : 1; k <= 3; ++k) {
        const int column = v.side > 0 ? 3 - k : 3 + k;  // right: j = 4, 3, 2, 1; left: 5, 6, 7
        row.pointsMm[static_cast<std::size_t>(column)] = sample(surfacePoint(v.start + (k / 3.0) * (v.end - v.start)));
      }
    }
    row.midribThicknessMm = roundTo(scale * (1.0 + 3.0 * std::pow(q, 0.9)), 0.001);
    row.veinOriginThicknessMm = roundTo(scale * (0.5 + 1.5 * std::sin(kPi * (0.15 + 0.6 * q))), 0.001);
    set.rows.push_back(row);
  }
  return set;
}

std::vector<TruthVein> SyntheticLeaf::veins(int pointsPerVein) const {
  std::vector<TruthVein> out;
  const std::array<std::vector<Eigen::Vector2d>, 2> margins{marginSamples(+1), marginSamples(-1)};
  const auto layouts =
      layout(*this, [&](int side, double y0, double a) { return veinLength(side, y0, a, margins[side > 0 ? 0 : 1]); });
  for (const VeinLayout& v : layouts) {
    TruthVein t{v.row, v.side, v.start, v.end, {}};
    for (int k = 0; k < pointsPerVein; ++k)
      t.points.push_back(surfacePoint(v.start + (static_cast<double>(k) / (pointsPerVein - 1)) * (v.end - v.start)));
    out.push_back(std::move(t));
  }
  return out;
}

std::vector<Eigen::Vector3d> SyntheticLeaf::midrib(int points) const {
  std::vector<Eigen::Vector3d> out;
  for (int k = 0; k < points; ++k) out.push_back(surfacePoint({0.0, spec_.outline.lengthMm * k / (points - 1)}));
  return out;
}

LeafMesh SyntheticLeaf::truthMesh(int alongPerSide, int across) const {
  require(alongPerSide >= 4 && across >= 1, "the truth mesh needs at least 4 steps along and 1 across");
  Mesh mesh;
  const int J = alongPerSide, K = across;
  // Vertex ids: base, tip, the midrib's inner points, then each half's grid.
  const auto add = [&](const Eigen::Vector2d& flat) {
    const SurfaceFrame f = surfaceFrame(spec_, width_, flat.x(), flat.y());
    mesh.positions.push_back(f.point);
    Eigen::Vector3d n = f.dx.cross(f.dy);
    mesh.normals.push_back(n.norm() > 0.0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::UnitZ());
    return static_cast<std::uint32_t>(mesh.positions.size() - 1);
  };
  const std::uint32_t base = add(outlinePoint(+1, 0.0));
  const std::uint32_t tip = add(outlinePoint(+1, kPi));
  std::vector<std::uint32_t> mid(static_cast<std::size_t>(J + 1));
  mid[0] = base;
  mid[static_cast<std::size_t>(J)] = tip;
  for (int j = 1; j < J; ++j) mid[static_cast<std::size_t>(j)] = add({0.0, baseOutline(+1, kPi * j / J).y()});
  for (int side : {+1, -1}) {
    std::vector<std::uint32_t> grid(static_cast<std::size_t>((J + 1) * (K + 1)));
    const auto at = [&](int j, int k) -> std::uint32_t& { return grid[static_cast<std::size_t>(j * (K + 1) + k)]; };
    for (int j = 0; j <= J; ++j) {
      const double phi = kPi * j / J;
      const Eigen::Vector2d m(0.0, baseOutline(side, phi).y());
      const Eigen::Vector2d e = outlinePoint(side, phi);
      for (int k = 0; k <= K; ++k) {
        if (j == 0)
          at(j, k) = base;
        else if (j == J)
          at(j, k) = tip;
        else if (k == 0)
          at(j, k) = mid[static_cast<std::size_t>(j)];
        else
          at(j, k) = add(m + (static_cast<double>(k) / K) * (e - m));
      }
    }
    const auto triangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      if (a == b || b == c || a == c) return;
      if (side > 0)
        mesh.triangles.push_back({a, b, c});
      else
        mesh.triangles.push_back({a, c, b});
    };
    for (int j = 0; j < J; ++j)
      for (int k = 0; k < K; ++k) {
        triangle(at(j, k), at(j, k + 1), at(j + 1, k + 1));
        triangle(at(j, k), at(j + 1, k + 1), at(j + 1, k));
        ++mesh.quads;
      }
  }
  LeafMesh out;
  out.organs.push_back({"blade", OrganKind::Blade, std::move(mesh), 0});
  return out;
}

const MarkerSet& sampleLeafShape() {
  static const MarkerSet shape = [] {
    SyntheticLeafSpec spec = defaultSyntheticSpec(LeafShape::Tobacco);
    spec.id = "built-in";
    spec.type = "sample";
    return SyntheticLeaf(spec).markers(0.0);
  }();
  return shape;
}

}  // namespace leafdig::model
