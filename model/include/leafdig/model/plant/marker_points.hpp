#pragma once
// Every position a leaf's markers or a digitized plant holds, visited in one order: `f(point)`
// with a reference to each (const or not as the set is), so the same walk moves a leaf into
// place, adds a digitizer's noise, bends it through a field or reads its points out.
//   a leaf:  the tip, then row by row its seven points;
//   a plant: its landmarks, the collar, then node by node its stem point and its leaf's points
//            (a full leaf as above; a quick leaf's base, tip and side).
#include <type_traits>
#include <variant>

#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/plant/plant_markers.hpp"

namespace leafdig::model {

template <class Set, class F>
requires std::is_same_v<std::remove_const_t<Set>, MarkerSet>
void forEachPoint(Set& leaf, F&& f) {
  f(leaf.tipMm);
  for (auto& row : leaf.rows)
    for (auto& p : row.pointsMm) f(p);
}

template <class Plant, class F>
requires std::is_same_v<std::remove_const_t<Plant>, PlantMarkers>
void forEachPoint(Plant& plant, F&& f) {
  for (auto& l : plant.landmarksMm) f(l);
  f(plant.collarMm);
  for (auto& n : plant.nodes) {
    f(n.pointMm);
    if (auto* full = std::get_if<MarkerSet>(&n.leaf)) forEachPoint(*full, f);
    if (auto* quick = std::get_if<QuickLeaf>(&n.leaf)) {
      f(quick->baseMm);
      f(quick->tipMm);
      f(quick->sideMm);
    }
  }
}

}  // namespace leafdig::model
