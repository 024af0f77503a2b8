// The live preview of a plant being digitized (docs/plants.md, "The station's plant capture
// view"): what the PlantEngine holds now, as a front end draws it. Once the plant frame can be
// made (three landmarks, the collar and the first node) everything is in the plant frame: the
// stem through the nodes taken, each leaf as far as it goes — a finished full leaf as
// digitized, a quick leaf shaped from the organ library (else the built-in sample), the full
// leaf under capture as its live preview — as the captured plant's model makes them
// (model/plant/surveyed_plant.hpp). Before that, the points alone, in the digitizer's frame.
//
// A node whose stem diameter is not read yet is drawn with the diameter below it (said in
// `notes`); a leaf whose points do not make a leaf yet is left out and named. Never throws for
// a partial or odd capture.
//
// Thread contract: a pure function of its arguments; call it on any thread (the station builds
// it off the capture thread and off the GUI thread).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "leafdig/acquisition/protocol/plant_engine.hpp"
#include "leafdig/acquisition/session/preview.hpp"
#include "leafdig/model/plant/plant.hpp"

namespace leafdig::acquisition {

struct PlantPreview {
  bool inPlantFrame = false;  // false: `points` in the digitizer's frame and no mesh yet
  model::LeafMesh mesh;       // the stem and the leaves so far ("stem", "leaf 3 …" organs)
  // Every stylus point taken, in the frame above, as items a preview draws as markers
  // (What::Marker; row: landmark or node number, col: which point of it), then the full
  // leaves' tips and markers (row: the node, col: 100 + their order in the leaf).
  std::vector<Item> points;
  int leaves = 0;  // leaves in `mesh` (finished ones and the one under capture)
  // The full leaf under capture (node number, 0 when none) and its own live preview, in the
  // digitizer's frame as the leaf view shows it.
  int leafNode = 0;
  std::vector<Item> leafItems;
  std::shared_ptr<const Preview> leaf;
  std::vector<std::string> notes;
};

// Builds previews of one capture as it goes, remeshing only what changed: the stem (every
// time: it is cheap) and the leaves whose points, state or frame changed since the last build;
// a finished leaf's mesh is kept. The result is the same as a one-shot build's.
class PlantPreviewer {
 public:
  explicit PlantPreviewer(std::vector<model::LibraryLeaf> library = {});
  [[nodiscard]] PlantPreview build(const PlantEngine& engine);
  // Leaves taken from the last builds instead of being remeshed (for tests and benchmarks).
  [[nodiscard]] int reused() const { return reused_; }

 private:
  struct CachedLeaf {
    std::string key;  // the frame and the node's leaf, as JSON
    std::vector<model::Organ> organs;
    std::string note;  // why the leaf could not be drawn (then no organs)
  };
  std::vector<model::LibraryLeaf> library_;
  std::map<int, CachedLeaf> leaves_;  // by node
  int reused_ = 0;
};

// One preview on its own (no cache): PlantPreviewer(library).build(engine).
[[nodiscard]] PlantPreview buildPlantPreview(const PlantEngine& engine, const std::vector<model::LibraryLeaf>& library);

}  // namespace leafdig::acquisition
