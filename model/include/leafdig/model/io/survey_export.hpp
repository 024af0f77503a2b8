#pragma once
// A plant digitized in place as files: an MTG coding file in the AMAP conventions (docs/plants.md,
// "The survey's MTG") that OpenAlea's reader and PlantFrame use: the stem as internodes
// `I<k>` ending at node k (`XX YY ZZ` the digitized node, `TopDia` the stem diameter there,
// `Length` the internode), `I0` the collar; each leaf `+L<k>` from its node's internode with
// `XX YY ZZ` (its base), `Length`, `Width`, `Area`, `Azimuth`, `Inclination`, `State` and
// its `Kind`; every entity carries the survey's `Date`. Lengths in mm, areas in mm², angles
// in degrees, in the plant frame; the header says so.
#include <string>

#include "leafdig/model/plant/plant_survey.hpp"

namespace leafdig::model {

// The survey as MTG text, dated `date` (the reserved `Date` feature, DD/MM/YYYY).
[[nodiscard]] std::string encodeSurveyMtg(const PlantSurvey& survey, const SurveyDate& date);

// The same entities as a CSV, one row each in the MTG's order, for a spreadsheet: entity
// (I0, I1, L2, …), class, index, parent entity, relation, date (ISO), x_mm, y_mm, z_mm,
// top_diameter_mm, length_mm, width_mm, area_mm2, area_low95_mm2, area_high95_mm2,
// azimuth_deg, inclination_deg, roll_deg, divergence_deg, state, kind; empty where a value
// does not apply. Numbers in fixed notation, 3 decimals.
[[nodiscard]] std::string encodeSurveyCsv(const PlantSurvey& survey, const SurveyDate& date);

}  // namespace leafdig::model
