#pragma once
// An archive's plant as leafdig writes it back (docs/plants.md, "Archives"): an MTG in
// millimetres with the axes it was drawn with, and a CSV of its points. Both name each point's
// entity and line in the source file, so a modeller can go back to the archive.
#include <filesystem>
#include <string>
#include <vector>

#include "leafdig/model/archive/plant_import.hpp"
#include "leafdig/model/io/plant_export.hpp"

namespace leafdig::model {

// `P1`, axes `A<n>` (scale 2: `+` from the entity of the axis bearing it, n the axis' number)
// made of the drawn entities `E<k>` (scale 3, `<` along the axis), features XX YY ZZ TopDia (mm),
// Source (the entity's label in the archive) and Line (its line there). A root axis' own
// coordinates, when it starts at a complex's point, are on its `A` line: its base.
[[nodiscard]] std::string encodeImportedMtg(const ImportedPlant& plant, const MtgArchive& archive,
                                            const std::string& generator);
// axis,order,bearer_axis,kind,entity,source_line,x_mm,y_mm,z_mm,diameter_mm: an axis' base
// (kind "base") then its points (kind "point").
[[nodiscard]] std::string encodeImportedCsv(const ImportedPlant& plant, const MtgArchive& archive);

// Every file for `paths`, by extension as encodePlantFiles writes a plant's (the import's own
// .mtg and .csv above): what `leafdig plant import -o` and Python's imported Plant write.
[[nodiscard]] std::vector<EncodedFile> encodeImportedFiles(const std::vector<std::filesystem::path>& paths,
                                                           const ImportedPlant& plant, const MtgArchive& archive,
                                                           const LeafMesh& mesh, const PlantMetrics& metrics,
                                                           const PlantExportOptions& options);

}  // namespace leafdig::model
