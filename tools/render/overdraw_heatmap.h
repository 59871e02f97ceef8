// The overdraw AOV as a picture: per pixel, its count of translucent fragments through a colour
// ramp, for the PNG a technical artist opens to see where a frame's blending piles up (the TIFF
// and EXR keep the counts themselves).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace pelt::render {

// The ramp's top: this many fragments and more share its last colour. Fixed rather than the
// frame's largest count, so that pictures of different frames, scenes and settings compare.
inline constexpr uint32_t kHeatmapTop = 256;

// The ramp's sRGB colour for `count` fragments: black for none, then from dark blue through
// blue, cyan, green and yellow to white at kHeatmapTop, evenly in log2(1 + count), so that 1, 3,
// 7, 15, ... 255 fragments lie one eighth apart; brighter (Rec. 709 luma) with every step.
void heatmap_rgb8(uint32_t count, uint8_t rgb[3]);

// heatmap_rgb8 of every count, three bytes a pixel in the counts' order.
std::vector<uint8_t> heatmap_rgb8(std::span<const uint32_t> counts);

}  // namespace pelt::render
