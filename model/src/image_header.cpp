#include "leafdig/model/image_header.hpp"

#include <array>
#include <cstring>

namespace leafdig::model {
namespace {

bool readAt(std::istream& in, std::uint64_t offset, std::uint8_t* out, std::size_t n) {
  in.clear();
  in.seekg(static_cast<std::streamoff>(offset));
  if (!in) return false;
  in.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n));
  return static_cast<std::size_t>(in.gcount()) == n;
}

std::uint32_t big32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
std::uint16_t big16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}
std::uint32_t little32(const std::uint8_t* p) {
  return (std::uint32_t{p[3]} << 24) | (std::uint32_t{p[2]} << 16) | (std::uint32_t{p[1]} << 8) | p[0];
}
std::uint16_t little16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((p[1] << 8) | p[0]);
}

std::optional<ImageHeader> png(std::istream& in) {
  std::array<std::uint8_t, 24> h{};
  if (!readAt(in, 0, h.data(), h.size())) return std::nullopt;
  // The signature, then the first chunk: 13 bytes of IHDR.
  if (big32(h.data() + 8) != 13 || std::memcmp(h.data() + 12, "IHDR", 4) != 0) return std::nullopt;
  return ImageHeader{"PNG", big32(h.data() + 16), big32(h.data() + 20)};
}

std::optional<ImageHeader> jpeg(std::istream& in) {
  // Segments from after SOI: FF xx, a 2-byte length (which counts itself), up to a start of
  // frame (SOF0..SOF15 but DHT C4, JPG C8, DAC CC). Bounded: 10 000 segments.
  std::uint64_t at = 2;
  for (int segment = 0; segment < 10000; ++segment) {
    std::array<std::uint8_t, 4> m{};
    if (!readAt(in, at, m.data(), m.size())) return std::nullopt;
    if (m[0] != 0xFF) return std::nullopt;
    if (m[1] == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    const std::uint8_t marker = m[1];
    if (marker == 0xD8 || (marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) {  // no length
      at += 2;
      continue;
    }
    if (marker == 0xD9 || marker == 0xDA) return std::nullopt;  // end, or scan data before a frame
    const std::uint16_t length = big16(m.data() + 2);
    if (length < 2) return std::nullopt;
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      std::array<std::uint8_t, 5> f{};  // precision, height, width
      if (length < 7 || !readAt(in, at + 4, f.data(), f.size())) return std::nullopt;
      return ImageHeader{"JPEG", big16(f.data() + 3), big16(f.data() + 1)};
    }
    at += 2u + length;
  }
  return std::nullopt;
}

std::optional<ImageHeader> tiff(std::istream& in, bool little) {
  const auto u16 = [little](const std::uint8_t* p) { return little ? little16(p) : big16(p); };
  const auto u32 = [little](const std::uint8_t* p) { return little ? little32(p) : big32(p); };
  std::array<std::uint8_t, 8> h{};
  if (!readAt(in, 0, h.data(), h.size()) || u16(h.data() + 2) != 42) return std::nullopt;
  const std::uint32_t ifd = u32(h.data() + 4);
  std::array<std::uint8_t, 2> count{};
  if (ifd < 8 || !readAt(in, ifd, count.data(), count.size())) return std::nullopt;
  const std::uint16_t entries = u16(count.data());
  std::optional<std::uint32_t> width, height;
  for (std::uint16_t e = 0; e < entries && e < 4096; ++e) {
    std::array<std::uint8_t, 12> entry{};
    if (!readAt(in, std::uint64_t{ifd} + 2 + 12ull * e, entry.data(), entry.size())) return std::nullopt;
    const std::uint16_t tag = u16(entry.data());
    const std::uint16_t type = u16(entry.data() + 2);
    if (tag != 256 && tag != 257) continue;
    // SHORT (3) or LONG (4), one value, held in the entry itself.
    std::uint32_t value = 0;
    if (type == 3)
      value = u16(entry.data() + 8);
    else if (type == 4)
      value = u32(entry.data() + 8);
    else
      return std::nullopt;
    (tag == 256 ? width : height) = value;
  }
  if (!width || !height) return std::nullopt;
  return ImageHeader{"TIFF", *width, *height};
}

std::optional<ImageHeader> bmp(std::istream& in) {
  std::array<std::uint8_t, 26> h{};
  if (!readAt(in, 0, h.data(), h.size())) return std::nullopt;
  const std::uint32_t infoSize = little32(h.data() + 14);
  if (infoSize == 12) return ImageHeader{"BMP", little16(h.data() + 18), little16(h.data() + 20)};  // OS/2
  if (infoSize < 40) return std::nullopt;
  const auto width = static_cast<std::int32_t>(little32(h.data() + 18));
  const auto height = static_cast<std::int32_t>(little32(h.data() + 22));  // negative: top-down
  if (width <= 0 || height == 0 || height == INT32_MIN) return std::nullopt;
  return ImageHeader{"BMP", static_cast<std::uint32_t>(width),
                     static_cast<std::uint32_t>(height < 0 ? -height : height)};
}

}  // namespace

std::optional<ImageHeader> readImageHeader(std::istream& in) {
  std::array<std::uint8_t, 8> magic{};
  if (!readAt(in, 0, magic.data(), magic.size())) return std::nullopt;
  static constexpr std::uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (std::memcmp(magic.data(), kPng, 8) == 0) return png(in);
  if (magic[0] == 0xFF && magic[1] == 0xD8 && magic[2] == 0xFF) return jpeg(in);
  if (magic[0] == 'I' && magic[1] == 'I') return tiff(in, true);
  if (magic[0] == 'M' && magic[1] == 'M') return tiff(in, false);
  if (magic[0] == 'B' && magic[1] == 'M') return bmp(in);
  return std::nullopt;
}

}  // namespace leafdig::model
