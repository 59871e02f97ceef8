// The colour of per-vertex-lit fur fragments, the renderer's default fur path: the strand
// texel tinted and lit by the light the rasterizer interpolated from the fur vertices
// (shading/fur_lighting.h evaluates that light per vertex). Per 4x4 block b of a batch, lane l
// of it (i = 16 b + l) and channel c of 3:
//   out[c][i] = min(1, texel[c][i] * tint[c][b]) * diffuse[c][i] + specular[c][i]
// with min(1, NaN) = 1 (a NaN product is not below 1), a product, then a sum (no fused
// multiply-add), so the kernel and its scalar reference agree bit for bit on every input (a
// NaN output is NaN in both; its sign and payload are not arithmetic's to define).
// With `height` (the fins, whose colour runs from root to tip along the fin), the tint is per
// lane instead: tint_root[c] + tint_slope[c] * h, h = height[i] clamped to [0, 1] (NaN: 0),
// again a product, then a sum.
// About 1.5 M lanes a furry-box frame.
#pragma once

#include <cstddef>

namespace pelt::shading {

// The per-lane tint of one channel: root + slope h, h = height clamped to [0, 1] (NaN: 0), a
// product, then a sum. The reference uses it, and so does the fur shader's per-pixel path.
inline float height_tint(float root, float slope, float height) {
  const float h = height > 0.0f ? (height < 1.0f ? height : 1.0f) : 0.0f;
  return slope * h + root;
}

struct FurVertexLitSoA {
  size_t blocks = 0;                     // 16 lanes each
  const float* texel[3] = {};            // per lane; the three may be one array (luminance shells)
  const float* tint[3] = {};             // per block; not read with `height`
  const float* height = nullptr;         // per lane, or null (per-block tint)
  float tint_root[3] = {}, tint_slope[3] = {};  // the per-lane tint's, with `height`
  const float* diffuse[3] = {};          // per lane; may be one array (a grey light)
  const float* specular[3] = {};         // per lane; may be one array
  float* out[3] = {};                    // per lane; must not overlap an input
};

// Highway kernel, dispatched once per call; allocation-free. Throws std::invalid_argument
// naming the field when a pointer is null (blocks = 0 reads nothing).
void shade_fur_vertex_lit(const FurVertexLitSoA& batch);
// The scalar reference: the same expression, lane by lane.
void shade_fur_vertex_lit_reference(const FurVertexLitSoA& batch);

}  // namespace pelt::shading
