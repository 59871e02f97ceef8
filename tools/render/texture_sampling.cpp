#include "tools/render/texture_sampling.h"

#include <algorithm>

#include "raster/config.h"

namespace pelt::render {
namespace {

constexpr size_t kChunk = raster::kMaxBatchLanes;

struct alignas(64) Scratch {
  double texel[4][kChunk];
  float u[kChunk], v[kChunk];  // sample_placed's transformed coordinates
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

void sample_placed(const raster::Texture& tex, const io::MapPlacement& placement, raster::Filter filter,
                   const float* u, const float* v, size_t lanes, float* const out[4], bool double_precision,
                   const uint16_t* block_mask) {
  raster::SamplerState state;
  state.filter = filter;
  state.wrap_u = placement.wrap_u;
  state.wrap_v = placement.wrap_v;
  if (!placement.transforms()) return sample_texture(tex, state, u, v, lanes, out, double_precision, block_mask);
  Scratch& s = tls_scratch;
  // Chunks of whole 4x4 blocks: each block's level of detail is unchanged.
  for (size_t first = 0; first < lanes; first += kChunk) {
    const size_t n = std::min(kChunk, lanes - first);
    for (size_t i = 0; i < n; ++i) {
      s.u[i] = placement.u_at(u[first + i], v[first + i]);
      s.v[i] = placement.v_at(u[first + i], v[first + i]);
    }
    float* const part[4] = {out[0] + first, out[1] + first, out[2] + first, out[3] + first};
    sample_texture(tex, state, s.u, s.v, n, part, double_precision,
                   block_mask ? block_mask + first / raster::kBlockLanes : nullptr);
  }
}

}  // namespace pelt::render
