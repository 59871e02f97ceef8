// The overdraw picture's ramp: black for no fragment, white from kHeatmapTop on, and brighter
// with more fragments in between, so that the PNG reads as counts even in grey.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "tools/render/overdraw_heatmap.h"

namespace pelt::render::test {
namespace {

// Rec. 709 weights on the sRGB bytes: enough to order the ramp's colours by brightness.
double luma(const uint8_t rgb[3]) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

TEST(OverdrawHeatmap, BlackForNoneWhiteAtTheTopBrighterInBetween) {
  uint8_t rgb[3];
  heatmap_rgb8(0, rgb);
  EXPECT_EQ(rgb[0] + rgb[1] + rgb[2], 0);
  for (uint32_t n : {kHeatmapTop, kHeatmapTop + 1, 100000u, UINT32_MAX}) {
    heatmap_rgb8(n, rgb);
    EXPECT_EQ(rgb[0] & rgb[1] & rgb[2], 255) << n;
  }
  // Never darker with a fragment more (within the rounding of blue, the one channel that falls
  // between stops, to a byte), and clearly brighter with each doubling.
  uint8_t prev[3];
  heatmap_rgb8(0, prev);
  for (uint32_t n = 1; n <= kHeatmapTop; ++n) {
    heatmap_rgb8(n, rgb);
    EXPECT_GE(luma(rgb) + 0.08, luma(prev)) << n;
    for (int c = 0; c < 3; ++c) prev[c] = rgb[c];
  }
  heatmap_rgb8(0, prev);
  for (uint32_t n = 1; n <= kHeatmapTop; n *= 2) {
    heatmap_rgb8(n, rgb);
    EXPECT_GT(luma(rgb), luma(prev) + 4.0) << n;
    for (int c = 0; c < 3; ++c) prev[c] = rgb[c];
  }
  // 1, 3, 7, ... 255 fragments one eighth of the ramp apart: 1 is well off black, 128 well below white.
  heatmap_rgb8(1, rgb);
  EXPECT_GT(luma(rgb), 15.0);
  heatmap_rgb8(128, rgb);
  EXPECT_LT(luma(rgb), 240.0);
}

TEST(OverdrawHeatmap, APlaneIsItsPixelsInOrder) {
  const std::vector<uint32_t> counts = {0, 1, 7, 300, 16, 2};
  const std::vector<uint8_t> plane = heatmap_rgb8(counts);
  ASSERT_EQ(plane.size(), counts.size() * 3);
  for (size_t i = 0; i < counts.size(); ++i) {
    uint8_t rgb[3];
    heatmap_rgb8(counts[i], rgb);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(plane[3 * i + c], rgb[c]) << i;
  }
}

}  // namespace
}  // namespace pelt::render::test
