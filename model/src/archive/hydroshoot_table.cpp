#include "leafdig/model/archive/hydroshoot_table.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "archive/archive_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"

namespace leafdig::model {

namespace {

using detail::isInteger;
using detail::realOf;
using detail::splitOn;
using detail::trimmed;

constexpr const char* kColumns = "Souche;tronc;element;sarment;rameau;rang;X;Y;Z[;Diam]";

// Python's repr of a float (what `str()` of a pandas float cell gives): the shortest digits that
// read back, fixed notation for exponents -4…15 ("1.0", "0.0001"), scientific beyond ("1e+16").
std::string pythonFloat(double v) {
  if (v == 0) return std::signbit(v) ? "-0.0" : "0.0";
  std::array<char, 64> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::scientific);
  std::string sci(buf.data(), r.ptr);  // "-1.2345e+02"
  const bool negative = sci[0] == '-';
  if (negative) sci.erase(0, 1);
  const std::size_t e = sci.find('e');
  std::string digits = sci.substr(0, e);
  digits.erase(std::remove(digits.begin(), digits.end(), '.'), digits.end());
  const int exponent = std::stoi(sci.substr(e + 1));
  std::string out;
  if (exponent >= -4 && exponent < 16) {
    if (exponent >= 0) {
      if (digits.size() <= static_cast<std::size_t>(exponent) + 1)
        digits.append(static_cast<std::size_t>(exponent) + 1 - digits.size(), '0');
      const std::string whole = digits.substr(0, static_cast<std::size_t>(exponent) + 1);
      const std::string fraction = digits.substr(static_cast<std::size_t>(exponent) + 1);
      out = whole + "." + (fraction.empty() ? "0" : fraction);
    } else {
      out = "0." + std::string(static_cast<std::size_t>(-exponent - 1), '0') + digits;
    }
  } else {
    out = digits.substr(0, 1) + (digits.size() > 1 ? "." + digits.substr(1) : std::string()) + "e" +
          (exponent < 0 ? "-" : "+") + (std::abs(exponent) < 10 ? "0" : "") + std::to_string(std::abs(exponent));
  }
  return negative ? "-" + out : out;
}

// Python's float() of a cell as vine_mtg calls it; nullopt where Python raises.
std::optional<double> pythonFloatOf(const std::string& s) {
  return realOf(trimmed(s));
}

bool containsAnyOf(const std::string& s, std::string_view chars) {
  return s.find_first_of(chars) != std::string::npos;
}

std::string roman(int n) {
  static constexpr std::array<std::pair<int, const char*>, 13> kNumerals{{{1000, "M"},
                                                                          {900, "CM"},
                                                                          {500, "D"},
                                                                          {400, "CD"},
                                                                          {100, "C"},
                                                                          {90, "XC"},
                                                                          {50, "L"},
                                                                          {40, "XL"},
                                                                          {10, "X"},
                                                                          {9, "IX"},
                                                                          {5, "V"},
                                                                          {4, "IV"},
                                                                          {1, "I"}}};
  std::string out;
  for (const auto& [value, numeral] : kNumerals)
    while (n >= value) {
      out += numeral;
      n -= value;
    }
  return out;
}

// The tree as vine_mtg edits it (openalea.mtg's MTG: add_component, add_child,
// add_child_and_complex; a vertex's complex is its own, or its parent's, up the parents).
class Builder {
 public:
  explicit Builder(MtgArchive& a) : a_(a) {
    MtgVertex root;
    a_.vertices.push_back(root);
    explicitComplex_.push_back(-1);
  }

  int addComponent(int complex, const std::string& symbol, const std::string& label, int line,
                   const std::vector<std::string>& cells) {
    const int v = make(symbol, label, line, cells);
    at(v).scale = at(complex).scale + 1;
    explicitComplex_[static_cast<std::size_t>(v)] = complex;
    return v;
  }
  int addChild(int parent, const std::string& symbol, const std::string& label, char edge, int line,
               const std::vector<std::string>& cells) {
    const int v = make(symbol, label, line, cells);
    at(v).scale = at(parent).scale;
    at(v).parent = parent;
    at(v).edge = edge;
    return v;
  }
  // An existing vertex made a child (add_child with `child` given): its parent and edge; its
  // values are the ones it has (vine_mtg passes the same ones again).
  void makeChild(int parent, int child, char edge) {
    at(child).parent = parent;
    at(child).edge = edge;
  }
  // A child in a new complex: the complex's number first, then the child's (openalea.mtg's order).
  std::pair<int, int> addChildAndComplex(int parent, const std::string& symbol, const std::string& label, char edge,
                                         int line, const std::vector<std::string>& cells) {
    const int complex = make("", "", line, {});
    const int child = addChild(parent, symbol, label, edge, line, cells);
    const int parentComplex = complexOf(parent);
    at(complex).parent = parentComplex;
    at(complex).scale = at(parentComplex).scale;
    explicitComplex_[static_cast<std::size_t>(child)] = complex;
    return {child, complex};
  }
  void name(int v, const std::string& symbol, const std::string& label, char edge) {
    at(v).symbol = symbol;
    at(v).label = label;
    at(v).edge = edge;
  }
  [[nodiscard]] int complexOf(int v) const {
    for (int x = v; x >= 0; x = a_.vertices[static_cast<std::size_t>(x)].parent)
      if (explicitComplex_[static_cast<std::size_t>(x)] >= 0) return explicitComplex_[static_cast<std::size_t>(x)];
    return -1;
  }
  // g.Axis(v): the '<' chain through v, from its first vertex (up while the edge is '<').
  [[nodiscard]] std::vector<int> axis(int v) {
    int first = v;
    while (at(first).edge == '<' && at(first).parent >= 0) first = at(first).parent;
    std::vector<int> out{first};
    for (;;) {
      const int next = firstChild(out.back(), '<');
      if (next < 0 || out.size() > a_.vertices.size()) return out;
      out.push_back(next);
    }
  }
  // g.Sons(v, EdgeType=edge)[0], or -1.
  [[nodiscard]] int firstChild(int v, char edge) const {
    for (std::size_t c = static_cast<std::size_t>(v) + 1; c < a_.vertices.size(); ++c)
      if (a_.vertices[c].parent == v && a_.vertices[c].edge == edge) return static_cast<int>(c);
    return -1;
  }
  void finish() {
    for (std::size_t v = 1; v < a_.vertices.size(); ++v) a_.vertices[v].complex = complexOf(static_cast<int>(v));
  }

 private:
  MtgVertex& at(int v) { return a_.vertices[static_cast<std::size_t>(v)]; }
  int make(const std::string& symbol, const std::string& label, int line, const std::vector<std::string>& cells) {
    if (a_.vertices.size() >= kMaxMtgVertices)
      throw InputError(a_.source + ", line " + std::to_string(line) + ": more than " + std::to_string(kMaxMtgVertices) +
                       " entities: split the table");
    MtgVertex v;
    v.symbol = symbol;
    v.label = label;
    v.line = line;
    v.cells = cells;
    v.cells.resize(a_.features.size());  // one cell per feature, empty when not given (as an MTG's)
    a_.vertices.push_back(std::move(v));
    explicitComplex_.push_back(-1);
    return static_cast<int>(a_.vertices.size() - 1);
  }

  MtgArchive& a_;
  std::vector<int> explicitComplex_;
};

// A row's first six cells as pandas reads their columns: a column of whole numbers as integers,
// one of numbers as floats (printed as Python prints them), any other as the text itself.
std::vector<std::vector<std::string>> pandasColumns(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::vector<std::string>> out(rows.size(), std::vector<std::string>(6));
  for (std::size_t c = 0; c < 6; ++c) {
    bool ints = true, floats = true;
    for (const auto& r : rows) {
      const std::string cell = trimmed(r[c]);
      ints = ints && isInteger(cell) && cell.size() <= 18;
      floats = floats && realOf(cell).has_value();
    }
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::string cell = trimmed(rows[i][c]);
      out[i][c] = ints ? std::to_string(std::stoll(cell)) : floats ? pythonFloat(*realOf(cell)) : cell;
    }
  }
  return out;
}

std::string rounded(double v) {
  // Python's round(v, 2): the double nearest the decimal rounded half to even, which printf's
  // correctly rounded %.2f gives; then the shortest digits that read back.
  std::array<char, 64> buf{};
  std::snprintf(buf.data(), buf.size(), "%.2f", v);
  const double r = std::strtod(buf.data(), nullptr);
  const auto end = std::to_chars(buf.data(), buf.data() + buf.size(), r).ptr;
  return std::string(buf.data(), end);
}

const char* fieldName(std::size_t c) {
  static constexpr std::array<const char*, 10> kNames{"Souche", "tronc", "element", "sarment", "rameau",
                                                      "rang",   "X",     "Y",       "Z",       "Diam"};
  return kNames[c];
}

// A row's cells as the table's rules want them, or InputError naming the line.
void checkRow(const std::vector<std::string>& cells, std::size_t width, int line, const std::string& source) {
  if (cells.size() != width)
    throw InputError(source + ", line " + std::to_string(line) + ": " + std::to_string(cells.size()) +
                     " fields where the header has " + std::to_string(width) + " (" + kColumns + ")");
  for (std::size_t c = 0; c < 9; ++c)
    if (trimmed(cells[c]).empty())
      throw InputError(source + ", line " + std::to_string(line) + ": the " + std::string(fieldName(c)) +
                       " column is empty; every row names its plant, axes and point");
  // Numbers within a kilometre (1e5 cm: a plant is far smaller; past it a unit is wrong, and
  // the import's own bound refuses it in words) and ranks within a million.
  const auto notANumber = [&](std::size_t c, const std::string& cell) {
    throw InputError(source + ", line " + std::to_string(line) + ": " + std::string(fieldName(c)) + " \"" + cell +
                     "\" is not a number of at most 100000 (decimals with a point, in cm)");
  };
  for (std::size_t c = 6; c < width; ++c) {
    const std::string cell = trimmed(cells[c]);
    if (c == 9 && cell.empty()) continue;  // no diameter
    const auto v = realOf(cell);
    if (!v || std::abs(*v) > 1e5) notANumber(c, cell);
  }
  const auto rank = realOf(trimmed(cells[5]));
  if (!rank || std::floor(*rank) != *rank || std::abs(*rank) > 1e6)
    throw InputError(source + ", line " + std::to_string(line) + ": rang \"" + trimmed(cells[5]) +
                     "\" is not a whole number (0 a spur's internode, 1, 2… a shoot's)");
}

// vine_mtg's walk over the rows: its running state (the last vertex of each kind and the last
// labels it compared), one row at a time.
class VineMtg {
 public:
  VineMtg(MtgArchive& a, std::string source, std::size_t width) : g(a), source_(std::move(source)), width_(width) {}

  // One row: its six first cells as pandas typed them, its raw cells, its line in the file.
  void row(const std::vector<std::string>& typed, const std::vector<std::string>& raw, int line) {
    const auto fail = [&](const std::string& what) {
      throw InputError(source_ + ", line " + std::to_string(line) + ": " + what);
    };
    const auto need = [&](int v, const std::string& what) {
      if (v < 0) fail(what);
      return v;
    };
    const std::string& plantId = typed[0];
    const std::string& trunkText = typed[1];
    const std::string& element = typed[2];
    const std::string& cane = typed[3];
    const std::string& shootId = typed[4];
    const std::string& orderText = typed[5];
    const auto order = static_cast<long long>(*realOf(trimmed(raw[5])));
    std::vector<std::string> cells;
    for (std::size_t c = 6; c < 9; ++c) cells.push_back(rounded(*realOf(trimmed(raw[c]))));
    cells.push_back(width_ == 10 ? trimmed(raw[9]) : std::string());

    std::string lower = trimmed(trunkText);
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    long long trunkId = 0;
    if (lower != "base") {
      const auto t = realOf(trimmed(trunkText));
      if (!t || std::floor(*t) != *t || std::abs(*t) > 1e9)
        fail("tronc \"" + trimmed(trunkText) + "\" is not a whole number (0 the trunk, 1, 2… its arms) nor \"base\"");
      trunkId = static_cast<long long>(*t);
    }
    const std::string trunkStr = std::to_string(trunkId);

    if (plantId != plantPrev) {
      plant = g.addComponent(0, "plant", "plant" + plantId, line, {});
      plantPrev = plantId;
    }
    // The perennial axes: the trunk, then arms branching from it.
    const std::string trunkLbl = plantId + "_" + trunkStr;
    if (trunkLbl != trunkLblPrev) {
      if (splitOn(trunkLbl, '_')[0] != splitOn(trunkLblPrev, '_')[0]) {
        if (trunkId != 0)
          fail("the first row of plant " + plantId + " is on arm " + trunkStr +
               ", not on the trunk (tronc 0): digitize the trunk first");
        perennial = g.addComponent(plant, "trunk", "trunk", line, {});
        trunk = perennial;
      } else {
        perennial = g.addChild(trunk, "arm", "arm" + trunkStr, '+', line, {});
      }
      trunkLblPrev = trunkLbl;
    }
    // Internodes of the perennial axes, and pruning complexes.
    const bool inComplex = element.find('.') != std::string::npos;
    const std::vector<std::string> elementParts =
        (element == "0" || element == "0.0") ? std::vector<std::string>{} : splitOn(element, '.');
    if (elementParts.size() == 1) {
      const std::string lbl = plantId + "_" + trunkStr + "_" + element;
      if (lbl != inTLblPrev) {
        const auto now = splitOn(lbl, '_'), before = splitOn(inTLblPrev, '_');
        if (now[0] != before[0]) {
          inT = g.addComponent(perennial, "inT", "inT" + element, line, cells);
        } else if (now[1] != before[1]) {
          if (before[1] == "0") inTTrunk = inT;
          inT = g.addComponent(perennial, "inT", "inT" + element, line, cells);
          if (now[1] != "0")
            g.makeChild(need(inTTrunk, "arm " + now[1] + " begins before any internode of the trunk"), inT, '+');
        } else {
          std::string low = element;
          std::transform(low.begin(), low.end(), low.begin(),
                         [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
          const bool onComplex = low.find("rl") != std::string::npos;
          const int from = onComplex ? need(complexe, "element " + element +
                                                          " continues a pruning complex that "
                                                          "no row before made")
                                     : need(inT, "element " + element + " follows no internode");
          inT = g.addChild(from, "inT", "inT" + element, onComplex ? '+' : '<', line, cells);
        }
        inTLblPrev = lbl;
      }
    } else if (elementParts.size() > 1) {
      const std::string lbl = plantId + "_" + trunkStr + "_" + element;
      if (lbl != cxLblPrev) {
        const auto now = splitOn(lbl, '.'), before = splitOn(cxLblPrev, '.');
        const bool refines = now[0] == before[0] && before.size() > 1 && now[1] == before[1];
        const int from = refines ? complexe
                                 : need(inT, "pruning complex " + element + " is on no internode: a row of element " +
                                                 elementParts[0] + " comes first");
        complexe = g.addChild(from, "cx", "cx" + element, '+', line, cells);
        cxLblPrev = lbl;
      }
    }
    // Internodes of three-year-old canes.
    const auto caneNumber = pythonFloatOf(cane);
    if (!caneNumber) fail("sarment \"" + cane + "\" is not a number (0, or the cane's internode: 1, 1.1, 2…)");
    if (*caneNumber != 0.0) {
      const std::string lbl = plantId + "_" + trunkStr + "_" + element + "_" + cane;
      if (lbl != inT3yLblPrev) {
        const auto now = splitOn(lbl, '_'), before = splitOn(inT3yLblPrev, '_');
        if (now.size() < 4 || before.size() < 4) fail("a '_' in element or sarment: the labels cannot be read");
        if (std::equal(now.begin(), now.begin() + 3, before.begin(), before.begin() + 3)) {
          const auto a0 = pythonFloatOf(now[3]), b0 = pythonFloatOf(before[3]);
          if (a0 && b0 && std::trunc(*a0) == std::trunc(*b0)) {
            connectInT3y = inT3y;
            edgeInT3y = '<';
          }
        } else {
          connectInT3y = inComplex ? complexe : inT;
          edgeInT3y = '+';
        }
        inT3y = g.addChild(need(connectInT3y, "cane " + cane + " is on nothing a row before made"), "inT3y",
                           "inT3y" + cane, edgeInT3y, line, cells);
        inT3yLblPrev = lbl;
      }
    }
    // Two- and one-year-old internodes: spurs, shoots and their secondary shoots.
    if (shootId == "0" || shootId == "0.0") return;
    if (containsAnyOf(shootId, "pPfFlL")) {
      ++readPast;  // a petiole's or a leaf's point
      return;
    }
    const auto parts = splitOn(shootId, '.');
    if (parts.size() == 1) {
      int connectInT2y = -1;
      std::string shootLabel = "shI";
      const bool g1 = containsAnyOf(shootId, "gG");
      const bool onCane = *caneNumber != 0.0;
      if (!inComplex && !onCane && g1) {
        connectInI = inT;
        shootLabel = "GI";
      } else if (!inComplex && !onCane) {
        connectInT2y = need(inT, "shoot " + shootId + " is on no internode");
      } else if (onCane && g1) {
        connectInI = inT3y;
        shootLabel = "GI";
      } else if (onCane) {
        connectInT2y = need(inT3y, "shoot " + shootId + " is on no cane");
      } else {
        connectInI = complexe;
        shootLabel = "GI";
      }
      const std::size_t digit = shootId.find_first_of("0123456789");
      if (digit == std::string::npos) fail("rameau \"" + shootId + "\" has no number");
      const std::size_t digitsEnd = shootId.find_first_not_of("0123456789", digit);
      const std::string firstNumber =
          shootId.substr(digit, digitsEnd == std::string::npos ? digitsEnd : digitsEnd - digit);
      const bool firstOfSpur = std::strtod(firstNumber.c_str(), nullptr) == 1.0;
      if (order == 0) {
        if (connectInT2y >= 0) {
          char edge = '+';
          if (!firstOfSpur) {
            edge = '<';
            connectInT2y = need(inT2y, "spur internode " + shootId + " follows none");
          }
          inT2y = g.addChild(connectInT2y, "inT2y", "inT2y" + shootId, edge, line, cells);
          connectInI = inT2y;
        }
      } else if (order == 1) {
        const auto [child, shoot] =
            g.addChildAndComplex(need(connectInI, "shoot " + shootId + " starts on nothing a row before made"), "inI",
                                 "inI" + orderText, '+', line, cells);
        inI = child;
        g.name(shoot, shootLabel, shootLabel + shootId, '+');
      } else {
        inI = g.addChild(need(inI, "rang " + orderText + " of shoot " + shootId + " follows no rang 1"), "inI",
                         "inI" + orderText, '<', line, cells);
      }
    } else {
      const std::size_t shootOrder = parts.size();
      const std::string inodeLabel = "in" + roman(static_cast<int>(shootOrder)) + orderText;
      if (order == 1) {
        int iter = need(inI, "secondary shoot " + shootId + " before any shoot");
        int connect = -1;
        const auto badRank = [&](const std::string& rank) {
          fail("rameau \"" + shootId + "\": \"" + rank + "\" is not the internode a shoot grows on");
        };
        const auto noSuchInternode = [&](const std::string& rank, std::size_t internodes) {
          fail("rameau \"" + shootId + "\" grows on internode " + rank + " of a shoot of " +
               std::to_string(internodes) + " internodes so far: digitize a shoot before its secondary ones");
        };
        for (std::size_t k = 1; k < parts.size(); ++k) {
          const std::string rank = splitOn(parts[k], '_')[0];
          if (!isInteger(trimmed(rank)) || rank.size() > 9) badRank(rank);
          const long long r = std::stoll(rank);
          const auto chain = g.axis(iter);
          if (r < 1 || static_cast<std::size_t>(r) > chain.size()) noSuchInternode(rank, chain.size());
          connect = chain[static_cast<std::size_t>(r - 1)];
          const int son = g.firstChild(connect, '+');
          if (son >= 0) iter = son;
        }
        const auto lastParts = splitOn(parts[shootOrder - 1], '_');
        if (lastParts.size() < 2) fail("rameau \"" + shootId + "\": a secondary shoot is written a.b_c");
        const auto [child, shoot] =
            g.addChildAndComplex(connect, "in" + roman(static_cast<int>(shootOrder)), inodeLabel, '+', line, cells);
        inode = child;
        const std::string shootSymbol = "sh" + roman(static_cast<int>(shootOrder));
        g.name(shoot, shootSymbol, shootSymbol + lastParts[1], '+');
      } else {
        inode = g.addChild(need(inode, "rang " + orderText + " of shoot " + shootId + " follows no rang 1"),
                           "in" + roman(static_cast<int>(shootOrder)), inodeLabel, '<', line, cells);
      }
    }
  }

  Builder g;
  std::size_t readPast = 0;

 private:
  std::string source_;
  std::size_t width_;
  std::string plantPrev = "\x01";  // differs from any plant (vine_mtg starts from the integer -1)
  std::string trunkLblPrev = "-1_-1", inTLblPrev = "-1_-1_-1", cxLblPrev = "-1_-1_-1.ab",
              inT3yLblPrev = "-1_-1_-1.ab_-1";
  int plant = -1, perennial = -1, trunk = -1, inT = -1, inTTrunk = -1, complexe = -1, inT3y = -1, inT2y = -1, inI = -1,
      inode = -1, connectInI = -1, connectInT3y = -1;
  char edgeInT3y = 0;
};

}  // namespace

bool looksLikeHydroShootTable(std::string_view text) {
  const std::string head(text.substr(0, text.find('\n')));
  const auto fields = splitOn(head, ';');
  return fields.size() == 9 || fields.size() == 10;
}

MtgArchive parseHydroShootTable(std::string_view raw, const std::string& source) {
  MtgArchive a;
  a.source = source;
  a.code = "HydroShoot digitizing table";
  a.features = {{"XX", "REAL"}, {"YY", "REAL"}, {"ZZ", "REAL"}, {"TopDiameter", "REAL"}};
  const std::string text = utf8FromLatin1IfNeeded(raw);
  auto lines = splitOn(text, '\n');
  for (auto& l : lines)
    if (!l.empty() && l.back() == '\r') l.pop_back();
  if (lines.empty() || !looksLikeHydroShootTable(lines[0]))
    throw InputError(source + ", line 1: a HydroShoot digitizing table begins with its header, " + kColumns +
                     " (nine or ten columns separated by ';')");
  const std::size_t width = splitOn(lines[0], ';').size();
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lineOf;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (trimmed(lines[i]).empty()) continue;  // pandas skips blank lines
    auto cells = splitOn(lines[i], ';');
    const int line = static_cast<int>(i + 1);
    checkRow(cells, width, line, source);
    rows.push_back(std::move(cells));
    lineOf.push_back(line);
  }
  if (rows.empty()) throw InputError(source + ": the table has its header and no row");
  const auto typed = pandasColumns(rows);

  VineMtg vine(a, source, width);
  for (std::size_t i = 0; i < rows.size(); ++i) vine.row(typed[i], rows[i], lineOf[i]);
  Builder& g = vine.g;
  const std::size_t readPast = vine.readPast;
  g.finish();
  std::vector<std::string> symbols;
  for (std::size_t v = 1; v < a.vertices.size(); ++v)
    if (std::find(symbols.begin(), symbols.end(), a.vertices[v].symbol) == symbols.end()) {
      symbols.push_back(a.vertices[v].symbol);
      a.classes.push_back({a.vertices[v].symbol, a.vertices[v].scale});
    }
  if (readPast > 0)
    a.notes.push_back(std::to_string(readPast) + " petiole and leaf rows (p, f or l in rameau) are read past");
  return a;
}

MtgArchive readHydroShootTable(const std::filesystem::path& path) {
  return parseHydroShootTable(readFile(path), path.string());
}

}  // namespace leafdig::model
