#include "model/mesh_choice.hpp"

#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

void addMeshChoice(CLI::App& c, MeshChoice& choice) {
  c.add_option("--mesh", choice.method,
               "Mesh method: uniform (the --resolution grid, default), seed (patent CN101650836: "
               "--min-length, --max-angle, --ring) or adaptive (--max-error)")
      ->check(CLI::IsMember(wordsIn(model::kMeshMethodNames)));
  c.add_option("--min-length", choice.minLengthMm, "Seed mode: division length M along skeletons, mm (default 2)");
  c.add_option("--max-angle", choice.maxAngleDeg,
               "Seed mode: merge segments while their angle exceeds this, degrees, 180 = straight (default 170)");
  c.add_option("--ring", choice.ringVertices, "Seed mode: vertices around every vein (default 8)");
  c.add_option("--max-error", choice.maxErrorMm,
               "Adaptive mode: largest distance to the exact surface, mm (default 0.1)");
  c.add_flag("--no-measure", choice.noMeasure,
             "With --json and --mesh seed|adaptive: skip measuring the mesh against the reference (faster)");
}

m::MeshOptions meshOptionsFrom(const MeshChoice& c, const m::MeshResolution& resolution) {
  m::MeshOptions o;
  o.method = m::meshMethodFromString(c.method);
  o.resolution = resolution;
  const bool seedOption = c.minLengthMm || c.maxAngleDeg || c.ringVertices;
  if (seedOption && o.method != m::MeshMethod::Seed)
    throw m::InputError("--min-length, --max-angle and --ring are seed-mode parameters: add --mesh seed");
  if (c.maxErrorMm && o.method != m::MeshMethod::Adaptive)
    throw m::InputError("--max-error is the adaptive mode's parameter: add --mesh adaptive");
  if (c.minLengthMm) {
    if (!(*c.minLengthMm > 0.0)) throw m::InputError("--min-length must be a positive length in mm, e.g. 2");
    o.seed.minLengthMm = *c.minLengthMm;
  }
  if (c.maxAngleDeg) {
    if (!(*c.maxAngleDeg > 90.0 && *c.maxAngleDeg <= 180.0))
      throw m::InputError("--max-angle must be in (90, 180] degrees (180 = straight), e.g. 170");
    o.seed.maxAngleDeg = *c.maxAngleDeg;
  }
  if (c.ringVertices) {
    if (*c.ringVertices < 3 || *c.ringVertices > 256)
      throw m::InputError("--ring must be between 3 and 256 vertices, e.g. 8");
    o.seed.ringVertices = *c.ringVertices;
  }
  if (c.maxErrorMm) {
    if (!(*c.maxErrorMm >= 0.005 && *c.maxErrorMm <= 50.0))
      throw m::InputError("--max-error must be between 0.005 and 50 mm, e.g. 0.1");
    o.maxErrorMm = *c.maxErrorMm;
  }
  return o;
}

nlohmann::json meshReportJson(const m::LeafMesh& mesh, const m::MeshOptions& o,
                              const std::optional<m::MeshDistance>& measured, std::optional<double> referenceErrorMm) {
  nlohmann::json organs = nlohmann::json::array();
  std::size_t total = 0;
  for (const m::Organ& organ : mesh.organs) {
    organs.push_back({{"name", organ.name}, {"triangles", organ.mesh.triangles.size()}});
    total += organ.mesh.triangles.size();
  }
  nlohmann::json parameters;
  switch (o.method) {
    case m::MeshMethod::Uniform: parameters = {{"resolution", o.resolution.name}}; break;
    case m::MeshMethod::Seed:
      parameters = {{"min_length_mm", o.seed.minLengthMm},
                    {"max_angle_deg", o.seed.maxAngleDeg},
                    {"ring_vertices", o.seed.ringVertices}};
      break;
    case m::MeshMethod::Adaptive: parameters = {{"max_error_mm", o.maxErrorMm}}; break;
  }
  nlohmann::json out = {
      {"method", m::toString(o.method)}, {"parameters", parameters}, {"triangles", total}, {"organs", organs}};
  if (measured) {
    out["measured"] = {{"hausdorff_mm", measured->hausdorff},
                       {"mean_mm", measured->mean},
                       {"rms_mm", measured->rms},
                       {"against", "resolution reference"},
                       {"reference_error_mm", referenceErrorMm ? nlohmann::json(*referenceErrorMm) : nullptr}};
  }
  return out;
}

nlohmann::json measuredMeshReportJson(const m::LeafMesh& mesh, const m::MeshOptions& options, bool noMeasure,
                                      const std::function<m::MeshSubject()>& subject, std::size_t samplesPerPart) {
  if (options.method == m::MeshMethod::Uniform || noMeasure) return meshReportJson(mesh, options, {}, {});
  const m::MeshSubject s = subject();
  return meshReportJson(mesh, options, s.measure(mesh, samplesPerPart), s.referenceErrorMm());
}

}  // namespace leafdig::cli
