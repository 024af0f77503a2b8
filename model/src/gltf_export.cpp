// glTF 2.0 binary export through tinygltf (Debian's libtinygltf-dev). Images are never
// written, so stb_image is left out.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <cstring>
#include <sstream>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/mesh_export.hpp"

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

}  // namespace

std::string encodeGlb(const LeafMesh& mesh, const ExportHeader& header) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = header.generator;
  model.buffers.emplace_back();
  const int veinMaterial = addMaterial(model, "vein", {0.78, 0.82, 0.55, 1.0}, false);
  // The blade is a surface seen from both sides.
  const int bladeMaterial = addMaterial(model, "blade", {0.36, 0.58, 0.24, 1.0}, true);

  tinygltf::Node root;
  root.name = header.leafId.empty() ? "leaf" : header.leafId;
  tinygltf::Value::Object extras;
  extras["source_units"] = tinygltf::Value(std::string("mm"));
  extras["frame"] = tinygltf::Value(header.frame);
  extras["up"] = tinygltf::Value(std::string("glTF +Y is the frame's +Z"));
  extras["radius_note"] = tinygltf::Value(std::string("vein radii are caliper thickness / 2"));
  root.extras = tinygltf::Value(extras);

  for (const Organ& organ : mesh.organs) {
    const Mesh& m = organ.mesh;
    std::vector<float> positions;
    std::vector<float> normals;
    std::vector<double> lo(3, std::numeric_limits<double>::max());
    std::vector<double> hi(3, std::numeric_limits<double>::lowest());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
      const Eigen::Vector3d p = toGltfAxes(m.positions[v]) * kMetresPerMm;
      const Eigen::Vector3f n = toGltfAxes(m.normals[v]).cast<float>().normalized();
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

    const int posView =
        addView(model, positions.data(), positions.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    const int posAcc =
        addAccessor(model, posView, TINYGLTF_COMPONENT_TYPE_FLOAT, m.positions.size(), TINYGLTF_TYPE_VEC3);
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
    prim.material = organ.kind == OrganKind::Blade ? bladeMaterial : veinMaterial;
    tinygltf::Mesh gm;
    gm.name = organ.name;
    gm.primitives.push_back(prim);
    model.meshes.push_back(gm);

    tinygltf::Node node;
    node.name = organ.name;
    node.mesh = static_cast<int>(model.meshes.size() - 1);
    model.nodes.push_back(node);
    root.children.push_back(static_cast<int>(model.nodes.size() - 1));
  }
  model.nodes.push_back(root);
  tinygltf::Scene scene;
  scene.name = "leafdig";
  scene.nodes.push_back(static_cast<int>(model.nodes.size() - 1));
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, out, false, true)) {
    throw IoError("glTF encoding failed");
  }
  return out.str();
}

}  // namespace leafdig::model
