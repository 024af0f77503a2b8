#include "leafdig/model/io/mesh_export.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "fixed_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"

namespace leafdig::model {

std::string encodeGlb(const LeafMesh& mesh, const ExportHeader& header);  // gltf_export.cpp

MeshFormat meshFormatForPath(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".glb") return MeshFormat::Glb;
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".stl") return MeshFormat::Stl;
  throw InputError("output " + path.string() + ": unknown mesh format \"" + ext +
                   "\"; name the file .glb, .obj, .ply or .stl");
}

Eigen::Vector3d toGltfAxes(const Eigen::Vector3d& p) {
  return {p.x(), p.z(), -p.y()};
}

namespace {

// Text from a plan, a leaf or a plant id on one line of a file's header (an OBJ or PLY comment,
// an OBJ object name, the STL header): a line break would start a line of its own that a
// reader takes as geometry, so control characters become \xNN.
std::string oneLine(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out;
}

std::string frameDescription(const ExportHeader& h) {
  if (h.frame == "plant") return "plant frame: origin at the stem base, +Z up the stem axis";
  if (h.frame == "leaf2d") {
    return "leaf frame: origin at the leaf base (where the petiole joins), +Y towards the tip, +Z the "
           "adaxial side (a 2-D leaf, curled)";
  }
  if (h.frame == "leaf") {
    return "leaf frame: origin at the last midrib marker P_N4, +Y towards the tip, +Z the mean "
           "adaxial blade normal";
  }
  return "digitizer frame: the digitizer's own axes, +Z taken as up";
}

// "v x y z\n" with `decimals` digits (positions get 4 decimals of a millimetre, 0.1 µm; unit
// normals 6), formatted in a buffer and appended once.
void appendTriple(std::string& out, const char* tag, const Eigen::Vector3d& p, int decimals) {
  char line[96];
  char* w = line;
  while (*tag != '\0') *w++ = *tag++;
  for (int i = 0; i < 3; ++i) {
    *w++ = ' ';
    w = detail::writeFixed(w, p[i], decimals);
  }
  *w++ = '\n';
  out.append(line, static_cast<std::size_t>(w - line));
}

std::string encodeObj(const LeafMesh& mesh, const ExportHeader& h) {
  std::string out = "# " + h.generator + (h.leafId.empty() ? "" : " leaf " + oneLine(h.leafId)) + "\n" +
                    "# units: mm\n# up: +Z\n# " + frameDescription(h) + "\n";
  for (const auto& [key, value] : h.provenance) out += "# provenance " + oneLine(key) + ": " + oneLine(value) + "\n";
  if (std::any_of(mesh.organs.begin(), mesh.organs.end(), [](const Organ& o) { return o.kind == OrganKind::Vein; })) {
    out += "# vein radii are caliper thickness / 2\n";
  }
  std::size_t vertices = 0, triangles = 0;
  for (const Organ& o : mesh.organs) {
    vertices += o.mesh.positions.size();
    triangles += o.mesh.triangles.size();
  }
  out.reserve(out.size() + 64 * vertices + 48 * triangles);  // one allocation for the whole file
  std::size_t base = 1;
  for (const Organ& o : mesh.organs) {
    out += "o " + oneLine(o.name) + "\n";
    for (const auto& p : o.mesh.positions) appendTriple(out, "v", p, 4);
    for (const auto& n : o.mesh.normals) appendTriple(out, "vn", n, 6);
    for (const auto& t : o.mesh.triangles) {
      char line[96];
      char* w = line;
      *w++ = 'f';
      for (auto idx : t) {
        char index[24];
        const char* const end = std::to_chars(index, index + sizeof index, base + idx).ptr;
        *w++ = ' ';
        for (const char* c = index; c != end; ++c) *w++ = *c;
        *w++ = '/';
        *w++ = '/';
        for (const char* c = index; c != end; ++c) *w++ = *c;
      }
      *w++ = '\n';
      out.append(line, static_cast<std::size_t>(w - line));
    }
    base += o.mesh.positions.size();
  }
  return out;
}

template <typename T>
void putLittleEndian(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // x86-64 and aarch64 Linux are little endian
  out.append(bytes, sizeof(T));
}

void putVector(std::string& out, const Eigen::Vector3d& v) {
  for (int i = 0; i < 3; ++i) putLittleEndian(out, static_cast<float>(v[i]));
}

std::string encodePly(const LeafMesh& mesh, const ExportHeader& h) {
  std::size_t vertices = 0;
  std::size_t faces = 0;
  for (const Organ& o : mesh.organs) {
    vertices += o.mesh.positions.size();
    faces += o.mesh.triangles.size();
  }
  std::ostringstream head;
  head << "ply\nformat binary_little_endian 1.0\n"
       << "comment " << h.generator << (h.leafId.empty() ? "" : " leaf " + oneLine(h.leafId)) << "\n"
       << "comment units mm, up +Z, " << frameDescription(h) << "\n";
  for (const auto& [key, value] : h.provenance)
    head << "comment provenance " << oneLine(key) << ": " << oneLine(value) << "\n";
  for (std::size_t i = 0; i < mesh.organs.size(); ++i) {
    head << "comment organ_id " << i << " " << oneLine(mesh.organs[i].name) << "\n";
  }
  head << "element vertex " << vertices << "\n"
       << "property float x\nproperty float y\nproperty float z\n"
       << "property float nx\nproperty float ny\nproperty float nz\n"
       << "element face " << faces << "\n"
       << "property list uchar int vertex_indices\nproperty int organ_id\nproperty int leaf_rank\nend_header\n";
  std::string out = head.str();
  for (const Organ& o : mesh.organs) {
    for (std::size_t v = 0; v < o.mesh.positions.size(); ++v) {
      putVector(out, o.mesh.positions[v]);
      putVector(out, o.mesh.normals[v]);
    }
  }
  std::int32_t base = 0;
  for (std::size_t i = 0; i < mesh.organs.size(); ++i) {
    const Mesh& m = mesh.organs[i].mesh;
    for (const auto& t : m.triangles) {
      putLittleEndian(out, static_cast<std::uint8_t>(3));
      for (auto idx : t) putLittleEndian(out, static_cast<std::int32_t>(base + static_cast<std::int32_t>(idx)));
      putLittleEndian(out, static_cast<std::int32_t>(i));
      putLittleEndian(out, static_cast<std::int32_t>(mesh.organs[i].leafRank));
    }
    base += static_cast<std::int32_t>(m.positions.size());
  }
  return out;
}

std::string encodeStl(const LeafMesh& mesh, const ExportHeader& h) {
  std::string header = h.generator + " leaf " + oneLine(h.leafId) + " units=mm up=+Z frame=" + h.frame;
  header.resize(80, ' ');
  // An STL header must not start with "solid" (readers would take it for ASCII STL).
  std::string out = header;
  std::uint32_t count = 0;
  for (const Organ& o : mesh.organs) count += static_cast<std::uint32_t>(o.mesh.triangles.size());
  out.reserve(84 + 50 * static_cast<std::size_t>(count));
  putLittleEndian(out, count);
  for (const Organ& o : mesh.organs) {
    for (const auto& t : o.mesh.triangles) {
      const Eigen::Vector3d& a = o.mesh.positions[t[0]];
      const Eigen::Vector3d& b = o.mesh.positions[t[1]];
      const Eigen::Vector3d& c = o.mesh.positions[t[2]];
      Eigen::Vector3d n = (b - a).cross(c - a);
      n = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
      putVector(out, n);
      putVector(out, a);
      putVector(out, b);
      putVector(out, c);
      putLittleEndian(out, static_cast<std::uint16_t>(0));
    }
  }
  return out;
}

}  // namespace

void requireFiniteMesh(const LeafMesh& mesh) {
  for (const auto& organ : mesh.organs) {
    for (const auto& v : organ.mesh.positions)
      if (!v.allFinite())
        throw InputError("the " + organ.name +
                         " has coordinates that are not finite numbers: the input holds numbers beyond what a leaf "
                         "can be. Nothing was written; check the markers and the thickness readings");
    for (const auto& n : organ.mesh.normals)
      if (!n.allFinite())
        throw InputError("the " + organ.name +
                         " has normals that are not finite numbers: its geometry is degenerate. "
                         "Nothing was written; check the markers");
  }
}

std::string encodeMesh(const LeafMesh& mesh, MeshFormat format, const ExportHeader& header) {
  requireFiniteMesh(mesh);  // every format: no NaN or infinity ever reaches a file
  switch (format) {
    case MeshFormat::Obj: return encodeObj(mesh, header);
    case MeshFormat::Ply: return encodePly(mesh, header);
    case MeshFormat::Stl: return encodeStl(mesh, header);
    case MeshFormat::Glb: return encodeGlb(mesh, header);
  }
  return {};
}

}  // namespace leafdig::model
