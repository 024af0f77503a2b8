#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "../support/small_file_system.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "test_support.hpp"

namespace leafdig::model {
namespace {

namespace fs = std::filesystem;

using test::freshDir;

TEST(MarkersJson, roundTripsEveryField) {
  const MarkerSet original = test::sample("upper-curved-leaf-n14.markers.json");
  const MarkerSet again = parseMarkersJson(markersToJson(original), "round-trip");
  EXPECT_EQ(again.leaf.id, original.leaf.id);
  EXPECT_EQ(again.leaf.position, original.leaf.position);
  EXPECT_EQ(again.leaf.measuredAreaMm2, original.leaf.measuredAreaMm2);
  EXPECT_EQ(again.tipMm, original.tipMm);
  ASSERT_EQ(again.rows.size(), original.rows.size());
  for (std::size_t i = 0; i < again.rows.size(); ++i) {
    EXPECT_EQ(again.rows[i].pointsMm, original.rows[i].pointsMm);
    EXPECT_EQ(again.rows[i].midribThicknessMm, original.rows[i].midribThicknessMm);
    EXPECT_EQ(again.rows[i].veinOriginThicknessMm, original.rows[i].veinOriginThicknessMm);
    EXPECT_EQ(again.rows[i].edgeThicknessMm, original.rows[i].edgeThicknessMm);
  }
  EXPECT_EQ(again.edgeThicknessMm, original.edgeThicknessMm);
}

TEST(MarkersJson, convertsCentimetresAndInchesToMillimetres) {
  nlohmann::json doc = nlohmann::json::parse(markersToJson(test::flatTriangleLeaf(1, 10, 20)));
  doc["units"] = "cm";
  MarkerSet cm = parseMarkersJson(doc.dump(), "cm");
  EXPECT_DOUBLE_EQ(cm.rows[0].pointsMm[0].x(), 300.0);
  EXPECT_DOUBLE_EQ(*cm.rows[0].midribThicknessMm, 20.0);
  doc["units"] = "in";
  MarkerSet in = parseMarkersJson(doc.dump(), "in");
  EXPECT_DOUBLE_EQ(in.rows[0].pointsMm[0].x(), 30 * 25.4);
  doc["units"] = "mm";
  doc["thickness_kind"] = "radius";
  MarkerSet radius = parseMarkersJson(doc.dump(), "radius");
  EXPECT_DOUBLE_EQ(*radius.rows[0].midribThicknessMm, 4.0);
}

TEST(MarkersJson, ignoresUnknownKeysAndNamesMissingOnes) {
  nlohmann::json doc = nlohmann::json::parse(markersToJson(test::flatTriangleLeaf(2, 10, 20)));
  doc["station_notes"] = "ignored";
  doc["rows"][0]["colour"] = "green";
  EXPECT_NO_THROW(static_cast<void>(parseMarkersJson(doc.dump(), "extra")));
  doc.erase("tip");
  try {
    static_cast<void>(parseMarkersJson(doc.dump(), "file.json"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"tip\""), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("file.json"), std::string::npos) << e.what();
  }
}

TEST(MarkersJson, reportsNaNWrittenByOtherToolsAtItsRowAndPoint) {
  std::string text = markersToJson(test::flatTriangleLeaf(3, 10, 20));
  const std::string needle = "[0, -40, 0]";  // row 2, point 4
  ASSERT_NE(text.find(needle), std::string::npos);
  text.replace(text.find(needle), needle.size(), "[0, NaN, 0]");
  try {
    static_cast<void>(parseMarkersJson(text, "nan.json"));
    FAIL();
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("row 2, point 4"), std::string::npos) << what;
    EXPECT_NE(what.find("coordinate y is NaN"), std::string::npos) << what;
  }
}

TEST(ModelJson, roundTripsVeinsBladeAndMetrics) {
  const LeafModel leaf = buildLeafModel(test::sample("lower-leaf-n10.markers.json"));
  const LeafMetrics metrics = computeLeafMetrics(leaf, {0, 0, 1});
  const ModelDocument doc = parseModelJson(modelToJson(leaf, "digitizer", metrics), "model");
  EXPECT_EQ(doc.frame, "digitizer");
  ASSERT_EQ(doc.veins.size(), leaf.veins.size());
  for (std::size_t v = 0; v < leaf.veins.size(); ++v) {
    EXPECT_EQ(doc.veins[v].name, leaf.veins[v].name);
    EXPECT_EQ(doc.veins[v].curve.spline().knots(), leaf.veins[v].curve.spline().knots());
    EXPECT_EQ(doc.veins[v].curve.spline().controlPoints(), leaf.veins[v].curve.spline().controlPoints());
    EXPECT_EQ(doc.veins[v].curve.dataParameters(), leaf.veins[v].curve.dataParameters());
    for (double t : {0.0, 0.33, 0.9, 1.0}) {
      EXPECT_EQ(doc.veins[v].curve.spline().evaluate(t), leaf.veins[v].curve.spline().evaluate(t));
    }
  }
  EXPECT_EQ(doc.blade.knotsU, leaf.blade.knotsU);
  EXPECT_EQ(doc.blade.knotsV, leaf.blade.knotsV);
  EXPECT_EQ(doc.blade.controlNet, leaf.blade.controlNet);
  EXPECT_EQ(doc.blade.evaluate(0.4, 0.6), leaf.blade.evaluate(0.4, 0.6));
  EXPECT_EQ(doc.bladeAreaMm2, metrics.blade.areaMm2);
  EXPECT_EQ(doc.projectedAreaMm2, metrics.blade.projectedAreaMm2);
}

TEST(ModelJson, statesThatRadiiAreHalfTheThickness) {
  const LeafModel leaf = buildLeafModel(test::flatTriangleLeaf(2, 10, 20));
  const auto doc = nlohmann::json::parse(modelToJson(leaf, "digitizer", computeLeafMetrics(leaf, {0, 0, 1})));
  EXPECT_EQ(doc["format"], "leafdig.model/1");
  EXPECT_EQ(doc["units"], "mm");
  EXPECT_EQ(doc["veins"][0]["name"], "midrib");
  EXPECT_DOUBLE_EQ(doc["veins"][0]["data_balls"][1][3].get<double>(), 1.0);  // r_14^1 = 2 mm
}

TEST(Files, atomicWriteReplacesTheFileAndLeavesNoTemporary) {
  const fs::path dir = freshDir("atomic");
  const fs::path target = dir / "leaf.obj";
  writeFileAtomically(target, "first");
  writeFileAtomically(target, "second");
  EXPECT_EQ(readFile(target), "second");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
  fs::remove_all(dir);
}

TEST(Files, failedWriteNamesThePathAndLeavesNothing) {
  const fs::path dir = freshDir("failed");
  const fs::path target = dir / "missing-folder" / "leaf.glb";
  try {
    writeFileAtomically(target, "bytes");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing-folder"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 0);
  fs::remove_all(dir);
}

// A folder where the file should go: refused before anything is written (issue 47: a target
// that is not a regular file is never replaced), and no temporary file is left.
TEST(Files, aFolderAsTheTargetIsRefusedAndNoTemporaryFileIsLeft) {
  const fs::path dir = freshDir("rename");
  fs::create_directories(dir / "leaf.glb");  // a folder where the file should go
  EXPECT_THROW(writeFileAtomically(dir / "leaf.glb", std::string(100000, 'x')), InputError);
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"leaf.glb"});  // only the folder: no temporary file
  fs::remove_all(dir);
}

// A file system that fills up halfway through the write (a 64 KB tmpfs, when root).
TEST(Files, aFullFileSystemNamesTheProblemAndLeavesNoTemporaryFile) {
  const fs::path dir = freshDir("full");
  leafdig::test::SmallFileSystem disk(dir / "small", 64 << 10);
  if (!disk.mounted()) GTEST_SKIP() << "not root: no tmpfs to fill (the rename test above covers the clean-up)";
  writeFileAtomically(disk.dir() / "before.obj", "kept");
  try {
    writeFileAtomically(disk.dir() / "leaf.glb", std::string(1 << 20, 'x'));
    FAIL() << "a 1 MB file fitted on a 64 KB file system";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("leaf.glb"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No space left"), std::string::npos) << e.what();
  }
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(disk.dir())) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"before.obj"});
  EXPECT_EQ(readFile(disk.dir() / "before.obj"), "kept");
}

TEST(Files, unwritableDestinationIsAnIoError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  // A destination that cannot hold a file is an IoError, never a crash or a silent success.
  EXPECT_THROW(writeFileAtomically("/dev/full/leaf.glb", "bytes"), IoError);
}

TEST(MeshExport, glbHasTheBinaryGltfHeaderAndOneNodePerOrgan) {
  const LeafModel leaf = buildLeafModel(test::sample("lower-leaf-n10.markers.json"));
  const LeafMesh mesh = meshLeaf(leaf, MeshResolution::preset("preview"));
  const std::string glb = encodeMesh(mesh, MeshFormat::Glb, {"S-lower-10", "digitizer", "leafdig"});
  ASSERT_GT(glb.size(), 20u);
  EXPECT_EQ(glb.substr(0, 4), "glTF");
  std::uint32_t length = 0;
  std::memcpy(&length, glb.data() + 8, 4);
  EXPECT_EQ(length, glb.size());
  std::uint32_t jsonLength = 0;
  std::memcpy(&jsonLength, glb.data() + 12, 4);
  const auto json = nlohmann::json::parse(glb.substr(20, jsonLength));
  EXPECT_EQ(json["nodes"].size(), mesh.organs.size() + 1);
  EXPECT_EQ(json["nodes"][0]["name"], "midrib");
  EXPECT_EQ(json["nodes"].back()["name"], "S-lower-10");
}

TEST(MeshExport, rejectsUnknownExtensionsWithTheSupportedList) {
  try {
    static_cast<void>(meshFormatForPath("leaf.fbx"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(".glb, .obj, .ply or .stl"), std::string::npos);
  }
  EXPECT_EQ(meshFormatForPath("LEAF.OBJ"), MeshFormat::Obj);
}

TEST(MeshExport, gltfAxesPutTheFramesUpOnPlusY) {
  EXPECT_EQ(toGltfAxes({0, 0, 1}), Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(toGltfAxes({0, 1, 0}), Eigen::Vector3d(0, 0, -1));
}

}  // namespace
}  // namespace leafdig::model
