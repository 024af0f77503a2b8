// HydroShoot's grapevine digitizing tables (docs/plants.md, "HydroShoot's digitizing tables"):
// the tree vine_mtg builds, checked vertex by vertex on a table written by hand (each vertex's
// number, label, scale, complex, parent and edge worked out from vine_mtg's rules on paper), and
// on the public GDC grapevine (tests/data/archives, CeCILL-C) against counts made row by row
// without building a tree.
#include "leafdig/model/archive/hydroshoot_table.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "leafdig/model/archive/plant_import.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"

namespace m = leafdig::model;

namespace {

std::string archive(const std::string& name) {
  return std::string(LEAFDIG_SOURCE_DIR) + "/tests/data/archives/" + name;
}

struct V {
  const char* label;
  int scale, complex, parent;
  char edge;
};

void expectTree(const m::MtgArchive& a, const std::vector<V>& expected) {
  ASSERT_EQ(a.vertices.size(), expected.size() + 1);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const m::MtgVertex& v = a.vertices[i + 1];
    const V& e = expected[i];
    SCOPED_TRACE("vertex " + std::to_string(i + 1) + " " + e.label);
    EXPECT_EQ(v.label, e.label);
    EXPECT_EQ(v.scale, e.scale);
    EXPECT_EQ(v.complex, e.complex);
    EXPECT_EQ(v.parent, e.parent);
    EXPECT_EQ(v.edge, e.edge);
  }
}

constexpr const char* kHandTable =
    "Souche;tronc;element;sarment;rameau;rang;X;Y;Z;Diam\n"
    "1;0;1;0;0;0;0;0;10;3\n"             // plant1 (1), trunk (2), inT1 (3)
    "1;0;2;0;0;0;0;0;20;3\n"             // inT2 (4) < 3
    "1;1;1;0;0;0;5;0;20;2\n"             // arm1 (5) + trunk; inT1 (6) in arm1, + from the trunk's inT2
    "1;1;2;0;0;0;10;0;20;2\n"            // inT2 (7) < 6
    "1;1;2.A;0;0;0;11;0;21;1\n"          // cx2.A (8) + 7
    "1;1;2.A;1;0;0;12;0;22;1\n"          // inT3y1.0 (9) + 8 (sarment is a column of floats)
    "1;1;2.A;1.1;0;0;13;0;23;1\n"        // inT3y1.1 (10) < 9: the same integer part
    "1;1;2.A;1.1;1;0;13;1;24;0.8\n"      // inT2y1 (11) + 10: the spur's first internode
    "1;1;2.A;1.1;1;1;13;2;25;0.7\n"      // shI1 (12) in arm1, then inI1 (13) + 11
    "1;1;2.A;1.1;1;2;13;3;26;0.7\n"      // inI2 (14) < 13
    "1;1;2.A;1.1;1;3;13;4;27;0.6\n"      // inI3 (15) < 14
    "1;1;2.A;1.1;1.2_1;1;14;3;27;0.4\n"  // shII1 (16) + shI1, inII1 (17) + 14 (internode 2 of the shoot)
    "1;1;2.A;1.1;1.2_1;2;15;3;27;0.4\n"  // inII2 (18) < 17
    "1;1;2.A;1.1;1p;0;15;3;28;0.2\n"     // a petiole's point: read past
    "1;1;2.A;0;G1;0;11;1;21;0.5\n"       // a G shoot on the complex: nothing yet at rang 0
    "1;1;2.A;0;G1;1;11;2;22;0.5\n"       // GIG1 (19) in arm1, inI1 (20) + 8
    "1;1;3;0;0;0;15;0;20;2\n";           // inT3 (21) < 7

}  // namespace

TEST(HydroShootTable, AHandWrittenTableIsTheTreeVineMtgBuilds) {
  const m::MtgArchive a = m::parseHydroShootTable(kHandTable, "hand.digit.input");
  expectTree(
      a, {{"plant1", 1, 0, -1, 0},    {"trunk", 2, 1, -1, 0},     {"inT1", 3, 2, -1, 0},     {"inT2", 3, 2, 3, '<'},
          {"arm1", 2, 1, 2, '+'},     {"inT1", 3, 5, 4, '+'},     {"inT2", 3, 5, 6, '<'},    {"cx2.A", 3, 5, 7, '+'},
          {"inT3y1.0", 3, 5, 8, '+'}, {"inT3y1.1", 3, 5, 9, '<'}, {"inT2y1", 3, 5, 10, '+'}, {"shI1", 2, 1, 5, '+'},
          {"inI1", 3, 12, 11, '+'},   {"inI2", 3, 12, 13, '<'},   {"inI3", 3, 12, 14, '<'},  {"shII1", 2, 1, 12, '+'},
          {"inII1", 3, 16, 14, '+'},  {"inII2", 3, 16, 17, '<'},  {"GIG1", 2, 1, 5, '+'},    {"inI1", 3, 19, 8, '+'},
          {"inT3", 3, 5, 7, '<'}});
  // Coordinates and diameters as vine_mtg keeps them, on the entities that carry them.
  EXPECT_EQ(a.vertices[17].cells, (std::vector<std::string>{"14", "3", "27", "0.4"}));
  EXPECT_EQ(a.vertices[12].cells, (std::vector<std::string>(4)));  // a shoot's complex has no point
  ASSERT_EQ(a.notes.size(), 1U);
  EXPECT_NE(a.notes[0].find("1 petiole and leaf rows"), std::string::npos);

  // Drawn: the trunk, the arm (its inT3 continuing it), and one axis per '+' above them.
  m::ArchiveImportOptions o;
  const m::ImportedPlant p = m::importMtgPlant(a, o);
  std::vector<std::pair<int, std::size_t>> axes;  // order, entities
  for (const auto& axis : p.axes) axes.emplace_back(axis.order, axis.vertices.size());
  EXPECT_EQ(axes,
            (std::vector<std::pair<int, std::size_t>>{{1, 2}, {2, 3}, {3, 1}, {4, 2}, {5, 1}, {6, 3}, {7, 2}, {4, 1}}));
  EXPECT_EQ(p.points, 15U);
  EXPECT_NEAR(p.axes[0].balls[1].center.z(), 200.0, 1e-9);  // cm to mm
  EXPECT_NEAR(p.axes[0].balls[1].radius, 15.0, 1e-9);
}

TEST(HydroShootTable, TheGdcGrapevineHasTheEntitiesItsRowsMake) {
  const std::string path = archive("grapevine_gdc_can1.digit.input");
  const m::MtgArchive a = m::readHydroShootTable(path);

  // The rows, read plainly: each level makes an entity where its label changes.
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::size_t inT = 0, cx = 0, cane = 0, spur = 0, primary = 0, secondary = 0, shoots = 0, gShoots = 0,
              secondaryShoots = 0, arms = 0, rows = 0;
  std::string lastInT, lastCx, lastCane, lastTrunk;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    ++rows;
    std::vector<std::string> c;
    std::stringstream split(line);
    for (std::string cell; std::getline(split, cell, ';');) c.push_back(cell);
    ASSERT_EQ(c.size(), 10U);
    const std::string trunk = c[0] + "_" + c[1], element = trunk + "_" + c[2];
    if (trunk != lastTrunk && c[1] != "0") ++arms;
    lastTrunk = trunk;
    const bool complexRow = c[2].find('.') != std::string::npos;
    if (!complexRow && element != lastInT) ++inT, lastInT = element;
    if (complexRow && element != lastCx) ++cx, lastCx = element;
    const bool onCane = std::stod(c[3]) != 0;
    if (onCane && element + "_" + c[3] != lastCane) ++cane, lastCane = element + "_" + c[3];
    const std::string& shoot = c[4];
    if (shoot == "0") continue;
    const bool g = shoot.find_first_of("gG") != std::string::npos;
    const int rank = std::stoi(c[5]);
    if (shoot.find('.') == std::string::npos) {
      if (rank == 0 && !g && (onCane || !complexRow)) ++spur;
      if (rank >= 1) ++primary;
      if (rank == 1) ++(g || (complexRow && !onCane) ? gShoots : shoots);
    } else {
      if (rank >= 1) ++secondary;
      if (rank == 1) ++secondaryShoots;
    }
  }
  std::map<std::string, std::size_t> count;
  for (std::size_t v = 1; v < a.vertices.size(); ++v) ++count[a.vertices[v].symbol];
  EXPECT_EQ(rows, 449U);
  EXPECT_EQ(count["plant"], 1U);
  EXPECT_EQ(count["trunk"], 1U);
  EXPECT_EQ(count["arm"], arms);
  EXPECT_EQ(count["inT"], inT);
  EXPECT_EQ(count["cx"], cx);
  EXPECT_EQ(count["inT3y"], cane);
  EXPECT_EQ(count["inT2y"], spur);
  EXPECT_EQ(count["inI"], primary);
  EXPECT_EQ(count["inII"], secondary);
  EXPECT_EQ(count["shI"], shoots);
  EXPECT_EQ(count["GI"], gShoots);
  EXPECT_EQ(count["shII"], secondaryShoots);
  EXPECT_EQ(a.vertices.size(),
            1 + 2 + arms + inT + cx + cane + spur + primary + secondary + shoots + gShoots + secondaryShoots);
  // The trunk's 25 internodes, then arm 1 from the trunk's top.
  EXPECT_EQ(a.vertices[3].label, "inT1");
  EXPECT_EQ(a.vertices[3].cells, (std::vector<std::string>{"-2.54", "0.68", "2.45", "7"}));
  EXPECT_EQ(a.vertices[27].label, "inT25");
  EXPECT_EQ(a.vertices[28].label, "arm1");
  EXPECT_EQ(a.vertices[29].label, "inT1");
  EXPECT_EQ(a.vertices[29].complex, 28);
  EXPECT_EQ(a.vertices[29].parent, 27);
  EXPECT_EQ(a.vertices[29].edge, '+');
  EXPECT_EQ(a.vertices[29].line, 27);
  EXPECT_TRUE(a.notes.empty());

  // Imported in cm (the table's unit): the trunk's foot at 24.5 mm, every point drawn.
  const m::ImportedFile f = m::importMtgFile(path, {}, "", 1);
  EXPECT_EQ(f.unit, "cm");
  EXPECT_EQ(f.plant.points, inT + cx + cane + spur + primary + secondary);
  EXPECT_NEAR(f.plant.axes[0].balls[0].center.z(), 24.5, 1e-9);
  EXPECT_NEAR(f.plant.axes[0].balls[0].radius, 35.0, 1e-9);
  EXPECT_DOUBLE_EQ(m::importMtgFile(path, {}, "mm", 1).plant.axes[0].balls[0].center.z(), 2.45);
}

TEST(HydroShootTable, WhatVineMtgWouldFailOnIsRefusedByLine) {
  const auto refusal = [](const std::string& body) {
    try {
      (void)m::parseHydroShootTable("Souche;tronc;element;sarment;rameau;rang;X;Y;Z;Diam\n" + body, "t.input");
    } catch (const m::InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("1;1;1;0;0;0;0;0;1;1\n").find("line 2: the first row of plant 1 is on arm 1"), std::string::npos);
  EXPECT_NE(refusal("1;0;1;0;0;0;0;0;1\n").find("line 2: 9 fields where the header has 10"), std::string::npos);
  EXPECT_NE(refusal("1;0;1;0;0;0;x;0;1;1\n").find("line 2: X \"x\" is not a number"), std::string::npos);
  EXPECT_NE(refusal("1;0;1;0;0;0;0;1e300;1;1\n").find("line 2: Y \"1e300\" is not a number of at most"),
            std::string::npos);
  EXPECT_NE(refusal("1;0;1;0;0;1e300;0;0;1;1\n").find("line 2: rang \"1e300\" is not a whole number"),
            std::string::npos);
  EXPECT_NE(refusal("1;0;1;0;0;0;1;0;1;1\n1;0;1;0;;0;1;0;1;1\n").find("line 3: the rameau column is empty"),
            std::string::npos);
  EXPECT_NE(refusal("1;0;1;0;0;0;0;0;1;1\n1;0;1;0;1;1.5;0;0;1;1\n").find("line 3: rang \"1.5\" is not a whole"),
            std::string::npos);
  // A shoot without its spur's internode (rang 0) first; a secondary shoot on the 9th internode of
  // a shoot of two.
  EXPECT_NE(refusal("1;0;1;0;0;0;0;0;1;1\n1;0;1;0;1;1;0;0;2;1\n").find("line 3: shoot 1 starts on nothing"),
            std::string::npos);
  EXPECT_NE(refusal("1;0;1;0;0;0;0;0;1;1\n1;0;1;0;1;0;0;0;1;1\n1;0;1;0;1;1;0;0;2;1\n1;0;1;0;1;2;0;0;3;1\n"
                    "1;0;1;0;1.9_1;1;0;0;4;1\n")
                .find("line 6: rameau \"1.9_1\" grows on internode 9 of a shoot of 2 internodes"),
            std::string::npos);
  EXPECT_NE(refusal("").find("the table has its header and no row"), std::string::npos);
  EXPECT_THROW((void)m::parseHydroShootTable("CODE:\tFORM-A\n", "x"), m::InputError);
}

TEST(HydroShootTable, TheFileKindIsToldByItsHeaderAndADressingFileIsRefused) {
  const auto dir = std::filesystem::temp_directory_path() / ("leafdig-hydro-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "vine.csv") << kHandTable;
  std::ofstream(dir / "notes.txt") << "a plant I liked\n";
  EXPECT_EQ(m::importMtgFile(dir / "vine.csv", {}, "", 1).plant.points, 15U);
  try {
    (void)m::importMtgFile(dir / "notes.txt", {}, "cm", 1);
    ADD_FAILURE() << "a text file was imported";
  } catch (const m::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("MTG files (.mtg) and HydroShoot's digitizing tables"), std::string::npos);
  }
  try {
    (void)m::importMtgFile(dir / "vine.csv", archive("walnut.drf"), "", 1);
    ADD_FAILURE() << "a dressing file was taken with a table";
  } catch (const m::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a dressing file goes with an MTG file"), std::string::npos);
  }
  EXPECT_THROW((void)m::importMtgFile(dir / "vine.csv", {}, "inch", 1), m::InputError);
  std::filesystem::remove_all(dir);
}
