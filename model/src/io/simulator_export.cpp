#include "leafdig/model/io/simulator_export.hpp"

#include <cmath>

#include "fixed_text.hpp"
#include "leafdig/model/errors.hpp"
#include "xml_text.hpp"

namespace leafdig::model {

namespace {

struct Colour {
  double r, g, b;
};
// A green leaf's blade, its veins a paler green, the wood brown.
Colour colourOf(const Organ& organ) {
  if (organ.leafRank == 0) return {0.45, 0.32, 0.18};
  if (organ.kind == OrganKind::Blade) return {0.20, 0.50, 0.12};
  return {0.55, 0.70, 0.35};
}

// Fixed notation with `decimals` digits (never an exponent, never "-0"), as the other mesh writers.
void append(std::string& out, double value, int decimals) {
  char buffer[32];
  out.append(buffer, detail::writeFixed(buffer, value, decimals));
}

}  // namespace

std::string encodeHeliosXml(const LeafMesh& mesh, const std::string& generator, int plantNumber) {
  std::string out;
  out += "<?xml version=\"1.0\"?>\n<!-- ";
  // "--" may not appear inside an XML comment.
  std::string note =
      detail::xmlText(generator) + ": metres; each triangle's transform maps Helios's unit triangle onto it";
  for (std::size_t at; (at = note.find("--")) != std::string::npos;) note.replace(at, 2, "- ");
  out += note + " -->\n<helios>\n";
  int objID = 0;
  int organID = 0;
  std::string objects;
  for (const Organ& organ : mesh.organs) {
    ++organID;
    if (organ.mesh.triangles.empty()) continue;
    ++objID;
    const Colour c = colourOf(organ);
    std::string colour;
    append(colour, c.r, 3);
    colour += ' ';
    append(colour, c.g, 3);
    colour += ' ';
    append(colour, c.b, 3);
    const std::string data = "\t\t<data_int label=\"plantID\">" + std::to_string(plantNumber) +
                             "</data_int>\n\t\t<data_int label=\"leafID\">" + std::to_string(organ.leafRank) +
                             "</data_int>\n\t\t<data_int label=\"organID\">" + std::to_string(organID) +
                             "</data_int>\n";
    for (const auto& t : organ.mesh.triangles) {
      const Eigen::Vector3d v0 = organ.mesh.positions[t[0]] / 1000.0, v1 = organ.mesh.positions[t[1]] / 1000.0,
                            v2 = organ.mesh.positions[t[2]] / 1000.0;
      const Eigen::Vector3d a = v2 - v1, b = v1 - v0, d = Eigen::Vector3d::Ones() - v2;
      out.append("\t<triangle>\n\t\t<objID>").append(std::to_string(objID)).append("</objID>\n\t\t<color>");
      out.append(colour).append("</color>\n").append(data).append("\t\t<transform>");
      for (int row = 0; row < 3; ++row) {
        for (const double value : {a[row], b[row], d[row], v0[row]}) {
          append(out, value, 9);
          out += ' ';
        }
      }
      out += "0 0 0 1</transform>\n\t</triangle>\n";
    }
    objects += "\t<polymesh>\n\t\t<objID>" + std::to_string(objID) + "</objID>\n" + data +
               "\t\t<data_string label=\"organ\">" + detail::xmlText(organ.name) + "</data_string>\n\t</polymesh>\n";
  }
  out += objects + "</helios>\n";
  return out;
}

std::string encodeVgx(const LeafMesh& mesh, int plantNumber) {
  std::string out =
      "Obj\tEchX\tEchY\tEchZ\tTransX\tTransY\tTransZ\tRotX\tRotY\tRotZ\tR\tG\tB\tX1\tY1\tZ1\tX2\tY2\tZ2\tX3\tY3\tZ3\tGr"
      "p1\t"
      "Grp2\n";
  int organID = 0;
  for (const Organ& organ : mesh.organs) {
    ++organID;
    const Colour c = colourOf(organ);
    const std::string rgb = std::to_string(std::lround(c.r * 255)) + "\t" + std::to_string(std::lround(c.g * 255)) +
                            "\t" + std::to_string(std::lround(c.b * 255));
    for (const auto& t : organ.mesh.triangles) {
      // Centimetres, Z down.
      Eigen::Vector3d v[3];
      for (int k = 0; k < 3; ++k) {
        v[k] = organ.mesh.positions[t[static_cast<std::size_t>(k)]] / 10.0;
        v[k].z() = -v[k].z();
      }
      const Eigen::Vector3d centroid = (v[0] + v[1] + v[2]) / 3.0;
      const double area = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).norm();
      const double ech = std::sqrt(area / 0.7);
      out += "0\t";
      append(out, ech, 4);
      out += '\t';
      append(out, ech, 4);
      out += "\t0";
      for (int k = 0; k < 3; ++k) {
        out += '\t';
        append(out, centroid[k], 4);
      }
      out += "\t0\t0\t0\t" + rgb;
      for (const auto& p : v)
        for (int k = 0; k < 3; ++k) {
          out += '\t';
          append(out, p[k], 4);
        }
      out += "\t" + std::to_string(organID) + "\t" + std::to_string(plantNumber) + "\n";
    }
  }
  return out;
}

}  // namespace leafdig::model
