// The command line's one signal handler. SIGINT and SIGTERM set a flag that the long
// commands (capture, demo, devices listen, sim) poll to stop in order; while no capture
// loop is running, a signal also stops the SQLite statement that runs, so a doctored file
// cannot hold the process (docs/decisions.md, "One error map, one command table, one signal handler").
#pragma once

namespace leafdig::cli {

// Installs the handler for SIGINT and SIGTERM (idempotent).
void installSignalHandlers();
// Whether a signal came since the process started.
[[nodiscard]] bool interrupted();
// A running capture stops itself in order when `interrupted()` (its last events are still
// written), so while it runs a signal leaves the store's statements alone.
void setCaptureRunning(bool running);

}  // namespace leafdig::cli
