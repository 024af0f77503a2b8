// The accuracy study's report: docs/accuracy.md, its CSV and its SVG figures.
#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "leafdig/model/study/accuracy.hpp"

namespace leafdig::model {

namespace {

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

double quantileOf(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const double pos = q * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

struct Series {
  std::string name;
  std::vector<std::pair<double, double>> points;
};

// A line chart: axes from 0 (or the data's minimum when negative) to the data's maximum,
// five ticks each, one colour per series, a legend on the right.
std::string lineChart(const std::string& title, const std::string& xLabel, const std::string& yLabel,
                      const std::vector<Series>& series, double yReference) {
  const double w = 640, h = 380, left = 64, right = 150, top = 36, bottom = 52;
  double x0 = 1e300, x1 = -1e300, y0 = std::min(0.0, yReference), y1 = std::max(0.0, yReference);
  for (const Series& s : series) {
    for (const auto& [x, y] : s.points) {
      if (!std::isfinite(y)) continue;
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
  }
  if (!(x1 > x0)) x1 = x0 + 1;
  if (!(y1 > y0)) y1 = y0 + 1;
  y1 += 0.05 * (y1 - y0);
  const auto X = [&](double x) { return left + (x - x0) / (x1 - x0) * (w - left - right); };
  const auto Y = [&](double y) { return h - bottom - (y - y0) / (y1 - y0) * (h - top - bottom); };
  static const char* const colours[] = {"#1b6b2f", "#c0392b", "#2c5aa0", "#b9770e", "#7d3c98", "#17a589"};
  std::ostringstream out;
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h << "\" viewBox=\"0 0 " << w
      << " " << h << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out << "<text x=\"" << w / 2 << "\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">" << title << "</text>\n";
  out << "<line x1=\"" << left << "\" y1=\"" << Y(y0) << "\" x2=\"" << left << "\" y2=\"" << Y(y1)
      << "\" stroke=\"black\"/>\n";
  out << "<line x1=\"" << left << "\" y1=\"" << h - bottom << "\" x2=\"" << w - right << "\" y2=\"" << h - bottom
      << "\" stroke=\"black\"/>\n";
  for (int k = 0; k <= 5; ++k) {
    const double yv = y0 + (y1 - y0) * k / 5.0;
    out << "<line x1=\"" << left << "\" y1=\"" << fixed(Y(yv), 1) << "\" x2=\"" << w - right << "\" y2=\""
        << fixed(Y(yv), 1) << "\" stroke=\"#e0e0e0\"/>\n";
    out << "<text x=\"" << left - 6 << "\" y=\"" << fixed(Y(yv) + 4, 1) << "\" text-anchor=\"end\">"
        << fixed(yv, std::abs(y1 - y0) < 2 ? 2 : 1) << "</text>\n";
  }
  // x ticks at the data's own x values (the row counts of the study).
  std::set<double> xs;
  for (const Series& s : series) {
    for (const auto& point : s.points) xs.insert(point.first);
  }
  for (double xv : xs) {
    out << "<text x=\"" << fixed(X(xv), 1) << "\" y=\"" << h - bottom + 16 << "\" text-anchor=\"middle\">"
        << fixed(xv, 0) << "</text>\n";
  }
  if (yReference != 0.0) {
    out << "<line x1=\"" << left << "\" y1=\"" << fixed(Y(yReference), 1) << "\" x2=\"" << w - right << "\" y2=\""
        << fixed(Y(yReference), 1) << "\" stroke=\"#888\" stroke-dasharray=\"6 4\"/>\n";
  }
  out << "<text x=\"" << (left + w - right) / 2 << "\" y=\"" << h - 12 << "\" text-anchor=\"middle\">" << xLabel
      << "</text>\n";
  out << "<text transform=\"translate(16 " << (top + h - bottom) / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
      << yLabel << "</text>\n";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const char* colour = colours[i % 6];
    // Every other series dashed or dotted, so one that lies on another (nurbs on approx)
    // still shows.
    const std::string dash = i % 4 == 1 ? " stroke-dasharray=\"8 4\"" : i % 4 == 3 ? " stroke-dasharray=\"2 6\"" : "";
    out << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\"" << dash << " points=\"";
    for (const auto& [x, y] : series[i].points) {
      if (std::isfinite(y)) out << fixed(X(x), 1) << "," << fixed(Y(y), 1) << " ";
    }
    out << "\"/>\n";
    for (const auto& [x, y] : series[i].points) {
      if (std::isfinite(y))
        out << "<circle cx=\"" << fixed(X(x), 1) << "\" cy=\"" << fixed(Y(y), 1) << "\" r=\"3\" fill=\"" << colour
            << "\"/>\n";
    }
    const double ly = top + 18.0 * static_cast<double>(i) + 10;
    out << "<line x1=\"" << w - right + 12 << "\" y1=\"" << ly << "\" x2=\"" << w - right + 36 << "\" y2=\"" << ly
        << "\" stroke=\"" << colour << "\" stroke-width=\"2\"" << dash << "/>\n";
    out << "<text x=\"" << w - right + 42 << "\" y=\"" << ly + 4 << "\">" << series[i].name << "</text>\n";
  }
  out << "</svg>\n";
  return out.str();
}

bool same(double a, double b) {
  return std::abs(a - b) < 1e-12;
}

// |area error| values of the results matching a filter.
template <typename F>
std::vector<double> absErrors(const std::vector<AccuracyResult>& results, F keep) {
  std::vector<double> out;
  for (const AccuracyResult& r : results) {
    if (keep(r)) out.push_back(std::abs(r.areaErrorPercent));
  }
  return out;
}

}  // namespace

AccuracyReport accuracyReport(const AccuracyPlan& plan, const std::vector<AccuracyResult>& all,
                              const std::string& command) {
  AccuracyReport report;
  // The smooth leaves make every table but the toothed margins' section.
  std::vector<AccuracyResult> results, toothed;
  for (const AccuracyResult& r : all) (r.leaf.serration == Serration::None ? results : toothed).push_back(r);
  {
    std::ostringstream csv;
    csv << "shape,length_mm,rows,sigma_mm,seed,blade,true_area_mm2,model_area_mm2,area_error_percent,"
           "true_midrib_mm,model_midrib_mm,midrib_error_percent,vein_mean_mm,vein_max_mm,interval_checked,"
           "true_area_in_interval,interval_low_mm2,interval_high_mm2,interpolation_estimate_mm2,serration,"
           "true_area_in_interval_undeclared\n";
    for (const AccuracyResult& r : all) {
      csv << toString(r.leaf.shape) << "," << r.leaf.lengthMm << "," << r.leaf.rows << "," << r.leaf.sigmaMm << ","
          << r.leaf.seed << "," << toString(r.blade) << "," << fixed(r.trueAreaMm2, 3) << ","
          << fixed(r.modelAreaMm2, 3) << "," << fixed(r.areaErrorPercent, 4) << "," << fixed(r.trueMidribMm, 3) << ","
          << fixed(r.modelMidribMm, 3) << "," << fixed(r.midribErrorPercent, 4) << "," << fixed(r.veinMeanMm, 4) << ","
          << fixed(r.veinMaxMm, 4) << "," << (r.intervalChecked ? 1 : 0) << "," << (r.inInterval ? 1 : 0) << ",";
      if (r.intervalChecked) {
        csv << fixed(r.interval.low95Mm2, 3) << "," << fixed(r.interval.high95Mm2, 3) << ","
            << fixed(r.interval.interpolationMm2, 3);
      } else {
        csv << ",,";
      }
      csv << "," << toString(r.leaf.serration) << "," << (r.intervalChecked ? (r.inIntervalUndeclared ? "1" : "0") : "")
          << "\n";
    }
    report.csv = csv.str();
  }
  const BladeKind mainKind = plan.blades.front();
  std::ostringstream md;
  md << "# Accuracy of captured leaves\n\n"
     << "Generated by `" << command << "` from " << all.size()
     << " reconstructions; do not edit by hand (the CSV beside this file holds every one).\n"
     << "Each case is a synthetic leaf of seed 002 ([synthetic-leaves.md](synthetic-leaves.md)) with its shape's\n"
     << "defaults, its bend scaled to its length, and markers placed by the protocol (rows from the tip, the last\n"
     << "row at the leaf base) with Gaussian noise of σ per coordinate (rounded to 0.01 mm as the digitizer's\n"
     << "records are). The leaf model is built from the markers exactly as the station builds it; its blade area\n"
     << "is converged to 0.02 % and compared with the truth's exact area (Green's theorem, better than 1e-9).\n"
     << "A Polhemus FASTRAK's stated accuracy is 0.03 in (0.76 mm) RMS per coordinate; a careful technician's\n"
     << "placement adds about as much again.\n\n";

  // The 95th percentile of |area error| over every shape (and seed) for one length, σ,
  // blade kind and row count.
  const auto p95 = [&](double length, double sigma, BladeKind kind, int rows) {
    return quantileOf(absErrors(results,
                                [&](const AccuracyResult& r) {
                                  return r.blade == kind && same(r.leaf.lengthMm, length) && r.leaf.rows == rows &&
                                         same(r.leaf.sigmaMm, sigma);
                                }),
                      0.95);
  };

  // 1. Rows needed, and the kind.
  md << "## How many rows does a leaf need for 0.5 % area, and which blade kind?\n\n"
     << "For each leaf length and digitizer noise: the fewest rows of the study with which 95 % of the captures of\n"
     << "every shape are within ±0.5 % of the true area, and the blade kind that does it; where none does, the\n"
     << "best the study found. More rows are not always better: `interp` passes through every marker, and with\n"
     << "rows a few millimetres apart the noise becomes wrinkles that add area.\n\n| leaf length |";
  for (double s : plan.sigmasMm) md << " σ = " << fixed(s, 2) << " mm |";
  md << "\n|---|";
  for (std::size_t k = 0; k < plan.sigmasMm.size(); ++k) md << "---|";
  md << "\n";
  for (double length : plan.lengthsMm) {
    md << "| " << fixed(length, 0) << " mm |";
    for (double sigma : plan.sigmasMm) {
      std::string cell;
      double bestErr = 1e300;
      std::string bestCell;
      for (int rows : plan.rows) {
        for (BladeKind kind : plan.blades) {
          const double e = p95(length, sigma, kind, rows);
          if (cell.empty() && e <= 0.5)
            cell = std::to_string(rows) + " rows, " + toString(kind) + " (" + fixed(e, 2) + " %)";
          if (e < bestErr) {
            bestErr = e;
            bestCell =
                "not reached; best " + fixed(e, 2) + " % with " + std::to_string(rows) + " rows, " + toString(kind);
          }
        }
      }
      md << " " << (cell.empty() ? bestCell : cell) << " |";
    }
    md << "\n";
  }
  md << "\n";

  // 2. Blade kinds.
  md << "## The blade kinds side by side\n\n"
     << "95th percentile of |area error| (%) over every shape, length and seed.\n\n";
  for (double sigma : plan.sigmasMm) {
    md << "σ = " << fixed(sigma, 2) << " mm:\n\n| rows |";
    for (BladeKind kind : plan.blades) md << " " << toString(kind) << " |";
    md << "\n|---|";
    for (std::size_t k = 0; k < plan.blades.size(); ++k) md << "---|";
    md << "\n";
    for (int rows : plan.rows) {
      md << "| " << rows << " |";
      for (BladeKind kind : plan.blades) {
        const double q =
            quantileOf(absErrors(results,
                                 [&](const AccuracyResult& r) {
                                   return r.blade == kind && r.leaf.rows == rows && same(r.leaf.sigmaMm, sigma);
                                 }),
                       0.95);
        md << " " << fixed(q, 2) << " |";
      }
      md << "\n";
    }
    md << "\n";
  }
  if (std::find(plan.blades.begin(), plan.blades.end(), BladeKind::Nurbs) != plan.blades.end()) {
    md << "`nurbs` with its default unit weights is the `approx` surface (the same control net, every weight 1), so "
          "it\n"
       << "measures the same; it differs only where weights are set. `approx` and `bezier` use the markers as control\n"
       << "points: the surface does not pass through them and falls inside the margin.\n\n";
  }
  report.figures.emplace_back("accuracy-blades.svg", [&] {
    std::vector<Series> series;
    const double sigma = plan.sigmasMm.size() > 2 ? plan.sigmasMm[2] : plan.sigmasMm.back();
    for (BladeKind kind : plan.blades) {
      Series s{toString(kind), {}};
      for (int rows : plan.rows) {
        s.points.emplace_back(rows, quantileOf(absErrors(results,
                                                         [&](const AccuracyResult& r) {
                                                           return r.blade == kind && r.leaf.rows == rows &&
                                                                  same(r.leaf.sigmaMm, sigma);
                                                         }),
                                               0.95));
      }
      series.push_back(std::move(s));
    }
    return lineChart("95th percentile |area error| by blade kind, σ = " + fixed(sigma, 2) + " mm", "marker rows",
                     "|area error| (%)", series, 0.5);
  }());
  md << "![|area error| by blade kind](accuracy-blades.svg)\n\n";

  // 3. Systematic error.
  md << "## The systematic error (σ = 0)\n\n"
     << "Area error (%) of the " << toString(mainKind)
     << " blade without noise: what the rows alone cost. Negative: the model is smaller than the leaf (the\n"
     << "blade's margin runs as a spline through the row ends, inside a convex margin).\n\n| rows |";
  for (LeafShape shape : plan.shapes) md << " " << toString(shape) << " |";
  md << "\n|---|";
  for (std::size_t k = 0; k < plan.shapes.size(); ++k) md << "---|";
  md << "\n";
  std::vector<Series> systematic;
  for (LeafShape shape : plan.shapes) systematic.push_back({toString(shape), {}});
  for (int rows : plan.rows) {
    md << "| " << rows << " |";
    for (std::size_t i = 0; i < plan.shapes.size(); ++i) {
      std::vector<double> errs;
      for (const AccuracyResult& r : results) {
        if (r.blade == mainKind && r.leaf.shape == plan.shapes[i] && r.leaf.rows == rows && same(r.leaf.sigmaMm, 0.0))
          errs.push_back(r.areaErrorPercent);
      }
      const double e = quantileOf(errs, 0.5);
      systematic[i].points.emplace_back(rows, e);
      md << " " << fixed(e, 2) << " |";
    }
    md << "\n";
  }
  md << "\n(Median over the leaf lengths.)\n\n";
  report.figures.emplace_back("accuracy-systematic.svg",
                              lineChart("Area error without noise (" + std::string(toString(mainKind)) + ")",
                                        "marker rows", "area error (%)", systematic, -0.5));
  md << "![area error without noise](accuracy-systematic.svg)\n\n";

  // 4. Noise.
  md << "## Noise and leaf size\n\n"
     << "95th percentile of |area error| (%), " << toString(mainKind) << " blade, every shape, by σ and length:\n\n"
     << "| rows | length |";
  for (double s : plan.sigmasMm) md << " σ " << fixed(s, 2) << " |";
  md << "\n|---|---|";
  for (std::size_t k = 0; k < plan.sigmasMm.size(); ++k) md << "---|";
  md << "\n";
  std::vector<Series> noise;
  for (double length : plan.lengthsMm) noise.push_back({fixed(length, 0) + " mm", {}});
  const double chartSigma = plan.sigmasMm.size() > 2 ? plan.sigmasMm[2] : plan.sigmasMm.back();
  for (int rows : plan.rows) {
    for (std::size_t li = 0; li < plan.lengthsMm.size(); ++li) {
      md << "| " << rows << " | " << fixed(plan.lengthsMm[li], 0) << " mm |";
      for (double sigma : plan.sigmasMm) {
        const double q = quantileOf(absErrors(results,
                                              [&](const AccuracyResult& r) {
                                                return r.blade == mainKind && r.leaf.rows == rows &&
                                                       same(r.leaf.lengthMm, plan.lengthsMm[li]) &&
                                                       same(r.leaf.sigmaMm, sigma);
                                              }),
                                    0.95);
        if (same(sigma, chartSigma)) noise[li].points.emplace_back(rows, q);
        md << " " << fixed(q, 2) << " |";
      }
      md << "\n";
    }
  }
  report.figures.emplace_back("accuracy-noise.svg",
                              lineChart("95th percentile |area error|, σ = " + fixed(chartSigma, 2) + " mm, by length",
                                        "marker rows", "|area error| (%)", noise, 0.5));
  md << "\n![|area error| with noise, by leaf length](accuracy-noise.svg)\n\n";

  // 5. Midrib and veins.
  md << "## Midrib length and vein positions\n\n"
     << "Midrib: the length of the model's midrib centre line against the true midrib's. Veins: the distance of\n"
     << "points on the model's vein centre lines (midrib and every lateral vein) from the true veins.\n\n"
     << "| σ | midrib error, median | midrib error, 95th pct | vein distance, mean | vein distance, max |\n"
     << "|---|---|---|---|---|\n";
  for (double sigma : plan.sigmasMm) {
    std::vector<double> midrib, veinMean;
    double veinMax = 0.0;
    for (const AccuracyResult& r : results) {
      if (r.blade != mainKind || !same(r.leaf.sigmaMm, sigma)) continue;
      midrib.push_back(std::abs(r.midribErrorPercent));
      veinMean.push_back(r.veinMeanMm);
      veinMax = std::max(veinMax, r.veinMaxMm);
    }
    double mean = 0.0;
    for (double v : veinMean) mean += v / static_cast<double>(veinMean.size());
    md << "| " << fixed(sigma, 2) << " mm | " << fixed(quantileOf(midrib, 0.5), 3) << " % | "
       << fixed(quantileOf(midrib, 0.95), 3) << " % | " << fixed(mean, 3) << " mm | " << fixed(veinMax, 3) << " mm |\n";
  }
  md << "\n";

  // 6. The interval.
  std::size_t checked = 0, inside = 0;
  std::string systematicFit;
  std::map<std::pair<int, double>, std::pair<std::size_t, std::size_t>> byRows;  // (rows, σ): checked, inside
  std::set<double> sigmas;
  for (const AccuracyResult& r : results) {
    if (!r.intervalChecked) continue;
    ++checked;
    inside += r.inInterval ? 1 : 0;
    sigmas.insert(r.leaf.sigmaMm);
    auto& c = byRows[{r.leaf.rows, r.leaf.sigmaMm}];
    c.first += 1;
    c.second += r.inInterval ? 1 : 0;
  }
  if (checked > 0) {
    md << "## The area's 95 % interval\n\n"
       << "Every leaf's area is reported with a 95 % interval (`leafdig model build --json`, the CSV export and the\n"
       << "station). Its noise part is a Monte-Carlo over the digitizer's stated accuracy: every marker coordinate\n"
       << "redrawn with Gaussian noise, the blade rebuilt, the 2.5 % and 97.5 % quantiles of the area changes\n"
       << "reflected about the captured area (the basic bootstrap: noise makes a surface rougher and larger, and\n"
       << "the reflection takes that bias out). Rows only ever lose area (the blade's margin is a spline through\n"
       << "the row ends, and the lobes below the last row's veins at the base are not sampled), so the interval\n"
       << "then reaches upwards by the larger of the row-drop estimate (how much the area changes when every\n"
       << "other row is left out) and, for interp, the under-estimate this study measured for the row count.\n"
       << "Here the interval was computed for every noisy interp capture, with the σ it had (" << plan.coverageDraws
       << " draws), and holds the true area in **" << fixed(100.0 * static_cast<double>(inside) / checked, 1)
       << " %** of " << checked << " captures:\n\n| rows |";
    for (double s : sigmas) md << " σ " << fixed(s, 2) << " mm |";
    md << "\n|---|";
    for (std::size_t k = 0; k < sigmas.size(); ++k) md << "---|";
    md << "\n";
    for (int rows : plan.rows) {
      md << "| " << rows << " |";
      for (double s : sigmas) {
        const auto it = byRows.find({rows, s});
        md << " "
           << (it == byRows.end()
                   ? std::string("–")
                   : fixed(100.0 * static_cast<double>(it->second.second) / static_cast<double>(it->second.first), 1) +
                         " %")
           << " |";
      }
      md << "\n";
    }
    // The systematic term's calibration: a + b / N² fitted (least squares) to the σ = 0
    // 95th percentiles of the main kind.
    double s0 = 0, s1 = 0, s2 = 0, t0 = 0, t1 = 0;
    for (int rows : plan.rows) {
      const double x = 1.0 / (static_cast<double>(rows) * rows);
      const double y =
          quantileOf(absErrors(results,
                               [&](const AccuracyResult& r) {
                                 return r.blade == mainKind && r.leaf.rows == rows && same(r.leaf.sigmaMm, 0.0);
                               }),
                     0.95);
      if (!std::isfinite(y)) continue;
      s0 += 1;
      s1 += x;
      s2 += x * x;
      t0 += y;
      t1 += x * y;
    }
    const double det = s0 * s2 - s1 * s1;
    if (s0 >= 2 && std::abs(det) > 0) {
      const double b = (s0 * t1 - s1 * t0) / det;
      const double a = (t0 - b * s1) / s0;
      systematicFit = "This study's σ = 0 figures fit " + fixed(a, 2) + " % + " + fixed(b, 0) +
                      " % / N² (the code uses 0.34 % + 62 % / N², from the full study).";
    }
    md << "\n" << systematicFit << "\n\n";
  }

  // 7. Toothed margins.
  if (!toothed.empty()) {
    std::map<std::pair<Serration, int>, std::array<std::size_t, 3>> cells;  // checked, inside, inside undeclared
    std::map<Serration, std::array<std::size_t, 3>> bySerration;
    std::map<Serration, std::vector<double>> widths;  // half-width, % of the area
    std::set<int> rowCounts;
    for (const AccuracyResult& r : toothed) {
      if (!r.intervalChecked) continue;
      rowCounts.insert(r.leaf.rows);
      for (auto* c : {&cells[{r.leaf.serration, r.leaf.rows}], &bySerration[r.leaf.serration]}) {
        (*c)[0] += 1;
        (*c)[1] += r.inInterval ? 1 : 0;
        (*c)[2] += r.inIntervalUndeclared ? 1 : 0;
      }
      widths[r.leaf.serration].push_back(r.interval.halfWidthPercent());
    }
    const auto percent = [](std::size_t part, std::size_t whole) {
      return fixed(100.0 * static_cast<double>(part) / static_cast<double>(whole), 1) + " %";
    };
    md << "## Toothed margins\n\n"
       << "Markers stand on the margin where the rows' veins meet it, at whatever phase of the teeth that is: the\n"
       << "model's margin is a spline through them and cannot see the teeth between. So when the leaf's serration\n"
       << "is declared (the set-up dialog, or `\"serration\"` in the markers file's `leaf`; a synthetic leaf\n"
       << "declares its own), the interval reaches up by margin length × tooth depth × the profile's mean (the\n"
       << "markers all in sinuses) and down by margin length × depth × (its largest − its mean) (all on tips);\n"
       << "a scan of the leaf replaces both by what its own margin shows (`--measured-area-scan`). Undeclared, the\n"
       << "interval leaves teeth out and says so in words (`note`). Every shape, length and row count of the study\n"
       << "with 20 teeth per side, 1.5 % of the width deep, captured with σ ";
    for (std::size_t k = 0; k < plan.marginSigmasMm.size(); ++k)
      md << (k ? (k + 1 == plan.marginSigmasMm.size() ? " and " : ", ") : "") << fixed(plan.marginSigmasMm[k], 2);
    md << " mm, " << plan.marginSeeds << " seed" << (plan.marginSeeds > 1 ? "s" : "") << " each, interp, "
       << plan.coverageDraws << " draws. Coverage of the true area, declared (a cell below 95 % says so):\n\n| rows |";
    for (const auto& [serration, c] : bySerration) md << " " << toString(serration) << " |";
    md << "\n|---|";
    for (std::size_t k = 0; k < bySerration.size(); ++k) md << "---|";
    md << "\n";
    for (int rows : rowCounts) {
      md << "| " << rows << " |";
      for (const auto& [serration, total] : bySerration) {
        const auto it = cells.find({serration, rows});
        if (it == cells.end()) {
          md << " – |";
          continue;
        }
        const auto& c = it->second;
        const bool holds = 100 * c[1] >= 95 * c[0];
        md << " " << percent(c[1], c[0]) << (holds ? "" : " (does not hold)") << " |";
      }
      md << "\n";
    }
    md << "\nOver all row counts, declared and not, with the interval's median half-width:\n\n"
       << "| serration | captures | declared | not declared | median half-width |\n|---|---|---|---|---|\n";
    for (const auto& [serration, c] : bySerration)
      md << "| " << toString(serration) << " | " << c[0] << " | " << percent(c[1], c[0]) << " | " << percent(c[2], c[0])
         << " | ±" << fixed(quantileOf(widths[serration], 0.5), 2) << " % |\n";
    md << "\nLobed 2-D outlines (docs/leaf2d.md) are built from the whole outline, not sampled by markers: no\n"
       << "margin term applies to them.\n\n";
  }
  report.markdown = md.str();
  return report;
}

}  // namespace leafdig::model
