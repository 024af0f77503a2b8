#pragma once
// A plant digitized in place as an MTG coding file in the AMAP conventions (docs/plants.md,
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

}  // namespace leafdig::model
