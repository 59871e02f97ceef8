// The texture sampler, written once with Highway and compiled for every target; dispatched
// once per sample() call. See raster/texture.h for the contract.
//
// Per vector of lanes: texel coordinates and wrapped integer indices per axis, one 32-bit
// gather per texel (RGBA8) or pair of 2-byte texels (La8), bytes unpacked with shifts (sRGB
// colour through a gather from the 256-float table), weighted straight (no division: the texture's
// transparent texels carry their surroundings' colour, see texture.h) and scaled once at the
// end. A 4x4 block's vectors are sampled together (SampleBlock), and its level pair is chosen
// per block before the sampling (ClampedLambdas), so every gather of a vector reads one level
// whose base and width are scalars.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/texture_kernels.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "raster/block_mask-inl.h"
#include "raster/config.h"
#include "raster/texture.h"

HWY_BEFORE_NAMESPACE();
namespace pelt::raster {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;

struct LevelView {
  const uint32_t* texels;  // Rgba8
  const uint16_t* la;      // La8
  int32_t w, h, stride;
};

LevelView View(const Texture& tex, int k) {
  const MipLevel& L = tex.level(k);
  return LevelView{tex.level_texels(k), tex.level_la(k), L.width, L.height, L.stride};
}

// The 32-bit word at texel index idx of every lane: the texel (Rgba8), or the 2-byte texel in
// the low half and its right neighbour in the high half (La8: a gather at byte offset 2 idx;
// indices stay below 2^29, kMaxTextureSide squared plus padding).
template <bool kLa>
HWY_INLINE hn::Vec<DU> FetchWord(const LevelView& L, VI idx) {
  if constexpr (kLa) {
    return hn::GatherOffset(DU(), reinterpret_cast<const uint32_t*>(L.la), hn::ShiftLeft<1>(idx));
  } else {
    return hn::GatherIndex(DU(), L.texels, idx);
  }
}

struct Acc {
  VF c[4];  // sum of w * channel (colour in bytes or linear, alpha in bytes)
};

// Continuous texel coordinate of c along an axis of `size` texels (texel centres at
// integers): repeat wraps c to [0, 1] first, so x lies in [-0.5, size - 0.5]; clamp keeps
// x within two texels of the edge. The float clamps change no finite in-range value; they
// give NaN and huge inputs a defined index (x86 and scalar Min/Max return the second
// operand for NaN).
HWY_INLINE VF TexelCoord(VF c, int32_t size, bool repeat) {
  const DF df;
  const VF fsize = hn::Set(df, float(size));
  if (repeat) {
    c = hn::Sub(c, hn::Floor(c));
    const VF x = hn::Sub(hn::Mul(c, fsize), hn::Set(df, 0.5f));
    return hn::Max(hn::Min(x, hn::Set(df, float(size) - 0.5f)), hn::Set(df, -0.5f));
  }
  const VF x = hn::Sub(hn::Mul(c, fsize), hn::Set(df, 0.5f));
  return hn::Max(hn::Min(x, hn::Set(df, float(size) + 1.0f)), hn::Set(df, -2.0f));
}

// Repeat on a power-of-two axis (every level of a power-of-two texture): TexelCoord's x,
// floor and fraction, with the wrap of x0 = -1 (and of x0 + 1 = size) as a mask instead of a
// compare and a blend. Bit for bit the general path: x lies in [-0.5, size - 0.5] already,
// so of TexelCoord's clamps only the Min that maps NaN to size - 0.5 does anything.
HWY_INLINE bool IsPow2(int32_t size) { return (size & (size - 1)) == 0; }

HWY_INLINE VI RepeatPow2(VF c, int32_t size, VF& frac) {
  const DF df;
  const DI di;
  c = hn::Sub(c, hn::Floor(c));
  const VF x = hn::Min(hn::Sub(hn::Mul(c, hn::Set(df, float(size))), hn::Set(df, 0.5f)),
                       hn::Set(df, float(size) - 0.5f));
  const VF xf = hn::Floor(x);
  frac = hn::Sub(x, xf);
  return hn::ConvertTo(di, xf);
}

// The two texel indices around coordinate c along an axis of `size` texels and the weight
// of the second. Repeat: x lies in [-0.5, size - 0.5] (TexelCoord), so only i0 = -1 and
// i1 = size need wrapping.
HWY_INLINE void AxisLinear(VF c, int32_t size, bool repeat, VI& i0, VI& i1, VF& frac) {
  const DI di;
  if (repeat && IsPow2(size)) {
    const VI mask = hn::Set(di, size - 1);
    const VI i = RepeatPow2(c, size, frac);
    i0 = hn::And(i, mask);
    i1 = hn::And(hn::Add(i, hn::Set(di, 1)), mask);
    return;
  }
  const VI isize = hn::Set(di, size);
  const VF x = TexelCoord(c, size, repeat);
  const VF xf = hn::Floor(x);
  frac = hn::Sub(x, xf);
  i0 = hn::ConvertTo(di, xf);
  i1 = hn::Add(i0, hn::Set(di, 1));
  if (repeat) {
    i0 = hn::IfThenElse(hn::Lt(i0, hn::Zero(di)), hn::Add(i0, isize), i0);
    i1 = hn::IfThenElse(hn::Gt(i1, hn::Set(di, size - 1)), hn::Sub(i1, isize), i1);
  } else {
    const VI last = hn::Set(di, size - 1);
    i0 = hn::Min(hn::Max(i0, hn::Zero(di)), last);
    i1 = hn::Min(hn::Max(i1, hn::Zero(di)), last);
  }
}

// The left texel x0 of the horizontal pair (x0, x0 + 1) around coordinate c and the weight
// of x0 + 1. The padding texel (index width, a copy of texel 0) makes the pair adjacent in
// memory for every x0 in [0, width - 1]: repeat wraps x0 = -1 to width - 1 and the pair's
// right texel is the padding; clamp puts all the weight on the edge texel (frac = 0) where
// both indices would clamp to it, which also keeps x0 + 1 <= width.
HWY_INLINE void AxisPair(VF c, int32_t size, bool repeat, VI& i0, VF& frac) {
  const DF df;
  const DI di;
  if (repeat && IsPow2(size)) {
    i0 = hn::And(RepeatPow2(c, size, frac), hn::Set(di, size - 1));
    return;
  }
  const VF x = TexelCoord(c, size, repeat);
  const VF xf = hn::Floor(x);
  frac = hn::Sub(x, xf);
  i0 = hn::ConvertTo(di, xf);
  if (repeat) {
    i0 = hn::IfThenElse(hn::Lt(i0, hn::Zero(di)), hn::Add(i0, hn::Set(di, size)), i0);
  } else {
    const VI last = hn::Set(di, size - 1);
    const auto edge = hn::Or(hn::Lt(i0, hn::Zero(di)), hn::Gt(i0, hn::Set(di, size - 2)));
    frac = hn::IfThenZeroElse(hn::RebindMask(df, edge), frac);
    i0 = hn::Min(hn::Max(i0, hn::Zero(di)), last);
  }
}

// RGBA8 texels idx and idx + 1 of every lane: two 32-bit gathers. (One 64-bit gather per lane
// fetches the pair too, but with the widening of the offsets and the even/odd split it
// measured no faster on the Zen 3 machine, so the simpler form stays.)
HWY_INLINE void FetchPair(const LevelView& L, VI idx, hn::Vec<DU>& left, hn::Vec<DU>& right) {
  left = FetchWord<false>(L, idx);
  right = FetchWord<false>(L, hn::Add(idx, hn::Set(DI(), 1)));
}

// The texel index under coordinate c (nearest).
HWY_INLINE VI AxisNearest(VF c, int32_t size, bool repeat) {
  const DF df;
  const DI di;
  const VF fsize = hn::Set(df, float(size));
  const VI isize = hn::Set(di, size);
  if (repeat) {
    c = hn::Sub(c, hn::Floor(c));
    const VF x = hn::Max(hn::Min(hn::Mul(c, fsize), fsize), hn::Zero(df));
    const VI i = hn::ConvertTo(di, x);  // x >= 0: truncation is floor
    return hn::IfThenElse(hn::Gt(i, hn::Set(di, size - 1)), hn::Sub(i, isize), i);
  }
  const VF x = hn::Max(hn::Min(hn::Mul(c, fsize), fsize), hn::Set(df, -1.0f));
  const VI i = hn::ConvertTo(di, hn::Floor(x));
  return hn::Min(hn::Max(i, hn::Zero(di)), hn::Set(di, size - 1));
}

struct Decoded {
  VF c[3];
  VF a;  // bytes
};

// Colour in bytes (linear) or linear [0, 1] (sRGB), alpha in bytes.
template <bool kSrgb>
HWY_INLINE Decoded Decode(hn::Vec<DU> t, const float* srgb) {
  const DF df;
  const DI di;
  const VI ti = hn::BitCast(di, t);
  const VI m = hn::Set(di, 0xFF);
  const VI b[3] = {hn::And(ti, m), hn::And(hn::ShiftRight<8>(ti), m), hn::And(hn::ShiftRight<16>(ti), m)};
  Decoded d;
  for (int ch = 0; ch < 3; ++ch)
    d.c[ch] = kSrgb ? hn::GatherIndex(df, srgb, b[ch]) : hn::ConvertTo(df, b[ch]);
  d.a = hn::ConvertTo(df, hn::BitCast(di, hn::ShiftRight<24>(t)));
  return d;
}

template <bool kSrgb>
HWY_INLINE void Tap(hn::Vec<DU> texel, VF w, const float* srgb, Acc& acc) {
  const Decoded d = Decode<kSrgb>(texel, srgb);
  for (int ch = 0; ch < 3; ++ch) acc.c[ch] = hn::MulAdd(w, d.c[ch], acc.c[ch]);
  acc.c[3] = hn::MulAdd(w, d.a, acc.c[3]);
}

// A bilinear footprint on level L: the texel indices of its top and bottom left texels and
// the four weights (top left, top right, bottom left, bottom right), scaled by `weight`.
struct Footprint {
  VI top, bottom;
  VF w[4];
};

HWY_INLINE Footprint FootprintOf(const LevelView& L, VF u, VF v, bool rep_u, bool rep_v, VF weight) {
  const DF df;
  const DI di;
  VI x0, y0, y1;
  VF ax, ay;
  AxisPair(u, L.w, rep_u, x0, ax);
  AxisLinear(v, L.h, rep_v, y0, y1, ay);
  const VI stride = hn::Set(di, L.stride);
  const VF one = hn::Set(df, 1.0f);
  const VF wy1 = hn::Mul(ay, weight);
  const VF wy0 = hn::Mul(hn::Sub(one, ay), weight);
  const VF bx = hn::Sub(one, ax);
  return Footprint{hn::Add(hn::Mul(y0, stride), x0),
                   hn::Add(hn::Mul(y1, stride), x0),
                   {hn::Mul(bx, wy0), hn::Mul(ax, wy0), hn::Mul(bx, wy1), hn::Mul(ax, wy1)}};
}

// ---- Level of detail (texture.h), per chunk of blocks ----

// block_lod_length2 with four-lane double vectors, where the target has them (AVX2 and up):
// the same differences, pair sums, products and comparison, so the same double. One block's
// rows are four vectors; its first and last columns come from two transposing shuffles each.
// (The scalar function took about 50 cycles a block here.)
HWY_INLINE double BlockLength2(const float* HWY_RESTRICT u, const float* HWY_RESTRICT v, int32_t width,
                               int32_t height) {
#if HWY_TARGET == HWY_SCALAR
  return block_lod_length2(u, v, width, height);
#else
  using D4 = hn::CappedTag<double, 4>;
  if constexpr (hn::MaxLanes(D4()) < 4) {
    return block_lod_length2(u, v, width, height);
  } else {
    const D4 d;
    const hn::Rebind<float, D4> f4;
    using V = hn::Vec<D4>;
    // Per row r, last - first; per column c, bottom - top: both exact in double.
    auto differences = [&](const float* p, V& per_row, V& per_column) {
      V r[4];
      for (int k = 0; k < 4; ++k) r[k] = hn::PromoteTo(d, hn::LoadU(f4, p + 4 * k));
      const V first = hn::ConcatLowerLower(d, hn::InterleaveLower(d, r[2], r[3]), hn::InterleaveLower(d, r[0], r[1]));
      const V last = hn::ConcatUpperUpper(d, hn::InterleaveUpper(d, r[2], r[3]), hn::InterleaveUpper(d, r[0], r[1]));
      per_row = hn::Sub(last, first);
      per_column = hn::Sub(r[3], r[0]);
    };
    V ux, vx, uy, vy;
    differences(u, ux, uy);
    differences(v, vx, vy);
    // Pair sums: lanes (0 + 1) and (2 + 3) of two vectors side by side, then those added.
    const V x = hn::Add(hn::InterleaveLower(d, ux, vx), hn::InterleaveUpper(d, ux, vx));
    const V y = hn::Add(hn::InterleaveLower(d, uy, vy), hn::InterleaveUpper(d, uy, vy));
    const V sums = hn::Add(hn::ConcatLowerLower(d, y, x), hn::ConcatUpperUpper(d, y, x));  // ux vx uy vy
    const double sx = width / 12.0, sy = height / 12.0;
    alignas(32) const double scale[4] = {sx, sy, sx, sy};
    const V scaled = hn::Mul(sums, hn::Load(d, scale));
    alignas(32) double sq[4];
    hn::Store(hn::Mul(scaled, scaled), d, sq);
    const double lx = sq[0] + sq[1], ly = sq[2] + sq[3];
    return lx < ly ? ly : lx;
  }
#endif
}

// clamped[k] = the level of detail of length2[k] as the reference clamps it: 0.5 log2(length2)
// + bias within [0, top]; NaN, 0 and -inf give 0, +inf gives top. `count` is a multiple of the
// double vector's lanes. log2 = the exponent plus log2 of the mantissa in [1, 2), so a power of
// two gives an exact integer (trilinear then reads one level, as with std::log2); elsewhere
// Highway's Log differs from std::log2 by an ulp or two, far below what moves a sample.
HWY_INLINE void ClampedLambdas(const double* HWY_RESTRICT length2, size_t count, double bias, double top,
                               double* HWY_RESTRICT clamped) {
  const hn::ScalableTag<double> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  const V inf = hn::Set(d, HUGE_VAL);
  const V kMinNormal = hn::Set(d, 0x1p-1022);
  for (size_t k = 0; k < count; k += hn::Lanes(d)) {
    const V x = hn::LoadU(d, length2 + k);
    // Subnormal lengths are scaled into the normal range first, their exponent corrected.
    const auto tiny = hn::Lt(x, kMinNormal);
    const V xs = hn::IfThenElse(tiny, hn::Mul(x, hn::Set(d, 0x1p64)), x);
    const auto bits = hn::BitCast(du, xs);
    // The biased exponent as a double: its integer in a mantissa of 2^52, minus 2^52.
    const V biased = hn::Sub(hn::BitCast(d, hn::Or(hn::ShiftRight<52>(bits), hn::Set(du, 0x4330000000000000ull))),
                             hn::Set(d, 0x1p52));
    const V exponent = hn::Sub(biased, hn::IfThenElse(tiny, hn::Set(d, 1023.0 + 64.0), hn::Set(d, 1023.0)));
    const V mantissa =
        hn::BitCast(d, hn::Or(hn::And(bits, hn::Set(du, 0x000FFFFFFFFFFFFFull)), hn::Set(du, 0x3FF0000000000000ull)));
    const V log2x = hn::Add(exponent, hn::Mul(hn::Log(d, mantissa), hn::Set(d, 1.4426950408889634)));
    const V lambda = hn::Add(hn::Mul(hn::Set(d, 0.5), log2x), hn::Set(d, bias));
    const V finite = hn::IfThenElseZero(hn::Gt(lambda, hn::Zero(d)), hn::Min(lambda, hn::Set(d, top)));
    const auto valid = hn::And(hn::Gt(x, hn::Zero(d)), hn::Lt(x, inf));  // NaN: false
    hn::StoreU(hn::IfThenElse(hn::Eq(x, inf), hn::Set(d, top), hn::IfThenElseZero(valid, finite)), d, clamped + k);
  }
}

// The sampler takes its blocks in chunks of this many: their levels first, then their taps.
constexpr size_t kChunkBlocks = 64;  // a multiple of every target's double lanes

// clamped[k] for the count <= kChunkBlocks blocks at u, v (16 floats a block): the clamped LOD
// of block k, or 0 for a block outside `block_mask` (one per block; null: all sampled).
HWY_INLINE void ChunkLods(const float* HWY_RESTRICT u, const float* HWY_RESTRICT v, size_t count,
                          const uint16_t* block_mask, int32_t width, int32_t height, double bias, double top,
                          double* HWY_RESTRICT clamped) {
  HWY_ALIGN double length2[kChunkBlocks];
  const size_t double_lanes = hn::Lanes(hn::ScalableTag<double>());
  const size_t padded = (count + double_lanes - 1) / double_lanes * double_lanes;
  for (size_t k = 0; k < padded; ++k) {
    const bool sampled = k < count && !(block_mask && block_mask[k] == 0);
    length2[k] = sampled ? BlockLength2(u + k * kBlockLanes, v + k * kBlockLanes, width, height) : 0.0;
  }
  ClampedLambdas(length2, padded, bias, top, clamped);
}

// One 4x4 block, bilinear on kLevels levels (two for trilinear, weights 1 - t and t), its
// kGroups vectors of lanes at once: the footprints and all the gathers of the block's wanted
// vectors first, then their taps. Vector by vector, each vector's taps waited on its own
// gathers before the next vector's were issued; issued together, the gathers overlap: on AVX2
// (texture_bench, 4 texels a pixel, two alternations) La8 trilinear 164-181 against 151-157
// M samples/s, RGBA8 bilinear 216-223 against 184-190, sRGB bilinear 114-119 against 87-90, and
// one-thread fur frames about 6 % faster. A vector without a wanted lane is not sampled and
// reads 0 (a partly covered block's other half, about a tenth of a fur frame's vectors).
//
// RGBA8: one gather per texel, four per footprint, each texel decoded and weighted (Tap).
// La8 (texture.h): a 32-bit read at a texel holds it and its right neighbour as (L, A) pairs,
// so one gather per row fetches a footprint's two texels (FetchWord); the weights and the
// order of the multiply-adds are those of RGBA8, so a La8 texture samples bit for bit like the
// RGBA8 texture with R = G = B = L (acc.c[1], acc.c[2] stay unused).
template <size_t kGroups, int kLevels, bool kSrgb, bool kLa>
HWY_INLINE void SampleBlock(const LevelView (&level)[2], const float (&weight)[2], const float* HWY_RESTRICT u,
                            const float* HWY_RESTRICT v, bool rep_u, bool rep_v, uint32_t wanted, const float* srgb,
                            float* const out[4], size_t b) {
  const DF df;
  const DI di;
  const DU du;
  const size_t N = hn::Lanes(df);
  constexpr int kWords = kLa ? 2 : 4;  // per footprint: (top, bottom) pairs, or the four texels
  Footprint f[kLevels][kGroups];
  hn::Vec<DU> word[kLevels][kGroups][kWords];
  bool want[kGroups];
  for (size_t g = 0; g < kGroups; ++g) want[g] = ((wanted >> (g * N)) & GroupBits()) != 0;
  for (size_t g = 0; g < kGroups; ++g) {
    if (!want[g]) continue;
    const VF uu = hn::LoadU(df, u + b + g * N), vv = hn::LoadU(df, v + b + g * N);
    for (int k = 0; k < kLevels; ++k) f[k][g] = FootprintOf(level[k], uu, vv, rep_u, rep_v, hn::Set(df, weight[k]));
  }
  for (int k = 0; k < kLevels; ++k)
    for (size_t g = 0; g < kGroups; ++g) {
      if (!want[g]) continue;
      if constexpr (kLa) {
        word[k][g][0] = FetchWord<true>(level[k], f[k][g].top);
        word[k][g][1] = FetchWord<true>(level[k], f[k][g].bottom);
      } else {
        FetchPair(level[k], f[k][g].top, word[k][g][0], word[k][g][1]);
        FetchPair(level[k], f[k][g].bottom, word[k][g][2], word[k][g][3]);
      }
    }
  const hn::Vec<DU> m = hn::Set(du, 0xFF);
  const VF colour_scale = hn::Set(df, kSrgb ? 1.0f : 1.0f / 255.0f), alpha_scale = hn::Set(df, 1.0f / 255.0f);
  for (size_t g = 0; g < kGroups; ++g) {
    if (!want[g]) {
      for (int ch = 0; ch < 4; ++ch) hn::StoreU(hn::Zero(df), df, out[ch] + b + g * N);
      continue;
    }
    Acc acc;
    for (VF& c : acc.c) c = hn::Zero(df);
    for (int k = 0; k < kLevels; ++k) {
      const Footprint& fp = f[k][g];
      if constexpr (kLa) {
        auto tap = [&](hn::Vec<DU> w32, VF w) {
          acc.c[0] = hn::MulAdd(w, hn::ConvertTo(df, hn::BitCast(di, hn::And(w32, m))), acc.c[0]);
          acc.c[3] = hn::MulAdd(w, hn::ConvertTo(df, hn::BitCast(di, hn::And(hn::ShiftRight<8>(w32), m))), acc.c[3]);
        };
        tap(word[k][g][0], fp.w[0]);
        tap(hn::ShiftRight<16>(word[k][g][0]), fp.w[1]);
        tap(word[k][g][1], fp.w[2]);
        tap(hn::ShiftRight<16>(word[k][g][1]), fp.w[3]);
      } else {
        for (int q = 0; q < 4; ++q) Tap<kSrgb>(word[k][g][q], fp.w[q], srgb, acc);
      }
    }
    const auto keep = BitsToMask(wanted, g);
    const size_t i = b + g * N;
    if constexpr (kLa) {
      const VF l = hn::IfThenElseZero(keep, hn::Mul(acc.c[0], colour_scale));
      for (int ch = 0; ch < 3; ++ch) hn::StoreU(l, df, out[ch] + i);
    } else {
      for (int ch = 0; ch < 3; ++ch)
        hn::StoreU(hn::IfThenElseZero(keep, hn::Mul(acc.c[ch], colour_scale)), df, out[ch] + i);
    }
    hn::StoreU(hn::IfThenElseZero(keep, hn::Mul(acc.c[3], alpha_scale)), df, out[3] + i);
  }
}

// Nearest: level 0's texel under each lane, one gather per vector; a vector without a wanted
// lane is not sampled and reads 0.
template <bool kSrgb, bool kLa>
void SampleNearest(const Texture& tex, const SamplerState& s, const float* HWY_RESTRICT u,
                   const float* HWY_RESTRICT v, size_t lanes, float* const out[4], const uint16_t* block_mask) {
  const DF df;
  const DI di;
  const DU du;
  const size_t N = hn::Lanes(df);
  const uint32_t group_bits = GroupBits();
  const bool rep_u = s.wrap_u == Wrap::Repeat, rep_v = s.wrap_v == Wrap::Repeat;
  const float* srgb = srgb8_to_linear_table();
  const VF colour_scale = hn::Set(df, kSrgb ? 1.0f : 1.0f / 255.0f);
  const VF alpha_scale = hn::Set(df, 1.0f / 255.0f);
  const LevelView base = View(tex, 0);
  for (size_t b = 0; b < lanes; b += kBlockLanes) {
    const uint32_t wanted = block_mask ? block_mask[b / kBlockLanes] : 0xFFFFu;
    for (size_t i = b; i < b + kBlockLanes; i += N) {
      if (((wanted >> (i - b)) & group_bits) == 0) {
        for (int ch = 0; ch < 4; ++ch) hn::StoreU(hn::Zero(df), df, out[ch] + i);
        continue;
      }
      const auto keep = BitsToMask(wanted, (i - b) / N);
      const VI xi = AxisNearest(hn::LoadU(df, u + i), base.w, rep_u);
      const VI yi = AxisNearest(hn::LoadU(df, v + i), base.h, rep_v);
      hn::Vec<DU> word = FetchWord<kLa>(base, hn::Add(hn::Mul(yi, hn::Set(di, base.stride)), xi));
      if constexpr (kLa) {
        // The texel's (L, A) as the RGBA8 word Decode reads.
        const hn::Vec<DU> l = hn::And(word, hn::Set(du, 0xFF));
        word = hn::Or(hn::Or(l, hn::ShiftLeft<8>(l)),
                      hn::Or(hn::ShiftLeft<16>(l), hn::ShiftLeft<16>(hn::And(word, hn::Set(du, 0xFF00)))));
      }
      const Decoded d = Decode<kSrgb>(word, srgb);
      for (int ch = 0; ch < 3; ++ch) hn::StoreU(hn::IfThenElseZero(keep, hn::Mul(d.c[ch], colour_scale)), df, out[ch] + i);
      hn::StoreU(hn::IfThenElseZero(keep, hn::Mul(d.a, alpha_scale)), df, out[3] + i);
    }
  }
}

// Bilinear, BilinearMip and Trilinear: per chunk of blocks, their levels first (ChunkLods, so
// the loop that samples makes no calls), then each block (SampleBlock).
template <bool kSrgb, Filter kFilter, bool kLa = false>
void SampleT(const Texture& tex, const SamplerState& s, const float* HWY_RESTRICT u,
             const float* HWY_RESTRICT v, size_t lanes, float* const out[4], const uint16_t* block_mask) {
  if constexpr (kFilter == Filter::Nearest) {
    return SampleNearest<kSrgb, kLa>(tex, s, u, v, lanes, out, block_mask);
  } else {
    const bool rep_u = s.wrap_u == Wrap::Repeat, rep_v = s.wrap_v == Wrap::Repeat;
    const float* srgb = srgb8_to_linear_table();
    const LevelView base = View(tex, 0);
    constexpr bool kMipmapped = kFilter == Filter::Trilinear || kFilter == Filter::BilinearMip;
    constexpr size_t kGroups = kBlockLanes / hn::MaxLanes(DF());  // vectors of lanes a block
    int32_t level[kChunkBlocks];
    float weight[kChunkBlocks];
    HWY_ALIGN double clamped[kChunkBlocks];
    for (size_t first = 0; first < lanes; first += kChunkBlocks * kBlockLanes) {
      const size_t blocks = std::min(kChunkBlocks, (lanes - first) / kBlockLanes);
      if constexpr (kMipmapped) {
        // A block outside the mask: level 0, weight 0.
        ChunkLods(u + first, v + first, blocks, block_mask ? block_mask + first / kBlockLanes : nullptr, base.w,
                  base.h, double(s.lod_bias), double(tex.levels() - 1), clamped);
        for (size_t k = 0; k < blocks; ++k) {
          if constexpr (kFilter == Filter::Trilinear) {
            level[k] = int32_t(clamped[k]);
            weight[k] = float(clamped[k] - level[k]);
          } else {
            level[k] = nearest_mip_level(clamped[k]);
            weight[k] = 0.0f;
          }
        }
      }
      for (size_t k = 0; k < blocks; ++k) {
        const size_t b = first + k * kBlockLanes;
        LevelView levels[2] = {base, base};
        float t = 0.0f;
        if constexpr (kMipmapped) {
          levels[0] = View(tex, level[k]);
          t = weight[k];
          if (t > 0.0f) levels[1] = View(tex, std::min(level[k] + 1, tex.levels() - 1));
        }
        const uint32_t wanted = block_mask ? block_mask[b / kBlockLanes] : 0xFFFFu;
        if (t > 0.0f) {
          const float weights[2] = {1.0f - t, t};
          SampleBlock<kGroups, 2, kSrgb, kLa>(levels, weights, u, v, rep_u, rep_v, wanted, srgb, out, b);
        } else {
          const float weights[2] = {1.0f, 0.0f};
          SampleBlock<kGroups, 1, kSrgb, kLa>(levels, weights, u, v, rep_u, rep_v, wanted, srgb, out, b);
        }
      }
    }
  }
}

void BlockLodsImpl(const float* u, const float* v, size_t blocks, int32_t width, int32_t height, float lod_bias,
                   int32_t levels, double* out) {
  HWY_ALIGN double clamped[kChunkBlocks];
  for (size_t first = 0; first < blocks; first += kChunkBlocks) {
    const size_t count = std::min(kChunkBlocks, blocks - first);
    ChunkLods(u + first * kBlockLanes, v + first * kBlockLanes, count, nullptr, width, height, double(lod_bias),
              double(levels - 1), clamped);
    std::copy_n(clamped, count, out + first);
  }
}

void SampleImpl(const Texture& tex, const SamplerState& s, const float* u, const float* v,
                size_t lanes, float* const out[4], const uint16_t* m) {
  if (tex.format() == TexelFormat::La8) {  // always linear
    switch (s.filter) {
      case Filter::Nearest:
        return SampleT<false, Filter::Nearest, true>(tex, s, u, v, lanes, out, m);
      case Filter::Bilinear:
        return SampleT<false, Filter::Bilinear, true>(tex, s, u, v, lanes, out, m);
      case Filter::Trilinear:
        return SampleT<false, Filter::Trilinear, true>(tex, s, u, v, lanes, out, m);
      case Filter::BilinearMip:
        return SampleT<false, Filter::BilinearMip, true>(tex, s, u, v, lanes, out, m);
    }
  }
  const bool srgb = tex.encoding() == TexelEncoding::Srgb;
  switch (s.filter) {
    case Filter::Nearest:
      return srgb ? SampleT<true, Filter::Nearest>(tex, s, u, v, lanes, out, m)
                  : SampleT<false, Filter::Nearest>(tex, s, u, v, lanes, out, m);
    case Filter::Bilinear:
      return srgb ? SampleT<true, Filter::Bilinear>(tex, s, u, v, lanes, out, m)
                  : SampleT<false, Filter::Bilinear>(tex, s, u, v, lanes, out, m);
    case Filter::Trilinear:
      return srgb ? SampleT<true, Filter::Trilinear>(tex, s, u, v, lanes, out, m)
                  : SampleT<false, Filter::Trilinear>(tex, s, u, v, lanes, out, m);
    case Filter::BilinearMip:
      return srgb ? SampleT<true, Filter::BilinearMip>(tex, s, u, v, lanes, out, m)
                  : SampleT<false, Filter::BilinearMip>(tex, s, u, v, lanes, out, m);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace pelt::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::raster {

HWY_EXPORT(SampleImpl);
HWY_EXPORT(BlockLodsImpl);

void block_lods(const float* u, const float* v, size_t blocks, int width, int height, float lod_bias, int levels,
                double* out) {
  if (width < 1 || height < 1 || levels < 1)
    throw std::invalid_argument("block_lods: width, height and levels must be positive");
  if (blocks == 0) return;
  if (u == nullptr || v == nullptr || out == nullptr) throw std::invalid_argument("block_lods: u, v or out is null");
  HWY_DYNAMIC_DISPATCH(BlockLodsImpl)(u, v, blocks, width, height, lod_bias, levels, out);
}

void sample(const Texture& tex, const SamplerState& state, const float* u, const float* v,
            size_t lanes, float* const out[4], const uint16_t* block_mask) {
  if (tex.empty()) throw std::invalid_argument("sample: tex is empty (no texels)");
  if (lanes % kBlockLanes != 0)
    throw std::invalid_argument("sample: lanes = " + std::to_string(lanes) +
                                " is not a multiple of 16 (whole 4x4 blocks)");
  if (lanes == 0) return;
  if (u == nullptr || v == nullptr) throw std::invalid_argument("sample: u or v is null");
  for (int ch = 0; ch < 4; ++ch)
    if (out == nullptr || out[ch] == nullptr)
      throw std::invalid_argument("sample: out[" + std::to_string(ch) + "] is null");
  if (state.filter != Filter::Nearest && state.filter != Filter::Bilinear &&
      state.filter != Filter::Trilinear && state.filter != Filter::BilinearMip)
    throw std::invalid_argument("sample: state.filter is not a Filter value");
  HWY_DYNAMIC_DISPATCH(SampleImpl)(tex, state, u, v, lanes, out, block_mask);
}

}  // namespace pelt::raster
#endif  // HWY_ONCE
