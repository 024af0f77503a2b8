// A stored leaf session (or a plant session's full leaf) written as files: meshes, the model,
// its markers, the CSV of its items (README.md, "Files"). The plant's own exports are
// plant_export.hpp's.
//
// Thread contract: like the Store they take, one thread at a time.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/db/event_store.hpp"
#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/model/metrics/metrics.hpp"

namespace leafdig::acquisition {

struct ExportRequest {
  std::vector<std::string> formats;   // glb obj ply stl model markers csv; empty: all
  std::string frame = "leaf";         // or "digitizer"
  std::string resolution = "export";  // a MeshResolution preset (mesh "uniform")
  std::string mesh = "uniform";       // or "adaptive" (maxErrorMm), "seed" (seed parameters)
  double maxErrorMm = 0.1;
  model::SeedMeshParameters seed;
  std::string blade = "interp";  // approx, bezier, nurbs
  // The meshes' organs (glb obj ply stl): all, or the blade alone (model::OrganChoice).
  model::OrganChoice organs = model::OrganChoice::All;
  std::string outDir;
  // A plant session's full leaf, alone: the leaf digitized at this node (files
  // session-N.node-K.*, in the digitizer's or the leaf's frame, the CSV of that leaf's items).
  std::optional<int> node;
};
struct ExportResult {
  std::vector<std::string> written;  // files, in the order written
  model::LeafMetrics metrics;
  std::size_t rows = 0;
};
// Checks the chain and the tables against the events (a session that fails verify is not
// exported: SessionError), writes each file atomically and records it in `exports`. Throws std::invalid_argument
// (unknown format, no directory) and model::InputError (the capture is not a whole leaf).
ExportResult exportSession(db::EventStore& store, std::int64_t id, const ExportRequest& request);
// A plant session's full leaf at `node` (1 at the base), as markers named after the plant and
// the node, in the digitizer's frame as the plant's survey has them (its session verified and
// replayed first): what `sessions export --node` writes and Python's `Store.leaf(id, node=)`
// builds. SessionError for a leaf's session or one that does not verify; std::invalid_argument
// naming the nodes that have a full leaf otherwise.
[[nodiscard]] model::MarkerSet plantLeafMarkers(const db::EventStore& store, std::int64_t id, int node);
// The format names exportSession knows, in order.
[[nodiscard]] const std::vector<std::string>& exportFormats();

}  // namespace leafdig::acquisition
