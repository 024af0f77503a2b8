#pragma once
// Reading and writing files. Every write goes to a temporary name in the destination's
// folder, is flushed to disk, then renamed over the destination: a failure (disk full,
// crash) never leaves a partial file under the real name.
#include <filesystem>
#include <string>
#include <string_view>

#include "leafdig/model/limits.hpp"

namespace leafdig::model {

// The one way leafdig writes a file. Throws IoError naming the path and the operating
// system's reason, and InputError (nothing written) when the target exists and is not a
// regular file (a device, FIFO or folder: never replaced), or is a file this process reads
// (noteInput: the same file by device and inode, through any symlink or second name). The
// temporary is created beside the target with an unpredictable name (O_EXCL: a planted file
// or symlink there is never followed), written, flushed, then renamed over the target.
void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

// Records `path` (its device and inode, symlinks resolved) as an input of this process:
// writeFileAtomically then refuses to write over it. readFile records what it reads; code that
// opens an input another way (an image library, a database) calls this. A path that does not
// exist is ignored.
void noteInput(const std::filesystem::path& path);

// Throws IoError naming the path and the operating system's reason, and InputError for what
// is not a regular file (a device, FIFO, folder) or is larger than maxBytes.
[[nodiscard]] std::string readFile(const std::filesystem::path& path, std::uintmax_t maxBytes = kMaxInputFileBytes);

// The path's extension in lower case, with its dot (".glb"), or empty.
[[nodiscard]] std::string lowerExtension(const std::filesystem::path& path);

}  // namespace leafdig::model
