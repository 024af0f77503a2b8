// The area interval and the accuracy study (issue 16): against synthetic leaves whose
// exact area is known.
#include "leafdig/model/study/accuracy.hpp"

#include <gtest/gtest.h>

#include <set>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"

namespace {

namespace m = leafdig::model;

m::SyntheticLeaf tobacco(int rows, double length = 300.0) {
  m::SyntheticLeafSpec spec = m::defaultSyntheticSpec(m::LeafShape::Tobacco);
  spec.outline.lengthMm = length;
  spec.rows = rows;
  return m::SyntheticLeaf(spec);
}

TEST(AreaInterval, HoldsTheTrueAreaOfNoisyCapturesAndIsReproducible) {
  const m::SyntheticLeaf leaf = tobacco(12);
  int inside = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const m::MarkerSet markers = leaf.markers(0.76, seed);
    const m::AreaUncertainty u = m::areaUncertainty(markers);
    EXPECT_LT(u.low95Mm2, u.areaMm2);
    EXPECT_GT(u.high95Mm2, u.areaMm2);
    EXPECT_LE(u.noiseLowMm2, u.noiseHighMm2);
    EXPECT_GT(u.systematicMm2, 0.0);
    EXPECT_LT(u.halfWidthPercent(), 3.0);  // an interval a curator can use, not a shrug
    inside += leaf.area() >= u.low95Mm2 && leaf.area() <= u.high95Mm2 ? 1 : 0;
    if (seed == 1) {
      const m::AreaUncertainty again = m::areaUncertainty(markers);
      EXPECT_EQ(again.low95Mm2, u.low95Mm2);
      EXPECT_EQ(again.high95Mm2, u.high95Mm2);
    }
  }
  EXPECT_GE(inside, 9);
}

TEST(AreaInterval, WithoutNoiseOnlyTheRowsWidenItAndMoreRowsNarrowIt) {
  m::AreaUncertaintyOptions exact;
  exact.sigmaMm = 0.0;
  const m::AreaUncertainty six = m::areaUncertainty(tobacco(6).markers(), exact);
  EXPECT_DOUBLE_EQ(six.noiseLowMm2, six.areaMm2);
  EXPECT_DOUBLE_EQ(six.noiseHighMm2, six.areaMm2);
  EXPECT_DOUBLE_EQ(six.low95Mm2, six.areaMm2);  // rows never add area: nothing below
  EXPECT_GT(six.high95Mm2, six.areaMm2);
  const m::AreaUncertainty twenty = m::areaUncertainty(tobacco(20).markers(), exact);
  EXPECT_LT(twenty.halfWidthPercent(), six.halfWidthPercent());
  // The true area is above the model's, inside the reach of the rows' term.
  const double truth = tobacco(6).area();
  EXPECT_GT(truth, six.areaMm2);
  EXPECT_LE(truth, six.high95Mm2);
}

TEST(AreaInterval, RefusesNonsense) {
  const m::MarkerSet markers = tobacco(8).markers();
  m::AreaUncertaintyOptions o;
  o.sigmaMm = -1;
  EXPECT_THROW((void)m::areaUncertainty(markers, o), m::InputError);
  o.sigmaMm = 0.5;
  o.draws = 3;
  EXPECT_THROW((void)m::areaUncertainty(markers, o), m::InputError);
}

TEST(AreaInterval, TheLeafMetricsCarryIt) {
  const m::LeafModel model = m::buildLeafModel(tobacco(10).markers(0.5, 2));
  const m::LeafMetrics metrics = m::computeLeafMetrics(model, {0, 0, 1});
  ASSERT_TRUE(metrics.areaInterval.has_value());
  EXPECT_NEAR(metrics.areaInterval->areaMm2, metrics.blade.areaMm2, 1e-9 * metrics.blade.areaMm2);
  EXPECT_DOUBLE_EQ(metrics.areaInterval->sigmaMm, m::kFastrakSigmaMm);
  const std::string json = m::metricsToJson(metrics);
  EXPECT_NE(json.find("\"blade_area_95_mm2\""), std::string::npos);
  EXPECT_NE(json.find("\"digitizer_sigma_mm\""), std::string::npos);
}

// Issue 26: `synth leaf --shape obovate --serration straight --rows 20 --noise 0.3 --seed S`
// for S = 1…10 gave areas 0.85–1.02 % under the truth, and intervals that all fell short of
// it. Declared (the synthetic leaf declares its own teeth), the interval reaches them; not
// declared, it says in words that teeth are not in it.
TEST(AreaInterval, DeclaredTeethAreInTheIntervalAndUndeclaredOnesAreNamed) {
  m::SyntheticLeafSpec spec = m::defaultSyntheticSpec(m::LeafShape::Obovate);
  spec.rows = 20;
  spec.outline.serration = m::Serration::Straight;
  spec.outline.teethPerSide = 20;
  spec.outline.toothDepthMm = 0.015 * spec.outline.lengthMm / m::aspectRatio(m::LeafShape::Obovate);
  const m::SyntheticLeaf leaf(spec);
  const double truth = leaf.area();
  int declaredHolds = 0, undeclaredHolds = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    m::MarkerSet markers = leaf.markers(0.3, seed);
    ASSERT_EQ(markers.leaf.serration, m::Serration::Straight);
    m::AreaUncertaintyOptions o;
    o.draws = 16;
    const m::AreaUncertainty declared = m::areaUncertainty(markers, o);
    EXPECT_GT(declared.marginHighMm2, 0.0);
    EXPECT_NE(declared.margin.find("declared: straight teeth"), std::string::npos) << declared.margin;
    EXPECT_TRUE(declared.note.empty());
    declaredHolds += truth >= declared.low95Mm2 && truth <= declared.high95Mm2;
    markers.leaf.serration.reset();
    markers.leaf.toothDepthMm.reset();
    const m::AreaUncertainty undeclared = m::areaUncertainty(markers, o);
    EXPECT_EQ(undeclared.marginHighMm2, 0.0);
    EXPECT_NE(undeclared.note.find("teeth between the markers are not in this interval"), std::string::npos);
    undeclaredHolds += truth >= undeclared.low95Mm2 && truth <= undeclared.high95Mm2;
  }
  EXPECT_EQ(declaredHolds, 10);
  EXPECT_LE(undeclaredHolds, 2) << "the teeth the markers miss were outside the interval, as the issue found";
}

TEST(AccuracyStudy, MeasuresWhatTheMethodPromisesAndTheThreadsChangeNothing) {
  const m::AccuracyPlan plan = m::AccuracyPlan::quick();
  const std::vector<m::AccuracyResult> one = m::runAccuracyStudy(plan, 1);
  // shapes × lengths × rows × (1 exact + seeds noisy) × blade kinds, then the toothed leaves:
  // shapes × lengths × rows × serrations × σ × seeds, interp alone
  const std::size_t cases = plan.shapes.size() * plan.lengthsMm.size() * plan.rows.size();
  const std::size_t expected =
      cases * (1 + static_cast<std::size_t>(plan.seedsPerNoisyCase)) * plan.blades.size() +
      cases * plan.margins.size() * plan.marginSigmasMm.size() * static_cast<std::size_t>(plan.marginSeeds);
  ASSERT_EQ(one.size(), expected);
  std::size_t checked = 0, inside = 0;
  for (const m::AccuracyResult& r : one) {
    EXPECT_GT(r.trueAreaMm2, 0.0);
    EXPECT_NEAR(r.modelMidribMm, r.trueMidribMm, 0.02 * r.trueMidribMm);
    if (r.leaf.sigmaMm == 0.0) {
      // Without noise the midrib is exact to the rounding of the markers, the veins close.
      EXPECT_LT(std::abs(r.midribErrorPercent), 0.05);
      EXPECT_LT(r.veinMeanMm, 0.5);
      if (r.blade == m::BladeKind::Interp) {
        EXPECT_LT(r.areaErrorPercent, 0.0) << "rows only ever lose area";
        EXPECT_GT(r.areaErrorPercent, -2.5);
      }
    }
    checked += r.intervalChecked ? 1 : 0;
    inside += r.inInterval ? 1 : 0;
  }
  ASSERT_GT(checked, 0u);
  EXPECT_GE(static_cast<double>(inside) / static_cast<double>(checked), 0.9);
  // interp beats approx without noise at every row count (approx's surface falls inside).
  for (const m::AccuracyResult& a : one) {
    if (a.blade != m::BladeKind::Approx || a.leaf.sigmaMm != 0.0) continue;
    for (const m::AccuracyResult& i : one) {
      if (i.blade == m::BladeKind::Interp && i.leaf.sigmaMm == 0.0 && i.leaf.shape == a.leaf.shape &&
          i.leaf.rows == a.leaf.rows) {
        EXPECT_LT(std::abs(i.areaErrorPercent), std::abs(a.areaErrorPercent));
      }
    }
  }
  // More rows, smaller systematic error (6 against 20 rows).
  const auto errorAt = [&](int rows) {
    for (const m::AccuracyResult& r : one) {
      if (r.blade == m::BladeKind::Interp && r.leaf.sigmaMm == 0.0 && r.leaf.rows == rows &&
          r.leaf.shape == m::LeafShape::Elliptic) {
        return std::abs(r.areaErrorPercent);
      }
    }
    return -1.0;
  };
  EXPECT_LT(errorAt(20), errorAt(6));
  const std::vector<m::AccuracyResult> two = m::runAccuracyStudy(plan, 2);
  ASSERT_EQ(two.size(), one.size());
  for (std::size_t k = 0; k < one.size(); ++k) {
    EXPECT_EQ(two[k].modelAreaMm2, one[k].modelAreaMm2) << k;
    EXPECT_EQ(two[k].inInterval, one[k].inInterval) << k;
  }
}

TEST(AccuracyStudy, TheReportAnswersTheQuestionsAndHoldsEveryResult) {
  const m::AccuracyPlan plan = m::AccuracyPlan::quick();
  const std::vector<m::AccuracyResult> results = m::runAccuracyStudy(plan, 2);
  const m::AccuracyReport report = m::accuracyReport(plan, results, "leafdig synth study --quick -o docs/accuracy.md");
  EXPECT_NE(report.markdown.find("How many rows does a leaf need for 0.5 %"), std::string::npos);
  EXPECT_NE(report.markdown.find("blade kinds side by side"), std::string::npos);
  EXPECT_NE(report.markdown.find("## Toothed margins"), std::string::npos);
  EXPECT_NE(report.markdown.find("| straight |"), std::string::npos);
  EXPECT_NE(report.markdown.find("95 % interval"), std::string::npos);
  EXPECT_NE(report.markdown.find("leafdig synth study --quick"), std::string::npos);
  std::size_t lines = 0;
  for (char c : report.csv) lines += c == '\n' ? 1 : 0;
  EXPECT_EQ(lines, results.size() + 1);
  std::set<std::string> names;
  for (const auto& [name, svg] : report.figures) {
    names.insert(name);
    EXPECT_NE(report.markdown.find("](" + name + ")"), std::string::npos) << name;
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    EXPECT_NE(svg.find("<polyline"), std::string::npos);
  }
  EXPECT_EQ(names.size(), 3u);
}

TEST(AccuracyStudy, RefusesAnEmptyPlan) {
  m::AccuracyPlan plan = m::AccuracyPlan::quick();
  plan.rows.clear();
  EXPECT_THROW((void)m::runAccuracyStudy(plan, 1), m::InputError);
}

}  // namespace

namespace {

TEST(CaptureWarnings, ALastRowAtTheBaseIsQuietAndOneMidLeafIsNamed) {
  for (m::LeafShape shape : {m::LeafShape::Tobacco, m::LeafShape::Elliptic, m::LeafShape::Ovate, m::LeafShape::Obovate,
                             m::LeafShape::Oblong}) {
    for (int rows : {6, 12, 25}) {
      m::SyntheticLeafSpec spec = m::defaultSyntheticSpec(shape);
      spec.rows = rows;
      EXPECT_TRUE(m::captureWarnings(m::SyntheticLeaf(spec).markers(0.76, 3)).empty())
          << m::toString(shape) << " " << rows;
    }
  }
  // The same leaf with its last four rows never captured: the rows stop mid-leaf.
  m::MarkerSet cut = tobacco(12).markers();
  cut.rows.resize(8);
  const auto warnings = m::captureWarnings(cut);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].name, "last-row-not-at-base");
  EXPECT_NE(warnings[0].message.find("row 8"), std::string::npos) << warnings[0].message;
  EXPECT_NE(warnings[0].message.find("leaf base"), std::string::npos);
  // ... and the metrics carry it, in the JSON too.
  const m::LeafMetrics metrics = m::computeLeafMetrics(m::buildLeafModel(cut), {0, 0, 1});
  ASSERT_EQ(metrics.warnings.size(), 1u);
  EXPECT_NE(m::metricsToJson(metrics).find("\"last-row-not-at-base\""), std::string::npos);
}

}  // namespace
