#include "module_core.hpp"

#include <filesystem>
#include <stdexcept>
#include <utility>

#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/archive_export.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/version.hpp"

namespace leafdig::python {
namespace {

namespace m = leafdig::model;
namespace acq = leafdig::acquisition;

std::vector<std::string> writeFiles(const std::vector<m::EncodedFile>& files) {
  std::vector<std::string> written;
  for (const auto& f : files) {
    m::writeFileAtomically(f.path, f.bytes);
    written.push_back(f.path.string());
  }
  return written;
}

std::vector<m::LibraryLeaf> libraryOf(const m::PlantPlan& plan) {
  if (!plan.libraryDb) return {};
  if (!std::filesystem::exists(*plan.libraryDb))
    throw m::InputError("library.db " + *plan.libraryDb + " does not exist: name the station's database");
  db::Store store(*plan.libraryDb, true);
  return acq::organLibrary(store).leaves;
}

}  // namespace

const std::string& generator() {
  static const std::string g = std::string("leafdig ") + leafdig::kVersion;
  return g;
}

m::MeshOptions meshOptions(const std::string& resolution, const std::string& method, std::optional<double> maxError) {
  m::MeshOptions o;
  o.method = m::meshMethodFromString(method);
  o.resolution = m::MeshResolution::preset(resolution);
  if (maxError) {
    if (o.method != m::MeshMethod::Adaptive)
      throw m::InputError("max_error is the adaptive mesh's parameter: add mesh=\"adaptive\"");
    if (!(*maxError >= 0.005 && *maxError <= 50.0))
      throw m::InputError("max_error must be between 0.005 and 50 mm, e.g. 0.1");
    o.maxErrorMm = *maxError;
  }
  return o;
}

Eigen::Vector3d lightOf(const std::array<double, 3>& light) {
  const Eigen::Vector3d d(light[0], light[1], light[2]);
  if (!d.allFinite() || d.cwiseAbs().maxCoeff() == 0.0)
    throw std::invalid_argument("light must be three finite numbers (x, y, z), not all zero, e.g. (0, 0, 1)");
  return d / d.cwiseAbs().maxCoeff();
}

std::vector<std::string> exportLeaf(const m::BuiltLeaf& leaf, const std::string& source, const std::string& path,
                                    const Eigen::Vector3d& light) {
  const std::filesystem::path p(path);
  std::vector<m::EncodedFile> files;
  const m::ExportHeader header{leaf.model.markers.leaf.id, leaf.frame, generator()};
  if (p.extension() == ".json") {
    files.push_back({p, m::modelToJson(leaf.model, leaf.frame, leaf.metrics)});
  } else {
    const m::PlantFormat f = m::plantFormatForPath(p);
    if (f == m::PlantFormat::Can || f == m::PlantFormat::Mtg || f == m::PlantFormat::Csv ||
        f == m::PlantFormat::HeliosXml || f == m::PlantFormat::Vgx) {
      const m::LeafAsPlant alone = m::leafAsPlant(leaf, source, light);
      files = m::encodePlant(p, alone.plant, alone.mesh, alone.metrics, {m::CanUnit::Metre, generator()});
    } else {
      files.push_back({p, m::encodeMesh(leaf.mesh, m::meshFormatForPath(p), header)});
    }
  }
  return writeFiles(files);
}

std::vector<PlantModel> buildPlants(const std::string& planText, const std::string& source, const std::string& baseDir,
                                    const std::vector<std::optional<double>>& times, const std::string& resolution,
                                    const Eigen::Vector3d& light) {
  const m::PlantPlan plan = m::parsePlantPlan(planText, source, baseDir);
  for (const auto& t : times)
    if (t && !plan.growth) throw m::InputError(source + ": the plan has no \"growth\"; add one to build growth states");
  const m::PlantBuilder builder(plan, libraryOf(plan));
  const m::MeshOptions options = meshOptions(resolution, "uniform", std::nullopt);
  std::vector<PlantModel> out;
  for (const auto& t : times) {
    PlantModel p;
    p.plant = builder.build(t);
    p.mesh = m::meshPlant(p.plant, options);
    p.metrics = m::computePlantMetrics(p.plant, p.mesh, light);
    out.push_back(std::move(p));
  }
  return out;
}

namespace {
std::vector<m::EncodedFile> encodeFor(const PlantModel& p, const std::filesystem::path& path) {
  const m::PlantExportOptions options{m::CanUnit::Metre, generator()};
  const m::PlantFormat format = m::plantFormatForPath(path);
  if (p.surveyMtgCsv && format == m::PlantFormat::Mtg) return {{path, p.surveyMtgCsv->first}};
  if (p.surveyMtgCsv && format == m::PlantFormat::Csv) return {{path, p.surveyMtgCsv->second}};
  if (p.imported)
    return m::encodeImportedFiles({path}, p.imported->plant, p.imported->archive, p.mesh, p.metrics, options);
  return m::encodePlant(path, p.plant, p.mesh, p.metrics, options);
}
}  // namespace

std::vector<std::string> exportPlant(const PlantModel& p, const std::string& path) {
  return writeFiles(encodeFor(p, path));
}

std::string encodeOne(const PlantModel& p, const std::string& extension) {
  return encodeFor(p, "plant" + extension).front().bytes;
}

PlantModel importPlant(const std::string& path, const std::string& drf, const std::string& units, int plant,
                       const std::string& resolution) {
  auto imported = std::make_shared<const m::ImportedFile>(m::importMtgFile(path, drf, units, plant));
  PlantModel p;
  p.plant = imported->plant.plant;
  p.mesh = m::meshPlant(p.plant, meshOptions(resolution, "uniform", std::nullopt));
  p.metrics = m::computePlantMetrics(p.plant, p.mesh, Eigen::Vector3d::UnitZ());
  p.imported = std::move(imported);
  return p;
}

void requireVerified(const db::EventStore& store, std::int64_t id, const std::string& refused) {
  const db::ChainReport chain = store.verify(id);
  if (!chain.ok)
    throw acq::SessionError("session " + std::to_string(id) + " fails 'sessions verify' (event " +
                            std::to_string(chain.firstBadSeq.value_or(0)) + ": " + chain.problem + ")" + refused);
}

PlantModel capturedPlant(const db::EventStore& store, std::int64_t id, const Eigen::Vector3d& light) {
  const acq::CapturedSurvey survey = acq::capturedSurvey(store, id);
  PlantModel p;
  p.plant = acq::capturedModel(survey).plant;
  acq::SurveyTexts texts = acq::surveyTexts(store, id, survey);
  p.surveyMtgCsv.emplace(std::move(texts.mtg), std::move(texts.csv));
  p.mesh = m::meshPlant(p.plant, m::MeshResolution::preset("export"));
  p.metrics = m::computePlantMetrics(p.plant, p.mesh, light);
  return p;
}

}  // namespace leafdig::python
