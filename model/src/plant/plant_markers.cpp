#include "leafdig/model/plant/plant_markers.hpp"

#include <array>
#include <cstdio>
#include <utility>

#include "json_reader.hpp"
#include "json_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

using nlohmann::json;

namespace {

constexpr NameTable<LeafState, 5> kStates{{{LeafState::Alive, "alive"},
                                           {LeafState::Dead, "dead"},
                                           {LeafState::Broken, "broken"},
                                           {LeafState::Yellow, "yellow"},
                                           {LeafState::Pruned, "pruned"}}};
constexpr NameTable<LeafKind, 3> kKinds{
    {{LeafKind::Full, "full"}, {LeafKind::Quick, "quick"}, {LeafKind::None, "none"}}};

// A stem diameter by caliper: positive, at most what a stem can be.
double stemDiameter(const detail::JsonReader& reader, const json& value, const std::string& where, double scale) {
  const double d =
      reader.bounded(value, where, "diameter", scale, 0.0, kMaxThicknessMm,
                     "a stem's diameter by caliper is at most " + detail::formatNumber(kMaxThicknessMm) + " mm");
  if (!(d > 0.0)) reader.fail(where, "diameter must be more than 0 mm: measure the stem with the caliper");
  return d;
}

std::string text(const json& object, const char* key) {
  const auto it = object.find(key);
  return it != object.end() && it->is_string() ? it->get<std::string>() : std::string();
}

}  // namespace

const char* toString(LeafState state) {
  return nameIn(kStates, state);
}

LeafState leafStateFromString(const std::string& word) {
  return parseName(kStates, word, "leaf state");
}

const char* toString(LeafKind kind) {
  return nameIn(kKinds, kind);
}

LeafKind leafKindFromString(const std::string& word) {
  return parseName(kKinds, word, "leaf kind");
}

std::optional<SurveyDate> parseSurveyDate(std::string_view iso) {
  const auto digits = [&](std::size_t from, std::size_t count) -> std::optional<int> {
    int v = 0;
    for (std::size_t i = from; i < from + count; ++i) {
      if (iso[i] < '0' || iso[i] > '9') return std::nullopt;
      v = v * 10 + (iso[i] - '0');
    }
    return v;
  };
  if (iso.size() != 10 || iso[4] != '-' || iso[7] != '-') return std::nullopt;
  const auto y = digits(0, 4), m = digits(5, 2), d = digits(8, 2);
  if (!y || !m || !d || *y < 1900 || *y > 2999 || *m < 1 || *m > 12 || *d < 1) return std::nullopt;
  const bool leap = (*y % 4 == 0 && *y % 100 != 0) || *y % 400 == 0;
  constexpr std::array<int, 12> kDays{31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const int days = kDays[static_cast<std::size_t>(*m - 1)] + (*m == 2 && leap ? 1 : 0);
  if (*d > days) return std::nullopt;
  return SurveyDate{*y, *m, *d};
}

std::string toIso(const SurveyDate& date) {
  char b[16];
  std::snprintf(b, sizeof b, "%04d-%02d-%02d", date.year, date.month, date.day);
  return b;
}

std::vector<NodeLink> plantTopology(const std::vector<PlantNode>& nodes, const std::string& source) {
  std::vector<NodeLink> links;
  std::vector<bool> followed(nodes.size() + 1, false);  // node k already has a node after it on its axis
  const auto fail = [&](std::size_t i, const std::string& what) {
    throw InputError(source + ": node " + std::to_string(i + 1) + ": " + what);
  };
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const PlantNode& n = nodes[i];
    const int self = static_cast<int>(i) + 1;
    NodeLink link;
    if (n.after && n.branchesFrom)
      fail(i,
           "says both \"after\" and \"branches_from\": a node follows a node on its axis or starts a branch, "
           "not both");
    const std::optional<int> named = n.after ? n.after : n.branchesFrom;
    if (named && (*named < 1 || *named >= self))
      fail(i, std::string(n.after ? "\"after\"" : "\"branches_from\"") + " names node " + std::to_string(*named) +
                  ": it must be a node listed before it (1 to " + std::to_string(self - 1) + ")");
    if (n.branchesFrom) {
      const NodeLink& bearer = links[static_cast<std::size_t>(*n.branchesFrom - 1)];
      link = {*n.branchesFrom, '+', bearer.order + 1, self};
      if (link.order > kMaxAxisOrder)
        fail(i, "would start an axis of order " + std::to_string(link.order) + " (node " +
                    std::to_string(*n.branchesFrom) + " is on one of order " + std::to_string(bearer.order) +
                    "): a plant takes axes up to order " + std::to_string(kMaxAxisOrder));
    } else {
      const int parent = n.after ? *n.after : self - 1;
      link.parent = parent;
      if (parent > 0) {
        const NodeLink& previous = links[static_cast<std::size_t>(parent - 1)];
        link.order = previous.order;
        link.axis = previous.axis;
      }
      if (followed[static_cast<std::size_t>(parent)])
        fail(i, "follows node " + std::to_string(parent) +
                    ", which another node already follows on its axis: give it \"after\" the last node of that "
                    "axis, or \"branches_from\" for a branch");
      followed[static_cast<std::size_t>(parent)] = true;
    }
    links.push_back(link);
  }
  return links;
}

bool hasBranches(const std::vector<NodeLink>& links) {
  for (const NodeLink& l : links)
    if (l.relation == '+') return true;
  return false;
}

PlantMarkers parsePlantMarkersJson(std::string_view textIn, const std::string& source) {
  const detail::JsonReader reader(source, kPlantMarkersFormat);
  if (textIn.find_first_not_of(" \t\r\n") == std::string_view::npos)
    throw InputError(source + ": the file is empty; expected a " + std::string(kPlantMarkersFormat) + " JSON document");
  const json doc = detail::parseJsonLeniently(textIn, source);
  if (!doc.is_object()) reader.fail("top level", "expected a JSON object");
  const json& format = reader.require(doc, "format", "top level");
  if (format != kPlantMarkersFormat)
    reader.fail("format", "expected \"" + std::string(kPlantMarkersFormat) + "\", found " + format.dump() +
                              "; this is not a leafdig plant-markers file");
  const double scale = reader.unitScale(reader.require(doc, "units", "top level"));

  PlantMarkers p;
  p.plant = text(doc, "plant");
  if (const auto d = doc.find("date"); d != doc.end() && !d->is_null()) {
    if (!d->is_string() || !(p.date = parseSurveyDate(d->get<std::string>())))
      reader.fail("date",
                  "must be the survey's day as \"YYYY-MM-DD\" (for example \"2026-11-26\"), found " + d->dump());
  }
  const json& landmarks = reader.require(doc, "landmarks", "top level");
  if (!landmarks.is_array() || landmarks.size() < 3)
    reader.fail("landmarks", "must list at least three points [x, y, z] on the pot rim (or a board)");
  if (landmarks.size() > 64) reader.fail("landmarks", "at most 64 landmarks");
  for (std::size_t i = 0; i < landmarks.size(); ++i)
    p.landmarksMm.push_back(reader.point(landmarks[i], "landmark " + std::to_string(i + 1), scale));

  const json& collar = reader.require(doc, "collar", "top level");
  p.collarMm = reader.point(reader.require(collar, "point", "collar"), "collar", scale);
  p.collarDiameterMm = stemDiameter(reader, reader.require(collar, "diameter", "collar"), "collar", scale);

  const json& nodes = reader.require(doc, "nodes", "top level");
  if (!nodes.is_array() || nodes.empty())
    reader.fail("nodes", "must list the stem's nodes from the base up, at least one");
  if (nodes.size() > kMaxPlantNodes)
    reader.fail("nodes",
                std::to_string(nodes.size()) + " nodes; a plant takes at most " + std::to_string(kMaxPlantNodes));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const std::string where = "node " + std::to_string(i + 1);
    const json& n = nodes[i];
    PlantNode node;
    node.pointMm = reader.point(reader.require(n, "point", where), where + " point", scale);
    node.diameterMm = stemDiameter(reader, reader.require(n, "diameter", where), where, scale);
    for (const char* key : {"after", "branches_from"}) {
      const auto it = n.find(key);
      if (it == n.end() || it->is_null()) continue;
      if (!it->is_number_integer() || it->get<long long>() < 1 || it->get<long long>() > static_cast<long long>(i))
        reader.fail(where + " " + key, "must be the number of a node listed before it (1 to " + std::to_string(i) +
                                           "), found " + it->dump());
      (std::string_view(key) == "after" ? node.after : node.branchesFrom) = static_cast<int>(it->get<long long>());
    }
    const auto leafIt = n.find("leaf");
    if (leafIt != n.end() && !leafIt->is_null()) {
      const json& leaf = *leafIt;
      const std::string lw = where + " leaf";
      if (!leaf.is_object()) reader.fail(lw, "must be null or an object with \"kind\": full, quick or none");
      const json& kindWord = reader.require(leaf, "kind", lw);
      if (!kindWord.is_string()) reader.fail(lw + " kind", "must be full, quick or none");
      LeafKind kind = LeafKind::None;
      try {
        kind = leafKindFromString(kindWord.get<std::string>());
      } catch (const UnknownName& e) {
        reader.fail(lw + " kind", e.what());
      }
      if (const auto s = leaf.find("state"); s != leaf.end() && !s->is_null()) {
        if (!s->is_string()) reader.fail(lw + " state", "must be alive, dead, broken, yellow or pruned");
        try {
          node.state = leafStateFromString(s->get<std::string>());
        } catch (const UnknownName& e) {
          reader.fail(lw + " state", e.what());
        }
      }
      if (kind == LeafKind::Full) {
        const json& markers = reader.require(leaf, "markers", lw);
        std::string markersSource = source;
        markersSource.append(": ").append(lw).append(" markers");
        node.leaf = parseMarkersJson(markers.dump(), markersSource);
      } else if (kind == LeafKind::Quick) {
        QuickLeaf q;
        q.baseMm = reader.point(reader.require(leaf, "base", lw), lw + " base", scale);
        q.tipMm = reader.point(reader.require(leaf, "tip", lw), lw + " tip", scale);
        q.sideMm = reader.point(reader.require(leaf, "side", lw), lw + " side", scale);
        q.type = text(leaf, "type");
        node.leaf = q;
      }
    }
    p.nodes.push_back(std::move(node));
  }
  (void)plantTopology(p.nodes, source);
  return p;
}

PlantMarkers readPlantMarkersFile(const std::filesystem::path& path) {
  return parsePlantMarkersJson(detail::readInputText(path), path.string());
}

namespace {

json point(const Eigen::Vector3d& p) {
  return json::array({p.x(), p.y(), p.z()});
}

}  // namespace

std::string plantMarkersToJson(const PlantMarkers& p) {
  json doc = {{"format", kPlantMarkersFormat}, {"units", "mm"}, {"plant", p.plant}};
  if (p.date) doc["date"] = toIso(*p.date);
  json landmarks = json::array();
  for (const auto& l : p.landmarksMm) landmarks.push_back(point(l));
  doc["landmarks"] = landmarks;
  doc["collar"] = {{"point", point(p.collarMm)}, {"diameter", p.collarDiameterMm}};
  json nodes = json::array();
  for (const PlantNode& n : p.nodes) {
    json node = {{"point", point(n.pointMm)}, {"diameter", n.diameterMm}};
    if (n.after) node["after"] = *n.after;
    if (n.branchesFrom) node["branches_from"] = *n.branchesFrom;
    json leaf;
    if (const auto* full = std::get_if<MarkerSet>(&n.leaf)) {
      leaf = {{"kind", toString(LeafKind::Full)}, {"markers", json::parse(markersToJson(*full))}};
    } else if (const auto* quick = std::get_if<QuickLeaf>(&n.leaf)) {
      leaf = {{"kind", toString(LeafKind::Quick)},
              {"base", point(quick->baseMm)},
              {"tip", point(quick->tipMm)},
              {"side", point(quick->sideMm)},
              {"type", quick->type}};
    } else if (n.state != LeafState::Alive) {
      leaf = {{"kind", toString(LeafKind::None)}};
    }
    if (!leaf.is_null() && n.state != LeafState::Alive) leaf["state"] = toString(n.state);
    node["leaf"] = leaf;
    nodes.push_back(node);
  }
  doc["nodes"] = nodes;
  return detail::dumpFinite(doc, 2) + "\n";
}

}  // namespace leafdig::model
