// leafdig: the command line front end. A thin composition root over the modules.
//
// Exit codes: 0 success; 2 bad input (a file or option the user must fix; nothing was
// written); 1 any other failure (I/O, internal error).
#include <CLI/CLI.hpp>
#include <iostream>

#include "capture_cmd.hpp"
#include "devices_cmd.hpp"
#include "lab_cmd.hpp"
#include "leaf2d_cmd.hpp"
#include "leafdig/version.hpp"
#include "mesh_cmd.hpp"
#include "model_build.hpp"
#include "plant_cmd.hpp"
#include "synth_cmd.hpp"

int main(int argc, char** argv) {
  CLI::App app{"leafdig: digitizer-and-caliper acquisition station for plant morphology labs", "leafdig"};
  app.set_version_flag("--version", std::string("leafdig ") + leafdig::kVersion);
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 success, 2 bad input (nothing written; the message says what to fix), "
      "1 other failures.");

  CLI::App* model = app.add_subcommand("model", "Build leaf models from marker files");
  model->require_subcommand(1);
  leafdig::cli::ModelBuildOptions buildOptions;
  leafdig::cli::addModelBuildCommand(*model, buildOptions);

  leafdig::cli::PlantOptions plantOptions;
  leafdig::cli::addPlantCommands(app, plantOptions);

  leafdig::cli::MeshCommandOptions meshOptions;
  leafdig::cli::addMeshCommands(app, meshOptions);

  leafdig::cli::SynthOptions synthOptions;
  leafdig::cli::addSynthCommands(app, synthOptions);

  leafdig::cli::Leaf2dCommandOptions leaf2dOptions;
  leafdig::cli::addLeaf2dCommands(app, leaf2dOptions);

  leafdig::cli::DevicesOptions deviceOptions;
  leafdig::cli::addDevicesCommands(app, deviceOptions);

  leafdig::cli::CaptureOptions captureOptions;
  leafdig::cli::addCaptureCommands(app, captureOptions);

  leafdig::cli::LabOptions labOptions;
  leafdig::cli::addLabCommands(app, labOptions);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "leafdig: " << e.what() << "\nRun 'leafdig --help' for usage.\n";
    return 2;
  }

  if (model->parsed() && model->got_subcommand("build")) return leafdig::cli::runModelBuild(buildOptions);
  if (const int rc = leafdig::cli::runPlantCommands(app, plantOptions); rc >= 0) return rc;
  if (const int rc = leafdig::cli::runMeshCommands(app, meshOptions); rc >= 0) return rc;
  if (const int rc = leafdig::cli::runSynthCommands(app, synthOptions); rc >= 0) return rc;
  if (const int rc = leafdig::cli::runLeaf2dCommands(app, leaf2dOptions); rc >= 0) return rc;
  if (const int rc = leafdig::cli::runDevicesCommands(app, deviceOptions); rc >= 0) return rc;
  if (const int rc = leafdig::cli::runCaptureCommands(app, captureOptions); rc >= 0) return rc;
  if (const int rc = leafdig::cli::runLabCommands(app, labOptions); rc >= 0) return rc;
  return 1;
}
