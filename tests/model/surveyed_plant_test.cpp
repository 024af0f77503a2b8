// A plant digitized in place as a plant model: the stem through the collar and the nodes, full
// leaves exactly as digitized, quick leaves shaped from the library (nearest aspect, of their
// type) or the built-in sample, stretched to their measured length and width and laid on
// their three points with the adaxial side up.
#include "leafdig/model/plant/surveyed_plant.hpp"

#include <gtest/gtest.h>

#include <string>

#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"

using namespace leafdig::model;
using Eigen::Vector3d;

namespace {

PlantSurvey sampleSurvey() {
  return surveyPlant(readPlantMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json"));
}

LibraryLeaf sample() {
  return {kSampleShapeSource, sampleLeafShape()};
}

const SurveyedLeaf& surveyed(const PlantSurvey& s, int node) {
  for (const SurveyedLeaf& l : s.leaves)
    if (l.node == node) return l;
  throw std::runtime_error("no leaf at node " + std::to_string(node));
}

const PlacedLeaf& placed(const Plant& p, int rank) {
  for (const PlacedLeaf& l : p.leaves)
    if (l.rank == rank) return l;
  throw std::runtime_error("no leaf of rank " + std::to_string(rank));
}

// A library leaf: the built-in shape made wider by `widen` across its midrib (in its frame,
// where +X is across), typed `type`.
LibraryLeaf libraryLeaf(const std::string& source, const std::string& type, double widen) {
  LibraryLeaf l{source, sampleLeafShape()};
  const Eigen::Isometry3d toLeaf = leafFrameFromDigitizer(buildLeafModel(l.markers));
  Eigen::Isometry3d stretch = Eigen::Isometry3d::Identity();
  stretch.linear() = Eigen::Vector3d(widen, 1.0, 1.0).asDiagonal();
  const Eigen::Isometry3d t = toLeaf.inverse() * stretch * toLeaf;
  l.markers.tipMm = t * l.markers.tipMm;
  for (auto& row : l.markers.rows)
    for (auto& p : row.pointsMm) p = t * p;
  l.markers.leaf.type = type;
  return l;
}

}  // namespace

TEST(SurveyedPlant, TheStemRunsThroughTheCollarAndEveryNodeWithTheCalipersDiameters) {
  const PlantSurvey s = sampleSurvey();
  const Plant p = surveyedPlant(s, {}, sample());
  ASSERT_TRUE(p.stem.has_value());
  EXPECT_LT(p.stem->curve.center(0.0).norm(), 1e-9);
  EXPECT_NEAR(p.stem->curve.radius(0.0), s.collarDiameterMm / 2, 1e-9);
  EXPECT_LT((p.stem->curve.center(1.0) - s.nodes.back().pointMm).norm(), 1e-9);
  EXPECT_NEAR(p.stem->curve.radius(1.0), s.nodes.back().diameterMm / 2, 1e-9);
  EXPECT_DOUBLE_EQ(p.stemHeightMm, s.nodes.back().heightMm);
  EXPECT_EQ(p.id, s.plant);
}

TEST(SurveyedPlant, AFullLeafIsItsDigitizedModelWithTheAreaTheSurveyMeasured) {
  const PlantSurvey s = sampleSurvey();
  const Plant p = surveyedPlant(s, {}, sample());
  const SurveyedLeaf& want = surveyed(s, 2);
  ASSERT_EQ(want.kind, LeafKind::Full);
  const PlacedLeaf& got = placed(p, 2);
  EXPECT_TRUE(got.shapeDigitized);
  EXPECT_EQ(got.source, "digitized");
  EXPECT_LT((got.base - *want.baseMm).norm(), 1e-9);
  EXPECT_LT((got.tip - *want.tipMm).norm(), 1e-9);
  const LeafMetrics metrics = computeLeafMetrics(got.model, Vector3d::UnitZ());
  EXPECT_NEAR(metrics.blade.areaMm2, *want.areaMm2, 1e-9 * *want.areaMm2);
  // The placement carries the leaf's own frame onto the plant: its origin is the base.
  EXPECT_LT((got.placement.translation() - got.base).norm(), 1e-6);
  EXPECT_DOUBLE_EQ(got.insertionHeightMm, s.nodes[1].heightMm);
}

TEST(SurveyedPlant, AQuickLeafWithoutALibraryTakesTheBuiltInShapeStretchedOntoItsThreePoints) {
  const PlantSurvey s = sampleSurvey();
  const Plant p = surveyedPlant(s, {}, sample());
  for (int node : {3, 4}) {
    const SurveyedLeaf& want = surveyed(s, node);
    ASSERT_EQ(want.kind, LeafKind::Quick);
    const PlacedLeaf& got = placed(p, node);
    EXPECT_FALSE(got.shapeDigitized);
    EXPECT_NE(got.source.find(kSampleShapeSource), std::string::npos) << got.source;
    EXPECT_NE(got.source.find("no approved leaf of type \"lower\""), std::string::npos) << got.source;
    // Base on the base, the chord along the measured chord and as long, the width as measured.
    EXPECT_LT((got.base - *want.baseMm).norm(), 1e-9);
    const Vector3d chord = got.tip - got.base, measured = *want.tipMm - *want.baseMm;
    EXPECT_NEAR(chord.norm(), want.pose->lengthMm, 0.01);
    EXPECT_LT(chord.normalized().cross(measured.normalized()).norm(), 1e-9);
    EXPECT_NEAR(bladeWidthMm(got.model.markers), *want.pose->widthMm, 0.05);
    // The width runs towards the side point, the adaxial side up.
    const Vector3d across = got.placement.linear() * Vector3d::UnitX();
    const Vector3d side = *want.sideMm - *want.baseMm;
    EXPECT_GT(std::abs(across.dot((side - side.dot(measured.normalized()) * measured.normalized()).normalized())),
              0.99);
    EXPECT_GT((got.placement.linear() * Vector3d::UnitZ()).z(), 0.0);
    EXPECT_NEAR(got.azimuthDeg, want.pose->azimuthDeg, 1e-12);
    EXPECT_NEAR(got.inclinationDeg, want.pose->inclinationDeg, 1e-12);
  }
  // Node 1 has no leaf, node 5 neither: the plant has the three that have points.
  EXPECT_EQ(p.leaves.size(), 3U);
}

TEST(SurveyedPlant, AQuickLeafTakesTheLibraryLeafOfItsTypeWhoseAspectIsNearest) {
  const PlantSurvey s = sampleSurvey();
  const SurveyedLeaf& quick = surveyed(s, 3);
  const double want = quick.pose->lengthMm / *quick.pose->widthMm;
  const MarkerSet& shape = sampleLeafShape();
  const double shapeAspect = (shape.tipMm - shape.rows.back().pointsMm[kMidribColumn]).norm() / bladeWidthMm(shape);
  // One "lower" leaf of exactly the measured aspect, one far from it, and an "upper" one of
  // exactly the aspect too (the wrong type: never taken).
  const std::vector<LibraryLeaf> library{libraryLeaf("session 11", "lower", 0.5),
                                         libraryLeaf("session 12", "lower", shapeAspect / want),
                                         libraryLeaf("session 13", "upper", shapeAspect / want)};
  const Plant p = surveyedPlant(s, library, sample());
  EXPECT_EQ(placed(p, 3).source, "library: session 12");
  EXPECT_FALSE(placed(p, 3).shapeDigitized);
  // Of its own aspect, the library leaf needs no stretch across more than along.
  EXPECT_NEAR(placed(p, 3).widthFactor / placed(p, 3).lengthFactor, 1.0, 0.02);
  // A leaf that asks for no type takes any.
  PlantSurvey anyType = s;
  for (SurveyedLeaf& l : anyType.leaves) l.type.clear();
  EXPECT_EQ(placed(surveyedPlant(anyType, {library[2]}, sample()), 3).source, "library: session 13");
}

// Issue 51: the survey's areas add up to the plant's leaves — a quick leaf's is its drawn
// shape's (named), the same as the plant's mesh of it, and no interval; a full leaf's unchanged.
TEST(SurveyedPlant, AQuickLeafsAreaIsItsDrawnShapesAndTheSurveysAreasAddUpToThePlants) {
  PlantSurvey s = sampleSurvey();
  const double fullBefore = *surveyed(s, 2).areaMm2;
  ASSERT_FALSE(surveyed(s, 3).areaMm2.has_value());
  const std::vector<LibraryLeaf> library{libraryLeaf("session 12", "lower", 1.1)};
  addDrawnAreas(s, library, sample());
  EXPECT_EQ(*surveyed(s, 2).areaMm2, fullBefore);
  EXPECT_TRUE(surveyed(s, 2).areaShape.empty());
  for (int node : {3, 4}) {
    EXPECT_EQ(surveyed(s, node).areaShape, "library: session 12");
    EXPECT_FALSE(surveyed(s, node).areaLow95Mm2.has_value());
  }
  const Plant p = surveyedPlant(s, library, sample());
  const LeafMesh mesh = meshPlant(p, MeshResolution::preset("export"));
  const PlantMetrics metrics = computePlantMetrics(p, mesh, Vector3d::UnitZ());
  double survey = 0, plant = 0;
  for (const SurveyedLeaf& l : s.leaves) survey += l.areaMm2.value_or(0.0);
  for (const LeafLight& l : metrics.leaves) {
    plant += l.areaMm2;
    EXPECT_NEAR(*surveyed(s, l.rank).areaMm2, l.areaMm2, 0.005 * l.areaMm2) << "leaf " << l.rank;
  }
  EXPECT_NEAR(survey, plant, 0.005 * plant);
  // Without a library, the built-in shape's, named.
  PlantSurvey alone = sampleSurvey();
  addDrawnAreas(alone, {}, sample());
  EXPECT_EQ(surveyed(alone, 3).areaShape.rfind(kSampleShapeSource, 0), 0U);
  EXPECT_GT(*surveyed(alone, 3).areaMm2, 0.0);
}
