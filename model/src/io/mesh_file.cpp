// Reading mesh files for comparison: assimp (Debian's libassimp-dev) reads OBJ, PLY, STL and
// glTF; this file only gathers triangles and fixes glTF's units and axes.
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/mesh/mesh_compare.hpp"

namespace leafdig::model {

TriangleSoup readMeshFile(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext != ".obj" && ext != ".ply" && ext != ".stl" && ext != ".glb" && ext != ".gltf")
    throw InputError(path + ": unknown mesh format \"" + ext + "\"; use .obj, .ply, .stl, .glb or .gltf");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such file");
  Assimp::Importer importer;
  // Node transforms applied, polygons fanned into triangles; points and lines dropped.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0)
    throw InputError(path + ": not a readable mesh (" + importer.GetErrorString() + ")");
  const bool gltf = ext == ".glb" || ext == ".gltf";
  TriangleSoup soup;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if ((mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
    const auto offset = static_cast<std::uint32_t>(soup.positions.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      if (gltf) {
        // glTF: metres, +Y up; leafdig: millimetres, +Z up (x, y, z) <- (x, -z, y).
        soup.positions.emplace_back(1000.0 * p.x, -1000.0 * p.z, 1000.0 * p.y);
      } else {
        soup.positions.emplace_back(p.x, p.y, p.z);
      }
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      soup.triangles.push_back({offset + face.mIndices[0], offset + face.mIndices[1], offset + face.mIndices[2]});
    }
  }
  if (soup.triangles.empty()) throw InputError(path + ": the file holds no triangles");
  return soup;
}

}  // namespace leafdig::model
