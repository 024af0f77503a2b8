// Strict readers of the simulation formats, written from docs/plants.md "Formats" (the rules found by running
// OpenAlea's MTG reader and CARIBU's canestrad), independently of leafdig's writers. They
// throw std::runtime_error naming the line and the rule broken.
#pragma once

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace leafdig::test {

inline std::vector<std::string> splitExact(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

inline std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> lines = splitExact(text, '\n');
  if (!lines.empty() && lines.back().empty()) lines.pop_back();
  return lines;
}

inline bool isInt(const std::string& s) {
  std::size_t i = (!s.empty() && s[0] == '-') ? 1 : 0;
  if (i >= s.size()) return false;
  for (; i < s.size(); ++i)
    if (s[i] < '0' || s[i] > '9') return false;
  return true;
}

// Fixed notation only: digits, one optional point, an optional leading minus. No exponent,
// no decimal comma.
// DD/MM/YYYY (or DD/MM/YY): a day of the calendar.
inline bool isMtgDate(const std::string& s, std::size_t yearDigits) {
  if (s.size() != 6 + yearDigits || s[2] != '/' || s[5] != '/') return false;
  for (std::size_t k : {0u, 1u, 3u, 4u})
    if (s[k] < '0' || s[k] > '9') return false;
  for (std::size_t k = 6; k < s.size(); ++k)
    if (s[k] < '0' || s[k] > '9') return false;
  const int day = std::stoi(s.substr(0, 2)), month = std::stoi(s.substr(3, 2)), year = std::stoi(s.substr(6));
  static constexpr int kDays[] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (month < 1 || month > 12 || day < 1 || day > kDays[month - 1]) return false;
  const bool leap = yearDigits == 2 || ((year % 4 == 0 && year % 100 != 0) || year % 400 == 0);
  return month != 2 || day <= 28 || leap;
}

inline bool isFixed(const std::string& s) {
  std::size_t i = (!s.empty() && s[0] == '-') ? 1 : 0;
  bool digits = false;
  bool point = false;
  for (; i < s.size(); ++i) {
    if (s[i] >= '0' && s[i] <= '9') {
      digits = true;
    } else if (s[i] == '.' && !point) {
      point = true;
    } else {
      return false;
    }
  }
  return digits;
}

// ---------------------------------------------------------------------------------------
// OpenAlea MTG coding file.

struct MtgEntity {
  char symbol = 0;
  int index = 0;
  int depth = 0;                                // leading tabs
  char relation = 0;                            // '/', '<' or '+' (the last one of the code)
  int parent = -1;                              // entity this one follows or branches from (-1: the plant)
  std::map<std::string, std::string> features;  // declared features present on the line
};

struct MtgFile {
  std::map<char, int> scales;                                 // class symbol -> scale
  std::vector<std::pair<std::string, std::string>> features;  // name, type in order
  std::set<std::tuple<char, char, char>> relations;           // left, right, reltype
  std::vector<MtgEntity> entities;
  [[nodiscard]] int nbScales() const {
    std::set<int> s;
    for (const auto& [sym, scale] : scales) s.insert(scale);
    return static_cast<int>(s.size());
  }
};

inline MtgFile readMtgStrictly(const std::string& text) {
  const auto fail = [](std::size_t line, const std::string& what) {
    throw std::runtime_error("MTG line " + std::to_string(line + 1) + ": " + what);
  };
  const std::vector<std::string> lines = linesOf(text);
  std::size_t i = 0;
  const auto skipBlankAndComments = [&] {
    while (i < lines.size() && (lines[i].empty() || lines[i][0] == '#')) ++i;
  };
  const auto expect = [&](const std::string& exact) {
    skipBlankAndComments();
    if (i >= lines.size() || lines[i] != exact) fail(i, "expected exactly \"" + exact + "\"");
    ++i;
  };
  MtgFile mtg;
  expect("CODE:\tFORM-A");
  expect("CLASSES:");
  expect("SYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION");
  static const std::set<std::string> decompositions{"FREE", "CONNECTED", "NOTCONNECTED", "LINEAR", "NONE"};
  for (; i < lines.size() && !lines[i].empty(); ++i) {
    const auto f = splitExact(lines[i], '\t');
    if (f.size() != 5) fail(i, "a class line has 5 tab-separated fields");
    if (f[0].size() != 1) fail(i, "a class symbol is one character");
    if (!isInt(f[1])) fail(i, "scale must be an integer");
    if (!decompositions.count(f[2])) fail(i, "unknown decomposition " + f[2]);
    if (f[3] != "FREE" && f[3] != "CONSECUTIVE") fail(i, "unknown indexation " + f[3]);
    if (f[4] != "IMPLICIT" && f[4] != "EXPLICIT") fail(i, "unknown definition " + f[4]);
    mtg.scales[f[0][0]] = std::stoi(f[1]);
  }
  if (!mtg.scales.count('$') || mtg.scales['$'] != 0) fail(i, "the first class is $ at scale 0");
  expect("DESCRIPTION:");
  expect("LEFT\tRIGHT\tRELTYPE\tMAX");
  for (; i < lines.size() && !lines[i].empty(); ++i) {
    const auto f = splitExact(lines[i], '\t');
    if (f.size() != 4) fail(i, "a description line has 4 tab-separated fields");
    if (f[2] != "<" && f[2] != "+") fail(i, "RELTYPE is < or +");
    if (f[3] != "?" && !isInt(f[3])) fail(i, "MAX is an integer or ?");
    for (const auto& s : {f[0], f[1]})
      if (s.size() != 1 || !mtg.scales.count(s[0])) fail(i, "undeclared class " + s);
    mtg.relations.insert({f[0][0], f[1][0], f[2][0]});
  }
  expect("FEATURES:");
  expect("NAME\tTYPE");
  static const std::set<std::string> types{"INT", "REAL", "ALPHA", "STRING", "DD/MM/YY", "DD/MM/YYYY"};
  for (; i < lines.size() && !lines[i].empty(); ++i) {
    const auto f = splitExact(lines[i], '\t');
    if (f.size() != 2) fail(i, "a feature line has NAME<TAB>TYPE");
    if (!types.count(f[1])) fail(i, "unknown feature type " + f[1] + " (FLOAT is not one)");
    mtg.features.emplace_back(f[0], f[1]);
  }
  // AMAP's reserved features come first, in this order, with their own types.
  static const std::vector<std::pair<std::string, std::string>> reserved{
      {"Alias", "ALPHA"},         {"Date", "DD/MM/YYYY"},  {"NbEl", "INT"},   {"Length", "REAL"},
      {"BottomDiameter", "REAL"}, {"TopDiameter", "REAL"}, {"State", "ALPHA"}};
  std::size_t nextReserved = 0;
  bool other = false;
  for (const auto& [name, type] : mtg.features) {
    const auto r = std::find_if(reserved.begin(), reserved.end(), [&](const auto& e) { return e.first == name; });
    if (r == reserved.end()) {
      other = true;
      continue;
    }
    if (other) fail(i, "reserved feature " + name + " must come before the others");
    const auto at = static_cast<std::size_t>(r - reserved.begin());
    if (at < nextReserved)
      fail(i, "reserved features in AMAP's order: Alias, Date, NbEl, Length, BottomDiameter, TopDiameter, State");
    if (name != "Date" && type != r->second) fail(i, "reserved feature " + name + " has type " + r->second);
    nextReserved = at + 1;
  }
  expect("MTG:");
  skipBlankAndComments();
  if (i >= lines.size()) fail(i, "no TOPO header");
  const auto header = splitExact(lines[i], '\t');
  if (header.empty() || header[0] != "TOPO") fail(i, "the MTG header starts with TOPO");
  std::size_t firstFeature = 1;
  while (firstFeature < header.size() && header[firstFeature].empty()) ++firstFeature;
  if (header.size() - firstFeature != mtg.features.size()) fail(i, "the header must name every declared feature");
  for (std::size_t k = 0; k < mtg.features.size(); ++k)
    if (header[firstFeature + k] != mtg.features[k].first) fail(i, "header column " + mtg.features[k].first);
  ++i;

  std::map<int, int> lastAtDepth;  // depth -> entity index
  for (; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    if (line.empty()) continue;
    if (line.find(' ') != std::string::npos) fail(i, "spaces are not allowed (tabs only)");
    const auto f = splitExact(line, '\t');
    std::size_t depth = 0;
    while (depth < f.size() && f[depth].empty()) ++depth;
    if (depth >= firstFeature) fail(i, "the entity code must stand in the TOPO columns");
    for (std::size_t k = depth + 1; k < firstFeature && k < f.size(); ++k)
      if (!f[k].empty()) fail(i, "two entity codes on one line");
    if (f.size() > firstFeature + mtg.features.size()) fail(i, "an extra tab shifts the features");
    // The code: optional ^, then (/|<|+)SymbolIndex, one or more.
    const std::string& code = f[depth];
    std::size_t p = 0;
    const bool caret = !code.empty() && code[0] == '^';
    if (caret) ++p;
    MtgEntity e;
    e.depth = static_cast<int>(depth);
    int parent = caret ? (lastAtDepth.count(e.depth) ? lastAtDepth[e.depth] : -2)
                       : (depth == 0 ? -1 : (lastAtDepth.count(e.depth - 1) ? lastAtDepth[e.depth - 1] : -2));
    if (parent == -2) fail(i, "the code refers to no entity above it");
    bool any = false;
    while (p < code.size()) {
      const char rel = code[p++];
      if (rel != '/' && rel != '<' && rel != '+') fail(i, "bad separator in " + code);
      if (p < code.size() && code[p] == '<') fail(i, "<< is not written by leafdig");
      if (p >= code.size() || !mtg.scales.count(code[p])) fail(i, "undeclared class in " + code);
      const char sym = code[p++];
      std::string digits;
      while (p < code.size() && code[p] >= '0' && code[p] <= '9') digits += code[p++];
      if (digits.empty()) fail(i, "an entity needs an index: " + code);
      if (rel != '/' && parent >= 0) {
        const char left = mtg.entities[static_cast<std::size_t>(parent)].symbol;
        if (!mtg.relations.count({left, sym, rel}))
          fail(i, std::string("relation ") + left + rel + sym + " is not in DESCRIPTION");
      }
      e.symbol = sym;
      e.index = std::stoi(digits);
      e.relation = rel;
      e.parent = parent;
      any = true;
      if (p < code.size()) {  // an intermediate entity (e.g. P1 in /P1/I1)
        MtgEntity mid = e;
        mtg.entities.push_back(mid);
        parent = static_cast<int>(mtg.entities.size() - 1);
      }
    }
    if (!any) fail(i, "empty entity code");
    for (std::size_t k = 0; firstFeature + k < f.size(); ++k) {
      const std::string& v = f[firstFeature + k];
      if (v.empty()) continue;
      const auto& [name, type] = mtg.features[k];
      if (type == "INT" && !isInt(v)) fail(i, name + " \"" + v + "\" is not an INT");
      if (type == "REAL" && !isFixed(v)) fail(i, name + " \"" + v + "\" is not a REAL in fixed notation");
      const bool date = type == "DD/MM/YYYY" || type == "DD/MM/YY";
      if (date && !isMtgDate(v, type.size() == 10 ? 4 : 2)) fail(i, name + " \"" + v + "\" is not a " + type + " day");
      if (v.find_first_of(date ? "+<[](),=" : "+</[](),=") != std::string::npos)
        fail(i, name + " holds an MTG syntax character");
      e.features[name] = v;
    }
    mtg.entities.push_back(e);
    lastAtDepth[e.depth] = static_cast<int>(mtg.entities.size() - 1);
    for (auto it = lastAtDepth.begin(); it != lastAtDepth.end();)
      it = it->first > e.depth ? lastAtDepth.erase(it) : std::next(it);
  }
  return mtg;
}

// ---------------------------------------------------------------------------------------
// CARIBU .can and .opt.

struct CanTriangle {
  std::string label;
  int species = 0, plant = 0, leaf = 0, element = 0;
  std::array<std::array<float, 3>, 3> v{};  // single precision, as canestrad reads them
  [[nodiscard]] std::array<double, 3> normal() const {
    const std::array<double, 3> a{v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
    const std::array<double, 3> b{v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  }
  [[nodiscard]] double area() const {
    const auto n = normal();
    return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }
};

struct CaribuOpt {
  int species = 0;
  double soil = 0;
  std::vector<std::array<double, 5>> optics;  // stem r, upper r t, lower r t
};

inline CaribuOpt readOptStrictly(const std::string& text) {
  if (text.empty() || text.back() != '\n') throw std::runtime_error(".opt: a trailing newline is required");
  CaribuOpt opt;
  bool haveN = false;
  for (const std::string& line : linesOf(text)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    std::vector<std::string> f;
    for (std::string w; in >> w;) f.push_back(w);
    if (f[0] == "n") {
      if (f.size() != 2 || !isInt(f[1])) throw std::runtime_error(".opt: n <species>");
      opt.species = std::stoi(f[1]);
      haveN = true;
    } else if (f[0] == "s") {
      if (f.size() != 3 || f[1] != "d" || !isFixed(f[2])) throw std::runtime_error(".opt: s d <soil reflectance>");
      opt.soil = std::stod(f[2]);
    } else if (f[0] == "e") {
      if (f.size() != 9 || f[1] != "d" || f[3] != "d" || f[6] != "d")
        throw std::runtime_error(".opt: e d <stem r> d <upper r> <upper t> d <lower r> <lower t>");
      std::array<double, 5> o{};
      std::size_t k = 0;
      for (std::size_t j : {2, 4, 5, 7, 8}) {
        if (!isFixed(f[j])) throw std::runtime_error(".opt: optical values in fixed notation");
        o[k++] = std::stod(f[j]);
      }
      for (double x : o)
        if (x < 0 || x > 1) throw std::runtime_error(".opt: reflectance and transmittance lie in [0, 1]");
      if (o[1] + o[2] > 1 || o[3] + o[4] > 1) throw std::runtime_error(".opt: r + t exceeds 1");
      opt.optics.push_back(o);
    } else {
      throw std::runtime_error(".opt: unknown line \"" + line + "\"");
    }
  }
  if (!haveN || opt.species != static_cast<int>(opt.optics.size()))
    throw std::runtime_error(".opt: n must equal the number of e lines");
  return opt;
}

inline std::vector<CanTriangle> readCanStrictly(const std::string& text, const CaribuOpt& opt) {
  if (text.empty() || text.back() != '\n') throw std::runtime_error(".can: a trailing newline is required");
  std::vector<CanTriangle> out;
  std::size_t number = 0;
  for (const std::string& line : linesOf(text)) {
    ++number;
    const auto fail = [number](const std::string& what) {
      throw std::runtime_error(".can line " + std::to_string(number) + ": " + what);
    };
    if (line.empty() || line[0] == '#') continue;
    if (line.find(',') != std::string::npos) fail("a decimal comma is read as an integer");
    const std::vector<std::string> f = splitExact(line, ' ');
    if (f.size() != 13) fail("expected p 1 <label> 3 and nine coordinates, single spaces");
    if (f[0] != "p" || f[1] != "1") fail("a primitive starts with \"p 1\"");
    const std::string& label = f[2];
    if (label.size() < 12 || label.size() > 15 || !isInt(label) || label[0] == '-') fail("a label is 12 to 15 digits");
    if (f[3] != "3") fail("triangles only (\"3\"): a quad is only half lit");
    CanTriangle t;
    t.label = label;
    t.species = std::stoi(label.substr(0, label.size() - 11));
    t.plant = std::stoi(label.substr(label.size() - 11, 5));
    t.leaf = std::stoi(label.substr(label.size() - 6, 3));
    t.element = std::stoi(label.substr(label.size() - 3, 3));
    if (t.species < 1 || t.species > opt.species) fail("optical species outside 1.." + std::to_string(opt.species));
    for (std::size_t k = 0; k < 9; ++k) {
      const std::string& v = f[4 + k];
      if (!isFixed(v)) fail("coordinate \"" + v + "\" is not in fixed notation");
      t.v[k / 3][k % 3] = std::stof(v);
    }
    const std::size_t at = line.find(" 3 ");
    const std::string geometry = line.substr(at);
    if (geometry.size() + 1 + f[12].size() > 124) fail("geometry longer than canestrad's 124 characters");
    if (!(t.area() > 0.0)) fail("a zero-area triangle (CARIBU rejects it)");
    out.push_back(t);
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Helios XML (core/src/Context_fileIO.cpp's loadXML, as docs/plants.md "Formats" states its rules):
// a <helios> root; each <triangle> made from its <transform> (16 numbers, row-major) of the unit
// triangle (0,0,0), (0,1,0), (1,1,0); <objID> a non-negative integer, each one above 0 claimed by
// exactly one <polymesh> (loadXML stops at a polymesh whose objID no triangle uses) and numbered
// 1, 2, … as they first appear (a fresh Context gives them those numbers); <data_int> integers.

struct HeliosTriangle {
  unsigned objID = 0;
  std::map<std::string, long> data;  // <data_int label=…>
  std::array<std::array<double, 3>, 3> v{};
  std::array<double, 3> color{};
};
struct HeliosFile {
  std::vector<HeliosTriangle> triangles;
  std::map<unsigned, std::map<std::string, std::string>> objects;  // polymesh objID -> its data (as text)
};

inline HeliosFile readHeliosStrictly(const std::string& text) {
  const auto fail = [](const std::string& what) { throw std::runtime_error("Helios XML: " + what); };
  // Tokens: tags (with their attributes) and the text between them; comments and the
  // declaration skipped.
  struct Tag {
    std::string name, label;
    bool close = false;
  };
  std::size_t at = 0;
  const auto skipSpace = [&] {
    while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at])) != 0) ++at;
  };
  const auto nextTag = [&](std::string& before) -> Tag {
    const std::size_t open = text.find('<', at);
    if (open == std::string::npos) fail("the file ends inside <helios>");
    before = text.substr(at, open - at);
    if (text.compare(open, 4, "<!--") == 0) {
      const std::size_t end = text.find("-->", open);
      if (end == std::string::npos) fail("a comment never ends");
      at = end + 3;
      Tag t = Tag{};
      t.name = "!--";
      return t;
    }
    const std::size_t close = text.find('>', open);
    if (close == std::string::npos) fail("a tag never ends");
    std::string inside = text.substr(open + 1, close - open - 1);
    at = close + 1;
    Tag t;
    if (!inside.empty() && inside[0] == '/') {
      t.close = true;
      inside.erase(0, 1);
    }
    const std::size_t space = inside.find(' ');
    t.name = inside.substr(0, space);
    if (space != std::string::npos) {
      const std::string attrs = inside.substr(space + 1);
      const std::string key = "label=\"";
      if (attrs.rfind(key, 0) != 0 || attrs.back() != '"') fail("<" + t.name + "> has an attribute other than label");
      t.label = attrs.substr(key.size(), attrs.size() - key.size() - 1);
    }
    return t;
  };
  const auto numbers = [&](const std::string& s, const std::string& what) {
    std::vector<double> out;
    std::istringstream in(s);
    for (std::string w; in >> w;) {
      char* end = nullptr;
      const float f = std::strtof(w.c_str(), &end);
      if (end != w.c_str() + w.size() || !std::isfinite(f)) fail(what + " holds \"" + w + "\", not a number");
      out.push_back(std::strtod(w.c_str(), nullptr));
    }
    return out;
  };
  skipSpace();
  if (text.compare(at, 5, "<?xml") == 0) at = text.find("?>", at) + 2;
  std::string between;
  Tag t;
  do {
    t = nextTag(between);
  } while (t.name == "!--");
  if (t.name != "helios" || t.close) fail("the root element is <helios>");
  HeliosFile file;
  std::set<unsigned> claimed;
  std::vector<unsigned> firstSeen;
  for (;;) {
    do {
      t = nextTag(between);
    } while (t.name == "!--");
    if (t.close && t.name == "helios") break;
    if (t.close || (t.name != "triangle" && t.name != "polymesh")) fail("<" + t.name + "> is not written by leafdig");
    const bool triangle = t.name == "triangle";
    HeliosTriangle tri;
    std::map<std::string, std::string> data;
    bool haveTransform = false, haveObj = false;
    std::vector<double> transform;
    for (;;) {
      Tag child = nextTag(between);
      if (child.close && child.name == (triangle ? "triangle" : "polymesh")) break;
      if (child.close) fail("</" + child.name + "> closes nothing");
      std::string value;
      const Tag end = nextTag(value);
      if (!end.close || end.name != child.name) fail("<" + child.name + "> holds another element");
      if (child.name == "objID") {
        const auto n = numbers(value, "<objID>");
        if (n.size() != 1 || n[0] < 0 || n[0] != std::floor(n[0])) fail("<objID> is a non-negative integer");
        tri.objID = static_cast<unsigned>(n[0]);
        haveObj = true;
      } else if (child.name == "transform" && triangle) {
        transform = numbers(value, "<transform>");
        if (transform.size() != 16) fail("<transform> holds 16 numbers, not " + std::to_string(transform.size()));
        haveTransform = true;
      } else if (child.name == "color" && triangle) {
        const auto c = numbers(value, "<color>");
        if (c.size() != 3 && c.size() != 4) fail("<color> is r g b [a]");
        for (double x : c)
          if (x < 0 || x > 1) fail("a colour component lies in [0, 1]");
        tri.color = {c[0], c[1], c[2]};
      } else if (child.name == "data_int") {
        if (child.label.empty()) fail("<data_int> needs a label");
        const auto n = numbers(value, "<data_int>");
        if (n.size() != 1 || n[0] != std::floor(n[0])) fail("<data_int label=\"" + child.label + "\"> is one integer");
        tri.data[child.label] = static_cast<long>(n[0]);
        data[child.label] = value;
      } else if (child.name == "data_string" && !triangle) {
        if (child.label.empty() || value.find_first_of("<&") != std::string::npos) fail("a bad <data_string>");
        data[child.label] = value;
      } else {
        fail("<" + child.name + "> is not expected in <" + (triangle ? "triangle" : "polymesh") + ">");
      }
    }
    if (triangle) {
      if (!haveTransform) fail("a triangle without <transform> is the unit triangle");
      if (transform[12] != 0 || transform[13] != 0 || transform[14] != 0 || transform[15] != 1)
        fail("a transform's last row is 0 0 0 1");
      const std::array<std::array<double, 3>, 3> unit{{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}}};
      for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t r = 0; r < 3; ++r)
          tri.v[k][r] = transform[4 * r] * unit[k][0] + transform[4 * r + 1] * unit[k][1] +
                        transform[4 * r + 2] * unit[k][2] + transform[4 * r + 3];
      if (tri.objID > 0 && std::find(firstSeen.begin(), firstSeen.end(), tri.objID) == firstSeen.end()) {
        if (tri.objID != firstSeen.size() + 1) fail("objIDs are numbered 1, 2, … as they first appear");
        firstSeen.push_back(tri.objID);
      }
      file.triangles.push_back(tri);
    } else {
      if (!haveObj || tri.objID == 0) fail("a <polymesh> names its objID (above 0)");
      if (!claimed.insert(tri.objID).second) fail("two <polymesh> claim objID " + std::to_string(tri.objID));
      file.objects[tri.objID] = data;
    }
  }
  skipSpace();
  if (at != text.size()) fail("text after </helios>");
  for (unsigned id : firstSeen)
    if (!claimed.count(id)) fail("objID " + std::to_string(id) + " has triangles but no <polymesh>");
  for (unsigned id : claimed)
    if (std::find(firstSeen.begin(), firstSeen.end(), id) == firstSeen.end())
      fail("<polymesh> " + std::to_string(id) + " has no triangle (loadXML stops there)");
  return file;
}

// ---------------------------------------------------------------------------------------
// VegeSTAR .vgx (PlantGL's vgsfile.cpp and PyRATP's vege3D.py): a title row of known column
// names, one separator (a tab), then rows of numbers only (PyRATP stops at the first that is
// not), as many as the titles; Obj 0 an explicit triangle X1 … Z3.

struct VgxRow {
  std::map<std::string, double> value;
  [[nodiscard]] std::array<std::array<double, 3>, 3> triangle() const {
    return {{{value.at("X1"), value.at("Y1"), value.at("Z1")},
             {value.at("X2"), value.at("Y2"), value.at("Z2")},
             {value.at("X3"), value.at("Y3"), value.at("Z3")}}};
  }
};

inline std::vector<VgxRow> readVgxStrictly(const std::string& text) {
  const std::vector<std::string> lines = linesOf(text);
  if (lines.empty()) throw std::runtime_error(".vgx: no title row");
  static const std::set<std::string> known{"Obj",  "EchX", "EchY",  "EchZ", "TransX", "TransY", "TransZ", "RotX",
                                           "RotY", "RotZ", "R",     "G",    "B",      "X1",     "Y1",     "Z1",
                                           "X2",   "Y2",   "Z2",    "X3",   "Y3",     "Z3",     "Mask",   "Grp1",
                                           "Grp2", "Pmax", "Alpha", "Teta", "Resp",   "VCmax",  "Jmax"};
  const std::vector<std::string> titles = splitExact(lines[0], '\t');
  for (const auto& t : titles)
    if (!known.count(t)) throw std::runtime_error(".vgx: unknown column " + t);
  for (const char* needed : {"Obj", "X1", "Y1", "Z1", "X2", "Y2", "Z2", "X3", "Y3", "Z3"})
    if (std::find(titles.begin(), titles.end(), needed) == titles.end())
      throw std::runtime_error(std::string(".vgx: no column ") + needed);
  std::vector<VgxRow> rows;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty() && i + 1 == lines.size()) break;
    const std::vector<std::string> cells = splitExact(lines[i], '\t');
    if (cells.size() != titles.size())
      throw std::runtime_error(".vgx line " + std::to_string(i + 1) + ": " + std::to_string(cells.size()) +
                               " values for " + std::to_string(titles.size()) + " titles");
    VgxRow row;
    for (std::size_t k = 0; k < cells.size(); ++k) {
      char* end = nullptr;
      const double v = std::strtod(cells[k].c_str(), &end);
      if (cells[k].empty() || end != cells[k].c_str() + cells[k].size() || !std::isfinite(v))
        throw std::runtime_error(".vgx line " + std::to_string(i + 1) + ": \"" + cells[k] + "\" is not a number");
      row.value[titles[k]] = v;
    }
    if (row.value["Obj"] != 0)
      throw std::runtime_error(".vgx line " + std::to_string(i + 1) + ": leafdig writes Obj 0");
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace leafdig::test
