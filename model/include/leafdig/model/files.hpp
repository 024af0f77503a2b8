#pragma once
// Reading and writing files. Every write goes to a temporary name in the destination's
// folder, is flushed to disk, then renamed over the destination: a failure (disk full,
// crash) never leaves a partial file under the real name.
#include <filesystem>
#include <string>
#include <string_view>

#include "leafdig/model/limits.hpp"

namespace leafdig::model {

// Throws IoError naming the path and the operating system's reason.
void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

// Throws IoError naming the path and the operating system's reason, and InputError for what
// is not a regular file (a device, FIFO, folder) or is larger than maxBytes.
[[nodiscard]] std::string readFile(const std::filesystem::path& path, std::uintmax_t maxBytes = kMaxInputFileBytes);

// The path's extension in lower case, with its dot (".glb"), or empty.
[[nodiscard]] std::string lowerExtension(const std::filesystem::path& path);

}  // namespace leafdig::model
