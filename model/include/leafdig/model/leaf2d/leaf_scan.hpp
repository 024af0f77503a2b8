#pragma once
// Leaf scans (seed 001's image input): a leaf on a flatbed scanner or a leaf-area meter's
// image, segmented into the blade's outline and area, as a lab does with ImageJ. OpenCV does
// the image work behind this interface, in one translation unit (leaf_scan.cpp) of its own
// library, leafdig_scan; nothing of OpenCV shows here.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "leafdig/model/leaf2d/leaf2d.hpp"

namespace leafdig::model {

struct ScanOptions {
  double dpi = 0.0;             // required: the scan's resolution, dots per inch
  double petioleWidthMm = 3.0;  // a part narrower than this and at least twice as long is the petiole
};

struct LeafScan {
  Outline2d outline;           // the blade's outer boundary, mm, y up; base where the petiole joins
  double areaMm2 = 0.0;        // leaf tissue: blade pixels, holes and petiole excluded
  double filledAreaMm2 = 0.0;  // the blade with its holes filled (what a model without holes holds)
  double holesAreaMm2 = 0.0;
  int holes = 0;
  bool petioleFound = false;
  double petioleAreaMm2 = 0.0;
  int otherObjects = 0;         // other dark objects of at least 1 mm^2 (dust, labels, rulers), ignored
  bool touchesBorder = false;   // the leaf reaches the image's edge: it may be cut off
  bool darkBackground = false;  // the background was darker than the leaf (a light box): inverted
  int widthPx = 0;
  int heightPx = 0;
  int threshold = 0;  // Otsu's grey level
  double pixelMm = 0.0;
};

// Reads a PNG, TIFF, JPEG or BMP (colour or grey, 8 or 16 bit). Throws InputError naming the
// problem and what to do: missing DPI, an unreadable file, no leaf found, a uniform image.
[[nodiscard]] LeafScan scanLeaf(const std::filesystem::path& image, const ScanOptions& options);

// A scan's resolution and size are what a scanner makes (limits.hpp: 25–20 000 DPI, at most
// 400 million pixels and 2 m on a side); throws InputError saying which and what to do.
void checkScanSize(std::uint64_t widthPx, std::uint64_t heightPx, double dpi);

// The same on grey pixels in memory (row-major, `stride` bytes per row).
[[nodiscard]] LeafScan scanLeafPixels(const std::uint8_t* grey, int width, int height, std::size_t stride,
                                      const ScanOptions& options);

// A synthetic scan: white page of the given size (mm) at `dpi`, the polygons (mm, origin at the
// page's lower left, y up) filled in a leaf's grey with anti-aliased edges, then `holes`
// filled white again. Written as an 8-bit grey PNG or TIFF (by the extension, .png .tif
// .tiff; else InputError). For ground truth and tests.
void renderScan(const std::vector<std::vector<Eigen::Vector2d>>& leafPolygons,
                const std::vector<std::vector<Eigen::Vector2d>>& holes, const Eigen::Vector2d& pageMm, double dpi,
                const std::filesystem::path& png);

}  // namespace leafdig::model
