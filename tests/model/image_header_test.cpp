// Image sizes from headers alone (the scan's bound is checked before OpenCV decodes): the
// seed corpus of the fuzzer, a real PNG written by OpenCV's reader's peer (renderScan), and
// what is not an image or is cut short.
#include "leafdig/model/image_header.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace m = leafdig::model;

namespace {

std::optional<m::ImageHeader> headerOf(const std::string& bytes) {
  std::istringstream in(bytes);
  return m::readImageHeader(in);
}

std::string corpus(const std::string& name) {
  std::ifstream in(std::string(LEAFDIG_SOURCE_DIR) + "/tests/fuzz/corpus/image_header/" + name, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ImageHeader, ReadsTheSizeOfEachFormatFromItsHeader) {
  struct Case {
    const char* file;
    const char* format;
    std::uint32_t width, height;
  };
  for (const Case& c :
       {Case{"grey.png", "PNG", 3, 2}, Case{"top-down.bmp", "BMP", 2, 2}, Case{"little.tif", "TIFF", 640, 480},
        Case{"big.tif", "TIFF", 640, 480}, Case{"baseline.jpg", "JPEG", 640, 480}}) {
    const auto h = headerOf(corpus(c.file));
    ASSERT_TRUE(h.has_value()) << c.file;
    EXPECT_EQ(h->format, c.format) << c.file;
    EXPECT_EQ(h->width, c.width) << c.file;
    EXPECT_EQ(h->height, c.height) << c.file;
  }
}

TEST(ImageHeader, NothingForWhatIsNotAnImageOrIsCutShort) {
  EXPECT_FALSE(headerOf("").has_value());
  EXPECT_FALSE(headerOf("leaf,x,y\n1,2,3\n").has_value());
  for (const char* file : {"grey.png", "baseline.jpg", "little.tif", "top-down.bmp"}) {
    const std::string bytes = corpus(file);
    EXPECT_FALSE(headerOf(bytes.substr(0, 12)).has_value()) << file;
  }
  // A JPEG whose segments loop on themselves (a length of 2 forever) ends, with nothing.
  std::string loop("\xff\xd8", 2);
  for (int i = 0; i < 20000; ++i) loop += std::string("\xff\xe1\x00\x02", 4);
  EXPECT_FALSE(headerOf(loop).has_value());
}

}  // namespace
