// `_leafdig`: the C++ core for Python (docs/python.md). The one translation unit that sees
// pybind11; the package `leafdig` (python/leafdig/__init__.py) wraps it in the names modellers
// use. Every heavy call (reading, building, meshing, metrics, export, opening a store) runs with
// the GIL released on objects no other Python thread can reach, so two threads build two leaves
// at once. Arrays are made once per call from the C++ meshes (organs are stored per organ in
// C++; the flat N×3 / M×3 arrays a modeller wants are a concatenation, so they are copies,
// made once and cached by the Python object).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "leafdig/acquisition/field/field_check.hpp"
#include "leafdig/acquisition/field/tip_calibration.hpp"
#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/leaf_export.hpp"
#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/history.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/leaf_build.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/plant/plant_survey.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"
#include "leafdig/version.hpp"
#include "module_core.hpp"

namespace py = pybind11;
namespace m = leafdig::model;
namespace acq = leafdig::acquisition;
namespace db = leafdig::db;
namespace core = leafdig::python;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

py::array_t<double> vec3(const Eigen::Vector3d& v) {
  py::array_t<double> a(3);
  auto r = a.mutable_unchecked<1>();
  for (py::ssize_t k = 0; k < 3; ++k) r(k) = v[k];
  return a;
}

// ---- markers ----------------------------------------------------------------------------

struct Markers {
  m::MarkerSet set;
};

py::array_t<double> rowsArray(const m::MarkerSet& s) {
  py::array_t<double> a({static_cast<py::ssize_t>(s.rows.size()), py::ssize_t{7}, py::ssize_t{3}});
  auto r = a.mutable_unchecked<3>();
  for (std::size_t i = 0; i < s.rows.size(); ++i)
    for (std::size_t j = 0; j < 7; ++j)
      for (std::size_t k = 0; k < 3; ++k)
        r(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j), static_cast<py::ssize_t>(k)) =
            s.rows[i].pointsMm[j][static_cast<Eigen::Index>(k)];
  return a;
}

py::array_t<double> perRow(const m::MarkerSet& s, std::optional<double> m::MarkerRow::*field) {
  py::array_t<double> a(static_cast<py::ssize_t>(s.rows.size()));
  auto r = a.mutable_unchecked<1>();
  for (std::size_t i = 0; i < s.rows.size(); ++i) r(static_cast<py::ssize_t>(i)) = (s.rows[i].*field).value_or(kNaN);
  return a;
}

py::array_t<double> measuredPoints(const m::MarkerSet& s) {
  py::array_t<double> a({static_cast<py::ssize_t>(s.rows.size()), py::ssize_t{7}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < s.rows.size(); ++i)
    for (std::size_t j = 0; j < 7; ++j)
      r(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = s.rows[i].measuredThicknessMm[j].value_or(kNaN);
  return a;
}

// The thickness rule's result: every marker's diameter (N×7) and the midrib's (N).
py::tuple ruleThickness(const m::MarkerSet& s) {
  const m::LeafThickness t = m::applyThicknessRule(s);
  py::array_t<double> lateral({static_cast<py::ssize_t>(t.rows.size()), py::ssize_t{7}});
  py::array_t<double> midrib(static_cast<py::ssize_t>(t.rows.size()));
  auto l = lateral.mutable_unchecked<2>();
  auto md = midrib.mutable_unchecked<1>();
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    for (std::size_t j = 0; j < 7; ++j)
      l(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = t.rows[i].lateralMm[j];
    md(static_cast<py::ssize_t>(i)) = t.rows[i].midribMm;
  }
  return py::make_tuple(lateral, midrib, t.tipMm, std::string(m::toString(t.mode)));
}

Markers readMarkers(const std::string& path) {
  py::gil_scoped_release free;
  return {m::readMarkersFile(path)};
}

Markers parseMarkers(const std::string& text, const std::string& source) {
  py::gil_scoped_release free;
  return {m::parseMarkersJson(text, source)};
}

// ---- leaves -----------------------------------------------------------------------------

struct Mesh {
  m::LeafMesh mesh;
};

// model build's model, mesh and metrics (model/io/leaf_build.hpp), and where the markers came from.
struct Leaf : m::BuiltLeaf {
  std::string source;  // the markers file as given (the simulation formats name it), else the leaf's id
};

// `model build`'s path (ui/cli/model/model_build.cpp), step for step: the same model, mesh and metrics.
Leaf buildLeaf(const m::MarkerSet& markers, const std::string& source, const std::string& blade,
               const std::string& resolution, const std::string& method, std::optional<double> maxError,
               const std::string& frame, const Eigen::Vector3d& light) {
  const m::MeshOptions options = core::meshOptions(resolution, method, maxError);
  const m::BladeKind kind = m::bladeKindFromString(blade);
  py::gil_scoped_release free;
  Leaf out;
  static_cast<m::BuiltLeaf&>(out) = m::buildLeafAsModelBuild(markers, kind, frame, options, light, 5.0);
  out.source = source.empty() ? markers.leaf.id : source;
  return out;
}

py::dict meshArrays(const m::LeafMesh& mesh) {
  std::size_t nv = 0, nt = 0;
  for (const m::Organ& o : mesh.organs) {
    nv += o.mesh.positions.size();
    nt += o.mesh.triangles.size();
  }
  py::array_t<double> vertices({static_cast<py::ssize_t>(nv), py::ssize_t{3}});
  py::array_t<double> normals({static_cast<py::ssize_t>(nv), py::ssize_t{3}});
  py::array_t<std::uint32_t> faces({static_cast<py::ssize_t>(nt), py::ssize_t{3}});
  py::array_t<std::int32_t> organs(static_cast<py::ssize_t>(nt));
  py::array_t<std::int32_t> ranks(static_cast<py::ssize_t>(mesh.organs.size()));
  py::list names;
  auto v = vertices.mutable_unchecked<2>();
  auto n = normals.mutable_unchecked<2>();
  auto f = faces.mutable_unchecked<2>();
  auto g = organs.mutable_unchecked<1>();
  auto rk = ranks.mutable_unchecked<1>();
  py::ssize_t vi = 0, ti = 0;
  for (std::size_t k = 0; k < mesh.organs.size(); ++k) {
    const m::Organ& o = mesh.organs[k];
    names.append(o.name);
    rk(static_cast<py::ssize_t>(k)) = o.leafRank;
    const auto base = static_cast<std::uint32_t>(vi);
    for (std::size_t i = 0; i < o.mesh.positions.size(); ++i, ++vi)
      for (py::ssize_t c = 0; c < 3; ++c) {
        v(vi, c) = o.mesh.positions[i][c];
        n(vi, c) = i < o.mesh.normals.size() ? o.mesh.normals[i][c] : kNaN;
      }
    for (const auto& t : o.mesh.triangles) {
      for (py::ssize_t c = 0; c < 3; ++c) f(ti, c) = base + t[static_cast<std::size_t>(c)];
      g(ti) = static_cast<std::int32_t>(k);
      ++ti;
    }
  }
  py::dict d;
  d["vertices"] = vertices;
  d["normals"] = normals;
  d["faces"] = faces;
  d["organs"] = organs;
  d["organ_names"] = names;
  d["organ_ranks"] = ranks;
  return d;
}

std::vector<std::string> exportLeaf(const Leaf& leaf, const std::string& path, const Eigen::Vector3d& light) {
  py::gil_scoped_release free;
  return core::exportLeaf(leaf, leaf.source, path, light);
}

// ---- plants -----------------------------------------------------------------------------

using Plant = core::PlantModel;

std::vector<Plant> buildPlants(const std::string& planText, const std::string& source, const std::string& baseDir,
                               const std::vector<std::optional<double>>& times, const std::string& resolution,
                               const Eigen::Vector3d& light) {
  py::gil_scoped_release free;
  return core::buildPlants(planText, source, baseDir, times, resolution, light);
}

py::list plantLeaves(const Plant& p) {
  py::list leaves;
  for (std::size_t i = 0; i < p.plant.leaves.size(); ++i) {
    const m::PlacedLeaf& l = p.plant.leaves[i];
    py::dict d;
    d["rank"] = l.rank;
    d["source"] = l.source;
    d["insertion_height_mm"] = l.insertionHeightMm;
    d["azimuth_deg"] = l.azimuthDeg;
    d["inclination_deg"] = l.inclinationDeg;
    d["scale"] = l.scale;
    d["bend_deg"] = l.bendDeg;
    d["length_mm"] = l.lengthMm;
    d["width_mm"] = l.widthMm;
    d["area_mm2"] = p.metrics.leaves[i].areaMm2;
    d["silhouette_mm2"] = p.metrics.leaves[i].silhouetteMm2;
    d["star"] = p.metrics.leaves[i].star;
    leaves.append(d);
  }
  return leaves;
}

std::string encodeOne(const Plant& p, const std::string& extension) {
  py::gil_scoped_release free;
  return core::encodeOne(p, extension);
}

// CARIBU's scene as CaribuScene takes it: {label: [((x,y,z),(x,y,z),(x,y,z)), …]} with the
// labels of our `.can` file (optical species 1, plant 1, leaf rank, organ index), in metres.
py::dict caribuScene(const Plant& p) {
  std::string text;
  {
    py::gil_scoped_release free;
    text = m::encodeCan(p.mesh, m::CanUnit::Metre).text;
  }
  py::dict scene;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = text.find('\n', at);
    const std::string line = text.substr(at, end == std::string::npos ? std::string::npos : end - at);
    at = end == std::string::npos ? text.size() : end + 1;
    if (line.rfind("p ", 0) != 0) continue;
    std::istringstream in(line);
    std::string p1, label;
    int one = 0, three = 0;
    in >> p1 >> one >> label >> three;
    double c[9];
    for (double& x : c) in >> x;
    const py::int_ key(std::stoll(label));
    if (!scene.contains(key)) scene[key] = py::list();
    py::list triangles = scene[key];
    triangles.append(py::make_tuple(py::make_tuple(c[0], c[1], c[2]), py::make_tuple(c[3], c[4], c[5]),
                                    py::make_tuple(c[6], c[7], c[8])));
  }
  return scene;
}

// ---- stores -----------------------------------------------------------------------------

struct Store {
  std::unique_ptr<db::EventStore> store;
  std::string where;
};

Store openStore(const std::string& pathOrUrl, bool writable) {
  if (!db::isServerUrl(pathOrUrl) && !std::filesystem::exists(pathOrUrl))
    throw db::StoreError(db::StoreErrorKind::Input, "no station file at " + pathOrUrl,
                         "give the path of a station's file (leafdig capture writes one) or postgresql://…");
  py::gil_scoped_release free;
  return {db::openEventStore(pathOrUrl, !writable), db::redactUrl(pathOrUrl)};
}

py::list sessions(const Store& s) {
  std::vector<db::SessionInfo> all;
  {
    py::gil_scoped_release free;
    all = s.store->sessions();
  }
  py::list out;
  for (const db::SessionInfo& i : all) {
    py::dict d;
    d["id"] = i.id;
    d["kind"] = i.kind;
    d["project"] = i.project;
    d["plant"] = i.plant;
    d["leaf"] = i.leafPosition;
    d["type"] = i.leafType;
    d["status"] = i.status;
    d["operator"] = i.operatorName;
    d["station"] = i.station;
    d["station_session_id"] = i.stationSessionId;
    d["created"] = i.createdUtc;
    d["events"] = i.headSeq;
    d["measured_area_mm2"] = i.measuredAreaMm2 ? py::cast(*i.measuredAreaMm2) : py::none();
    out.append(d);
  }
  return out;
}

// A leaf session's markers, as `sessions export --format markers` writes them (verified first);
// with `node` > 0, a plant session's full leaf at that node, as `sessions export --node` does.
Markers sessionMarkers(const Store& s, std::int64_t id, int node) {
  py::gil_scoped_release free;
  core::requireVerified(*s.store, id, ": its markers are not given");
  try {
    if (node > 0) return {acq::plantLeafMarkers(*s.store, id, node)};
  } catch (const std::invalid_argument& e) {
    throw m::InputError(e.what());
  }
  return {acq::sessionMarkers(acq::openForReview(*s.store, id))};
}

py::list sessionEvents(const Store& s, std::int64_t id) {
  std::vector<db::Event> events;
  {
    py::gil_scoped_release free;
    core::requireVerified(*s.store, id, "");
    events = s.store->events(id);
  }
  py::list out;
  for (const db::Event& e : events) {
    py::dict d;
    d["seq"] = e.seq;
    d["utc"] = e.utc;
    d["mono_ns"] = e.monoNs;
    d["kind"] = e.kind;
    d["payload"] = e.payloadJson;
    d["raw"] = e.raw;
    d["hash"] = e.hash;
    out.append(d);
  }
  return out;
}

// A captured plant (a plant session) as a model: the survey's plant with its quick leaves shaped
// from this store's organ library, meshed at the export resolution — the model `sessions export`
// writes as GLB, CARIBU and plant-model JSON.
Plant capturedPlant(const Store& s, std::int64_t id, const Eigen::Vector3d& light) {
  py::gil_scoped_release free;
  return core::capturedPlant(*s.store, id, light);
}

std::string plantSurveyJson(const Store& s, std::int64_t id) {
  py::gil_scoped_release free;
  return m::plantSurveyToJson(acq::capturedSurvey(*s.store, id).survey);
}

}  // namespace

PYBIND11_MODULE(_leafdig, mod) {
  mod.doc() = "leafdig's C++ core (the package `leafdig` wraps it: docs/python.md)";
  mod.attr("__version__") = leafdig::kVersion;

  // Errors carry the CLI's words: bad input is a ValueError, a store's refusal its own.
  static py::exception<m::InputError> inputError(mod, "InputError", PyExc_ValueError);
  static py::exception<db::StoreError> storeError(mod, "StoreError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const m::IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const m::InputError& e) {
      inputError(e.what());
    } catch (const db::StoreError& e) {
      storeError((std::string(e.what()) + (e.remedy().empty() ? "" : ": " + e.remedy())).c_str());
    } catch (const acq::SessionError& e) {
      storeError(e.what());
    } catch (const std::invalid_argument& e) {  // an unknown word, a value out of range: bad input
      inputError(e.what());
    }
  });

  py::class_<Markers>(mod, "Markers", "A leaf's markers (leafdig.markers/1), in mm")
      .def_property_readonly("tip", [](const Markers& s) { return vec3(s.set.tipMm); })
      .def_property_readonly(
          "rows", [](const Markers& s) { return rowsArray(s.set); }, "N×7×3, tip row first")
      .def_property_readonly("midrib_thickness",
                             [](const Markers& s) { return perRow(s.set, &m::MarkerRow::midribThicknessMm); })
      .def_property_readonly("vein_origin_thickness",
                             [](const Markers& s) { return perRow(s.set, &m::MarkerRow::veinOriginThicknessMm); })
      .def_property_readonly("row_edge_thickness",
                             [](const Markers& s) { return perRow(s.set, &m::MarkerRow::edgeThicknessMm); })
      .def_property_readonly("point_thickness", [](const Markers& s) { return measuredPoints(s.set); })
      .def_property_readonly(
          "edge_thickness",
          [](const Markers& s) { return s.set.edgeThicknessMm ? py::cast(*s.set.edgeThicknessMm) : py::none(); })
      .def("rule_thickness", [](const Markers& s) { return ruleThickness(s.set); })
      .def_property_readonly("id", [](const Markers& s) { return s.set.leaf.id; })
      .def_property_readonly("plant", [](const Markers& s) { return s.set.leaf.plant; })
      .def_property_readonly(
          "position",
          [](const Markers& s) { return s.set.leaf.position ? py::cast(*s.set.leaf.position) : py::none(); })
      .def_property_readonly("type", [](const Markers& s) { return s.set.leaf.type; })
      .def_property_readonly("measured_area_mm2",
                             [](const Markers& s) {
                               return s.set.leaf.measuredAreaMm2 ? py::cast(*s.set.leaf.measuredAreaMm2) : py::none();
                             })
      .def("to_json", [](const Markers& s) { return m::markersToJson(s.set); });
  mod.def("read_markers", &readMarkers, py::arg("path"));
  // A file the package reads itself (a plan): through the same checks as every reader (a
  // regular file, not a device or a FIFO, within leafdig's size bound), as bytes.
  mod.def(
      "read_file", [](const std::string& path) { return py::bytes(m::readFile(path)); }, py::arg("path"));
  mod.def("parse_markers", &parseMarkers, py::arg("text"), py::arg("source") = "markers");

  py::class_<Leaf>(mod, "Leaf")
      .def("metrics_json", [](const Leaf& l) { return m::metricsToJson(l.metrics); })
      .def("model_json", [](const Leaf& l) { return m::modelToJson(l.model, l.frame, l.metrics); })
      .def("mesh", [](const Leaf& l) { return meshArrays(l.mesh); })
      .def_property_readonly("frame", [](const Leaf& l) { return l.frame; })
      .def_property_readonly("markers", [](const Leaf& l) { return Markers{l.model.markers}; })
      .def("vein_names",
           [](const Leaf& l) {
             std::vector<std::string> n;
             for (const auto& v : l.model.veins) n.push_back(v.name);
             return n;
           })
      .def(
          "vein",
          [](const Leaf& l, std::size_t i, const std::vector<double>& ts) {
            if (i >= l.model.veins.size()) throw py::index_error("no vein " + std::to_string(i));
            py::array_t<double> a({static_cast<py::ssize_t>(ts.size()), py::ssize_t{4}});
            auto r = a.mutable_unchecked<2>();
            for (std::size_t k = 0; k < ts.size(); ++k) {
              if (!(ts[k] >= 0.0 && ts[k] <= 1.0)) throw m::InputError("a vein's parameter lies in [0, 1]");
              const Eigen::Vector3d c = l.model.veins[i].curve.center(ts[k]);
              for (py::ssize_t j = 0; j < 3; ++j) r(static_cast<py::ssize_t>(k), j) = c[j];
              r(static_cast<py::ssize_t>(k), 3) = l.model.veins[i].curve.radius(ts[k]);
            }
            return a;
          },
          py::arg("index"), py::arg("t"))
      .def(
          "blade",
          [](const Leaf& l, const std::vector<double>& us, const std::vector<double>& vs) {
            if (us.size() != vs.size()) throw m::InputError("u and v must have the same length");
            py::array_t<double> a({static_cast<py::ssize_t>(us.size()), py::ssize_t{3}});
            auto r = a.mutable_unchecked<2>();
            for (std::size_t k = 0; k < us.size(); ++k) {
              if (!(us[k] >= 0.0 && us[k] <= 1.0 && vs[k] >= 0.0 && vs[k] <= 1.0))
                throw m::InputError("the blade's parameters lie in [0, 1]");
              const Eigen::Vector3d p = l.model.blade.evaluate(us[k], vs[k]);
              for (py::ssize_t j = 0; j < 3; ++j) r(static_cast<py::ssize_t>(k), j) = p[j];
            }
            return a;
          },
          py::arg("u"), py::arg("v"))
      .def(
          "export",
          [](const Leaf& l, const std::string& path, const std::array<double, 3>& light) {
            return exportLeaf(l, path, core::lightOf(light));
          },
          py::arg("path"), py::arg("light") = std::array<double, 3>{0, 0, 1});
  mod.def(
      "build_leaf",
      [](const Markers& markers, const std::string& source, const std::string& blade, const std::string& resolution,
         const std::string& mesh, std::optional<double> maxError, const std::string& frame,
         const std::array<double, 3>& light) {
        return buildLeaf(markers.set, source, blade, resolution, mesh, maxError, frame, core::lightOf(light));
      },
      py::arg("markers"), py::arg("source") = "", py::arg("blade") = "interp", py::arg("resolution") = "export",
      py::arg("mesh") = "uniform", py::arg("max_error") = py::none(), py::arg("frame") = "digitizer",
      py::arg("light") = std::array<double, 3>{0, 0, 1});

  py::class_<Plant>(mod, "Plant")
      .def("metrics",
           [](const Plant& p) {
             py::dict d;
             d["area_mm2"] = p.metrics.areaMm2;
             d["silhouette_mm2"] = p.metrics.silhouetteMm2;
             d["star"] = p.metrics.star;
             return d;
           })
      .def("leaves", &plantLeaves)
      .def_property_readonly("id", [](const Plant& p) { return p.plant.id; })
      .def_property_readonly("time", [](const Plant& p) { return p.plant.time ? py::cast(*p.plant.time) : py::none(); })
      .def_property_readonly("stem_height_mm", [](const Plant& p) { return p.plant.stemHeightMm; })
      .def("mesh", [](const Plant& p) { return meshArrays(p.mesh); })
      .def("encode", &encodeOne, py::arg("extension"))
      .def("caribu_scene", &caribuScene)
      .def(
          "export",
          [](const Plant& p, const std::string& path) {
            py::gil_scoped_release free;
            return core::exportPlant(p, path);
          },
          py::arg("path"));
  mod.def(
      "build_plants",
      [](const std::string& text, const std::string& source, const std::string& baseDir,
         const std::vector<std::optional<double>>& times, const std::string& resolution,
         const std::array<double, 3>& light) {
        return buildPlants(text, source, baseDir, times, resolution, core::lightOf(light));
      },
      py::arg("text"), py::arg("source"), py::arg("base_dir"), py::arg("times"), py::arg("resolution") = "export",
      py::arg("light") = std::array<double, 3>{0, 0, 1});

  mod.def(
      "import_plant",
      [](const std::string& path, const std::string& drf, const std::string& units, int plant,
         const std::string& resolution) {
        py::gil_scoped_release free;
        return core::importPlant(path, drf, units, plant, resolution);
      },
      py::arg("path"), py::arg("drf"), py::arg("units"), py::arg("plant") = 1, py::arg("resolution") = "export");
  // An imported plant's reading: the file's entities, the plant's points and axes by order.
  mod.def("import_report", [](const Plant& p) {
    py::dict d;
    if (!p.imported) return d;
    const auto& i = p.imported->plant;
    d["source"] = i.source;
    d["plant"] = i.plantLabel;
    d["vertices"] = i.vertices;
    d["plant_vertices"] = i.plantVertices;
    d["points"] = i.points;
    d["units"] = p.imported->unit;
    py::dict classes, orders;
    for (const auto& [symbol, count] : i.perClass) classes[py::str(symbol)] = count;
    for (const auto& axis : i.axes) {
      const py::int_ order(axis.order);
      orders[order] = orders.contains(order) ? py::cast<int>(orders[order]) + 1 : 1;
    }
    d["classes"] = classes;
    d["axes_by_order"] = orders;
    d["notes"] = i.notes;
    return d;
  });

  py::class_<Store>(mod, "Store")
      .def("sessions", &sessions)
      .def("markers", &sessionMarkers, py::arg("id"), py::arg("node") = 0)
      .def("events", &sessionEvents, py::arg("id"))
      .def("plant_survey_json", &plantSurveyJson, py::arg("id"))
      .def("field_checks_json",
           [](const Store& s) {
             py::gil_scoped_release free;
             // A station's own record: the lab server does not hold field checks.
             const auto* local = dynamic_cast<const db::Store*>(s.store.get());
             if (!local)
               throw m::InputError(
                   "field checks are kept in the station's file, not on the lab server: open the station's file");
             std::string out = "[";
             for (const acq::FieldCalibration& c : acq::fieldCalibrations(*local))
               out += (out.size() > 1 ? "," : "") + acq::fieldCheckSummaryJson(c);
             return out + "]";
           })
      .def("tip_calibrations_json",
           [](const Store& s) {
             py::gil_scoped_release free;
             const auto* local = dynamic_cast<const db::Store*>(s.store.get());
             if (!local)
               throw m::InputError(
                   "tip calibrations are kept in the station's file, not on the lab server: open the station's file");
             std::string out = "[";
             for (const acq::TipCalibration& c : acq::tipCalibrations(*local))
               out += (out.size() > 1 ? "," : "") + acq::tipCalibrationSummaryJson(c);
             return out + "]";
           })
      .def(
          "history_json",
          [](const Store& s, std::int64_t id) {
            py::gil_scoped_release free;
            core::requireVerified(*s.store, id, "");
            return db::reviewHistoryJson(db::reviewHistory(s.store->events(id)));
          },
          py::arg("id"))
      .def(
          "plant",
          [](const Store& s, std::int64_t id, const std::array<double, 3>& light) {
            return capturedPlant(s, id, core::lightOf(light));
          },
          py::arg("id"), py::arg("light") = std::array<double, 3>{0, 0, 1})
      .def_property_readonly("where", [](const Store& s) { return s.where; })
      .def(
          "review",
          [](Store& s, std::int64_t id, const std::string& status, const std::string& who, const std::string& why) {
            py::gil_scoped_release free;
            try {
              return acq::review(*s.store, id, status, who, why);
            } catch (const std::invalid_argument& e) {
              throw m::InputError(e.what());
            }
          },
          py::arg("id"), py::arg("status"), py::arg("who"), py::arg("why") = "")
      .def(
          "reopen",
          [](Store& s, std::int64_t id, const std::string& who, const std::string& why) {
            py::gil_scoped_release free;
            try {
              return acq::reopen(*s.store, id, who, why);
            } catch (const std::invalid_argument& e) {
              throw m::InputError(e.what());
            }
          },
          py::arg("id"), py::arg("who"), py::arg("why"))
      .def(
          "correct",
          [](Store& s, std::int64_t id, const std::string& what, int row, int col, int node,
             const std::optional<std::array<double, 3>>& position, const std::optional<double>& value,
             const std::string& who, const std::string& why, bool confirm, const std::string& frame) {
            acq::Correction c;
            if (!confirm) c.confirmAboveMm = acq::kConfirmMoveAboveMm;
            try {
              acq::setCorrectionItem(c, what, node);
              // A plant's points in the plant frame unless told (as the CLI's --frame).
              if (!frame.empty()) {
                c.frame = acq::positionFrameFromString(frame);
              } else if (position) {
                py::gil_scoped_release free;
                const auto info = s.store->session(id);
                if (info && info->kind == "plant") c.frame = acq::PositionFrame::Plant;
              }
            } catch (const std::invalid_argument& e) {
              throw m::InputError(e.what());
            }
            c.row = row;
            c.col = col;
            if (position) c.positionMm = acq::Vec3{(*position)[0], (*position)[1], (*position)[2]};
            c.valueMm = value;
            c.who = who;
            c.reason = why;
            py::gil_scoped_release free;
            try {
              return acq::correct(*s.store, id, c);
            } catch (const std::invalid_argument& e) {
              throw m::InputError(e.what());
            }
          },
          py::arg("id"), py::arg("what"), py::arg("row"), py::arg("col"), py::arg("node"), py::arg("position"),
          py::arg("value"), py::arg("who"), py::arg("why"), py::arg("confirm") = false, py::arg("frame") = "");
  mod.def("open_store", &openStore, py::arg("path_or_url"), py::arg("writable") = false);

  mod.def(
      "synth_leaf",
      [](const std::string& shape, const std::string& serration, int rows, double noise, std::uint64_t seed,
         double length) {
        if (!(noise >= 0.0 && noise <= 50.0)) throw m::InputError("noise is a stylus error in mm, between 0 and 50");
        m::SyntheticLeafSpec s = m::defaultSyntheticSpec(m::leafShapeFromString(shape));
        s.outline.lengthMm = length;
        s.outline.serration = m::serrationFromString(serration);
        if (s.outline.serration != m::Serration::None) {
          const double width = s.outline.widthMm.value_or(s.outline.lengthMm / m::aspectRatio(s.outline.shape));
          s.outline.toothDepthMm = 0.015 * width;
          s.outline.teethPerSide = 20;
        }
        s.rows = rows;
        s.id = "SYN-" + shape + "-" + std::to_string(seed);
        py::gil_scoped_release free;
        const m::SyntheticLeaf leaf(s);
        return std::make_pair(Markers{leaf.markers(noise, seed)}, m::truthToJson(leaf, noise, seed));
      },
      py::arg("shape") = "tobacco", py::arg("serration") = "none", py::arg("rows") = 12, py::arg("noise") = 0.0,
      py::arg("seed") = 1, py::arg("length") = 500.0);
}
