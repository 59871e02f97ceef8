#include "tools/render/texture_sampling.h"

#include <algorithm>

#include "raster/config.h"

namespace pelt::render {
namespace {

constexpr size_t kChunk = raster::kMaxBatchLanes;

struct alignas(64) Scratch {
  double texel[4][kChunk];
};
thread_local Scratch tls_scratch;

}  // namespace

void sample_texture(const raster::Texture& tex, const raster::SamplerState& state, const float* u,
                    const float* v, size_t lanes, float* const out[4], bool double_precision,
                    const uint16_t* block_mask) {
  if (!double_precision) {
    raster::sample(tex, state, u, v, lanes, out, block_mask);
    return;
  }
  Scratch& s = tls_scratch;
  double* const d[4] = {s.texel[0], s.texel[1], s.texel[2], s.texel[3]};
  // Chunks are whole 4x4 blocks, so each block's level of detail is unchanged.
  for (size_t first = 0; first < lanes; first += kChunk) {
    const size_t n = std::min(kChunk, lanes - first);
    raster::sample_reference(tex, state, u + first, v + first, n, d,
                             block_mask ? block_mask + first / raster::kBlockLanes : nullptr);
    for (int c = 0; c < 4; ++c)
      for (size_t i = 0; i < n; ++i) out[c][first + i] = static_cast<float>(d[c][i]);
  }
}

}  // namespace pelt::render
