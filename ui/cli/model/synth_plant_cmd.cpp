// `leafdig synth plant`: a ground-truth plant digitized in place (leafdig.plant-markers/1 in
// a transmitter's frame, with noise) and its truth (docs/plants.md, "Synthetic plants").
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/study/synthetic_plant.hpp"
#include "model/synth_cmd.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

namespace {

struct SynthPlantOptions {
  m::SyntheticPlantSpec spec;
  std::string pose = "random";
  std::string date;
  std::string markers, truth;
  bool json = false;
};

int runSynthPlant(const SynthPlantOptions& o) {
  m::SyntheticPlantSpec spec = o.spec;
  spec.randomPose = o.pose == "random";
  if (!o.date.empty()) {
    spec.date = m::parseSurveyDate(o.date);
    if (!spec.date) throw m::InputError("--date \"" + o.date + "\" is not a day: give it as YYYY-MM-DD");
  }
  // Two outputs, two files: the markers written over the truth would leave neither (issue 47).
  {
    std::error_code ec;
    const bool same =
        std::filesystem::exists(o.markers, ec) && std::filesystem::exists(o.truth, ec)
            ? std::filesystem::equivalent(o.markers, o.truth, ec)
            : std::filesystem::weakly_canonical(o.markers, ec) == std::filesystem::weakly_canonical(o.truth, ec);
    if (same)
      throw m::InputError("--markers and --truth name the same file (" + o.markers +
                          "): give each its own path; nothing was written");
  }
  const m::SyntheticPlant plant = m::synthesizePlant(spec);
  // Both files or neither: the truth first, then the markers.
  m::writeFileAtomically(o.truth, m::syntheticPlantTruthToJson(spec.id, plant.truth));
  m::writeFileAtomically(o.markers, m::plantMarkersToJson(plant.markers));
  int full = 0, quick = 0;
  for (const auto& l : plant.truth.leaves) {
    if (l.kind == m::LeafKind::Full) ++full;
    if (l.kind == m::LeafKind::Quick) ++quick;
  }
  if (o.json) {
    std::cout << nlohmann::json{{"plant", spec.id},     {"nodes", plant.truth.nodesMm.size()},
                                {"full_leaves", full},  {"quick_leaves", quick},
                                {"markers", o.markers}, {"truth", o.truth}}
                     .dump()
              << "\n";
  } else {
    std::cout << "plant " << spec.id << ": " << plant.truth.nodesMm.size() << " nodes, " << full << " full and "
              << quick << " quick leaves, digitized "
              << (spec.randomPose ? "through a transmitter at a random pose" : "in the plant's own frame")
              << "\n  markers: " << o.markers << "\n  truth:   " << o.truth << "\n";
  }
  return 0;
}

}  // namespace

void addSynthPlantCommand(CLI::App& synth, CommandTable& table) {
  auto o = std::make_shared<SynthPlantOptions>();
  CLI::App* plant = synth.add_subcommand(
      "plant", "A plant digitized in place with its truth: synthetic leaves of known area at known angles on a stem");
  plant->add_option("--markers", o->markers, "Write the plant here (leafdig.plant-markers/1)")->required();
  plant->add_option("--truth", o->truth, "Write the truth here (leafdig.plant-truth/1)")->required();
  plant->add_option("--id", o->spec.id, "Plant id (default P-synth)");
  plant->add_option("--nodes", o->spec.nodes, "Nodes on the stem, the top one bare (default 10)")
      ->check(CLI::Range(2, 60));
  plant
      ->add_option("--full-every", o->spec.fullEvery,
                   "Every k-th node's leaf digitized in full, and the largest (default 3); the others quick")
      ->check(CLI::Range(1, 60));
  plant->add_option("--rows", o->spec.leafRows, "Marker rows of a full leaf (default 10)")->check(CLI::Range(2, 60));
  plant->add_option("--noise", o->spec.noiseMm, "Gaussian noise per stylus coordinate, σ in mm (default 0.3)")
      ->check(CLI::Range(0.0, 10.0));
  plant->add_option("--seed", o->spec.seed, "Seed of the pose and the noise (default 1)")->check(seedText());
  plant->add_option("--pose", o->pose, "The transmitter: random (default) or plant (the plant's own frame)")
      ->check(CLI::IsMember({"random", "plant"}));
  plant->add_option("--date", o->date, "The survey's day, YYYY-MM-DD (written in the file)");
  plant->add_flag("--json", o->json, "Print what was written as JSON");
  table.add(plant, [o] { return runSynthPlant(*o); });
}

}  // namespace leafdig::cli
