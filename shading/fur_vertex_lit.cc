// The per-vertex-lit fur colour kernel (fur_vertex_lit.h), compiled per Highway target, and its
// scalar reference. Written as a kernel because the compiler's own vectorization of the scalar
// loop, at the baseline's SSE2 width and with the min as compare-and-blend, took about 6 % of
// a one-thread furry-box frame.

#include <stdexcept>
#include <string>

#include "shading/fur_vertex_lit.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shading/fur_vertex_lit.cc"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace pelt::shading::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The whole batch, vector by vector (16 lanes a block, a multiple of every width). kHeight: the
// fins' per-lane tint from the lane's height, root to tip (else the block's tint). kShared: one
// texel, diffuse and specular array for all three channels (a luminance shell or fin under a
// grey light, the renderer's usual case), each loaded once per lane instead of three times.
template <bool kHeight, bool kShared>
HWY_INLINE void LitLanes(const FurVertexLitSoA& b) {
  const hn::ScalableTag<float> d;
  using V = hn::Vec<decltype(d)>;
  const size_t n = hn::Lanes(d);
  const V one = hn::Set(d, 1.0f), zero = hn::Zero(d);
  for (size_t i = 0; i < b.blocks * 16; i += n) {
    V h = zero;
    if constexpr (kHeight) {
      const V x = hn::LoadU(d, b.height + i);
      h = hn::IfThenElse(hn::Gt(x, zero), hn::IfThenElse(hn::Lt(x, one), x, one), zero);
    }
    V texel = zero, diffuse = zero, specular = zero;
    if constexpr (kShared) {
      texel = hn::LoadU(d, b.texel[0] + i);
      diffuse = hn::LoadU(d, b.diffuse[0] + i);
      specular = hn::LoadU(d, b.specular[0] + i);
    }
    for (int c = 0; c < 3; ++c) {
      if constexpr (!kShared) {
        texel = hn::LoadU(d, b.texel[c] + i);
        diffuse = hn::LoadU(d, b.diffuse[c] + i);
        specular = hn::LoadU(d, b.specular[c] + i);
      }
      V tint;
      if constexpr (kHeight) {
        tint = hn::Add(hn::Mul(hn::Set(d, b.tint_slope[c]), h), hn::Set(d, b.tint_root[c]));
      } else {
        tint = hn::Set(d, b.tint[c][i / 16]);
      }
      const V p = hn::Mul(texel, tint);
      hn::StoreU(hn::Add(hn::Mul(hn::IfThenElse(hn::Lt(p, one), p, one), diffuse), specular), d, b.out[c] + i);
    }
  }
}

void FurVertexLitBatch(const FurVertexLitSoA& b) {
  const bool shared = b.texel[0] == b.texel[1] && b.texel[0] == b.texel[2] && b.diffuse[0] == b.diffuse[1] &&
                      b.diffuse[0] == b.diffuse[2] && b.specular[0] == b.specular[1] &&
                      b.specular[0] == b.specular[2];
  if (b.height) {
    shared ? LitLanes<true, true>(b) : LitLanes<true, false>(b);
  } else {
    shared ? LitLanes<false, true>(b) : LitLanes<false, false>(b);
  }
}

}  // namespace pelt::shading::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::shading {

HWY_EXPORT(FurVertexLitBatch);

namespace {

void require(const void* p, const char* field, int channel) {
  if (p) return;
  std::string message = "shade_fur_vertex_lit: ";
  message += field;
  message += '[';
  message += std::to_string(channel);
  message += "] is null";
  throw std::invalid_argument(message);
}

void check(const FurVertexLitSoA& b) {
  if (b.blocks == 0) return;
  for (int c = 0; c < 3; ++c) {
    require(b.texel[c], "texel", c);
    if (!b.height) require(b.tint[c], "tint", c);
    require(b.diffuse[c], "diffuse", c);
    require(b.specular[c], "specular", c);
    require(b.out[c], "out", c);
  }
}

}  // namespace

void shade_fur_vertex_lit(const FurVertexLitSoA& batch) {
  check(batch);
  if (batch.blocks == 0) return;
  HWY_DYNAMIC_DISPATCH(FurVertexLitBatch)(batch);
}

void shade_fur_vertex_lit_reference(const FurVertexLitSoA& b) {
  check(b);
  for (size_t blk = 0; blk < b.blocks; ++blk)
    for (int c = 0; c < 3; ++c)
      for (size_t i = blk * 16; i < blk * 16 + 16; ++i) {
        const float tint = b.height ? height_tint(b.tint_root[c], b.tint_slope[c], b.height[i]) : b.tint[c][blk];
        const float p = b.texel[c][i] * tint;
        const float clamped = p < 1.0f ? p : 1.0f;
        b.out[c][i] = clamped * b.diffuse[c][i] + b.specular[c][i];
      }
}

}  // namespace pelt::shading
#endif  // HWY_ONCE
