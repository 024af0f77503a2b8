#pragma once
// Digitized plants from the archives (docs/plants.md, "Archives"): the AMAP / OpenAlea MTG
// coding file as digitizing stations wrote it (FORM-A), read into its multiscale tree, and the
// dressing file (.drf) that says its units.
//
// The tree is built as OpenAlea's reader builds it (openalea.mtg.io: the column-aligned code
// turned into a bracketed string, then the multiscale edit with scales implicit from CLASSES),
// so the vertices — their number, order, labels, scales, complexes, parents, edges and values —
// are those OpenAlea's `read_mtg` gives for the same file: vertex 0 is the root ($), the others
// in the order they are made. Where OpenAlea's reader guesses, warns on the console or shifts
// columns silently (openalea/mtg#10), this one refuses in words naming the file and line (and
// the column): a value in a column FEATURES does not name, a number that is not of its column's
// type, an unknown class, a range that runs backwards, a '^' that continues nothing.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace leafdig::model {

struct MtgFeature {
  std::string name;
  std::string type;  // INT, REAL, ALPHA, STRING, DD/MM, DD/MM/YY, DD/MM/YYYY
  [[nodiscard]] bool numeric() const { return type == "INT" || type == "REAL"; }
};

struct MtgClass {
  std::string symbol;
  int scale = 0;
};

struct MtgVertex {
  std::string label;   // "S12"; the root's is empty
  std::string symbol;  // its class ("S")
  int index = 0;       // the label's number (12), 0 when it has none
  int scale = 0;       // 0 the root, 1 a plant, …
  int complex = -1;    // the vertex one scale up it is a component of (-1: the root has none)
  int parent = -1;     // at its own scale, the vertex it follows or branches from (-1: none)
  char edge = 0;       // '<' follows, '+' branches (0: no parent)
  int line = 0;        // the file's line that named it, 1-based (a range's inner vertices: its line)
  // One cell per feature of the file (FEATURES order): empty when not given.
  std::vector<std::string> cells;
  // Not in OpenAlea's tree: the entity the code relates this one to when that tree leaves it
  // without a parent (`<B95` after an entity decomposed further: OpenAlea links it only through
  // its first component, so one with no component stays an orphan there), and the relation.
  int after = -1;
  char afterEdge = 0;
};

struct MtgArchive {
  std::string source;  // the file, for messages
  std::string code;    // "FORM-A"
  std::vector<MtgClass> classes;
  std::vector<MtgFeature> features;
  std::vector<MtgVertex> vertices;  // [0] the root
  std::vector<std::string> notes;   // what the reader read past (the import's report repeats it)
  // The feature's column, or -1 when the file has none of that name.
  [[nodiscard]] int feature(std::string_view name) const;
  // Vertex v's value of feature f as a number (its column is INT or REAL), when given.
  [[nodiscard]] std::optional<double> number(std::size_t v, int f) const;
  // The vertices at a scale, and every vertex's components (in the order they were made).
  [[nodiscard]] std::size_t countAtScale(int scale) const;
  [[nodiscard]] std::vector<std::vector<int>> components() const;
};

// The most vertices one file may make (a range such as E1<<E9999999 included).
inline constexpr std::size_t kMaxMtgVertices = 2'000'000;

// Reads the text of an MTG file (UTF-8, or Latin-1 as the old stations wrote it: read as
// Latin-1 when it is not valid UTF-8). Throws InputError naming `source`, the line and what
// to do.
[[nodiscard]] MtgArchive parseMtgArchive(std::string_view text, const std::string& source);
[[nodiscard]] MtgArchive readMtgArchive(const std::filesystem::path& path);

// The dressing file's numbers leafdig uses (the rest — symbol files, colours — is for
// PlantFrame's drawing and is read past). Values in the MTG are divided by the units, as
// PlantFrame does.
struct MtgDressing {
  double lengthUnit = 1.0;    // XX YY ZZ and lengths are divided by it
  double diameterUnit = 1.0;  // TopDia, TopDiameter, BottomDiameter are divided by it
  double alphaUnit = 1.0;     // angles are divided by it (to degrees)
  std::string leafClass;      // the class of leaves in the MTG ("L" when not said)
  std::optional<double> leafLength;
  std::optional<double> phyllotaxyDeg;
  std::vector<std::string> ignored;  // keys read past, for the report
};
[[nodiscard]] MtgDressing parseMtgDressing(std::string_view text, const std::string& source);
[[nodiscard]] MtgDressing readMtgDressing(const std::filesystem::path& path);

// Text as UTF-8: valid UTF-8 as it is, anything else read as Latin-1 (every byte a code point).
[[nodiscard]] std::string utf8FromLatin1IfNeeded(std::string_view text);

}  // namespace leafdig::model
