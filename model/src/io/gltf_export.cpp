// glTF 2.0 binary export through tinygltf (Debian's libtinygltf-dev). Images are never
// written, so stb_image is left out.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <sstream>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/io/survey_export.hpp"

namespace leafdig::model {

namespace {

constexpr double kMetresPerMm = 1e-3;

// Appends raw bytes to the single buffer and returns the new buffer view's index.
int addView(tinygltf::Model& model, const void* data, std::size_t bytes, int target) {
  auto& buffer = model.buffers.front().data;
  while (buffer.size() % 4 != 0) buffer.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), p, p + bytes);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size() - 1);
}

int addAccessor(tinygltf::Model& model, int view, int componentType, std::size_t count, int type) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = componentType;
  a.count = count;
  a.type = type;
  model.accessors.push_back(a);
  return static_cast<int>(model.accessors.size() - 1);
}

int addMaterial(tinygltf::Model& model, const char* name, std::vector<double> rgba, bool doubleSided) {
  tinygltf::Material m;
  m.name = name;
  m.pbrMetallicRoughness.baseColorFactor = std::move(rgba);
  m.pbrMetallicRoughness.metallicFactor = 0.0;
  m.pbrMetallicRoughness.roughnessFactor = 0.8;
  m.doubleSided = doubleSided;
  model.materials.push_back(m);
  return static_cast<int>(model.materials.size() - 1);
}

// A glTF model with its buffer and the leaf's two materials (veins; the blade, seen from both
// sides): what every leafdig GLB starts from.
struct Start {
  tinygltf::Model model;
  int vein = -1, blade = -1;
};
Start startModel(const std::string& generator, const Provenance& provenance = {}) {
  Start s;
  s.model.asset.version = "2.0";
  s.model.asset.generator = generator;
  if (!provenance.empty()) {
    // Where the file came from (a stored session's), in the asset's extras as glTF allows.
    tinygltf::Value::Object from;
    for (const auto& [key, value] : provenance) from[key] = tinygltf::Value(value);
    tinygltf::Value::Object extras;
    extras["provenance"] = tinygltf::Value(from);
    s.model.asset.extras = tinygltf::Value(extras);
  }
  s.model.buffers.emplace_back();
  s.vein = addMaterial(s.model, "vein", {0.78, 0.82, 0.55, 1.0}, false);
  s.blade = addMaterial(s.model, "blade", {0.36, 0.58, 0.24, 1.0}, true);
  return s;
}

// One glTF mesh for an organ: positions (mm -> m) and normals through `axes`, 32-bit indices.
// Returns the mesh's index.
int addOrganMesh(tinygltf::Model& model, const Organ& organ, int material,
                 const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& axes) {
  const Mesh& m = organ.mesh;
  std::vector<float> positions;
  std::vector<float> normals;
  std::vector<double> lo(3, std::numeric_limits<double>::max());
  std::vector<double> hi(3, std::numeric_limits<double>::lowest());
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    const Eigen::Vector3d p = axes(m.positions[v]) * kMetresPerMm;
    const Eigen::Vector3f n = axes(m.normals[v]).cast<float>().normalized();
    for (int i = 0; i < 3; ++i) {
      const auto f = static_cast<float>(p[i]);
      positions.push_back(f);
      normals.push_back(n[i]);
      lo[i] = std::min(lo[i], static_cast<double>(f));
      hi[i] = std::max(hi[i], static_cast<double>(f));
    }
  }
  std::vector<std::uint32_t> indices;
  for (const auto& t : m.triangles) indices.insert(indices.end(), t.begin(), t.end());

  const int posView = addView(model, positions.data(), positions.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  const int posAcc = addAccessor(model, posView, TINYGLTF_COMPONENT_TYPE_FLOAT, m.positions.size(), TINYGLTF_TYPE_VEC3);
  model.accessors[static_cast<std::size_t>(posAcc)].minValues = lo;
  model.accessors[static_cast<std::size_t>(posAcc)].maxValues = hi;
  const int nrmView = addView(model, normals.data(), normals.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  const int nrmAcc = addAccessor(model, nrmView, TINYGLTF_COMPONENT_TYPE_FLOAT, m.normals.size(), TINYGLTF_TYPE_VEC3);
  const int idxView =
      addView(model, indices.data(), indices.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  const int idxAcc =
      addAccessor(model, idxView, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, indices.size(), TINYGLTF_TYPE_SCALAR);

  tinygltf::Primitive prim;
  prim.attributes["POSITION"] = posAcc;
  prim.attributes["NORMAL"] = nrmAcc;
  prim.indices = idxAcc;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.material = material;
  tinygltf::Mesh gm;
  gm.name = organ.name;
  gm.primitives.push_back(prim);
  model.meshes.push_back(gm);
  return static_cast<int>(model.meshes.size() - 1);
}

// The root node as the scene's only node, then the binary container.
std::string finishGlb(tinygltf::Model& model, tinygltf::Node root, const char* sceneName) {
  model.nodes.push_back(std::move(root));
  tinygltf::Scene scene;
  scene.name = sceneName;
  scene.nodes.push_back(static_cast<int>(model.nodes.size() - 1));
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, out, false, true)) throw IoError("glTF encoding failed");
  return out.str();
}

}  // namespace

std::string encodeGlb(const LeafMesh& mesh, const ExportHeader& header) {
  Start start = startModel(header.generator, header.provenance);
  tinygltf::Model& model = start.model;
  const int veinMaterial = start.vein, bladeMaterial = start.blade;

  tinygltf::Node root;
  root.name = header.leafId.empty() ? "leaf" : header.leafId;
  tinygltf::Value::Object extras;
  extras["source_units"] = tinygltf::Value(std::string("mm"));
  extras["frame"] = tinygltf::Value(header.frame);
  extras["up"] = tinygltf::Value(std::string("glTF +Y is the frame's +Z"));
  extras["radius_note"] = tinygltf::Value(std::string("vein radii are caliper thickness / 2"));
  root.extras = tinygltf::Value(extras);

  for (const Organ& organ : mesh.organs) {
    const int meshIndex = addOrganMesh(model, organ, organ.kind == OrganKind::Blade ? bladeMaterial : veinMaterial,
                                       [](const Eigen::Vector3d& v) { return toGltfAxes(v); });
    tinygltf::Node node;
    node.name = organ.name;
    node.mesh = meshIndex;
    model.nodes.push_back(node);
    root.children.push_back(static_cast<int>(model.nodes.size() - 1));
  }
  return finishGlb(model, std::move(root), "leafdig");
}

namespace {

// An axis' mesh (the stem, or a branch) cut at its nodes: each triangle goes to the internode
// (the segment from the node it hangs on — the collar at the plant frame's origin for node 1 —
// to node k) nearest its centroid; the mesh's rings fall on the nodes, so no triangle straddles
// two. Named "<axis>/I<k>".
std::vector<Organ> axisPerInternode(const Organ& stem, const PlantSurvey& survey, int axis) {
  std::vector<Eigen::Vector3d> ends;
  std::vector<int> numbers;
  for (const SurveyedNode& n : survey.nodes) {
    if (n.link.axis != axis) continue;
    if (ends.empty())
      ends.push_back(n.link.parent > 0 ? survey.nodes[static_cast<std::size_t>(n.link.parent - 1)].pointMm
                                       : Eigen::Vector3d::Zero());
    ends.push_back(n.pointMm);
    numbers.push_back(n.index);
  }
  const auto distance = [](const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d ab = b - a;
    const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    return (a + t * ab - p).norm();
  };
  std::vector<Organ> pieces(numbers.size());
  std::vector<std::vector<std::int64_t>> remap(pieces.size(),
                                               std::vector<std::int64_t>(stem.mesh.positions.size(), -1));
  for (std::size_t k = 0; k < pieces.size(); ++k)
    pieces[k] = Organ{stem.name + "/I" + std::to_string(numbers[k]), stem.kind, {}, 0};
  for (const auto& t : stem.mesh.triangles) {
    const Eigen::Vector3d c = (stem.mesh.positions[t[0]] + stem.mesh.positions[t[1]] + stem.mesh.positions[t[2]]) / 3.0;
    std::size_t best = 0;
    double nearest = distance(c, ends[0], ends[1]);
    for (std::size_t k = 1; k < pieces.size(); ++k)
      if (const double d = distance(c, ends[k], ends[k + 1]); d < nearest) {
        nearest = d;
        best = k;
      }
    Mesh& m = pieces[best].mesh;
    std::array<std::uint32_t, 3> local{};
    for (std::size_t v = 0; v < 3; ++v) {
      std::int64_t& at = remap[best][t[v]];
      if (at < 0) {
        at = static_cast<std::int64_t>(m.positions.size());
        m.positions.push_back(stem.mesh.positions[t[v]]);
        if (t[v] < stem.mesh.normals.size()) m.normals.push_back(stem.mesh.normals[t[v]]);
      }
      local[v] = static_cast<std::uint32_t>(at);
    }
    m.triangles.push_back(local);
  }
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(), [](const Organ& o) { return o.mesh.triangles.empty(); }),
               pieces.end());
  return pieces;
}

// "plant/stem/I3" hangs on I3; the stem whole (no nodes) on I0.
std::string stemOwner(const std::string& name) {
  const auto slash = name.rfind("/I");
  return slash == std::string::npos ? "I0" : name.substr(slash + 1);
}

}  // namespace

std::string encodeSurveyGlb(const PlantSurvey& survey, const SurveyDate& date, const LeafMesh& mesh,
                            const std::string& generator, const Provenance& provenance) {
  Start start = startModel(generator, provenance);
  tinygltf::Model& model = start.model;
  const int veinMaterial = start.vein, bladeMaterial = start.blade;
  const int stemMaterial = addMaterial(model, "stem", {0.86, 0.80, 0.55, 1.0}, false);

  // The entities first (their indices are the MTG's order), then the meshes hung on them.
  const std::vector<SurveyEntity> entities = surveyEntities(survey);
  std::map<std::string, int> index;
  for (const SurveyEntity& e : entities) {
    tinygltf::Node node;
    node.name = e.name;
    tinygltf::Value::Object extras;
    extras["mtg_class"] = tinygltf::Value(e.name.substr(0, 1));
    if (e.relation != 0) {
      extras["mtg_parent"] = tinygltf::Value(e.parent);
      extras["mtg_relation"] = tinygltf::Value(std::string(1, e.relation));
    }
    for (const auto& [feature, value] : e.features) {
      if (const auto* number = std::get_if<double>(&value))
        extras[feature] = tinygltf::Value(*number);
      else
        extras[feature] = tinygltf::Value(std::get<std::string>(value));
    }
    node.extras = tinygltf::Value(extras);
    model.nodes.push_back(std::move(node));
    index[e.name] = static_cast<int>(model.nodes.size() - 1);
  }
  for (const SurveyEntity& e : entities)
    if (e.relation != 0) model.nodes[static_cast<std::size_t>(index.at(e.parent))].children.push_back(index.at(e.name));
  // The stem and the branches in pieces, one per internode, each under its I<k>.
  std::vector<Organ> organs;
  for (const Organ& organ : mesh.organs) {
    if (organ.leafRank != 0 || survey.nodes.empty()) {
      organs.push_back(organ);
      continue;
    }
    // "plant/stem" is the main stem's (axis 1), "plant/branch-<k>" the branch whose first node is k.
    const auto dash = organ.name.rfind("/branch-");
    const int axis = dash == std::string::npos ? 1 : std::stoi(organ.name.substr(dash + 8));
    for (Organ& piece : axisPerInternode(organ, survey, axis)) organs.push_back(std::move(piece));
  }
  for (const Organ& organ : organs) {
    const std::string owner = organ.leafRank == 0 ? stemOwner(organ.name) : "L" + std::to_string(organ.leafRank);
    const auto found = index.find(owner);
    if (found == index.end())
      throw InputError("the plant's mesh has organ " + organ.name + " but the survey has no " + owner);
    const int material = organ.leafRank == 0              ? stemMaterial
                         : organ.kind == OrganKind::Blade ? bladeMaterial
                                                          : veinMaterial;
    tinygltf::Node node;
    node.name = organ.name;
    node.mesh = addOrganMesh(model, organ, material, [](const Eigen::Vector3d& v) { return toGltfAxes(v); });
    model.nodes.push_back(std::move(node));
    model.nodes[static_cast<std::size_t>(found->second)].children.push_back(static_cast<int>(model.nodes.size() - 1));
  }
  tinygltf::Node root;
  root.name = survey.plant.empty() ? "plant" : survey.plant;
  tinygltf::Value::Object extras;
  extras["source_units"] = tinygltf::Value(std::string("mm (features); positions in metres"));
  extras["frame"] = tinygltf::Value(std::string(
      "plant: origin at the collar, +Z the upward normal of the pot rim's landmarks, +X towards the first landmark"));
  extras["up"] = tinygltf::Value(std::string("glTF +Y is the frame's +Z"));
  extras["date"] = tinygltf::Value(toIso(date));
  extras["mtg"] = tinygltf::Value(std::string(
      "one node per MTG entity: I0 the collar, I<k> the internode ending at node k (child of the one it follows) "
      "holding the stem's piece from node k-1 (the collar for k = 1) to node k, L<k> node k's leaf (child of I<k>); "
      "features in each node's extras, in mm, mm2 and degrees"));
  bool branched = false;
  for (const SurveyedNode& n : survey.nodes) branched = branched || n.link.relation == '+';
  if (branched)
    extras["branches"] = tinygltf::Value(std::string(
        "a branch's first I<k> is a child of the I of the node bearing it (mtg_relation +) and holds the branch's "
        "piece from that node to node k"));
  root.extras = tinygltf::Value(extras);
  root.children.push_back(index.at("I0"));
  return finishGlb(model, std::move(root), "leafdig");
}

}  // namespace leafdig::model

namespace leafdig::model {

namespace {

int addFloats(tinygltf::Model& model, const std::vector<float>& values, int type, std::size_t count) {
  const int view = addView(model, values.data(), values.size() * sizeof(float), 0);
  model.bufferViews[static_cast<std::size_t>(view)].target = 0;  // animation data: no GPU target
  return addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, count, type);
}

template <typename Vector>
void animate(tinygltf::Model& model, tinygltf::Animation& animation, int input, int node, const char* path,
             const std::vector<Vector>& values) {
  std::vector<float> out;
  for (const auto& v : values)
    for (int i = 0; i < v.size(); ++i) out.push_back(static_cast<float>(v[i]));
  tinygltf::AnimationSampler sampler;
  sampler.input = input;
  sampler.output =
      addFloats(model, out, Vector::RowsAtCompileTime == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, values.size());
  sampler.interpolation = "LINEAR";
  animation.samplers.push_back(sampler);
  tinygltf::AnimationChannel channel;
  channel.sampler = static_cast<int>(animation.samplers.size() - 1);
  channel.target_node = node;
  channel.target_path = path;
  animation.channels.push_back(channel);
}

}  // namespace

std::string encodeGrowthGlb(const Plant& final, const std::vector<Plant>& states, const MeshOptions& resolution,
                            const std::string& generator) {
  if (states.empty() || !final.stem) throw InputError("a growth animation needs a plant with a stem and some states");
  Start start = startModel(generator);
  tinygltf::Model& model = start.model;
  const int veinMaterial = start.vein, bladeMaterial = start.blade;

  // Time: the whole series plays in 10 seconds.
  const double t0 = *states.front().time;
  const double t1 = *states.back().time;
  std::vector<float> seconds;
  for (const Plant& s : states)
    seconds.push_back(t1 > t0 ? static_cast<float>(10.0 * (*s.time - t0) / (t1 - t0)) : 0.0f);
  const int input = addFloats(model, seconds, TINYGLTF_TYPE_SCALAR, seconds.size());
  model.accessors[static_cast<std::size_t>(input)].minValues = {seconds.front()};
  model.accessors[static_cast<std::size_t>(input)].maxValues = {seconds.back()};
  tinygltf::Animation animation;
  animation.name = "growth";

  tinygltf::Node root;
  root.name = final.id;
  tinygltf::Value::Object extras;
  extras["time_unit"] = tinygltf::Value(final.timeUnit);
  extras["time_start"] = tinygltf::Value(t0);
  extras["time_end"] = tinygltf::Value(t1);
  extras["seconds_for_the_series"] = tinygltf::Value(10.0);
  extras["note"] = tinygltf::Value(std::string(
      "leaves scale anisotropically (width, length) about their base; the per-time exports are the exact states"));
  root.extras = tinygltf::Value(extras);
  const auto addNode = [&model](tinygltf::Node node) {
    model.nodes.push_back(std::move(node));
    return static_cast<int>(model.nodes.size() - 1);
  };

  // The stem elongates along glTF's +Y (the plant's +Z) from its base.
  const LeafMesh stemMesh = meshPlant(Plant{final.id,
                                            std::nullopt,
                                            "",
                                            final.stemHeightMm,
                                            final.stemBaseDiameterMm,
                                            final.stemTopDiameterMm,
                                            final.stem,
                                            {},
                                            final.branches},
                                      resolution);
  tinygltf::Node stem;
  stem.name = "plant/stem";
  stem.mesh = addOrganMesh(model, stemMesh.organs.front(), veinMaterial,
                           [](const Eigen::Vector3d& v) { return toGltfAxes(v); });
  const int stemNode = addNode(stem);
  root.children.push_back(stemNode);
  std::vector<Eigen::Vector3d> stemScale;
  for (const Plant& s : states) stemScale.emplace_back(1.0, s.stemHeightMm / final.stemHeightMm, 1.0);
  animate(model, animation, input, stemNode, "scale", stemScale);

  Eigen::Matrix3d axes;
  axes << 1, 0, 0, 0, 0, 1, 0, -1, 0;  // toGltfAxes as a matrix
  for (const PlacedLeaf& leaf : final.leaves) {
    const std::string prefix = "plant/leaf-" + std::to_string(leaf.rank);
    // The leaf's meshes in its (shaped, full-grown) leaf frame; the node above places it.
    const LeafMesh inLeafFrame = meshLeaf(transformed(leaf.model, leaf.placement.inverse()), resolution);
    tinygltf::Node growth;
    growth.name = prefix + "/growth";
    for (const Organ& organ : inLeafFrame.organs) {
      tinygltf::Node node;
      node.name = prefix + "/" + organ.name;
      node.mesh = addOrganMesh(model, organ, organ.kind == OrganKind::Blade ? bladeMaterial : veinMaterial,
                               [](const Eigen::Vector3d& v) { return v; });
      growth.children.push_back(addNode(node));
    }
    const int growthNode = addNode(growth);
    tinygltf::Node place;
    place.name = prefix;
    const Eigen::Quaterniond q(axes * leaf.placement.linear());
    place.rotation = {q.x(), q.y(), q.z(), q.w()};
    place.children.push_back(growthNode);
    const int placeNode = addNode(place);
    root.children.push_back(placeNode);

    std::vector<Eigen::Vector3d> translation, scale;
    std::vector<Eigen::Vector4d> rotation;  // x, y, z, w: the chord turns a little as width and length grow apart
    for (const Plant& s : states) {
      const PlacedLeaf* at = nullptr;
      for (const PlacedLeaf& l : s.leaves)
        if (l.rank == leaf.rank) at = &l;
      // Not yet appeared: shrunk to nothing at its future insertion point.
      const Eigen::Vector3d base =
          at ? at->base
             : Eigen::Vector3d(leaf.base.x(), leaf.base.y(), leaf.base.z() * s.stemHeightMm / final.stemHeightMm);
      translation.push_back(axes * base * kMetresPerMm);
      const Eigen::Quaterniond r(axes * (at ? at->placement : leaf.placement).linear());
      rotation.emplace_back(r.x(), r.y(), r.z(), r.w());
      scale.push_back(at ? Eigen::Vector3d(at->widthFactor, at->lengthFactor, at->lengthFactor)
                         : Eigen::Vector3d::Constant(1e-6));
    }
    animate(model, animation, input, placeNode, "translation", translation);
    animate(model, animation, input, placeNode, "rotation", rotation);
    animate(model, animation, input, growthNode, "scale", scale);
  }
  model.animations.push_back(animation);
  return finishGlb(model, std::move(root), "leafdig growth");
}

}  // namespace leafdig::model
