#include "leafdig/model/io/scan_json.hpp"

#include <nlohmann/json.hpp>

namespace leafdig::model {

std::string scanToJson(const LeafScan& s, const std::string& file, double dpi) {
  nlohmann::json j = {{"file", file},
                      {"dpi", dpi},
                      {"area_mm2", s.areaMm2},
                      {"filled_area_mm2", s.filledAreaMm2},
                      {"holes", s.holes},
                      {"holes_area_mm2", s.holesAreaMm2},
                      {"petiole", s.petioleFound},
                      {"petiole_area_mm2", s.petioleAreaMm2},
                      {"other_objects", s.otherObjects},
                      {"touches_border", s.touchesBorder},
                      {"dark_background", s.darkBackground},
                      {"width_px", s.widthPx},
                      {"height_px", s.heightPx},
                      {"threshold", s.threshold},
                      {"pixel_mm", s.pixelMm},
                      {"outline_points", s.outline.pointsMm.size()}};
  j["base_mm"] = s.outline.baseMm ? nlohmann::json{s.outline.baseMm->x(), s.outline.baseMm->y()} : nlohmann::json();
  return j.dump();
}

}  // namespace leafdig::model
