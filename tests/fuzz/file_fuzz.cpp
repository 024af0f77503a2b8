// libFuzzer targets for the files a user hands us (issue 26), one per kind, chosen at compile
// time (LEAFDIG_FUZZ_FILE): markers, plant plans, plants digitized in place, plant protocols, outlines (JSON and CSV)
// scans' headers, archives' MTG files and HydroShoot's digitizing tables. Each input is read as that file: it is either
// refused with InputError or read into values within the bounds of limits.hpp; anything else (a crash, another
// exception, a number out of bounds, a hang past libFuzzer's timeout) is a finding.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "leafdig/model/archive/hydroshoot_table.hpp"
#include "leafdig/model/archive/mtg_archive.hpp"
#include "leafdig/model/archive/plant_import.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/field/correction.hpp"
#include "leafdig/model/field/jig.hpp"
#include "leafdig/model/image_header.hpp"
#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/leaf2d/leaf2d.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/model/plant/plant_protocol.hpp"

namespace m = leafdig::model;

namespace {

void require(bool ok) {
  if (!ok) std::abort();
}

void checkPoint(const Eigen::Vector3d& p) {
  require(p.allFinite() && p.cwiseAbs().maxCoeff() <= m::kMaxCoordinateMm);
}

void markers(const std::string& text) {
  const m::MarkerSet set = m::parseMarkersJson(text, "fuzz");
  require(!set.rows.empty() && set.rows.size() <= m::kMaxRows);
  checkPoint(set.tipMm);
  for (const auto& row : set.rows)
    for (const auto& p : row.pointsMm) checkPoint(p);
  m::validateMarkerGeometry(set);
  const m::LeafThickness t = m::applyThicknessRule(set);
  for (const auto& row : t.rows) {
    require(row.midribMm > 0 && row.midribMm <= m::kMaxThicknessMm);
    for (double v : row.lateralMm) require(std::isfinite(v) && v <= m::kMaxThicknessMm);
  }
}

// A jig it takes has 4 to 1000 points with unique ids; fitted to itself it leaves nothing over.
void jig(const std::string& text) {
  const m::Jig j = m::parseJig(text, "fuzz");
  require(j.points.size() >= 4 && j.points.size() <= 1000);
  std::vector<Eigen::Vector3d> at;
  for (const auto& p : j.points) {
    checkPoint(p.pointMm);
    at.push_back(p.pointMm);
  }
  const m::JigFit fit = m::fitJig(j, at);
  require(std::isfinite(fit.rmsMm) && fit.rmsMm < 1e-6 * (1 + m::kMaxCoordinateMm));
}

// A field correction it takes (as a stored check holds it) moves any point by a finite amount,
// and writes back to what reads the same.
void correction(const std::string& text) {
  const m::FieldCorrection c = m::parseCorrection(text, "fuzz");
  require(c.degree >= 0 && c.degree <= m::kMaxCorrectionDegree);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(5000, -5000, 5000)})
    require(c.apply(p).allFinite());
  const m::FieldCorrection back = m::parseCorrection(m::encodeCorrection(c), "again");
  require(back.degree == c.degree && back.coefficients == c.coefficients);
}

void plan(const std::string& text) {
  const m::PlantPlan p = m::parsePlantPlan(text, "fuzz", "/nonexistent");
  require(std::isfinite(p.stem.heightMm) && p.stem.heightMm > 0 && p.stem.heightMm <= m::kMaxCoordinateMm);
  require(!p.leaves.empty());
  for (const auto& l : p.leaves) require(l.insertionHeightMm >= 0 && l.insertionHeightMm <= p.stem.heightMm);
}

void plantMarkers(const std::string& text) {
  const m::PlantMarkers p = m::parsePlantMarkersJson(text, "fuzz");
  require(p.landmarksMm.size() >= 3 && !p.nodes.empty() && p.nodes.size() <= m::kMaxPlantNodes);
  for (const auto& l : p.landmarksMm) checkPoint(l);
  checkPoint(p.collarMm);
  require(p.collarDiameterMm > 0 && p.collarDiameterMm <= m::kMaxThicknessMm);
  for (const auto& n : p.nodes) {
    checkPoint(n.pointMm);
    require(n.diameterMm > 0 && n.diameterMm <= m::kMaxThicknessMm);
    if (const auto* q = std::get_if<m::QuickLeaf>(&n.leaf)) {
      checkPoint(q->baseMm);
      checkPoint(q->tipMm);
      checkPoint(q->sideMm);
    }
    if (const auto* full = std::get_if<m::MarkerSet>(&n.leaf)) require(!full->rows.empty());
  }
  // What it writes reads back to the same text.
  const std::string written = m::plantMarkersToJson(p);
  require(m::plantMarkersToJson(m::parsePlantMarkersJson(written, "written")) == written);
}

void plantProtocol(const std::string& text) {
  const m::PlantProtocol p = m::parsePlantProtocolJson(text, "fuzz");
  require(!p.entities.empty() && p.minLandmarks >= 3 && p.maxLandmarks >= p.minLandmarks);
  for (std::size_t i = 0; i < p.entities.size(); ++i) {
    const auto& e = p.entities[i];
    require(e.mtgClass >= 'A' && e.mtgClass <= 'Z' && e.mtgClass != 'P');
    require(i == 0 ? e.parent.empty() : p.find(e.parent) != nullptr);
    require(!e.points.empty() || !e.readings.empty() || e.leaf.has_value());
  }
  require(!m::describeSteps(p).empty());
  // What it writes reads back to the same text.
  const std::string written = m::plantProtocolToJson(p);
  require(m::plantProtocolToJson(m::parsePlantProtocolJson(written, "written")) == written);
}

void outline(const std::string& text, bool json) {
  const m::Outline2d o = json ? m::parseOutlineJson(text, "fuzz") : m::parseOutlineCsv(text, "fuzz");
  require(o.pointsMm.size() >= 8);
  for (const auto& p : o.pointsMm) require(p.allFinite() && p.cwiseAbs().maxCoeff() <= m::kMaxCoordinateMm);
  require(m::polygonArea(o.pointsMm) > 0);
}

// An archive's MTG: read into a tree whose every link points back (a complex one scale up, a
// parent at the same scale, both made before), then drawn; refused in words otherwise.
// An MTG file (hydroshoot false) or a HydroShoot digitizing table: either is a tree whose
// complexes and parents come before their vertices, on the scales they must be on.
void mtgArchive(const std::string& text, bool hydroshoot) {
  const m::MtgArchive a = hydroshoot ? m::parseHydroShootTable(text, "fuzz") : m::parseMtgArchive(text, "fuzz");
  require(!a.vertices.empty() && a.vertices[0].scale == 0 && a.vertices.size() <= m::kMaxMtgVertices);
  for (std::size_t v = 1; v < a.vertices.size(); ++v) {
    const m::MtgVertex& x = a.vertices[v];
    require(x.complex >= 0 && static_cast<std::size_t>(x.complex) < v);
    require(x.scale == a.vertices[static_cast<std::size_t>(x.complex)].scale + 1);
    require(x.parent < static_cast<int>(v));
    if (x.parent >= 0) require(a.vertices[static_cast<std::size_t>(x.parent)].scale == x.scale);
    require(x.cells.size() == a.features.size());
  }
  m::ArchiveImportOptions o;
  o.mmPerUnit = 1;
  const m::ImportedPlant p = m::importMtgPlant(a, o);
  std::size_t drawn = 0;
  for (const m::ImportedAxis& axis : p.axes) {
    require(axis.balls.size() == axis.vertices.size() && axis.order >= 1);
    drawn += axis.vertices.size();
  }
  require(drawn == p.points && p.points > 0);
}

void imageHeader(const std::string& bytes) {
  std::istringstream in(bytes);
  const auto h = m::readImageHeader(in);
  if (h) require(!h->format.empty());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string kind = LEAFDIG_FUZZ_FILE;
  try {
    if (kind == "markers") markers(text);
    if (kind == "plan") plan(text);
    if (kind == "plant_markers") plantMarkers(text);
    if (kind == "plant_protocol") plantProtocol(text);
    if (kind == "outline_json") outline(text, true);
    if (kind == "outline_csv") outline(text, false);
    if (kind == "image_header") imageHeader(text);
    if (kind == "jig") jig(text);
    if (kind == "correction") correction(text);
    if (kind == "mtg_archive") mtgArchive(text, false);
    if (kind == "hydroshoot_table") mtgArchive(text, true);
  } catch (const m::InputError&) {
    // refused in words: what a bad file should get
  }
  return 0;
}
