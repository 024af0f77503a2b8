#pragma once
// The size of an image from its header alone, before anything is decoded: a leaf scan's
// pixels are bounded (limits.hpp) before OpenCV allocates them, so a 3.5 MB PNG that claims
// 32 000 × 32 000 pixels is refused in words instead of taking 10 GB. PNG, JPEG (baseline and
// progressive), TIFF (both byte orders) and BMP; written here because these four headers are a
// few dozen lines and no library in Debian reads headers without decoding.
#include <cstdint>
#include <istream>
#include <optional>
#include <string>

namespace leafdig::model {

struct ImageHeader {
  std::string format;  // "PNG", "JPEG", "TIFF", "BMP"
  std::uint32_t width = 0, height = 0;
};

// Reads the header from `in` (seeking as the format needs). Nothing when the bytes are none
// of the four formats or the header is cut short or inconsistent.
[[nodiscard]] std::optional<ImageHeader> readImageHeader(std::istream& in);

}  // namespace leafdig::model
