#pragma once
// Sections of a 2-D outline: where a line across it meets its edges (base_tip.cpp, leaf2d.cpp).
#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

namespace leafdig::model::detail {

// Where the polygon's edges cross the line {p : (p - origin) . axis = s}, measured along
// `across`, sorted (half-open rule: a vertex on the line counts once).
[[nodiscard]] std::vector<double> sectionCrossings(const std::vector<Eigen::Vector2d>& poly,
                                                   const Eigen::Vector2d& origin, const Eigen::Vector2d& axis,
                                                   const Eigen::Vector2d& across, double s);
// The same across the leaf frame's midrib: the x of each crossing of the line y.
[[nodiscard]] std::vector<double> crossingsAt(const std::vector<Eigen::Vector2d>& poly, double y);
// Extremes of the polygon's intersection with that line; nullopt when the line misses.
[[nodiscard]] std::optional<std::pair<double, double>> sectionExtent(const std::vector<Eigen::Vector2d>& poly,
                                                                     const Eigen::Vector2d& origin,
                                                                     const Eigen::Vector2d& axis,
                                                                     const Eigen::Vector2d& across, double s);

}  // namespace leafdig::model::detail
