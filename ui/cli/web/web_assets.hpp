// The web review's pages (ui/cli/web/assets/), embedded in the program at build time by
// cmake/embed_files.cmake: a lab network without internet gets every byte from leafdig.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

namespace leafdig::cli::web {

struct EmbeddedFile {
  std::string_view path;  // under assets/, e.g. "app.js"
  const char* data;
  std::size_t size;
};

// One entry per file of assets/.
[[nodiscard]] std::span<const EmbeddedFile> embeddedFiles();

}  // namespace leafdig::cli::web
