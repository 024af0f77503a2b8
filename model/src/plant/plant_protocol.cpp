#include "leafdig/model/plant/plant_protocol.hpp"

#include <algorithm>
#include <set>

#include "json_reader.hpp"
#include "json_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

using nlohmann::json;

namespace {

constexpr std::size_t kMaxEntities = 32;
constexpr std::size_t kMaxSteps = 16;
constexpr int kMaxOrder = 3;

bool isWord(const std::string& s) {
  if (s.empty() || s.size() > 32 || s[0] < 'a' || s[0] > 'z') return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; });
}

std::string word(const detail::JsonReader& reader, const json& value, const std::string& where) {
  if (!value.is_string() || !isWord(value.get<std::string>()))
    reader.fail(where, "must be a word of 1 to 32 lower-case letters, digits or _ starting with a letter, found " +
                           value.dump().substr(0, 40));
  return value.get<std::string>();
}

std::vector<std::string> words(const detail::JsonReader& reader, const json& object, const char* key,
                               const std::string& where, std::set<std::string>& taken) {
  std::vector<std::string> out;
  const auto it = object.find(key);
  if (it == object.end() || it->is_null()) return out;
  const std::string at = where + " " + key;
  if (!it->is_array()) reader.fail(at, "must be a list of names, e.g. [\"node\"]");
  if (it->size() > kMaxSteps) reader.fail(at, "at most " + std::to_string(kMaxSteps) + " names");
  for (std::size_t i = 0; i < it->size(); ++i) {
    const std::string w = word(reader, (*it)[i], at + " " + std::to_string(i + 1));
    if (!taken.insert(w).second)
      reader.fail(at, "\"" + w + "\" is named twice in this entity; give each point and reading its own name");
    out.push_back(w);
  }
  return out;
}

ProtocolLeaf readLeaf(const detail::JsonReader& reader, const json& leaf, const std::string& where) {
  ProtocolLeaf out;
  if (!leaf.is_object()) reader.fail(where, "must be an object: {\"kinds\", \"quick_points\", \"full_every\"}");
  if (const auto k = leaf.find("kinds"); k != leaf.end() && !k->is_null()) {
    if (!k->is_array() || k->empty()) reader.fail(where + " kinds", "must list one or more of full, quick, none");
    out.kinds.clear();
    for (const json& v : *k) {
      if (!v.is_string()) reader.fail(where + " kinds", "must list words: full, quick or none");
      LeafKind kind = LeafKind::None;
      try {
        kind = leafKindFromString(v.get<std::string>());
      } catch (const UnknownName& e) {
        reader.fail(where + " kinds", e.what());
      }
      if (out.allows(kind)) reader.fail(where + " kinds", "\"" + std::string(toString(kind)) + "\" is listed twice");
      out.kinds.push_back(kind);
    }
  }
  if (const auto q = leaf.find("quick_points"); q != leaf.end() && !q->is_null()) {
    std::set<std::string> taken;
    out.quickPoints = words(reader, leaf, "quick_points", where, taken);
  }
  const bool quick = out.allows(LeafKind::Quick);
  if (quick && out.quickPoints.size() != 3)
    reader.fail(where + " quick_points",
                "a quick leaf takes exactly three points (its base, its tip and the widest point of one margin)");
  if (const auto f = leaf.find("full_every"); f != leaf.end() && !f->is_null()) {
    if (!f->is_number_integer() || f->get<long long>() < 1 || f->get<long long>() > 1000)
      reader.fail(where + " full_every", "must be a whole number from 1 (every leaf in full) to 1000");
    out.fullEvery = f->get<int>();
  }
  if (const auto l = leaf.find("largest_full"); l != leaf.end() && !l->is_null()) {
    if (!l->is_boolean()) reader.fail(where + " largest_full", "must be true or false");
    out.largestFull = l->get<bool>();
  }
  return out;
}

// "every leaf", "every 2nd", "every 3rd", "every 11th", "every 21st".
std::string everyKth(int k) {
  if (k == 1) return "every leaf";
  const int last = k % 10, lastTwo = k % 100;
  const char* suffix = lastTwo >= 11 && lastTwo <= 13 ? "th"
                       : last == 1                    ? "st"
                       : last == 2                    ? "nd"
                       : last == 3                    ? "rd"
                                                      : "th";
  return "every " + std::to_string(k) + suffix;
}

PlantProtocol makeDefault() {
  PlantProtocol p;
  p.species = "tobacco";
  ProtocolEntity internode;
  internode.name = "internode";
  internode.mtgClass = 'I';
  internode.repeat = true;
  internode.points = {"node"};
  internode.readings = {"diameter"};
  ProtocolEntity leaf;
  leaf.name = "leaf";
  leaf.mtgClass = 'L';
  leaf.parent = "internode";
  leaf.relation = '+';
  leaf.leaf = ProtocolLeaf{};
  p.entities = {internode, leaf};
  return p;
}

}  // namespace

bool ProtocolLeaf::allows(LeafKind kind) const {
  return std::find(kinds.begin(), kinds.end(), kind) != kinds.end();
}

const ProtocolEntity* PlantProtocol::find(std::string_view name) const {
  for (const ProtocolEntity& e : entities)
    if (e.name == name) return &e;
  return nullptr;
}

const PlantProtocol& defaultPlantProtocol() {
  static const PlantProtocol kDefault = makeDefault();
  return kDefault;
}

PlantProtocol parsePlantProtocolJson(std::string_view textIn, const std::string& source) {
  const detail::JsonReader reader(source, kPlantProtocolFormat);
  if (textIn.find_first_not_of(" \t\r\n") == std::string_view::npos)
    throw InputError(source + ": the file is empty; expected a " + std::string(kPlantProtocolFormat) +
                     " JSON document");
  const json doc = detail::parseJsonLeniently(textIn, source);
  if (!doc.is_object()) reader.fail("top level", "expected a JSON object");
  const json& format = reader.require(doc, "format", "top level");
  if (format != kPlantProtocolFormat)
    reader.fail("format", "expected \"" + std::string(kPlantProtocolFormat) + "\", found " +
                              format.dump().substr(0, 60) + "; this is not a leafdig plant protocol");
  PlantProtocol p;
  p.species = word(reader, reader.require(doc, "species", "top level"), "species");
  if (const auto l = doc.find("landmarks"); l != doc.end() && !l->is_null()) {
    if (!l->is_object()) reader.fail("landmarks", "must be an object {\"min\", \"max\"}");
    const auto count = [&](const char* key, int fallback) {
      const auto v = l->find(key);
      if (v == l->end() || v->is_null()) return fallback;
      if (!v->is_number_integer() || v->get<long long>() < 3 || v->get<long long>() > 64)
        reader.fail(std::string("landmarks ") + key, "must be a whole number from 3 to 64 (three fix a plane)");
      return v->get<int>();
    };
    p.minLandmarks = count("min", 3);
    p.maxLandmarks = count("max", 64);
    if (p.maxLandmarks < p.minLandmarks) reader.fail("landmarks", "max is below min");
  }
  if (const auto c = doc.find("collar"); c != doc.end() && !c->is_null()) {
    if (!c->is_object()) reader.fail("collar", "must be an object {\"diameter\": true|false}");
    if (const auto d = c->find("diameter"); d != c->end() && !d->is_null()) {
      if (!d->is_boolean()) reader.fail("collar diameter", "must be true or false");
      p.collarDiameter = d->get<bool>();
    }
  }
  const json& entities = reader.require(doc, "entities", "top level");
  if (!entities.is_array() || entities.empty())
    reader.fail("entities", "must list what is digitized after the collar, at least one entity");
  if (entities.size() > kMaxEntities) reader.fail("entities", "at most " + std::to_string(kMaxEntities) + " entities");
  for (std::size_t i = 0; i < entities.size(); ++i) {
    const json& e = entities[i];
    const std::string where = "entity " + std::to_string(i + 1);
    if (!e.is_object()) reader.fail(where, "must be an object with \"name\" and \"class\"");
    ProtocolEntity out;
    out.name = word(reader, reader.require(e, "name", where), where + " name");
    const std::string named = where + " (" + out.name + ")";
    if (p.find(out.name))
      reader.fail(named, "the name \"" + out.name + "\" is already an entity's; give each entity its own name");
    const json& cls = reader.require(e, "class", named);
    const std::string c = cls.is_string() ? cls.get<std::string>() : std::string();
    if (c.size() != 1 || c[0] < 'A' || c[0] > 'Z' || c[0] == 'P')
      reader.fail(named + " class",
                  "must be one capital letter, not P (the plant's), found " + cls.dump().substr(0, 40));
    out.mtgClass = c[0];
    for (const ProtocolEntity& other : p.entities)
      if (other.mtgClass == out.mtgClass)
        reader.fail(named + " class",
                    std::string("\"") + c + "\" is " + other.name + "'s already: one class per entity");
    if (const auto parent = e.find("parent"); parent != e.end() && !parent->is_null()) {
      out.parent = word(reader, *parent, named + " parent");
      if (!p.find(out.parent))
        reader.fail(named + " parent",
                    "\"" + out.parent + "\" is not an entity listed before this one; list what a thing hangs on first");
    }
    if (i == 0 && !out.parent.empty()) reader.fail(named + " parent", "the first entity starts the plant: no parent");
    if (i > 0 && out.parent.empty())
      reader.fail(named, "only the first entity starts the plant: give \"parent\", the entity it hangs on");
    if (const auto leaf = e.find("leaf"); leaf != e.end() && !leaf->is_null())
      out.leaf = readLeaf(reader, *leaf, named + " leaf");
    out.relation = out.leaf ? '+' : '<';
    if (const auto r = e.find("relation"); r != e.end() && !r->is_null()) {
      if (*r != "<" && *r != "+")
        reader.fail(named + " relation", "must be \"<\" (follows on the same axis) or \"+\" (branches from it)");
      out.relation = r->get<std::string>()[0];
    }
    if (out.leaf && out.relation != '+') reader.fail(named + " relation", "a leaf branches from its node: \"+\"");
    const ProtocolEntity* parent = out.parent.empty() ? nullptr : p.find(out.parent);
    if (parent && parent->leaf)
      reader.fail(named + " parent", "\"" + parent->name + "\" is a leaf: nothing hangs on a leaf");
    out.order = parent ? parent->order + (out.relation == '+' && !out.leaf ? 1 : 0) : 1;
    if (const auto o = e.find("order"); o != e.end() && !o->is_null()) {
      if (!o->is_number_integer() || o->get<long long>() != out.order)
        reader.fail(named + " order",
                    "is " + std::to_string(out.order) +
                        " by where it hangs (an axis branching with + is one order above its parent)");
    }
    if (out.order > kMaxOrder) reader.fail(named + " order", "axes up to order " + std::to_string(kMaxOrder));
    if (const auto r = e.find("repeat"); r != e.end() && !r->is_null()) {
      if (!r->is_boolean()) reader.fail(named + " repeat", "must be true or false");
      out.repeat = r->get<bool>();
    }
    std::set<std::string> taken;
    out.points = words(reader, e, "points", named, taken);
    out.readings = words(reader, e, "readings", named, taken);
    if (out.points.empty() && out.readings.empty() && !out.leaf)
      reader.fail(named, "asks for nothing: give \"points\", \"readings\" or \"leaf\"");
    p.entities.push_back(std::move(out));
  }
  return p;
}

PlantProtocol readPlantProtocolFile(const std::filesystem::path& path) {
  return parsePlantProtocolJson(detail::readInputText(path), path.string());
}

std::string plantProtocolToJson(const PlantProtocol& p) {
  json entities = json::array();
  for (const ProtocolEntity& e : p.entities) {
    json j = {{"name", e.name}, {"class", std::string(1, e.mtgClass)}};
    if (!e.parent.empty()) {
      j["parent"] = e.parent;
      j["relation"] = std::string(1, e.relation);
    }
    j["order"] = e.order;
    j["repeat"] = e.repeat;
    j["points"] = e.points;
    j["readings"] = e.readings;
    if (e.leaf) {
      json kinds = json::array();
      for (const LeafKind k : e.leaf->kinds) kinds.push_back(toString(k));
      j["leaf"] = {{"kinds", kinds},
                   {"quick_points", e.leaf->quickPoints},
                   {"full_every", e.leaf->fullEvery},
                   {"largest_full", e.leaf->largestFull}};
    }
    entities.push_back(j);
  }
  const json doc = {{"format", kPlantProtocolFormat},
                    {"species", p.species},
                    {"landmarks", {{"min", p.minLandmarks}, {"max", p.maxLandmarks}}},
                    {"collar", {{"diameter", p.collarDiameter}}},
                    {"entities", entities}};
  return detail::dumpFinite(doc, 2);
}

std::vector<std::string> describeSteps(const PlantProtocol& p) {
  std::vector<std::string> out;
  out.push_back("landmarks · " + std::to_string(p.minLandmarks) + " to " + std::to_string(p.maxLandmarks) +
                " points on the pot rim (or a board) · stylus");
  out.push_back("collar · point · stylus");
  if (p.collarDiameter) out.push_back("collar · diameter · caliper");
  for (const ProtocolEntity& e : p.entities) {
    std::string head = e.name + " (" + std::string(1, e.mtgClass);
    if (!e.parent.empty()) head += std::string(e.relation == '+' ? ", branching from " : ", after ") + e.parent;
    if (e.order > 1) head += ", axis of order " + std::to_string(e.order);
    if (e.repeat) head += ", one after another";
    head += ")";
    const auto step = [&head](std::string_view what, std::string_view device) {
      std::string s = head;
      s.append(" · ").append(what);
      if (!device.empty()) s.append(" · ").append(device);
      return s;
    };
    for (const std::string& point : e.points) out.push_back(step(point, "stylus"));
    for (const std::string& reading : e.readings) out.push_back(step(reading, "caliper"));
    if (e.leaf) {
      std::string kinds;
      for (const LeafKind k : e.leaf->kinds) {
        if (!kinds.empty()) kinds += " | ";
        if (k == LeafKind::Full) kinds += "full: the leaf protocol";
        if (k == LeafKind::Quick) {
          kinds += "quick:";
          for (std::size_t i = 0; i < e.leaf->quickPoints.size(); ++i)
            kinds.append(i ? ", " : " ").append(e.leaf->quickPoints[i]);
        }
        if (k == LeafKind::None) kinds += "none: a state";
      }
      const bool full = e.leaf->allows(LeafKind::Full);
      if (full)
        kinds += " (default: " + everyKth(e.leaf->fullEvery) + " in full" +
                 (e.leaf->largestFull && e.leaf->fullEvery > 1 ? ", and the largest" : "") + ")";
      out.push_back(step(kinds, ""));
    }
  }
  return out;
}

}  // namespace leafdig::model
