// `leafdig plant import` driven as a modeller would (docs/plants.md, "Archives"): the public
// archives in tests/data/archives (OpenAlea's walnut and apple tree, HydroShoot's grapevine,
// CeCILL-C) into every format,
// each opened by an independent reader — the Khronos glTF validator, assimp, the strict MTG and
// CARIBU readers of docs/plants.md "Formats" — and the refusals a bad file or option gets.
#include <set>

#include "../support/strict_formats.hpp"
#include "cli_support.hpp"

namespace {

std::string archive(const std::string& name) {
  return std::string(LEAFDIG_SOURCE_DIR) + "/tests/data/archives/" + name;
}

class PlantImportCli : public Cli {};

}  // namespace

TEST_F(PlantImportCli, TheWalnutImportsToEveryFormatEachOpenedByAnIndependentReader) {
  std::string outputs;
  for (const char* ext : {"glb", "obj", "can", "mtg", "csv", "json"})
    outputs += " -o " + quote(dir_ / (std::string("walnut.") + ext));
  const Result r = leafdig("plant import " + quote(archive("noylum2.mtg")) + " --drf " + quote(archive("walnut.drf")) +
                           " --units cm --resolution preview --json" + outputs);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json report = json::parse(r.out);
  // Every entity of the file (OpenAlea's count: the root and 8 303 entities), the plant's points
  // and axes of eight orders.
  EXPECT_EQ(report["vertices"], 8304);
  EXPECT_EQ(report["plant_vertices"], 8303);
  EXPECT_EQ(report["classes"]["S"].get<int>() + report["classes"]["U"].get<int>() + report["classes"]["A"].get<int>() +
                report["classes"]["P"].get<int>(),
            8303);
  const int points = report["points"], axes = report["axes"];
  EXPECT_GT(points, 6000);
  int byOrder = 0;
  for (const auto& [order, count] : report["axes_by_order"].items()) byOrder += count.get<int>();
  EXPECT_EQ(byOrder, axes);
  EXPECT_GE(report["axes_by_order"].size(), 8U);
  // The walnut's box: its trunk's base 27 cm below the file's origin, about 8 m tall.
  EXPECT_NEAR(report["box_mm"]["low"][2].get<double>(), -272.3, 1e-9);
  EXPECT_GT(report["box_mm"]["high"][2].get<double>(), 7000);
  const long triangles = report["triangles"];

  const std::string validator = std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs";
  const Result check = run("node " + quote(validator) + " " + quote(dir_ / "walnut.glb"));
  ASSERT_EQ(check.exitCode, 0) << check.out << check.err;
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;
  ASSERT_EQ(run("command -v assimp").exitCode, 0) << "assimp is not installed: run scripts/setup.sh";
  const std::string info = run("assimp info " + quote(dir_ / "walnut.obj") + " -r").out;
  const std::size_t faces = info.find("\nFaces:");
  ASSERT_NE(faces, std::string::npos) << info;
  EXPECT_EQ(std::stol(info.substr(faces + 8)), triangles);

  // CARIBU: all wood (leaf 000, opaque; the axes past the 998th share element 999); every
  // triangle but those that are a line once written to the micrometre (a thin twig's tube
  // between points a fraction of a millimetre apart), which the writer leaves out.
  const auto opt = leafdig::test::readOptStrictly(slurp(dir_ / "walnut.opt"));
  const auto can = leafdig::test::readCanStrictly(slurp(dir_ / "walnut.can"), opt);
  EXPECT_LE(static_cast<long>(can.size()), triangles);
  EXPECT_GT(static_cast<double>(can.size()), 0.999 * static_cast<double>(triangles));
  std::set<int> leaves;
  for (const auto& t : can) leaves.insert(t.leaf);
  EXPECT_EQ(leaves, std::set<int>{0});

  // MTG: the strict reader; one E per digitized point, one A per axis, every point with its
  // coordinates, diameter and the entity and line it came from.
  const auto mtg = leafdig::test::readMtgStrictly(slurp(dir_ / "walnut.mtg"));
  int e = 0, a = 0;
  for (const auto& entity : mtg.entities) {
    if (entity.symbol == 'E') {
      ++e;
      for (const char* f : {"XX", "YY", "ZZ", "TopDia", "Source", "Line"}) EXPECT_EQ(entity.features.count(f), 1U) << f;
    }
    a += entity.symbol == 'A' ? 1 : 0;
  }
  EXPECT_EQ(e, points);
  EXPECT_EQ(a, axes);
  // The CSV: a comment, the titles, a row per point and per axis' base.
  const std::string csv = slurp(dir_ / "walnut.csv");
  EXPECT_EQ(csv.rfind("# plant P1 imported from noylum2.mtg", 0), 0U);
  EXPECT_GE(std::count(csv.begin(), csv.end(), '\n'), points + 2);
  EXPECT_NE(csv.find("\n1,1,0,point,S1,50,-25.000,-176.800,1214.300,180.000\n"), std::string::npos);
  EXPECT_EQ(json::parse(slurp(dir_ / "walnut.json"))["format"], "leafdig.plant-model/1");

  // The MTG leafdig wrote, imported again, is the same plant: the same axes and points.
  const Result again =
      leafdig("plant import " + quote(dir_ / "walnut.mtg") + " --units mm --json -o " + quote(dir_ / "again.csv"));
  ASSERT_EQ(again.exitCode, 0) << again.err;
  const json second = json::parse(again.out);
  EXPECT_EQ(second["points"], points);
  EXPECT_EQ(second["axes_by_order"], report["axes_by_order"]);
  const std::string csv2 = slurp(dir_ / "again.csv");
  const auto geometry = [](const std::string& text) {  // rows without the entity and line columns
    std::string out;
    std::istringstream in(text);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      std::vector<std::string> cells;
      std::stringstream s(line);
      std::string cell;
      while (std::getline(s, cell, ',')) cells.push_back(cell);
      for (std::size_t i = 0; i < cells.size(); ++i)
        if (i != 4 && i != 5) out += cells[i] + ",";
      out += "\n";
    }
    return out;
  };
  EXPECT_EQ(geometry(csv), geometry(csv2));
}

TEST_F(PlantImportCli, TheAppleTreesRangesAndFruitsImportWithTheirUnits) {
  const Result r = leafdig("plant import " + quote(archive("agraf.mtg")) + " --drf " + quote(archive("agraf.drf")) +
                           " --units mm --json -o " + quote(dir_ / "apple.mtg"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json report = json::parse(r.out);
  // Ranges made every entity between (E: 2 971 of them), every class of the file counted.
  EXPECT_EQ(report["classes"]["E"], 2971);
  EXPECT_EQ(report["classes"]["U"], 79);
  EXPECT_EQ(report["plant"], "P1");
  EXPECT_GT(report["without_point"].get<int>(), 2000);               // a range's inner entities have no coordinates
  EXPECT_NEAR(report["box_mm"]["low"][2].get<double>(), 0.0, 1e-9);  // U94's (0, 0, 0): the trunk's base
  const auto mtg = leafdig::test::readMtgStrictly(slurp(dir_ / "apple.mtg"));
  EXPECT_GT(mtg.entities.size(), 400U);
  // The dressing keys leafdig does not draw with are named, once each.
  std::set<std::string> notes;
  for (const auto& n : report["notes"]) EXPECT_TRUE(notes.insert(n.get<std::string>()).second) << n;
  EXPECT_EQ(notes.count("dressing key SMBModel is read past"), 1U);
}

TEST_F(PlantImportCli, ABadFileOrOptionExitsTwoNamingWhatToDoAndWritesNothing) {
  const fs::path out = dir_ / "tree.glb";
  // No unit: an MTG does not say it.
  Result r = leafdig("plant import " + quote(archive("agraf.mtg")) + " -o " + quote(out));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("give --units mm, cm or m"), std::string::npos) << r.err;
  // A plant the file does not have.
  r = leafdig("plant import " + quote(archive("agraf.mtg")) + " --units mm --plant 2 -o " + quote(out));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("there is no plant 2 (the file has 1)"), std::string::npos) << r.err;
  // A line shifted by one tab: refused at its line and column (OpenAlea's reader reads it one
  // column off).
  std::string text = slurp(archive("agraf.mtg"));
  const std::size_t at = text.find("^/U94\t");
  ASSERT_NE(at, std::string::npos);
  text.insert(at + 6, "\t");
  const fs::path shifted = dir_ / "shifted.mtg";
  std::ofstream(shifted) << text;
  r = leafdig("plant import " + quote(shifted) + " --units mm -o " + quote(out));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("shifted.mtg, line 50: column 23"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("past the last feature (bidon)"), std::string::npos) << r.err;
  // A file that is no archive, and an output leafdig cannot write.
  const fs::path notes = dir_ / "notes.txt";
  std::ofstream(notes) << "the walnut by the gate\n";
  r = leafdig("plant import " + quote(notes) + " --units cm -o " + quote(out));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("MTG files (.mtg) and HydroShoot's digitizing tables"), std::string::npos) << r.err;
  r = leafdig("plant import " + quote(archive("agraf.mtg")) + " --units mm -o " + quote(dir_ / "tree.docx"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_FALSE(fs::exists(out));
  // A bad dressing file names its line.
  const fs::path drf = dir_ / "bad.drf";
  std::ofstream(drf) << "# units\nDiameterUnit = ten\n";
  r = leafdig("plant import " + quote(archive("agraf.mtg")) + " --units mm --drf " + quote(drf) + " -o " + quote(out));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("bad.drf, line 2: DiameterUnit = \"ten\": a unit is a number above 0"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(PlantImportCli, TheHydroShootGrapevineImportsInCentimetresAndOpensInEveryReader) {
  const std::string table = archive("grapevine_gdc_can1.digit.input");
  std::string outputs;
  for (const char* ext : {"glb", "mtg", "csv", "xml", "vgx"})
    outputs += " -o " + quote(dir_ / (std::string("vine.") + ext));
  const Result r = leafdig("plant import " + quote(table) + " --resolution preview --json" + outputs);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json report = json::parse(r.out);
  EXPECT_EQ(report["units"], "cm");  // the table's unit, unless --units says otherwise
  EXPECT_EQ(report["plant"], "plant1");
  EXPECT_EQ(report["classes"]["trunk"], 1);
  EXPECT_EQ(report["classes"]["arm"], 2);
  // Every digitized entity is a point: the internodes of every kind and the pruning complexes.
  int internodes = 0, all = 0;
  for (const auto& [symbol, count] : report["classes"].items()) {
    all += count.get<int>();
    if (symbol.rfind("in", 0) == 0 || symbol == "cx") internodes += count.get<int>();
  }
  EXPECT_EQ(all, report["plant_vertices"].get<int>());
  EXPECT_EQ(report["points"], internodes);
  EXPECT_EQ(report["without_point"], 0);
  // The trunk's foot at 24.5 mm, the canopy about 2.3 m high.
  EXPECT_NEAR(report["box_mm"]["low"][2].get<double>(), 24.5, 1e-9);
  EXPECT_NEAR(report["box_mm"]["high"][2].get<double>(), 2294.2, 1e-9);

  const std::string validator = std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs";
  const Result check = run("node " + quote(validator) + " " + quote(dir_ / "vine.glb"));
  ASSERT_EQ(check.exitCode, 0) << check.out << check.err;
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;
  const auto mtg = leafdig::test::readMtgStrictly(slurp(dir_ / "vine.mtg"));
  int e = 0;
  for (const auto& entity : mtg.entities) e += entity.symbol == 'E' ? 1 : 0;
  EXPECT_EQ(e, internodes);
  const auto helios = leafdig::test::readHeliosStrictly(slurp(dir_ / "vine.xml"));
  EXPECT_FALSE(helios.triangles.empty());
  EXPECT_FALSE(leafdig::test::readVgxStrictly(slurp(dir_ / "vine.vgx")).empty());
  // The CSV names each point's row in the table: the trunk's first internode on line 2.
  EXPECT_NE(slurp(dir_ / "vine.csv").find("\n1,1,0,point,inT1,2,-25.400,6.800,24.500,70.000\n"), std::string::npos);

  // A plant named with a terminal's control sequence in the table is printed as text.
  const fs::path hostile = dir_ / "hostile.input";
  std::ofstream(hostile) << "Souche;tronc;element;sarment;rameau;rang;X;Y;Z;Diam\n"
                         << "\x1b[31mowned\x07;0;1;0;0;0;0;0;10;3\n\x1b[31mowned\x07;0;2;0;0;0;0;0;20;3\n";
  const Result named = leafdig("plant import " + quote(hostile));
  ASSERT_EQ(named.exitCode, 0) << named.err;
  EXPECT_EQ(named.out.find('\x1b'), std::string::npos) << named.out;
  EXPECT_EQ(named.out.find('\x07'), std::string::npos) << named.out;
  EXPECT_NE(named.out.find("owned"), std::string::npos) << named.out;

  // A table written in millimetres says so.
  const Result mm = leafdig("plant import " + quote(table) + " --units mm --json");
  ASSERT_EQ(mm.exitCode, 0) << mm.err;
  EXPECT_EQ(json::parse(mm.out)["units"], "mm");
  EXPECT_NEAR(json::parse(mm.out)["box_mm"]["high"][2].get<double>(), 229.42, 1e-9);
}
