// `leafdig mesh compare|study` and `--mesh` on model/plant build, driven as a user would:
// files written by one command, measured by another, opened by assimp and the Khronos
// glTF validator.
#include "cli_support.hpp"

namespace {

class MeshCli : public Cli {
 protected:
  long assimpFaces(const fs::path& file) {
    const std::string out = run("assimp info " + quote(file) + " -r").out;
    const std::size_t at = out.find("\nFaces:");
    return at == std::string::npos ? -1L : std::stol(out.substr(at + 8));
  }
  json compare(const fs::path& a, const fs::path& b) {
    const Result r = leafdig("mesh compare " + quote(a) + " " + quote(b) + " --json");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return json::parse(r.out);
  }
};

TEST_F(MeshCli, CompareMeasuresTheSameMeshInEveryFormatAsTheSameAndAnAdaptiveMeshWithinItsError) {
  const std::string leaf = sample("upper-small-leaf-n17.markers.json");
  const Result uniform =
      leafdig("model build " + quote(leaf) + " --frame leaf -o " + quote(dir_ / "u.ply") + " -o " +
              quote(dir_ / "u.obj") + " -o " + quote(dir_ / "u.glb") + " -o " + quote(dir_ / "u.stl") + " --json");
  ASSERT_EQ(uniform.exitCode, 0) << uniform.err;
  // The same mesh in four formats (GLB in metres with +Y up, read back into mm, +Z up).
  for (const char* other : {"u.obj", "u.glb", "u.stl"}) {
    const json d = compare(dir_ / "u.ply", dir_ / other);
    EXPECT_LT(d["hausdorff_mm"].get<double>(), 1e-3) << other;
    EXPECT_EQ(d["a"]["triangles"], d["b"]["triangles"]) << other;
  }
  const Result adaptive = leafdig("model build " + quote(leaf) + " --frame leaf --mesh adaptive --max-error 0.2 -o " +
                                  quote(dir_ / "a.ply") + " --json");
  ASSERT_EQ(adaptive.exitCode, 0) << adaptive.err;
  const json report = json::parse(adaptive.out)["mesh"];
  EXPECT_EQ(report["method"], "adaptive");
  EXPECT_EQ(report["parameters"]["max_error_mm"], 0.2);
  // Triangles per organ add up, and match what assimp reads.
  long sum = 0;
  for (const auto& organ : report["organs"]) sum += organ["triangles"].get<long>();
  EXPECT_EQ(sum, report["triangles"].get<long>());
  EXPECT_EQ(assimpFaces(dir_ / "a.ply"), sum);
  EXPECT_EQ(report["organs"].back()["name"], "blade");
  EXPECT_LE(report["measured"]["hausdorff_mm"].get<double>(), 0.2);
  // Measured again, independently, against the export resolution (itself ~0.1 mm off).
  const json d = compare(dir_ / "a.ply", dir_ / "u.ply");
  EXPECT_LT(d["hausdorff_mm"].get<double>(), 0.3);
  EXPECT_LT(sum, json::parse(uniform.out)["mesh"]["triangles"].get<long>() / 5);
}

TEST_F(MeshCli, CompareRefusesMissingOrUnreadableFilesWithExitTwo) {
  const fs::path junk = write("junk.ply", "ply\nformat nonsense\n");
  const Result missing = leafdig("mesh compare " + quote(dir_ / "none.obj") + " " + quote(junk));
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_NE(missing.err.find("none.obj: no such file"), std::string::npos) << missing.err;
  const Result bad = leafdig("mesh compare " + quote(junk) + " " + quote(junk));
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("junk.ply: not a readable mesh"), std::string::npos) << bad.err;
  const Result ext = leafdig("mesh compare " + quote(write("a.dxf", "x")) + " " + quote(junk));
  EXPECT_EQ(ext.exitCode, 2);
  EXPECT_NE(ext.err.find("use .obj, .ply, .stl, .glb"), std::string::npos) << ext.err;
}

TEST_F(MeshCli, MeshOptionsThatDoNotFitTheMethodAreRefusedBeforeAnythingIsWritten) {
  const std::string leaf = sample("lower-leaf-n10.markers.json");
  const fs::path out = dir_ / "x.glb";
  const Result r1 = leafdig("model build " + quote(leaf) + " --max-error 0.1 -o " + quote(out));
  EXPECT_EQ(r1.exitCode, 2);
  EXPECT_NE(r1.err.find("add --mesh adaptive"), std::string::npos) << r1.err;
  const Result r2 = leafdig("model build " + quote(leaf) + " --mesh adaptive --min-length 2 -o " + quote(out));
  EXPECT_EQ(r2.exitCode, 2);
  EXPECT_NE(r2.err.find("add --mesh seed"), std::string::npos) << r2.err;
  const Result r3 = leafdig("model build " + quote(leaf) + " --mesh seed --max-angle 45 -o " + quote(out));
  EXPECT_EQ(r3.exitCode, 2);
  EXPECT_NE(r3.err.find("--max-angle must be in (90, 180]"), std::string::npos) << r3.err;
  const Result r4 = leafdig("model build " + quote(leaf) + " --mesh fine -o " + quote(out));
  EXPECT_EQ(r4.exitCode, 2);
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(MeshCli, SeedModeBuildsALeafAndAPlantAndItsGlbIsValid) {
  const std::string leaf = sample("lower-leaf-n10.markers.json");
  const Result seed =
      leafdig("model build " + quote(leaf) +
              " --mesh seed --min-length 3 --max-angle 170 --ring 6 --no-measure --json -o " + quote(dir_ / "s.obj"));
  ASSERT_EQ(seed.exitCode, 0) << seed.err;
  const json report = json::parse(seed.out)["mesh"];
  EXPECT_EQ(report["parameters"]["ring_vertices"], 6);
  EXPECT_FALSE(report.contains("measured"));
  EXPECT_EQ(assimpFaces(dir_ / "s.obj"), report["triangles"].get<long>());

  const std::string plan = std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/tobacco-p07.plant.json";
  const Result plant = leafdig("plant build " + quote(plan) + " --mesh adaptive --max-error 0.3 --no-measure -o " +
                               quote(dir_ / "p.glb") + " --json");
  ASSERT_EQ(plant.exitCode, 0) << plant.err;
  const json state = json::parse(plant.out)["states"][0];
  EXPECT_EQ(state["mesh"]["method"], "adaptive");
  EXPECT_EQ(state["mesh"]["organs"][0]["name"], "plant/stem");
  const std::string validator = std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs";
  const Result check = run("node " + quote(validator) + " " + quote(dir_ / "p.glb"));
  ASSERT_EQ(check.exitCode, 0) << check.out << check.err;
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;
  const Result uniform = leafdig("plant build " + quote(plan) + " -o " + quote(dir_ / "q.glb") + " --json");
  ASSERT_EQ(uniform.exitCode, 0) << uniform.err;
  EXPECT_LT(state["triangles"].get<long>(), json::parse(uniform.out)["states"][0]["triangles"].get<long>() / 5);
}

// The study of the issue: every file within E of the reference (measured again here by
// `mesh compare` on the written files), adaptive with >= 60 % fewer triangles than uniform
// and fewer than meshoptimizer, and its silhouette within 0.2 % of the reference's.
TEST_F(MeshCli, TheStudyMeetsTheTargetsOnASampleLeaf) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  // Unsanitized it takes ~40 s; under ASan 11 minutes of both cores, which starved the
  // timing-sensitive device fault tests running beside it. Its code is covered under the
  // sanitizers by the MeshStudy, MeshCompare and AdaptiveMesh model tests.
  GTEST_SKIP() << "the full meshing study runs in the unsanitized pass only";
#endif
  const Result r = leafdig("mesh study " + quote(sample("upper-small-leaf-n17.markers.json")) +
                           " --max-error 0.1 --samples 40000 --out " + quote(dir_ / "study") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json study = json::parse(r.out);
  EXPECT_EQ(study["max_error_mm"], 0.1);
  const json& m = study["meshes"];
  for (const char* name : {"reference", "uniform", "seed", "adaptive", "meshopt"}) {
    ASSERT_TRUE(m.contains(name)) << name;
    const fs::path file = dir_ / "study" / m[name]["file"].get<std::string>();
    ASSERT_TRUE(fs::exists(file)) << file;
    EXPECT_EQ(assimpFaces(file), m[name]["triangles"].get<long>()) << name;
  }
  EXPECT_LT(m["reference"]["hausdorff_mm"].get<double>(), 0.1 / 3);
  for (const char* name : {"uniform", "adaptive", "meshopt"}) {
    EXPECT_LE(m[name]["hausdorff_mm"].get<double>(), 0.1) << name;
    EXPECT_TRUE(m[name]["meets_error"].get<bool>()) << name;
    const json d = compare(dir_ / "study" / (std::string(name) + ".ply"), dir_ / "study" / "reference.ply");
    EXPECT_LE(d["hausdorff_mm"].get<double>(), 0.1) << name << " measured by mesh compare";
  }
  const double adaptive = m["adaptive"]["triangles"].get<double>();
  EXPECT_LE(adaptive, 0.4 * m["uniform"]["triangles"].get<double>());
  EXPECT_LT(adaptive, m["meshopt"]["triangles"].get<double>());
  EXPECT_LT(std::abs(m["adaptive"]["silhouette_vs_reference_percent"].get<double>()), 0.2);
  // The seed's blades have no interior points: on a curved leaf they cannot meet 0.1 mm,
  // and the study says so rather than hiding it.
  EXPECT_FALSE(m["seed"]["meets_error"].get<bool>());
  EXPECT_GT(m["seed"]["parameters"]["ring_vertices"].get<int>(), 2);
}

}  // namespace
