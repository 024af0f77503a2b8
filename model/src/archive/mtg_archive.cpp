#include "leafdig/model/archive/mtg_archive.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <map>

#include "archive/archive_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"

namespace leafdig::model {

namespace {

using detail::isInteger;
using detail::realOf;
using detail::splitOn;
using detail::trimmed;

std::vector<std::string> words(std::string_view s) {
  std::vector<std::string> out;
  std::string w;
  for (char c : s) {
    if (std::isspace(static_cast<unsigned char>(c)) != 0) {
      if (!w.empty()) out.push_back(std::move(w));
      w.clear();
    } else {
      w += c;
    }
  }
  if (!w.empty()) out.push_back(std::move(w));
  return out;
}

std::string withoutComment(const std::string& line) {
  return line.substr(0, line.find('#'));
}

bool startsWith(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

const char* const kFeatureTypes[] = {"INT", "REAL", "ALPHA", "STRING", "DD/MM", "DD/MM/YY", "DD/MM/YYYY"};

// One line of the file kept with its number.
struct Line {
  int number = 0;
  std::string text;
};

// The element of a code: "+D94" → tag "+", name "D94".
struct Element {
  std::string tag;  // "/", "+", "<", "<<"
  std::string label, symbol;
  int index = 0;
  bool hasIndex = false;
};

// What the column-aligned code becomes (as OpenAlea's preprocessing makes it a bracketed string).
struct Token {
  enum class Kind { Open, Close, Element } kind = Kind::Element;
  Element element;
  int line = 0;
  int cells = -1;  // the line's values (lineCells_), on its last element
};

class Reader {
 public:
  Reader(std::string_view text, std::string source) : source_(std::move(source)) {
    const std::string utf8 = utf8FromLatin1IfNeeded(text);
    int number = 0;
    for (std::string& l : splitOn(utf8, '\n')) {
      ++number;
      if (!l.empty() && l.back() == '\r') l.pop_back();
      const std::string t = trimmed(l);
      if (t.empty() || t[0] == '#') continue;
      lines_.push_back({number, std::move(l)});
    }
  }

  MtgArchive read() {
    MtgArchive a;
    a.source = source_;
    header(a);
    code(a);
    return a;
  }

 private:
  [[noreturn]] void fail(int line, const std::string& what) const {
    throw InputError(source_ + ", line " + std::to_string(line) + ": " + what);
  }
  [[noreturn]] void failEnd(const std::string& what) const { throw InputError(source_ + ": " + what); }

  const Line& next(const char* expecting) {
    if (at_ >= lines_.size()) failEnd(std::string("the file ends before ") + expecting + ": is it an MTG file?");
    return lines_[at_++];
  }

  void header(MtgArchive& a) {
    const Line& codeLine = next("CODE:");
    const std::string c = withoutComment(codeLine.text);
    const auto colon = c.find(':');
    if (c.find("CODE") == std::string::npos || colon == std::string::npos)
      fail(codeLine.number, "an MTG file begins with \"CODE: FORM-A\"; this is \"" + trimmed(codeLine.text) + "\"");
    a.code = trimmed(c.substr(colon + 1));
    if (a.code != "FORM-A" && a.code != "FORM-B")
      fail(codeLine.number, "the code form \"" + a.code + "\" is not FORM-A or FORM-B");

    const Line& classes = next("CLASSES:");
    if (!startsWith(trimmed(classes.text), "CLASSES")) fail(classes.number, "CLASSES: must follow CODE:");
    const Line& classTitles = next("the CLASSES titles");
    if (words(withoutComment(classTitles.text)) !=
        std::vector<std::string>{"SYMBOL", "SCALE", "DECOMPOSITION", "INDEXATION", "DEFINITION"})
      fail(classTitles.number, "the CLASSES titles are SYMBOL SCALE DECOMPOSITION INDEXATION DEFINITION");
    for (;;) {
      const Line& l = next("DESCRIPTION:");
      if (startsWith(trimmed(l.text), "DESCRIPTION")) break;
      const auto w = words(withoutComment(l.text));
      if (w.size() != 5) fail(l.number, "a class is five words: SYMBOL SCALE DECOMPOSITION INDEXATION DEFINITION");
      if (w[0] == "$") continue;
      const bool letters = std::all_of(w[0].begin(), w[0].end(),
                                       [](char ch) { return std::isalpha(static_cast<unsigned char>(ch)) != 0; });
      if (!letters) fail(l.number, "the class symbol \"" + w[0] + "\" is not letters");
      if (!isInteger(w[1]) || w[1][0] == '-' || w[1].size() > 3)
        fail(l.number, "the scale of class " + w[0] + " (\"" + w[1] + "\") is not a scale number");
      for (const MtgClass& k : a.classes)
        if (k.symbol == w[0]) fail(l.number, "class " + w[0] + " is declared twice");
      a.classes.push_back({w[0], std::stoi(w[1])});
    }
    if (a.classes.empty()) failEnd("CLASSES declares no class besides $");
    const Line& descTitles = next("the DESCRIPTION titles");
    if (words(withoutComment(descTitles.text)) != std::vector<std::string>{"LEFT", "RIGHT", "RELTYPE", "MAX"})
      fail(descTitles.number, "the DESCRIPTION titles are LEFT RIGHT RELTYPE MAX");
    // The description says which relations the file's authors meant to allow; like OpenAlea's
    // reader, the topology is read from the code whatever it says.
    for (;;) {
      const Line& l = next("FEATURES:");
      if (startsWith(trimmed(l.text), "FEATURES")) break;
    }
    const Line& featureTitles = next("the FEATURES titles");
    if (words(withoutComment(featureTitles.text)) != std::vector<std::string>{"NAME", "TYPE"})
      fail(featureTitles.number, "the FEATURES titles are NAME TYPE");
    for (;;) {
      const Line& l = next("MTG:");
      if (startsWith(trimmed(l.text), "MTG")) break;
      const auto w = words(withoutComment(l.text));
      if (w.size() != 2) fail(l.number, "a feature is two words: NAME TYPE");
      if (std::find(std::begin(kFeatureTypes), std::end(kFeatureTypes), w[1]) == std::end(kFeatureTypes))
        fail(l.number, "feature " + w[0] + "'s type \"" + w[1] +
                           "\" is none of INT, REAL, ALPHA, STRING, DD/MM, DD/MM/YY, DD/MM/YYYY");
      declared_[w[0]] = w[1];
    }
  }

  void code(MtgArchive& a) {
    const Line& titles = next("ENTITY-CODE");
    const std::vector<std::string> cells = splitOn(titles.text, '\t');
    const std::string first = trimmed(cells[0]);
    if (!startsWith(first, "ENTITY-CODE") && !startsWith(first, "TOPO"))
      fail(titles.number, "the MTG body begins with ENTITY-CODE (or TOPO) and the feature titles");
    if (first != "ENTITY-CODE" && first != "TOPO")
      fail(titles.number, "separate ENTITY-CODE from the feature titles by tabs (\"" + first + "\")");
    start_ = 0;
    for (std::size_t i = 1; i < cells.size() && start_ == 0; ++i)
      if (!trimmed(cells[i]).empty()) start_ = i;
    if (start_ == 0) start_ = cells.size();  // no feature: any number of code columns
    for (std::size_t i = start_; i < cells.size(); ++i) {
      const std::string name = trimmed(cells[i]);
      if (name.empty()) {
        bool more = false;
        for (std::size_t j = i + 1; j < cells.size(); ++j) more = more || !trimmed(cells[j]).empty();
        if (more)
          fail(titles.number, "an empty column between the features " + a.features.back().name +
                                  " and the next: every value after it would be read one column off");
        break;
      }
      if (name.find_first_of(" \t") != std::string::npos)
        fail(titles.number, "separate the feature titles \"" + name + "\" by tabs");
      const auto d = declared_.find(name);
      if (d == declared_.end())
        fail(titles.number, "the column " + name + " is not a feature FEATURES declares: declare it (NAME TYPE)");
      for (const MtgFeature& f : a.features)
        if (f.name == name) fail(titles.number, "the feature " + name + " has two columns");
      a.features.push_back({name, d->second});
    }
    for (const MtgClass& k : a.classes) scales_[k.symbol] = k.scale;

    std::vector<Token> tokens;
    std::vector<std::size_t> indent{0};
    std::vector<char> edges;
    for (; at_ < lines_.size(); ++at_) {
      const Line& l = lines_[at_];
      std::size_t tabs = 0;
      while (tabs < l.text.size() && l.text[tabs] == '\t') ++tabs;
      if (tabs < l.text.size() && l.text[tabs] == ' ')
        fail(l.number, "the line is indented with a space: MTG columns are tabs");
      const std::vector<std::string> row = splitOn(l.text, '\t');
      std::string s = trimmed(row[tabs]);
      if (s.find_first_of(" \t") != std::string::npos)
        fail(l.number, "\"" + s + "\" is one code followed by text in its cell: separate values by tabs");
      if (!a.features.empty() && tabs >= start_)
        fail(l.number, "the code " + s + " is in column " + std::to_string(tabs + 1) + ", where the feature " +
                           a.features[tabs - start_ < a.features.size() ? tabs - start_ : 0].name +
                           " is: the ENTITY-CODE title gives the code " + std::to_string(start_) + " columns");
      for (std::size_t i = tabs + 1; i < std::min(start_, row.size()); ++i)
        if (!trimmed(row[i]).empty())
          fail(l.number, "column " + std::to_string(i + 1) + " (\"" + trimmed(row[i]) +
                             "\") is among the code's columns, before the first feature " +
                             (a.features.empty() ? std::string("") : a.features[0].name) +
                             ": the line's values are shifted; align them under the titles");
      for (std::size_t i = start_ + a.features.size(); i < row.size(); ++i)
        if (!trimmed(row[i]).empty())
          fail(l.number, "column " + std::to_string(i + 1) + " (\"" + trimmed(row[i]) + "\") is past the last feature" +
                             (a.features.empty() ? std::string("") : " (" + a.features.back().name + ")") +
                             ": the line's values are shifted; align them under the titles");
      std::vector<std::string> values(a.features.size());
      for (std::size_t f = 0; f < a.features.size(); ++f) {
        if (start_ + f >= row.size()) break;
        values[f] = trimmed(row[start_ + f]);
        const std::string& v = values[f];
        if (v.empty()) continue;
        if (a.features[f].type == "INT" && !isInteger(v))
          fail(l.number, "column " + std::to_string(start_ + f + 1) + " (" + a.features[f].name + ", INT) holds \"" +
                             v + "\": not a whole number; is the line shifted?");
        if (a.features[f].type == "REAL" && !realOf(v))
          fail(l.number, "column " + std::to_string(start_ + f + 1) + " (" + a.features[f].name + ", REAL) holds \"" +
                             v + "\": not a number; is the line shifted?");
      }
      lineCells_.push_back(std::move(values));

      // The column-aligned code in brackets, as OpenAlea's preprocessing does it.
      std::vector<Token> before;
      const auto sameColumn = [&](bool emptyStackPlus) {
        if (!s.empty() && s[0] == '^') {
          s.erase(0, 1);
        } else if (!edges.empty()) {
          const bool close = edges.back() == '+' || edges.back() == '/';
          if (!s.empty() && (s[0] == '+' || s[0] == '/')) {
            if (close) {
              edges.pop_back();
              before.push_back({Token::Kind::Close, {}, l.number, -1});
            }
            edges.push_back(s[0]);
            before.push_back({Token::Kind::Open, {}, l.number, -1});
          }
        } else if (emptyStackPlus && !s.empty() && s[0] == '+') {
          edges.push_back('+');
        }
      };
      if (tabs == indent.back()) {
        sameColumn(true);
      } else if (tabs > indent.back()) {
        if (!s.empty() && s[0] == '^')
          fail(l.number,
               "'^' continues the entity above in the same column, but this line is deeper than the one "
               "above: remove the '^' or move the code one column left");
        indent.push_back(tabs);
        if (!s.empty() && (s[0] == '+' || s[0] == '/')) before.push_back({Token::Kind::Open, {}, l.number, -1});
        if (!s.empty()) edges.push_back(s[0]);
      } else {
        while (tabs < indent.back()) {
          indent.pop_back();
          if (!edges.empty()) {
            const char e = edges.back();
            edges.pop_back();
            if (e == '+' || e == '/') before.push_back({Token::Kind::Close, {}, l.number, -1});
          }
        }
        if (tabs != indent.back())
          fail(l.number, "the code " + s + " is in column " + std::to_string(tabs + 1) +
                             ", which lines up with no line above it: move it under the entity it continues");
        sameColumn(false);
      }
      for (Token& t : before) tokens.push_back(std::move(t));
      const std::vector<Element> elements = split(s, l.number);
      for (std::size_t i = 0; i < elements.size(); ++i)
        tokens.push_back({Token::Kind::Element, elements[i], l.number,
                          i + 1 == elements.size() ? static_cast<int>(lineCells_.size() - 1) : -1});
    }
    while (!edges.empty()) {
      if (edges.back() == '+' || edges.back() == '/')
        tokens.push_back({Token::Kind::Close, {}, lines_.empty() ? 0 : lines_.back().number, -1});
      edges.pop_back();
    }
    build(a, tokens);
  }

  // "^/E1<<E35" without its '^' → "/E1", "<<E35".
  [[nodiscard]] std::vector<Element> split(const std::string& code, int line) const {
    if (code.empty()) fail(line, "the line has values but no code");
    if (code[0] == '*') fail(line, "a dated MTG ('*') is not read; remove the dates or export the MTG without them");
    std::vector<Element> out;
    std::size_t i = 0;
    while (i < code.size()) {
      Element e;
      if (code.compare(i, 2, "<<") == 0) {
        e.tag = "<<";
        i += 2;
      } else if (code[i] == '/' || code[i] == '+' || code[i] == '<') {
        e.tag = std::string(1, code[i]);
        ++i;
      } else {
        fail(line, "\"" + code + "\": an entity begins with /, +, < or << (and ^ to continue the line above)");
      }
      std::size_t j = i;
      while (j < code.size() && std::isalpha(static_cast<unsigned char>(code[j])) != 0) ++j;
      e.symbol = code.substr(i, j - i);
      std::size_t k = j;
      while (k < code.size() && std::isdigit(static_cast<unsigned char>(code[k])) != 0) ++k;
      if (e.symbol.empty() || (k < code.size() && std::string_view("/+<").find(code[k]) == std::string_view::npos))
        fail(line, "\"" + code + "\": \"" + code.substr(i, k + 1 - i) +
                       "\" is no entity (a class symbol and a number, e.g. S12)");
      if (scales_.count(e.symbol) == 0)
        fail(line, "\"" + code + "\": " + e.symbol + " is not a class CLASSES declares");
      if (k > j) {
        if (k - j > 9) fail(line, "\"" + code + "\": the entity number " + code.substr(j, k - j) + " is too large");
        e.index = std::stoi(code.substr(j, k - j));
        e.hasIndex = true;
      }
      e.label = code.substr(i, k - i);
      if (e.tag == "<<" && !e.hasIndex) fail(line, "\"" + code + "\": a range (<<) ends at a numbered entity");
      out.push_back(std::move(e));
      i = k;
    }
    return out;
  }

  // The multiscale tree from the tokens, as OpenAlea's multiscale edit makes it with scales
  // implicit from CLASSES: `support` is the last vertex of the support tree, `current` the
  // vertex the next one relates to, `scale` the scale being written.
  void build(MtgArchive& a, const std::vector<Token>& tokens) {
    auto& v = a.vertices;
    v.push_back({});
    int support = 0, current = 0, scale = 0;
    char pending = 0;
    std::vector<int> stack;
    const auto made = [&](int line) {
      if (v.size() >= kMaxMtgVertices)
        fail(line, "the file makes more than " + std::to_string(kMaxMtgVertices) + " entities");
    };
    // OpenAlea's reader puts an entity at the scale the code reaches, whatever its class says
    // (P1 followed by +S1 makes a plant-scale S1): refused here.
    const auto checkScale = [&](const MtgVertex& x, const std::string& tag) {
      const int declared = scales_.at(x.symbol);
      if (x.scale != declared)
        fail(x.line,
             tag + x.label + " is of class " + x.symbol + " (scale " + std::to_string(declared) +
                 ") but the code puts it at scale " + std::to_string(x.scale) +
                 ": decompose with '/' through the scales between, or go up with a new entity of the coarser class");
    };
    const auto component = [&](int of, const Element& e, int line) {
      made(line);
      MtgVertex x;
      x.label = e.label, x.symbol = e.symbol, x.index = e.index, x.scale = v[static_cast<std::size_t>(of)].scale + 1;
      x.complex = of, x.line = line;
      checkScale(x, e.tag);
      v.push_back(std::move(x));
      return static_cast<int>(v.size() - 1);
    };
    const auto child = [&](int of, char edge, const Element& e, int line) {
      made(line);
      MtgVertex x;
      x.label = e.label, x.symbol = e.symbol, x.index = e.index, x.scale = v[static_cast<std::size_t>(of)].scale;
      x.complex = v[static_cast<std::size_t>(of)].complex, x.parent = of, x.edge = edge, x.line = line;
      checkScale(x, e.tag);
      v.push_back(std::move(x));
      return static_cast<int>(v.size() - 1);
    };
    const auto at = [&](int id) -> MtgVertex& { return v[static_cast<std::size_t>(id)]; };
    for (const Token& t : tokens) {
      if (t.kind == Token::Kind::Open) {
        stack.push_back(support);
        continue;
      }
      if (t.kind == Token::Kind::Close) {
        if (stack.empty()) fail(t.line, "a branch closes that never opened");
        support = current = stack.back();
        stack.pop_back();
        scale = at(support).scale;
        continue;
      }
      const Element& e = t.element;
      int target = scales_.at(e.symbol);
      if (e.tag == "/" && target <= scale) {
        --target;
        pending = '/';
      }
      while (target < scale) {
        --scale;
        current = at(current).complex;
        if (current < 0) fail(t.line, e.tag + e.label + " goes above the root: a '/' too many before it?");
      }
      if (e.tag == "+" || e.tag == "<") {
        if (at(support).scale == scale) {
          support = current = child(support, e.tag[0], e, t.line);
          pending = 0;
        } else {
          const int c = at(current).complex;
          if (c < 0) fail(t.line, e.tag + e.label + " has nothing to follow or branch from");
          const int before = current;
          current = component(c, e, t.line);
          at(current).after = before;
          at(current).afterEdge = e.tag[0];
          pending = e.tag[0];
        }
      } else if (e.tag == "<<") {
        const int from = at(current).index;
        if (e.index <= from)
          fail(t.line, "the range to " + e.label + " runs from " + at(current).label + ": it must end above " +
                           std::to_string(from));
        if (static_cast<std::size_t>(e.index - from) > kMaxMtgVertices - v.size())
          fail(t.line, "the range to " + e.label + " makes more than " + std::to_string(kMaxMtgVertices) + " entities");
        pending = 0;
        for (int i = from + 1; i <= e.index; ++i) {
          Element each = e;
          each.index = i;
          each.label = e.symbol + std::to_string(i);
          support = current = child(support, '<', each, t.line);
        }
      } else {  // '/'
        if (at(support).scale == scale) {
          support = current = component(support, e, t.line);
          ++scale;
        } else if (at(support).scale > scale) {
          ++scale;
          const int c = component(current, e, t.line);
          if (at(support).scale == scale && pending != '/') {
            at(c).parent = support;
            at(c).edge = pending;
            support = current = c;
          } else {
            current = c;
            if (pending == '/') {
              support = current;
              scale = at(support).scale;
            }
          }
        } else {
          support = current = component(current, e, t.line);
        }
      }
      if (t.cells >= 0) at(current).cells = lineCells_[static_cast<std::size_t>(t.cells)];
    }
    for (MtgVertex& x : v)
      if (x.cells.empty()) x.cells.resize(a.features.size());
  }

  std::string source_;
  std::vector<Line> lines_;
  std::size_t at_ = 0;
  std::map<std::string, std::string> declared_;
  std::map<std::string, int> scales_;
  std::size_t start_ = 0;
  std::vector<std::vector<std::string>> lineCells_;
};

}  // namespace

int MtgArchive::feature(std::string_view name) const {
  for (std::size_t i = 0; i < features.size(); ++i)
    if (features[i].name == name) return static_cast<int>(i);
  return -1;
}

std::optional<double> MtgArchive::number(std::size_t v, int f) const {
  if (f < 0 || v >= vertices.size()) return std::nullopt;
  const auto column = static_cast<std::size_t>(f);
  if (!features[column].numeric() || column >= vertices[v].cells.size()) return std::nullopt;
  return realOf(vertices[v].cells[column]);
}

std::size_t MtgArchive::countAtScale(int scale) const {
  return static_cast<std::size_t>(
      std::count_if(vertices.begin(), vertices.end(), [scale](const MtgVertex& x) { return x.scale == scale; }));
}

std::vector<std::vector<int>> MtgArchive::components() const {
  std::vector<std::vector<int>> out(vertices.size());
  for (std::size_t i = 1; i < vertices.size(); ++i)
    if (vertices[i].complex >= 0) out[static_cast<std::size_t>(vertices[i].complex)].push_back(static_cast<int>(i));
  return out;
}

MtgArchive parseMtgArchive(std::string_view text, const std::string& source) {
  return Reader(text, source).read();
}

MtgArchive readMtgArchive(const std::filesystem::path& path) {
  return parseMtgArchive(readFile(path), path.string());
}

MtgDressing parseMtgDressing(std::string_view text, const std::string& source) {
  MtgDressing d;
  int number = 0;
  const auto fail = [&](const std::string& what) {
    throw InputError(source + ", line " + std::to_string(number) + ": " + what);
  };
  for (std::string& raw : splitOn(utf8FromLatin1IfNeeded(text), '\n')) {
    ++number;
    const auto w = words(withoutComment(raw));
    if (w.empty()) continue;
    const auto eq = std::find(w.begin(), w.end(), "=");
    if (eq == w.end() || eq + 1 == w.end())
      fail("\"" + trimmed(raw) + "\" is no setting: a dressing line is Key = value (or Key Class = value)");
    const std::string& key = w[0];
    const std::string& value = *(eq + 1);
    const auto positive = [&]() {
      const auto n = realOf(value);
      if (!n || *n <= 0) fail(std::string(key).append(" = \"").append(value).append("\": a unit is a number above 0"));
      return *n;
    };
    if (key == "LengthUnit") {
      d.lengthUnit = positive();
    } else if (key == "DiameterUnit") {
      d.diameterUnit = positive();
    } else if (key == "AlphaUnit") {
      d.alphaUnit = positive();
    } else if (key == "LeafClass") {
      d.leafClass = value;
    } else if (key == "LeafLength") {
      d.leafLength = positive();
    } else if (key == "Phyllotaxy") {
      const auto slash = value.find('/');
      if (slash != std::string::npos) {
        const auto turns = realOf(value.substr(0, slash)), leaves = realOf(value.substr(slash + 1));
        if (!turns || !leaves || *leaves <= 0) fail("Phyllotaxy = \"" + value + "\": degrees, or turns/leaves (2/5)");
        d.phyllotaxyDeg = 360.0 * *turns / *leaves;
      } else {
        const auto deg = realOf(value);
        if (!deg) fail("Phyllotaxy = \"" + value + "\": degrees, or turns/leaves (2/5)");
        d.phyllotaxyDeg = *deg;
      }
    } else {
      d.ignored.push_back(key);
    }
  }
  return d;
}

MtgDressing readMtgDressing(const std::filesystem::path& path) {
  return parseMtgDressing(readFile(path), path.string());
}

std::string utf8FromLatin1IfNeeded(std::string_view text) {
  bool valid = true;
  for (std::size_t i = 0; i < text.size() && valid;) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    if (n == 0 || i + n > text.size()) {
      valid = false;
      break;
    }
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(text[i + k]) & 0xC0) != 0x80) valid = false;
    i += n;
  }
  if (valid) return std::string(text);
  std::string out;
  out.reserve(text.size() + text.size() / 8);
  for (char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out += ch;
    } else {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

}  // namespace leafdig::model
