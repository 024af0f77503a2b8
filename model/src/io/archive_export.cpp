#include "leafdig/model/io/archive_export.hpp"

#include <algorithm>
#include <map>
#include <sstream>
#include <vector>

#include "io/mtg_text.hpp"
#include "leafdig/model/io/csv_text.hpp"

namespace leafdig::model {

using detail::mtgAlpha;
using detail::mtgReal;
using detail::writeMtgLine;

namespace {

std::vector<std::string> values(const Ball& b, const std::string& source, int line) {
  return {mtgReal(b.center.x()),
          mtgReal(b.center.y()),
          mtgReal(b.center.z()),
          mtgReal(2 * b.radius),
          source.empty() ? std::string() : mtgAlpha(source),
          line > 0 ? std::to_string(line) : std::string()};
}

}  // namespace

std::string encodeImportedMtg(const ImportedPlant& plant, const MtgArchive& archive, const std::string& generator) {
  // The axes borne by each entity, in the order they were drawn.
  std::map<int, std::vector<std::size_t>> borne;
  int deepest = 1;
  for (std::size_t k = 0; k < plant.axes.size(); ++k) {
    if (plant.axes[k].bearer > 0) borne[plant.axes[k].baseVertex].push_back(k);
    deepest = std::max(deepest, plant.axes[k].order);
  }
  const int columns = deepest + 1;
  std::ostringstream out;
  out << "# " << mtgAlpha(generator) << ": plant " << mtgAlpha(plant.plantLabel) << " imported from "
      << mtgAlpha(std::filesystem::path(plant.source).filename().string()) << "\n"
      << "# units: XX YY ZZ TopDia in mm, in the archive's own axes and origin\n"
      << "# A<n> axis n (its order in the number of + above it), E<k> its k-th digitized entity; Source and Line "
         "name that entity in the archive\n"
      << "CODE:\tFORM-A\n\nCLASSES:\nSYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION\n"
      << "$\t0\tFREE\tFREE\tIMPLICIT\nP\t1\tCONNECTED\tFREE\tEXPLICIT\nA\t2\tFREE\tFREE\tEXPLICIT\n"
      << "E\t3\tNONE\tFREE\tEXPLICIT\n\nDESCRIPTION:\nLEFT\tRIGHT\tRELTYPE\tMAX\nE\tE\t<\t1\nE\tA\t+\t?\n\n"
      << "FEATURES:\nNAME\tTYPE\nXX\tREAL\nYY\tREAL\nZZ\tREAL\nTopDia\tREAL\nSource\tALPHA\nLine\tINT\n\n"
      << "MTG:\nTOPO" << std::string(static_cast<std::size_t>(columns - 1), '\t')
      << "\tXX\tYY\tZZ\tTopDia\tSource\tLine\n";
  writeMtgLine(out, 0, "/P1", {}, columns);
  const auto entity = [&](const ImportedAxis& axis, std::size_t i) {
    const MtgVertex& v = archive.vertices.at(static_cast<std::size_t>(axis.vertices[i]));
    return values(axis.balls[i], v.label, v.line);
  };
  // Depth first without recursion (an archive may nest axes deeply): a frame is an axis being
  // written, `next` its next entity (-1: its first line, +A<n>/E1, not written yet).
  struct Frame {
    std::size_t axis;
    int next;
    int column;
  };
  std::vector<Frame> stack;
  const auto pushBorne = [&](int vertex, int column) {
    const auto it = borne.find(vertex);
    if (it == borne.end()) return;
    for (auto k = it->second.rbegin(); k != it->second.rend(); ++k) stack.push_back({*k, -1, column});
  };
  for (std::size_t r = 0; r < plant.axes.size(); ++r) {
    const ImportedAxis& root = plant.axes[r];
    if (root.bearer > 0) continue;
    const std::string name = "A" + std::to_string(r + 1);
    writeMtgLine(out, 0, "^/" + name, root.base ? values(*root.base, "", 0) : std::vector<std::string>{}, columns);
    writeMtgLine(out, 0, "^/E1", entity(root, 0), columns);
    stack.push_back({r, 1, 0});
    pushBorne(root.vertices[0], 1);
    while (!stack.empty()) {
      Frame& f = stack.back();
      const ImportedAxis& axis = plant.axes[f.axis];
      const int column = f.column;
      if (f.next == -1) {
        f.next = 1;
        writeMtgLine(out, column, "+A" + std::to_string(f.axis + 1) + "/E1", entity(axis, 0), columns);
        pushBorne(axis.vertices[0], column + 1);
      } else if (static_cast<std::size_t>(f.next) < axis.vertices.size()) {
        const auto i = static_cast<std::size_t>(f.next++);
        writeMtgLine(out, column, "^<E" + std::to_string(i + 1), entity(axis, i), columns);
        pushBorne(axis.vertices[i], column + 1);
      } else {
        stack.pop_back();
      }
    }
  }
  return out.str();
}

std::string encodeImportedCsv(const ImportedPlant& plant, const MtgArchive& archive) {
  std::ostringstream out;
  out << "# "
      << csvText("plant " + plant.plantLabel + " imported from " +
                 std::filesystem::path(plant.source).filename().string() + "; lengths in mm")
      << "\naxis,order,bearer_axis,kind,entity,source_line,x_mm,y_mm,z_mm,diameter_mm\n";
  const auto row = [&](std::size_t k, const char* kind, const std::string& entity, int line, const Ball& b) {
    const ImportedAxis& a = plant.axes[k];
    out << k + 1 << "," << a.order << "," << a.bearer << "," << kind << "," << csvText(entity) << ","
        << (line > 0 ? std::to_string(line) : std::string()) << "," << mtgReal(b.center.x()) << ","
        << mtgReal(b.center.y()) << "," << mtgReal(b.center.z()) << "," << mtgReal(2 * b.radius) << "\n";
  };
  for (std::size_t k = 0; k < plant.axes.size(); ++k) {
    const ImportedAxis& a = plant.axes[k];
    if (a.base) {
      const MtgVertex* v = a.baseVertex >= 0 ? &archive.vertices.at(static_cast<std::size_t>(a.baseVertex)) : nullptr;
      row(k, "base", v ? v->label : std::string(), v ? v->line : 0, *a.base);
    }
    for (std::size_t i = 0; i < a.vertices.size(); ++i) {
      const MtgVertex& v = archive.vertices.at(static_cast<std::size_t>(a.vertices[i]));
      row(k, "point", v.label, v.line, a.balls[i]);
    }
  }
  return out.str();
}

std::vector<EncodedFile> encodeImportedFiles(const std::vector<std::filesystem::path>& paths,
                                             const ImportedPlant& plant, const MtgArchive& archive,
                                             const LeafMesh& mesh, const PlantMetrics& metrics,
                                             const PlantExportOptions& options) {
  std::vector<EncodedFile> files;
  std::vector<std::filesystem::path> others;
  for (const auto& path : paths) {
    const PlantFormat f = plantFormatForPath(path);
    if (f == PlantFormat::Mtg)
      files.push_back({path, encodeImportedMtg(plant, archive, options.generator)});
    else if (f == PlantFormat::Csv)
      files.push_back({path, encodeImportedCsv(plant, archive)});
    else
      others.push_back(path);
  }
  for (auto& f : encodePlantFiles(others, plant.plant, mesh, metrics, options)) files.push_back(std::move(f));
  return files;
}

}  // namespace leafdig::model
