// The archives' MTG reader and the plant it imports (docs/plants.md, "Archives"), on the public
// files in tests/data/archives (OpenAlea's walnut and apple tree, CeCILL-C; see its README).
//
// What OpenAlea's read_mtg makes of a file is derived here independently of the reader: one
// vertex per entity of the code in file order (a range E1<<E35 making E2…E35 after E1), the
// line's values on its last entity. The reader must give exactly those vertices, in that order,
// with those labels and coordinates.
#include "leafdig/model/archive/mtg_archive.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "leafdig/model/archive/plant_import.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"

namespace m = leafdig::model;

namespace {

std::string archive(const std::string& name) {
  return std::string(LEAFDIG_SOURCE_DIR) + "/tests/data/archives/" + name;
}

struct Expected {
  std::vector<std::string> labels;                  // vertices 1… in order
  std::vector<std::size_t> lastOfLine;              // for each code line, the index (1-based) of its last vertex
  std::vector<std::vector<std::string>> lineCells;  // that line's tab cells
  std::size_t firstFeatureColumn = 0;
  std::vector<std::string> featureTitles;
};

// The file read the simple way: the body's lines, each code split at / + < <<.
Expected expectedOf(const std::string& text) {
  Expected e;
  std::istringstream in(text);
  std::string line;
  bool body = false;
  const std::regex element(R"((<<|[/+<])([A-Za-z]+)(\d*))");
  int previousIndex = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::vector<std::string> cells;
    std::stringstream split(line);
    std::string cell;
    while (std::getline(split, cell, '\t')) cells.push_back(cell);
    if (!body) {
      if (line.rfind("ENTITY-CODE", 0) == 0) {
        body = true;
        for (std::size_t i = 1; i < cells.size(); ++i)
          if (!cells[i].empty() && e.firstFeatureColumn == 0) e.firstFeatureColumn = i;
        for (std::size_t i = e.firstFeatureColumn; i < cells.size(); ++i) {
          std::string t = cells[i];
          while (!t.empty() && t.back() == ' ') t.pop_back();
          if (!t.empty()) e.featureTitles.push_back(t);
        }
      }
      continue;
    }
    std::istringstream words(line);
    std::string code;
    if (!(words >> code) || code[0] == '#') continue;
    for (std::sregex_iterator it(code.begin(), code.end(), element), end; it != end; ++it) {
      const std::string tag = (*it)[1], symbol = (*it)[2], digits = (*it)[3];
      const int index = digits.empty() ? 0 : std::stoi(digits);
      if (tag == "<<") {
        for (int i = previousIndex + 1; i <= index; ++i) e.labels.push_back(symbol + std::to_string(i));
      } else {
        e.labels.push_back(symbol + digits);
      }
      previousIndex = index;
    }
    e.lastOfLine.push_back(e.labels.size());
    e.lineCells.push_back(cells);
  }
  return e;
}

void expectAsOpenAleaReadsIt(const std::string& name) {
  const std::string text = m::readFile(archive(name));
  const m::MtgArchive a = m::parseMtgArchive(text, name);
  const Expected e = expectedOf(text);
  ASSERT_EQ(a.vertices.size(), e.labels.size() + 1) << name << ": one vertex per entity, and the root";
  for (std::size_t i = 0; i < e.labels.size(); ++i)
    ASSERT_EQ(a.vertices[i + 1].label, e.labels[i]) << "vertex " << i + 1;
  ASSERT_EQ(a.features.size(), e.featureTitles.size());
  for (std::size_t f = 0; f < a.features.size(); ++f) EXPECT_EQ(a.features[f].name, e.featureTitles[f]);
  // Each line's values on its last entity, column by column as the title row places them.
  for (std::size_t l = 0; l < e.lastOfLine.size(); ++l) {
    const m::MtgVertex& v = a.vertices[e.lastOfLine[l]];
    for (std::size_t f = 0; f < a.features.size(); ++f) {
      const std::size_t column = e.firstFeatureColumn + f;
      std::string cell = column < e.lineCells[l].size() ? e.lineCells[l][column] : "";
      while (!cell.empty() && cell.back() == ' ') cell.pop_back();
      ASSERT_EQ(v.cells[f], cell) << name << " code line " << l + 1 << ", feature " << a.features[f].name;
    }
  }
}

}  // namespace

TEST(MtgArchive, TheWalnutsEntitiesAreOpenAleasOneByOne) {
  expectAsOpenAleaReadsIt("noylum2.mtg");
}

TEST(MtgArchive, TheAppleTreesRangesMakeEveryEntityBetween) {
  expectAsOpenAleaReadsIt("agraf.mtg");
}

TEST(MtgArchive, TheWalnutsTreeIsBuiltAcrossScalesAsOpenAleaBuildsIt) {
  const m::MtgArchive a = m::readMtgArchive(archive("noylum2.mtg"));
  // /P1, then /A1 ^/S1 (the trunk's first growth unit), +A1 ^/S1 (a branch on it), ^<S2.
  const auto& v = a.vertices;
  EXPECT_EQ(v[0].scale, 0);
  EXPECT_EQ(v[1].label, "P1");
  EXPECT_EQ(v[1].scale, 1);
  EXPECT_EQ(v[2].label, "A1");
  EXPECT_EQ(v[2].complex, 1);
  EXPECT_EQ(v[3].label, "S1");
  EXPECT_EQ(v[3].complex, 2);
  EXPECT_EQ(v[3].parent, -1);  // the trunk's first unit follows nothing
  EXPECT_EQ(v[4].label, "A1");
  EXPECT_EQ(v[4].complex, 1);  // the branch, an axis of the plant
  EXPECT_EQ(v[5].label, "S1");
  EXPECT_EQ(v[5].complex, 4);
  EXPECT_EQ(v[5].parent, 3);  // borne by the trunk's S1
  EXPECT_EQ(v[5].edge, '+');
  EXPECT_EQ(v[6].label, "S2");
  EXPECT_EQ(v[6].complex, 2);  // back on the trunk
  EXPECT_EQ(v[6].parent, 3);
  EXPECT_EQ(v[6].edge, '<');
  EXPECT_EQ(a.countAtScale(1), 1U);
  EXPECT_EQ(*a.number(2, a.feature("ZZ")), -27.23);
  EXPECT_EQ(*a.number(3, a.feature("ZZ")), 121.43);
  EXPECT_EQ(*a.number(3, a.feature("TopDia")), 180);
}

TEST(MtgArchive, TheAppleTreesRangeCarriesItsValuesOnItsLastEntity) {
  const m::MtgArchive a = m::readMtgArchive(archive("agraf.mtg"));
  // ^/U94 (0, 0, 0) then ^/E1<<E35: E1…E35 components of U94 in a '<' chain, E35 digitized.
  const auto& v = a.vertices;
  ASSERT_EQ(v[2].label, "U94");
  EXPECT_EQ(*a.number(2, a.feature("ZZ")), 0);
  ASSERT_EQ(v[37].label, "E35");
  EXPECT_EQ(v[37].complex, 2);
  EXPECT_EQ(v[37].parent, 36);
  EXPECT_EQ(*a.number(37, a.feature("ZZ")), 825);
  EXPECT_FALSE(a.number(36, a.feature("ZZ")).has_value());
  // +D94/E1: a new growth unit whose first E is borne by E35.
  EXPECT_EQ(v[38].label, "D94");
  EXPECT_EQ(v[39].label, "E1");
  EXPECT_EQ(v[39].complex, 38);
  EXPECT_EQ(v[39].parent, 37);
  EXPECT_EQ(v[39].edge, '+');
  // ^<B95 after D94: OpenAlea's tree leaves it without a parent (it has no component); the code
  // said it follows D94.
  EXPECT_EQ(v[40].label, "B95");
  EXPECT_EQ(v[40].parent, -1);
  EXPECT_EQ(v[40].after, 38);
  EXPECT_EQ(v[40].afterEdge, '<');
}

TEST(MtgArchive, TheDressingFilesUnits) {
  const m::MtgDressing walnut = m::readMtgDressing(archive("walnut.drf"));
  EXPECT_EQ(walnut.diameterUnit, 10);
  EXPECT_EQ(walnut.lengthUnit, 1);
  const m::MtgDressing apple = m::readMtgDressing(archive("agraf.drf"));
  EXPECT_EQ(apple.diameterUnit, 10);
  EXPECT_EQ(apple.leafClass, "Z");
  EXPECT_EQ(apple.leafLength, 100);
  EXPECT_EQ(apple.phyllotaxyDeg, 150);
  EXPECT_NE(std::find(apple.ignored.begin(), apple.ignored.end(), "SMBModel"), apple.ignored.end());
  EXPECT_THROW((void)m::parseMtgDressing("LengthUnit = 0\n", "bad.drf"), m::InputError);
  EXPECT_THROW((void)m::parseMtgDressing("DiameterUnit 10\n", "bad.drf"), m::InputError);
}

namespace {

const char* const kHeader =
    "CODE:\tFORM-A\nCLASSES:\nSYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION\n$\t0\tFREE\tFREE\tIMPLICIT\n"
    "P\t1\tFREE\tFREE\tEXPLICIT\nA\t2\tFREE\tFREE\tEXPLICIT\nS\t3\tFREE\tFREE\tEXPLICIT\n"
    "DESCRIPTION:\nLEFT\tRIGHT\tRELTYPE\tMAX\nS\tS\t<\t1\nFEATURES:\nNAME\tTYPE\nXX\tREAL\nYY\tREAL\nZZ\tREAL\n"
    "TopDia\tINT\nMTG:\nENTITY-CODE\t\t\tXX\tYY\tZZ\tTopDia\n";

std::string refusal(const std::string& body) {
  try {
    (void)m::parseMtgArchive(std::string(kHeader) + body, "t.mtg");
  } catch (const m::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MtgArchive, ARefusalNamesTheLineAndTheColumnWhereOpenAleaWouldShiftOrGuess) {
  const std::string ok = "/P1\n^/A1\t\t\t0\t0\t0\t30\n^/S1\t\t\t0\t0\t10\t25\n^<S2\t\t\t0\t1\t20\t20\n";
  EXPECT_EQ(refusal(ok), "");
  // One tab too many: every value moves right and TopDia falls off the end.
  const std::string shifted = refusal("/P1\n^/A1\t\t\t\t0\t0\t0\t30\n");
  EXPECT_NE(shifted.find("t.mtg, line 20"), std::string::npos) << shifted;
  EXPECT_NE(shifted.find("column 8"), std::string::npos) << shifted;
  EXPECT_NE(shifted.find("past the last feature (TopDia)"), std::string::npos) << shifted;
  const std::string notInt = refusal("/P1\n^/A1\t\t\t0\t0\t0\t2.5\n");
  EXPECT_NE(notInt.find("TopDia, INT) holds \"2.5\""), std::string::npos) << notInt;
  const std::string unknown = refusal("/P1\n^/Q1\t\t\t0\t0\t0\t3\n");
  EXPECT_NE(unknown.find("Q is not a class CLASSES declares"), std::string::npos) << unknown;
  const std::string backwards = refusal("/P1\n^/A1\n^/S5<<S3\t\t\t0\t0\t0\t3\n");
  EXPECT_NE(backwards.find("runs from S5"), std::string::npos) << backwards;
  const std::string deeper = refusal("/P1\n\t^/A1\n");
  EXPECT_NE(deeper.find("'^' continues"), std::string::npos) << deeper;
  const std::string wrongScale = refusal("/P1\n+S1\n");
  EXPECT_NE(wrongScale.find("scale 3) but the code puts it at scale 1"), std::string::npos) << wrongScale;
  const std::string words = refusal("/P1\n^/A1\t\t\t0\tabc\t0\t3\n");
  EXPECT_NE(words.find("(YY, REAL) holds \"abc\""), std::string::npos) << words;
  // A title the FEATURES section does not declare.
  std::string header = kHeader;
  header.replace(header.find("\tTopDia\n", header.find("ENTITY-CODE")), 8, "\tTopDiam\n");
  try {
    (void)m::parseMtgArchive(header + ok, "t.mtg");
    ADD_FAILURE() << "an undeclared title was read";
  } catch (const m::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("TopDiam is not a feature FEATURES declares"), std::string::npos) << e.what();
  }
}

TEST(MtgArchive, Latin1CommentsAreReadAsTheOldStationsWroteThem) {
  const std::string text =
      std::string("# Noyer digitalis\xE9 \xE0 Montpellier\n") + kHeader + "/P1\n^/A1\t\t\t0\t0\t0\t3\n";
  const m::MtgArchive a = m::parseMtgArchive(text, "latin1.mtg");
  EXPECT_EQ(a.vertices.size(), 3U);
  EXPECT_EQ(m::utf8FromLatin1IfNeeded("caf\xE9"), "caf\xC3\xA9");
  EXPECT_EQ(m::utf8FromLatin1IfNeeded("caf\xC3\xA9"), "caf\xC3\xA9");
}

TEST(PlantImport, TheWalnutIsDrawnThroughItsDigitizedPointsInMillimetres) {
  const m::MtgArchive a = m::readMtgArchive(archive("noylum2.mtg"));
  m::ArchiveImportOptions o;
  o.mmPerUnit = 10;  // the walnut's coordinates are centimetres
  o.dressing = m::readMtgDressing(archive("walnut.drf"));
  const m::ImportedPlant p = m::importMtgPlant(a, o);
  ASSERT_TRUE(p.plant.stem.has_value());
  EXPECT_EQ(p.plantLabel, "P1");
  EXPECT_EQ(p.vertices, a.vertices.size());
  // The trunk starts at A1's own point and goes through its first growth unit's top.
  const auto& balls = p.plant.stem->curve.dataBalls();
  ASSERT_GE(balls.size(), 2U);
  EXPECT_NEAR((balls[0].center - Eigen::Vector3d(-34.5, -210.7, -272.3)).norm(), 0, 1e-9);
  EXPECT_NEAR((balls[1].center - Eigen::Vector3d(-25.0, -176.8, 1214.3)).norm(), 0, 1e-9);
  EXPECT_NEAR(balls[1].radius, 180.0 / 10 * 10 / 2, 1e-12);  // TopDia 180 / DiameterUnit 10 = 18 cm
  // Axes of several orders, every drawn point one of the file's own.
  int highest = 0;
  for (const m::ImportedAxis& x : p.axes) highest = std::max(highest, x.order);
  EXPECT_GE(highest, 3);
  EXPECT_EQ(
      p.points + p.withoutPoint, p.plantVertices - [&] {
        std::size_t complexes = 0;  // entities whose points are their components'
        const auto comps = a.components();
        for (std::size_t v = 1; v < a.vertices.size(); ++v) complexes += comps[v].empty() ? 0 : 1;
        return complexes;
      }() + 0);
  std::size_t drawn = 0;
  for (const m::ImportedAxis& x : p.axes) drawn += x.vertices.size();
  EXPECT_EQ(drawn, p.points);
  const int xx = a.feature("XX");
  for (const m::Vein& branch : p.plant.branches)
    for (const m::Ball& b : branch.curve.dataBalls()) {
      bool found = false;
      for (std::size_t v = 1; v < a.vertices.size() && !found; ++v) {
        const auto x = a.number(v, xx);
        found = x && std::abs(*x * 10 - b.center.x()) < 1e-9 &&
                std::abs(*a.number(v, xx + 1) * 10 - b.center.y()) < 1e-9 &&
                std::abs(*a.number(v, xx + 2) * 10 - b.center.z()) < 1e-9;
      }
      ASSERT_TRUE(found) << branch.name << " has a point the file does not: " << b.center.transpose();
    }
}

TEST(PlantImport, TheAppleTreesRangesAndOrphansJoinTheirAxes) {
  const m::MtgArchive a = m::readMtgArchive(archive("agraf.mtg"));
  m::ArchiveImportOptions o;
  o.mmPerUnit = 1;  // the apple tree's integers are millimetres
  o.dressing = m::readMtgDressing(archive("agraf.drf"));
  const m::ImportedPlant p = m::importMtgPlant(a, o);
  ASSERT_TRUE(p.plant.stem.has_value());
  const auto& balls = p.plant.stem->curve.dataBalls();
  // U94's own (0, 0, 0) is the trunk's base; E35 (-19, -20, 825) its first digitized point.
  EXPECT_NEAR(balls[0].center.norm(), 0, 1e-12);
  EXPECT_NEAR((balls[1].center - Eigen::Vector3d(-19, -20, 825)).norm(), 0, 1e-12);
  EXPECT_NEAR(balls[1].radius, 33.0 / 2, 1e-12);  // TopDia 330 / DiameterUnit 10
  // B95 (-34, -38, 858) follows D94 (whose E1 is at (-23, -27, 844)) on the branch D94 starts.
  bool found = false;
  for (const m::Vein& b : p.plant.branches) {
    const auto& d = b.curve.dataBalls();
    for (std::size_t i = 1; i < d.size(); ++i)
      found = found || ((d[i - 1].center - Eigen::Vector3d(-23, -27, 844)).norm() < 1e-12 &&
                        (d[i].center - Eigen::Vector3d(-34, -38, 858)).norm() < 1e-12);
  }
  EXPECT_TRUE(found) << "B95 does not follow D94's point";
  EXPECT_THROW((void)m::importMtgPlant(a, {1, o.dressing, 2}), m::InputError);
}
