// The scalar reference rasterizer: one pixel at a time, exact int64 edge functions
// evaluated directly at every pixel centre of the viewport, the top-left rule applied
// literally. It shares with pelt only the clipper, the snapping and the depth-plane
// formula (the contract the SIMD kernels must reproduce bit for bit); coverage, culling,
// orientation and bounding are computed independently.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "raster/pipeline.h"

namespace pelt::raster::test {

// A fragment that passed the depth test: its draw (index into the draws), triangle and depth.
struct ReferenceFragment {
  uint32_t draw = 0, primitive = 0;
  float depth = 0.0f;
};

struct ReferenceImage {
  int width = 0, height = 0;
  std::vector<float> depth;      // 1 where empty
  std::vector<uint32_t> id;      // 0 where empty
  std::vector<uint32_t> count;   // fragments that passed the depth test, per pixel
  // With record_fragments: per pixel, those fragments in the order they were drawn.
  std::vector<std::vector<ReferenceFragment>> fragments;
};

// A fragment's alpha, for alpha-tested draws: of draw `draw`'s triangle `primitive` at pixel
// (px, py).
using ReferenceAlpha = std::function<float(uint32_t draw, uint32_t primitive, int px, int py)>;

// Opaque draws only (state.blend == Opaque), in order; honours depth_func and cull. Draws with
// state.alpha_test come after all the others, in their order, and keep only fragments whose
// `alpha` reaches the cutoff (the renderer's contract, PipelineState::alpha_test).
ReferenceImage reference_render(std::span<const DrawCall> draws, int width, int height,
                                bool record_fragments = false, const ReferenceAlpha& alpha = {});

// Inside test of pixel (px, py) against a triangle of snapped vertices (1/256 pixel,
// y down) with positive orientation, by the literal top-left rule.
bool reference_covers(const int32_t x[3], const int32_t y[3], int32_t px, int32_t py);

}  // namespace pelt::raster::test
