#include "leafdig/model/io/survey_export.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <sstream>
#include <vector>

#include "io/mtg_text.hpp"
#include "leafdig/model/io/csv_text.hpp"

namespace leafdig::model {

namespace {

using detail::mtgAlpha;
using detail::mtgReal;

enum Column { kDate };

constexpr std::size_t kColumns = 16;  // one per Column, the MTG's features in their order
using Values = std::array<std::string, kColumns>;

std::string ddmmyyyy(const SurveyDate& d) {
  char b[16];
  std::snprintf(b, sizeof b, "%02d/%02d/%04d", d.day, d.month, d.year);
  return b;
}

std::string optionalReal(const std::optional<double>& v) {
  return v ? mtgReal(*v) : std::string();
}

// A posed leaf's length, as surveyEntities() gives it.
std::string lengthText(const SurveyedLeaf& l) {
  return mtgReal(l.midribLengthMm.value_or(l.pose->lengthMm));
}

// The azimuth in [0, 360) after rounding too.
std::string azimuthText(const LeafPose& pose) {
  const std::string a = mtgReal(pose.azimuthDeg);
  return a == "360.000" ? mtgReal(0.0) : a;
}

// The nodes (0-based) in the MTG's order with their lines' depth: depth first along each axis
// from the collar — a node, then the branches it bears (each whole, one deeper), then the node
// after it on its axis.
std::vector<std::pair<std::size_t, int>> mtgOrder(const PlantSurvey& survey) {
  std::vector<std::pair<std::size_t, int>> out;
  const auto visit = [&](const auto& self, std::size_t first, int depth) -> void {
    for (std::optional<std::size_t> k = first; k;) {
      out.emplace_back(*k, depth);
      const int number = survey.nodes[*k].index;
      std::optional<std::size_t> next;
      for (std::size_t j = *k + 1; j < survey.nodes.size(); ++j) {
        const NodeLink& l = survey.nodes[j].link;
        if (l.parent != number) continue;
        if (l.relation == '+')
          self(self, j, depth + 1);
        else
          next = j;
      }
      k = next;
    }
  };
  if (!survey.nodes.empty()) visit(visit, 0, 0);
  return out;
}

}  // namespace

std::vector<SurveyEntity> surveyEntities(const PlantSurvey& survey) {
  std::vector<SurveyEntity> out;
  SurveyEntity collar{"I0", "", 0, 0, {}};
  collar.features = {{"XX", 0.0}, {"YY", 0.0}, {"ZZ", 0.0}, {"TopDia", survey.collarDiameterMm}};
  out.push_back(std::move(collar));
  for (const auto& [k, depth] : mtgOrder(survey)) {
    const SurveyedNode& n = survey.nodes[k];
    const std::string internode = "I" + std::to_string(n.index);
    SurveyEntity i{internode, "I" + std::to_string(n.link.parent), n.link.relation, depth, {}};
    i.features = {{"Length", n.internodeMm},
                  {"XX", n.pointMm.x()},
                  {"YY", n.pointMm.y()},
                  {"ZZ", n.pointMm.z()},
                  {"TopDia", n.diameterMm}};
    out.push_back(std::move(i));
    for (const SurveyedLeaf& l : survey.leaves) {
      if (l.node != n.index) continue;
      SurveyEntity leaf{"L" + std::to_string(n.index), internode, '+', depth + 1, {}};
      auto& f = leaf.features;
      // A posed leaf's length: along the midrib for a full leaf, base to tip for a quick one.
      if (l.pose) f.emplace_back("Length", l.midribLengthMm.value_or(l.pose->lengthMm));
      f.emplace_back("State", std::string(toString(l.state)));
      // An entity's XX YY ZZ is its top, which PlantFrame draws it to from its parent's: a
      // leaf's is its tip (from the node), its base in BaseX BaseY BaseZ.
      if (const auto& top = l.tipMm ? l.tipMm : l.baseMm) {
        f.emplace_back("XX", top->x());
        f.emplace_back("YY", top->y());
        f.emplace_back("ZZ", top->z());
      }
      if (l.pose && l.pose->widthMm) f.emplace_back("Width", *l.pose->widthMm);
      if (l.areaMm2) f.emplace_back("Area", *l.areaMm2);
      if (l.pose) {
        // The azimuth in [0, 360) after rounding too.
        const double azimuth = mtgReal(l.pose->azimuthDeg) == "360.000" ? 0.0 : l.pose->azimuthDeg;
        f.emplace_back("Azimuth", azimuth);
        f.emplace_back("Inclination", l.pose->inclinationDeg);
      }
      f.emplace_back("Kind", std::string(toString(l.kind)));
      if (l.tipMm && l.baseMm) {
        f.emplace_back("BaseX", l.baseMm->x());
        f.emplace_back("BaseY", l.baseMm->y());
        f.emplace_back("BaseZ", l.baseMm->z());
      }
      if (!l.areaShape.empty()) f.emplace_back("Shape", mtgAlpha(l.areaShape));
      out.push_back(std::move(leaf));
    }
  }
  return out;
}

std::string encodeSurveyMtg(const PlantSurvey& survey, const SurveyDate& date) {
  std::ostringstream out;
  out << "# leafdig plant survey " << mtgAlpha(survey.plant) << " of " << toIso(date) << "\n"
      << "# units: XX YY ZZ Length TopDia Width in mm, Area in mm2, Azimuth Inclination in degrees\n"
      << "# plant frame: origin at the collar, +Z the upward normal of the pot rim's landmarks, +X towards the "
         "first landmark\n"
      << "# I0 is the collar, I<k> the internode that ends at node k (XX YY ZZ the node, TopDia the stem there)\n"
      << "# L<k> the leaf of node k: XX YY ZZ its tip (PlantFrame draws it from the node to there), BaseX BaseY BaseZ "
         "its base, Azimuth counterclockwise from +X seen from above in [0, 360), Inclination of the base-to-tip chord "
         "from +Z\n"
      << "# Length of a full leaf along its midrib, of a quick leaf base to tip; Area of a full leaf its digitized "
         "blade's, of a quick leaf its drawn shape's (Shape: where that shape came from; no interval)\n";
  const std::vector<SurveyEntity> entities = surveyEntities(survey);
  int columns = 2;  // TOPO's: the deepest line's depth + 1
  bool branched = false;
  for (const SurveyEntity& e : entities) {
    columns = std::max(columns, e.depth + 1);
    branched = branched || (e.relation == '+' && e.name[0] == 'I');
  }
  if (branched)
    out << "# a branch: +I<k> branches from the internode of the node that bears it, its next internodes follow with "
           "^<; Length of +I<k> from the bearing node\n";
  // AMAP's reserved features first, in their order (Date, Length, State), then the
  // coordinates and sizes PlantFrame reads, then ours.
  static const std::vector<std::pair<const char*, const char*>> kFeatures{
      {"Date", "DD/MM/YYYY"}, {"Length", "REAL"},  {"State", "ALPHA"},      {"XX", "REAL"},
      {"YY", "REAL"},         {"ZZ", "REAL"},      {"TopDia", "REAL"},      {"Width", "REAL"},
      {"Area", "REAL"},       {"Azimuth", "REAL"}, {"Inclination", "REAL"}, {"Kind", "ALPHA"},
      {"BaseX", "REAL"},      {"BaseY", "REAL"},   {"BaseZ", "REAL"},       {"Shape", "ALPHA"}};
  detail::writeMtgHeader(out, kFeatures, branched, columns);
  const std::string day = ddmmyyyy(date);
  for (const SurveyEntity& e : entities) {
    Values v;
    v[kDate] = day;
    for (const auto& [name, value] : e.features) {
      std::size_t column = 0;
      while (column < kColumns && name != kFeatures[column].first) ++column;
      const auto* number = std::get_if<double>(&value);
      v[column] = number ? mtgReal(*number) : std::get<std::string>(value);
    }
    const std::string code = e.relation == 0 ? "/P1/" + e.name : std::string(e.relation == '<' ? "^<" : "+") + e.name;
    detail::writeMtgLine(out, e.depth, code, std::vector<std::string>(v.begin(), v.end()), columns);
  }
  return out.str();
}

std::string encodeSurveyCsv(const PlantSurvey& survey, const SurveyDate& date) {
  std::ostringstream out;
  out << "entity,class,index,parent,relation,date,x_mm,y_mm,z_mm,top_diameter_mm,length_mm,width_mm,area_mm2,"
         "area_low95_mm2,area_high95_mm2,azimuth_deg,inclination_deg,roll_deg,divergence_deg,state,kind,base_x_mm,"
         "base_y_mm,base_z_mm,area_shape\n";
  const std::string day = toIso(date);
  const auto xyz = [](const Eigen::Vector3d& p) {
    return mtgReal(p.x()) + "," + mtgReal(p.y()) + "," + mtgReal(p.z());
  };
  out << "I0,I,0,,," << day << "," << xyz(Eigen::Vector3d::Zero()) << "," << mtgReal(survey.collarDiameterMm)
      << ",,,,,,,,,,,,,,,\n";
  for (const auto& [k, depth] : mtgOrder(survey)) {
    const SurveyedNode& n = survey.nodes[k];
    const std::string entity = "I" + std::to_string(n.index);
    out << entity << ",I," << n.index << ",I" << n.link.parent << "," << n.link.relation << "," << day << ","
        << xyz(n.pointMm) << "," << mtgReal(n.diameterMm) << "," << mtgReal(n.internodeMm) << ",,,,,,,,,,,,,,\n";
    for (const SurveyedLeaf& l : survey.leaves) {
      if (l.node != n.index) continue;
      out << "L" << n.index << ",L," << n.index << "," << entity << ",+," << day << ","
          << (l.tipMm    ? xyz(*l.tipMm)
              : l.baseMm ? xyz(*l.baseMm)
                         : std::string(",,"))
          << ",,";
      if (l.pose) {
        out << lengthText(l) << "," << optionalReal(l.pose->widthMm) << "," << optionalReal(l.areaMm2) << ","
            << optionalReal(l.areaLow95Mm2) << "," << optionalReal(l.areaHigh95Mm2) << "," << azimuthText(*l.pose)
            << "," << mtgReal(l.pose->inclinationDeg) << "," << optionalReal(l.pose->rollDeg) << ","
            << optionalReal(l.divergenceDeg);
      } else {
        out << ",,,,,,,,";
      }
      out << "," << toString(l.state) << "," << toString(l.kind) << ","
          << (l.tipMm && l.baseMm ? xyz(*l.baseMm) : std::string(",,")) << "," << csvText(l.areaShape) << "\n";
    }
  }
  return out.str();
}

}  // namespace leafdig::model
