// `leafdig plant measure`: a plant digitized in place (leafdig.plant-markers/1) measured in its
// own frame — nodes, internodes, stem diameters, each leaf's angles and size, divergences —
// and, with --mtg, written as an MTG in the AMAP conventions.
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/survey_export.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/model/plant/plant_survey.hpp"
#include "leafdig/model/plant/surveyed_plant.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"
#include "plant/plant_cmd.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

namespace {

struct MeasureOptions {
  std::string input;
  bool json = false;
  std::string mtg;   // where to write the MTG, if anywhere
  std::string csv;   // and the CSV
  std::string date;  // YYYY-MM-DD, over the file's
};

// The survey's day: --date, else the file's "date", else today (UTC).
m::SurveyDate surveyDay(const MeasureOptions& o, const m::PlantSurvey& survey) {
  if (!o.date.empty()) {
    if (const auto d = m::parseSurveyDate(o.date)) return *d;
    throw m::InputError("--date \"" + o.date +
                        "\" is not a day: give the survey's day as YYYY-MM-DD, for example 2026-11-26");
  }
  if (survey.date) return *survey.date;
  const std::chrono::year_month_day today{std::chrono::floor<std::chrono::days>(std::chrono::system_clock::now())};
  return {static_cast<int>(today.year()), static_cast<int>(static_cast<unsigned>(today.month())),
          static_cast<int>(static_cast<unsigned>(today.day()))};
}

std::string fixed(double v, int digits) {
  if (std::abs(v) < 0.5 * std::pow(10.0, -digits)) v = 0.0;  // no "-0.0"
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << v;
  return out.str();
}

int runMeasure(const MeasureOptions& o) {
  const m::PlantMarkers markers = m::readPlantMarkersFile(o.input);
  m::PlantSurvey survey = m::surveyPlant(markers);
  // A quick leaf's area is the sample shape's as the plant's model draws it from this file alone.
  m::addDrawnAreas(survey, {}, m::LibraryLeaf{m::kSampleShapeSource, m::sampleLeafShape()});
  if (!o.mtg.empty() || !o.csv.empty() || !o.date.empty()) survey.date = surveyDay(o, survey);
  if (!o.mtg.empty()) m::writeFileAtomically(o.mtg, m::encodeSurveyMtg(survey, *survey.date));
  if (!o.csv.empty()) m::writeFileAtomically(o.csv, m::encodeSurveyCsv(survey, *survey.date));
  if (o.json) {
    std::cout << m::plantSurveyToJson(survey) << "\n";
  } else {
    printSurvey(survey, o.input);
    if (!o.mtg.empty()) std::cout << "wrote " << o.mtg << " (MTG, survey of " << m::toIso(*survey.date) << ")\n";
    if (!o.csv.empty()) std::cout << "wrote " << o.csv << " (CSV, one row per entity)\n";
  }
  return 0;
}

}  // namespace

void printSurvey(const m::PlantSurvey& s, const std::string& label) {
  std::cout << terminalText(label) << ": plant " << (s.plant.empty() ? "(no id)" : terminalText(s.plant)) << ", "
            << s.nodes.size() << " node(s), " << s.leaves.size() << " leaf record(s); landmarks flat within "
            << fixed(s.frame.flatnessMm, 2) << " mm RMS\n";
  std::cout << "  collar: stem " << fixed(s.collarDiameterMm, 1) << " mm\n";
  for (const m::SurveyedNode& n : s.nodes) {
    std::cout << "  node " << n.index;
    // Where a node of a branched plant hangs, when not on the node before it on the main stem.
    if (n.link.relation == '+')
      std::cout << " (branch of order " << n.link.order << " from node " << n.link.parent << ")";
    else if (n.link.order > 1 || n.link.parent != n.index - 1)
      std::cout << " (after node " << n.link.parent << (n.link.order > 1 ? ", on a branch" : ", on the main stem")
                << ")";
    std::cout << ": height " << fixed(n.heightMm, 1) << " mm, internode " << fixed(n.internodeMm, 1) << " mm, stem "
              << fixed(n.diameterMm, 1) << " mm\n";
  }
  for (const m::SurveyedLeaf& l : s.leaves) {
    std::cout << "  leaf at node " << l.node << " (" << m::toString(l.kind);
    if (l.state != m::LeafState::Alive) std::cout << ", " << m::toString(l.state);
    std::cout << ")";
    if (l.pose) {
      std::cout << ": azimuth " << fixed(l.pose->azimuthDeg, 1) << "°, inclination " << fixed(l.pose->inclinationDeg, 1)
                << "°, chord " << fixed(l.pose->lengthMm, 1) << " mm";
      if (l.pose->widthMm) std::cout << ", width " << fixed(*l.pose->widthMm, 1) << " mm";
      if (l.pose->rollDeg) std::cout << ", roll " << fixed(*l.pose->rollDeg, 1) << "°";
    }
    if (l.areaMm2) {
      std::cout << ", area " << fixed(*l.areaMm2, 0) << " mm^2";
      if (l.areaLow95Mm2 && l.areaHigh95Mm2)
        std::cout << " (95 % " << fixed(*l.areaLow95Mm2, 0) << " – " << fixed(*l.areaHigh95Mm2, 0) << ")";
    }
    if (l.divergenceDeg) std::cout << ", divergence " << fixed(*l.divergenceDeg, 1) << "°";
    std::cout << "\n";
  }
}

void addPlantMeasureCommand(CLI::App& plant, CommandTable& table) {
  auto o = std::make_shared<MeasureOptions>();
  CLI::App* measure =
      plant.add_subcommand("measure", "Measure a plant digitized in place (leafdig.plant-markers/1) in its own frame");
  measure->add_option("input", o->input, "Plant markers file (leafdig.plant-markers/1 JSON)")->required();
  measure->add_flag("--json", o->json, "Print nodes, leaves, angles and divergences as one JSON object");
  measure->add_option("--mtg", o->mtg,
                      "Also write the plant as an MTG (AMAP names: XX YY ZZ TopDia, L with Length ...)");
  measure->add_option("--csv", o->csv, "Also write the MTG's entities as a CSV, one row each");
  measure->add_option("--date", o->date,
                      "The survey's day, YYYY-MM-DD (default: the file's \"date\", else today); the MTG's Date");
  table.add(measure, [o] { return runMeasure(*o); });
}

}  // namespace leafdig::cli
