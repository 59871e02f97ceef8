// Texture sampling at the frame's precision: the SIMD sampler, or (the double-precision
// quality) raster::sample_reference evaluated in double and rounded to float once.
#pragma once

#include <cstddef>
#include <cstdint>

#include "raster/texture.h"

namespace pelt::render {

// As raster::sample; `lanes` a multiple of 16, any count (the reference runs in chunks of
// raster::kMaxBatchLanes through per-thread scratch, so nothing is allocated).
void sample_texture(const raster::Texture& tex, const raster::SamplerState& state, const float* u,
                    const float* v, size_t lanes, float* const out[4], bool double_precision,
                    const uint16_t* block_mask = nullptr);

}  // namespace pelt::render
