// The one translation unit that sees OpenCV (core, imgproc, imgcodecs from Debian).
#include "leafdig/model/leaf2d/leaf_scan.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/image_header.hpp"
#include "leafdig/model/limits.hpp"

namespace leafdig::model {

namespace {

constexpr double kMinLeafMm2 = 25.0;   // smaller: not a leaf (dust, a mark)
constexpr double kMinObjectMm2 = 1.0;  // other objects counted in the report from this size
constexpr int kUniformGreyRange = 30;  // max - min below this: nothing to segment

int largestLabel(const cv::Mat& stats, int count, int minArea) {
  int best = -1;
  int bestArea = minArea - 1;
  for (int l = 1; l < count; ++l) {
    const int a = stats.at<int>(l, cv::CC_STAT_AREA);
    if (a > bestArea) {
      bestArea = a;
      best = l;
    }
  }
  return best;
}

// The largest 8-connected part of a 0/255 mask, as a 0/255 mask.
cv::Mat largestPart(const cv::Mat& mask) {
  cv::Mat labels;
  cv::Mat stats;
  cv::Mat centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  const int best = largestLabel(stats, n, 1);
  if (best < 0) return cv::Mat::zeros(mask.size(), CV_8U);
  return labels == best;
}

}  // namespace

void checkScanSize(std::uint64_t width, std::uint64_t height, double dpi) {
  if (!(dpi >= kMinScanDpi && dpi <= kMaxScanDpi)) {
    std::ostringstream out;
    out << "--dpi " << dpi << " is not a scanner's resolution (" << kMinScanDpi << " to " << kMaxScanDpi
        << " dots per inch; e.g. 300, as set in the scanner's software)";
    throw InputError(out.str());
  }
  const double sideMm = static_cast<double>(std::max(width, height)) / dpi * 25.4;
  const std::uint64_t pixels = width * height;
  if (pixels > kMaxScanPixels || sideMm > kMaxScanSideMm) {
    std::ostringstream out;
    out << "a leaf scan of " << width << " x " << height << " px at " << dpi << " DPI is " << std::fixed
        << std::setprecision(1) << sideMm / 1000.0 << " m wide (" << std::setprecision(0)
        << static_cast<double>(pixels) / 1e6 << " million pixels): a scanner's bed is under " << kMaxScanSideMm / 1000.0
        << " m and leafdig reads at most " << kMaxScanPixels / 1'000'000
        << " million pixels. Check --dpi, or scan at a lower resolution";
    throw InputError(out.str());
  }
}

LeafScan scanLeafPixels(const std::uint8_t* grey, int width, int height, std::size_t stride,
                        const ScanOptions& options) {
  if (!(options.dpi > 0.0) || !std::isfinite(options.dpi)) {
    throw InputError("the scan's resolution is needed: give --dpi (e.g. 300, as set in the scanner's software)");
  }
  checkScanSize(static_cast<std::uint64_t>(std::max(width, 0)), static_cast<std::uint64_t>(std::max(height, 0)),
                options.dpi);
  if (!(options.petioleWidthMm >= 0.0)) throw InputError("--petiole-width must be >= 0 mm (0: no petiole search)");
  if (width < 8 || height < 8)
    throw InputError("the image is too small to hold a leaf (" + std::to_string(width) + " x " +
                     std::to_string(height) + " pixels)");
  LeafScan scan;
  scan.widthPx = width;
  scan.heightPx = height;
  scan.pixelMm = 25.4 / options.dpi;
  const double pixelArea = scan.pixelMm * scan.pixelMm;
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-const-cast): OpenCV's Mat header is read-only here
  const cv::Mat image(height, width, CV_8UC1, const_cast<std::uint8_t*>(grey), stride);

  double lo = 0.0;
  double hi = 0.0;
  cv::minMaxLoc(image, &lo, &hi);
  if (hi - lo < kUniformGreyRange) {
    std::ostringstream msg;
    msg << "the image is nearly uniform (grey " << lo << " to " << hi
        << "): no leaf to find; scan the leaf flat on a light background";
    throw InputError(msg.str());
  }
  cv::Mat fg;
  scan.threshold = static_cast<int>(cv::threshold(image, fg, 0, 255, cv::THRESH_BINARY_INV | cv::THRESH_OTSU));
  // A light box (leaf light on dark) is the other way round: the border is mostly background.
  {
    const int borderFg = cv::countNonZero(fg.row(0)) + cv::countNonZero(fg.row(height - 1)) +
                         cv::countNonZero(fg.col(0)) + cv::countNonZero(fg.col(width - 1));
    if (borderFg > width + height) {
      cv::bitwise_not(fg, fg);
      scan.darkBackground = true;
    }
  }
  cv::Mat labels;
  cv::Mat stats;
  cv::Mat centroids;
  const int count = cv::connectedComponentsWithStats(fg, labels, stats, centroids, 8, CV_32S);
  const int leafLabel = largestLabel(stats, count, static_cast<int>(std::ceil(kMinLeafMm2 / pixelArea)));
  if (leafLabel < 0) {
    std::ostringstream msg;
    msg << "no leaf found: no dark object of at least " << kMinLeafMm2 << " mm^2 at " << options.dpi
        << " DPI (grey threshold " << scan.threshold << "); check --dpi and that the leaf lies on a light background";
    throw InputError(msg.str());
  }
  for (int l = 1; l < count; ++l) {
    if (l != leafLabel && stats.at<int>(l, cv::CC_STAT_AREA) * pixelArea >= kMinObjectMm2) ++scan.otherObjects;
  }
  const cv::Rect box(stats.at<int>(leafLabel, cv::CC_STAT_LEFT), stats.at<int>(leafLabel, cv::CC_STAT_TOP),
                     stats.at<int>(leafLabel, cv::CC_STAT_WIDTH), stats.at<int>(leafLabel, cv::CC_STAT_HEIGHT));
  scan.touchesBorder = box.x == 0 || box.y == 0 || box.x + box.width == width || box.y + box.height == height;

  // Work in the leaf's box, padded so that its border is background.
  const int petiolePx = static_cast<int>(std::lround(options.petioleWidthMm / scan.pixelMm));
  const int pad = std::max(2, petiolePx + 2);
  const cv::Rect roi = (box + cv::Point(-pad, -pad) + cv::Size(2 * pad, 2 * pad)) & cv::Rect(0, 0, width, height);
  cv::Mat leaf = cv::Mat::zeros(roi.height + 2, roi.width + 2, CV_8U);  // 1 px frame of background
  {
    cv::Mat inner = leaf(cv::Rect(1, 1, roi.width, roi.height));
    inner.setTo(255, labels(roi) == leafLabel);
  }
  // Holes: background parts not connected to the frame.
  cv::Mat filled;
  {
    cv::Mat outside = leaf.clone();
    cv::floodFill(outside, cv::Point(0, 0), cv::Scalar(128), nullptr, cv::Scalar(), cv::Scalar(), 4);
    filled = outside != 128;
    cv::Mat holeMask = filled & ~leaf;
    cv::Mat holeLabels;
    cv::Mat holeStats;
    cv::Mat holeCentroids;
    const int holeCount = cv::connectedComponentsWithStats(holeMask, holeLabels, holeStats, holeCentroids, 4, CV_32S);
    for (int l = 1; l < holeCount; ++l) {
      if (holeStats.at<int>(l, cv::CC_STAT_AREA) * pixelArea >= 0.5) ++scan.holes;
    }
  }
  // The petiole: a part of the filled leaf narrower than the petiole width (what an opening by
  // a disc of that diameter removes) and at least twice as long as wide, joined to the blade.
  cv::Mat blade = filled.clone();
  std::optional<Eigen::Vector2d> basePx;
  if (petiolePx >= 3) {
    const double r = petiolePx / 2.0;
    cv::Mat dist;
    cv::distanceTransform(filled, dist, cv::DIST_L2, cv::DIST_MASK_5);
    cv::Mat notCore = dist <= r;  // 255 where no disc of radius r fits
    cv::Mat toCore;
    cv::distanceTransform(notCore, toCore, cv::DIST_L2, cv::DIST_MASK_5);
    const cv::Mat opened = (toCore <= r) & filled;
    const cv::Mat thin = filled & ~opened;
    cv::Mat thinLabels;
    cv::Mat thinStats;
    cv::Mat thinCentroids;
    const int thinCount = cv::connectedComponentsWithStats(thin, thinLabels, thinStats, thinCentroids, 8, CV_32S);
    const int petiole = largestLabel(thinStats, thinCount, 2 * petiolePx * petiolePx);
    if (petiole >= 0 && cv::countNonZero(opened) > 0) {
      const cv::Mat petioleMask = thinLabels == petiole;
      cv::Mat grown;
      cv::dilate(opened, grown, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
      const cv::Mat joint = grown & petioleMask;
      const cv::Moments m = cv::moments(joint, true);
      if (m.m00 > 0.0) {
        scan.petioleFound = true;
        const int petiolePixels = cv::countNonZero(petioleMask & leaf);
        scan.petioleAreaMm2 = petiolePixels * pixelArea;
        blade.setTo(0, petioleMask);
        blade = largestPart(blade);
        basePx = Eigen::Vector2d(m.m10 / m.m00, m.m01 / m.m00);
      }
    }
  }
  const int filledPixels = cv::countNonZero(blade);
  const int tissuePixels = cv::countNonZero(blade & leaf);
  scan.filledAreaMm2 = filledPixels * pixelArea;
  scan.areaMm2 = tissuePixels * pixelArea;
  scan.holesAreaMm2 = scan.filledAreaMm2 - scan.areaMm2;

  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(blade, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  const auto outer = std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
    return std::abs(cv::contourArea(a)) < std::abs(cv::contourArea(b));
  });
  std::vector<cv::Point> simple;
  cv::approxPolyDP(*outer, simple, 0.5, true);
  // Pixel (c, r) of the ROI frame is image pixel (c - 1 + roi.x, r - 1 + roi.y); its centre
  // in mm, y up: ((col + 0.5) p, (height - row - 0.5) p).
  const auto toMm = [&](double c, double r) {
    return Eigen::Vector2d((c - 1 + roi.x + 0.5) * scan.pixelMm, (height - (r - 1 + roi.y) - 0.5) * scan.pixelMm);
  };
  for (const cv::Point& p : simple) scan.outline.pointsMm.push_back(toMm(p.x, p.y));
  if (basePx) {
    // The joint's centre, moved onto the nearest outline point (the base lies on the margin).
    const Eigen::Vector2d b = toMm(basePx->x(), basePx->y());
    scan.outline.baseMm =
        *std::min_element(scan.outline.pointsMm.begin(), scan.outline.pointsMm.end(),
                          [&](const auto& a, const auto& c) { return (a - b).squaredNorm() < (c - b).squaredNorm(); });
  }
  scan.outline.measuredAreaMm2 = scan.filledAreaMm2;
  if (scan.outline.pointsMm.size() < 8) throw InputError("no leaf found: the dark object is too small to outline");
  return scan;
}

LeafScan scanLeaf(const std::filesystem::path& path, const ScanOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string() + ": no such image file; check the path");
  }
  if (!(options.dpi > 0.0) || !std::isfinite(options.dpi))
    throw InputError(path.string() +
                     ": the scan's resolution is needed: give --dpi (e.g. 300, as set in the scanner's software)");
  // Its size from the header, bounded before a pixel is decoded.
  {
    std::ifstream in(path, std::ios::binary);
    const auto header = readImageHeader(in);
    if (!header)
      throw InputError(path.string() +
                       ": cannot decode the image: it is not a PNG, TIFF, JPEG or BMP (or its header "
                       "is damaged); give the scan as one of these");
    try {
      checkScanSize(header->width, header->height, options.dpi);
    } catch (const InputError& e) {
      throw InputError(path.string() + ": " + e.what());
    }
  }
  cv::Mat image;
  noteInput(path);  // read by OpenCV, not readFile: named so no output replaces it
  try {
    image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
  } catch (const cv::Exception& e) {
    throw InputError(path.string() + ": cannot decode the image (" + e.what() +
                     "); give a PNG, TIFF, JPEG or BMP scan");
  }
  if (image.empty()) {
    throw InputError(path.string() + ": cannot decode the image; give a PNG, TIFF, JPEG or BMP scan");
  }
  if (image.depth() != CV_8U) {
    cv::Mat eight;
    image.convertTo(eight, CV_8U, image.depth() == CV_16U ? 1.0 / 257.0 : 255.0);
    image = eight;
  }
  try {
    LeafScan scan = scanLeafPixels(image.ptr<std::uint8_t>(0), image.cols, image.rows, image.step[0], options);
    scan.outline.id = path.stem().string();
    return scan;
  } catch (const InputError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

void renderScan(const std::vector<std::vector<Eigen::Vector2d>>& leafPolygons,
                const std::vector<std::vector<Eigen::Vector2d>>& holes, const Eigen::Vector2d& pageMm, double dpi,
                const std::filesystem::path& png) {
  const std::string ext = lowerExtension(png);
  if (ext != ".png" && ext != ".tif" && ext != ".tiff") {
    throw InputError(png.string() + ": a synthetic scan is written as .png or .tif");
  }
  if (!(dpi > 0.0)) throw InputError("renderScan: dpi must be positive");
  const double pixel = 25.4 / dpi;
  const int width = static_cast<int>(std::ceil(pageMm.x() / pixel));
  const int height = static_cast<int>(std::ceil(pageMm.y() / pixel));
  if (width < 8 || height < 8 || static_cast<double>(width) * height > 4e8) {
    throw InputError("renderScan: the page is too small or too large");
  }
  cv::Mat image(height, width, CV_8UC1, cv::Scalar(255));
  // Coverage by 4 x 4 supersampling inside the polygons' box, averaged down (INTER_AREA):
  // an unbiased anti-aliased edge (OpenCV's LINE_AA fill grows a shape by about half a pixel).
  constexpr int kFactor = 4;
  constexpr int kShift = 8;  // sub-pixel vertices: 1/256 of a supersample
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const auto& poly : leafPolygons) {
    for (const auto& p : poly) {
      // Page pixels, continuous: x right, y down.
      const Eigen::Vector2d q(p.x() / pixel, height - p.y() / pixel);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  }
  if (lo.x() <= hi.x()) {
    const cv::Rect box =
        cv::Rect(static_cast<int>(std::floor(lo.x())) - 1, static_cast<int>(std::floor(lo.y())) - 1,
                 static_cast<int>(std::ceil(hi.x() - lo.x())) + 3, static_cast<int>(std::ceil(hi.y() - lo.y())) + 3) &
        cv::Rect(0, 0, width, height);
    const auto toSamples = [&](const std::vector<std::vector<Eigen::Vector2d>>& polygons) {
      std::vector<std::vector<cv::Point>> out;
      for (const auto& poly : polygons) {
        std::vector<cv::Point> pts;
        for (const auto& p : poly) {
          // Supersample (i, j) covers [i, i + 1) x [j, j + 1); OpenCV's integer coordinates are
          // sample centres, so continuous x maps to x - 0.5.
          const double x = (p.x() / pixel - box.x) * kFactor - 0.5;
          const double y = (height - p.y() / pixel - box.y) * kFactor - 0.5;
          pts.emplace_back(static_cast<int>(std::lround(x * (1 << kShift))),
                           static_cast<int>(std::lround(y * (1 << kShift))));
        }
        out.push_back(std::move(pts));
      }
      return out;
    };
    cv::Mat fine(box.height * kFactor, box.width * kFactor, CV_8UC1, cv::Scalar(0));
    // One polygon at a time: fillPoly fills several by the even-odd rule, and the leaf is
    // their union (a petiole overlapping the blade).
    for (const auto& poly : toSamples(leafPolygons))
      cv::fillPoly(fine, std::vector{poly}, cv::Scalar(255), cv::LINE_8, kShift);
    for (const auto& poly : toSamples(holes)) cv::fillPoly(fine, std::vector{poly}, cv::Scalar(0), cv::LINE_8, kShift);
    cv::Mat coverage;
    cv::resize(fine, coverage, box.size(), 0, 0, cv::INTER_AREA);
    // Leaf grey 60 on white: grey = 255 - 195 x coverage.
    cv::Mat roi = image(box);
    coverage.convertTo(roi, CV_8U, -195.0 / 255.0, 255.0);
  }
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(ext, image, bytes)) throw IoError(png.string() + ": " + ext + " encoding failed");
  writeFileAtomically(png, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace leafdig::model
