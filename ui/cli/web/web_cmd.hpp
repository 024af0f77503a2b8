// `leafdig server web`: the web review served until SIGINT or SIGTERM (docs/web.md).
#pragma once

#include <string>

#include "web_app.hpp"

namespace leafdig::cli::web {

// Serves the review of options.serverUrl on `listen` (HOST:PORT; port 0: any free one, the
// first line printed names it). Returns the exit code.
int serve(const WebOptions& options, const std::string& listen);

}  // namespace leafdig::cli::web
