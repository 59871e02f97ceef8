#include "tools/render/overdraw_heatmap.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace pelt::render {

namespace {

// Stops of the ramp at t = k / 6, sRGB bytes: black, dark blue, blue, cyan, green, yellow, white.
// Their Rec. 709 luma rises from stop to stop (0, 28, 78, 140, 187, 218, 255) and only blue ever
// falls between two stops, so the picture also reads in grey: more fragments, never darker.
constexpr uint8_t kStops[7][3] = {{0, 0, 0},      {20, 20, 130},  {20, 80, 230},  {20, 170, 200},
                                  {140, 215, 50}, {255, 225, 40}, {255, 255, 255}};

}  // namespace

void heatmap_rgb8(uint32_t count, uint8_t rgb[3]) {
  const double t = std::min(1.0, std::log2(1.0 + double(count)) / std::log2(1.0 + double(kHeatmapTop)));
  const double x = t * 6.0;
  const int k = std::min(5, int(x));
  const double f = x - k;
  for (int c = 0; c < 3; ++c)
    rgb[c] = uint8_t(std::lround(kStops[k][c] + (double(kStops[k + 1][c]) - kStops[k][c]) * f));
}

std::vector<uint8_t> heatmap_rgb8(std::span<const uint32_t> counts) {
  // The ramp's kHeatmapTop + 1 colours once, rather than a logarithm a pixel.
  uint8_t table[kHeatmapTop + 1][3];
  for (uint32_t n = 0; n <= kHeatmapTop; ++n) heatmap_rgb8(n, table[n]);
  std::vector<uint8_t> out(counts.size() * 3);
  for (size_t i = 0; i < counts.size(); ++i) std::memcpy(out.data() + 3 * i, table[std::min(counts[i], kHeatmapTop)], 3);
  return out;
}

}  // namespace pelt::render
