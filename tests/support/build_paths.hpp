// The paths of this build that tests and benchmarks need, as functions (force-included; one
// generated definition per target, tests/CMakeLists.txt `leafdig_build_paths`). As string
// macros they would put the clone's folder into every object of the target, and ccache could
// not reuse a single one of them from a clone in another folder (CI's clean clone).
#pragma once

const char* leafdigTestSourceDir();   // LEAFDIG_SOURCE_DIR: the source tree
const char* leafdigTestCli();         // LEAFDIG_CLI: the leafdig program of this build
const char* leafdigTestStationExe();  // LEAFDIG_STATION_EXE: the leafdig-station program
