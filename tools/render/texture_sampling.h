// Texture sampling at the frame's precision: the SIMD sampler, or (the double-precision
// quality) raster::sample_reference evaluated in double and rounded to float once.
#pragma once

#include <cstddef>
#include <cstdint>

#include "raster/texture.h"
#include "tools/io/map_placement.h"

namespace pelt::render {

// As raster::sample; `lanes` a multiple of 16, any count (the reference runs in chunks of
// raster::kMaxBatchLanes through per-thread scratch, so nothing is allocated).
void sample_texture(const raster::Texture& tex, const raster::SamplerState& state, const float* u,
                    const float* v, size_t lanes, float* const out[4], bool double_precision,
                    const uint16_t* block_mask = nullptr);

// A map sampled where its mesh file places it: at the placement's transform of (u, v) (an
// affine map of uv commutes with the rasterizer's interpolation, so the transformed uv is the
// one a vertex transform would give; the level of detail follows the transformed derivatives),
// wrapped as the placement says. Without a transform, sample_texture at (u, v) itself.
void sample_placed(const raster::Texture& tex, const io::MapPlacement& placement, raster::Filter filter,
                   const float* u, const float* v, size_t lanes, float* const out[4], bool double_precision,
                   const uint16_t* block_mask = nullptr);

}  // namespace pelt::render
