// The texture sampler, written once with Highway and compiled for every target; dispatched
// once per sample() call. See raster/texture.h for the contract.
//
// Per vector of lanes: texel coordinates and wrapped integer indices per axis, one 32-bit
// gather per texel (RGBA8) or pair of 2-byte texels (La8), bytes unpacked with shifts (sRGB
// colour through a gather from the 256-float table), weighted straight (no division: the texture's
// transparent texels carry their surroundings' colour, see texture.h) and scaled once at the
// end. A 4x4 block's vectors are sampled together (SampleBlock), and its level pair is chosen
// per block before the sampling (ClampedLambdas), so every gather of a vector reads one level
// whose base and width are scalars. With a block mask on a 16-lane target, the wanted lanes of
// many blocks are packed into whole vectors instead, each lane with its block's level
// (SampleDenseChunk): a gather costs the same however few of its lanes are wanted.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/texture_kernels.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

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
HWY_INLINE VF TexelCoord(VF c, VF fsize, bool repeat) {
  const DF df;
  if (repeat) {
    c = hn::Sub(c, hn::Floor(c));
    const VF x = hn::Sub(hn::Mul(c, fsize), hn::Set(df, 0.5f));
    return hn::Max(hn::Min(x, hn::Sub(fsize, hn::Set(df, 0.5f))), hn::Set(df, -0.5f));
  }
  const VF x = hn::Sub(hn::Mul(c, fsize), hn::Set(df, 0.5f));
  return hn::Max(hn::Min(x, hn::Add(fsize, hn::Set(df, 1.0f))), hn::Set(df, -2.0f));
}

// floor(x) as a texel index, and the fraction of x above it (the weight of the next texel).
// Every caller's x is finite and within a few texels of [0, kMaxTextureSide] (TexelCoord and
// RepeatPow2 clamp it, NaN included), so the integral float xf converts exactly through the
// float 1.5 * 2^23 + xf, whose bits are 0x4B400000 + xf: an add and a subtract, where ConvertTo
// adds four operations to fix up out-of-range lanes that cannot occur here (four conversions
// a trilinear vector).
HWY_INLINE VI FloorIndex(VF x, VF& frac) {
  static_assert(kMaxTextureSide < (1 << 22), "FloorIndex's exact conversion needs |x| < 2^22");
  const DI di;
  const VF xf = hn::Floor(x);
  frac = hn::Sub(x, xf);
  const VF biased = hn::Add(xf, hn::Set(DF(), 12582912.0f));
  return hn::Sub(hn::BitCast(di, biased), hn::Set(di, 0x4B400000));
}

// Repeat on a power-of-two axis (every level of a power-of-two texture): TexelCoord's x,
// floor and fraction, with the wrap of x0 = -1 (and of x0 + 1 = size) as a mask instead of a
// compare and a blend. Bit for bit the general path: x lies in [-0.5, size - 0.5] already,
// so of TexelCoord's clamps only the Min that maps NaN to size - 0.5 does anything.
HWY_INLINE bool IsPow2(int32_t size) { return (size & (size - 1)) == 0; }

HWY_INLINE VI RepeatPow2(VF c, VF fsize, VF& frac) {
  const DF df;
  c = hn::Sub(c, hn::Floor(c));
  const VF half = hn::Set(df, 0.5f);
  const VF x = hn::Min(hn::Sub(hn::Mul(c, fsize), half), hn::Sub(fsize, half));
  return FloorIndex(x, frac);
}

// The axis functions below take the size per lane (isize, and fsize its float), as the dense
// lanes need; the texture's own sampling passes one size broadcast. `repeat` there means a
// power-of-two size: AxisLinear and AxisPair keep the general repeat for other sizes.

// The two texel indices around coordinate c along an axis of `size` texels and the weight
// of the second: repeat on a power-of-two size, or clamp.
HWY_INLINE void AxisLinearLanes(VF c, VI isize, VF fsize, bool repeat, VI& i0, VI& i1, VF& frac) {
  const DI di;
  const VI one = hn::Set(di, 1);
  const VI last = hn::Sub(isize, one);
  if (repeat) {
    const VI i = RepeatPow2(c, fsize, frac);
    i0 = hn::And(i, last);
    i1 = hn::And(hn::Add(i, one), last);
    return;
  }
  const VF x = TexelCoord(c, fsize, false);
  i0 = FloorIndex(x, frac);
  i1 = hn::Add(i0, one);
  i0 = hn::Min(hn::Max(i0, hn::Zero(di)), last);
  i1 = hn::Min(hn::Max(i1, hn::Zero(di)), last);
}

// Any size. Repeat: x lies in [-0.5, size - 0.5] (TexelCoord), so only i0 = -1 and i1 = size
// need wrapping.
HWY_INLINE void AxisLinear(VF c, int32_t size, bool repeat, VI& i0, VI& i1, VF& frac) {
  const DF df;
  const DI di;
  const VI isize = hn::Set(di, size);
  const VF fsize = hn::Set(df, float(size));
  if (!repeat || IsPow2(size)) return AxisLinearLanes(c, isize, fsize, repeat, i0, i1, frac);
  const VF x = TexelCoord(c, fsize, true);
  i0 = FloorIndex(x, frac);
  i1 = hn::Add(i0, hn::Set(di, 1));
  i0 = hn::IfThenElse(hn::Lt(i0, hn::Zero(di)), hn::Add(i0, isize), i0);
  i1 = hn::IfThenElse(hn::Gt(i1, hn::Set(di, size - 1)), hn::Sub(i1, isize), i1);
}

// The left texel x0 of the horizontal pair (x0, x0 + 1) around coordinate c and the weight
// of x0 + 1. The padding texel (index width, a copy of texel 0) makes the pair adjacent in
// memory for every x0 in [0, width - 1]: repeat wraps x0 = -1 to width - 1 and the pair's
// right texel is the padding; clamp puts all the weight on the edge texel (frac = 0) where
// both indices would clamp to it, which also keeps x0 + 1 <= width. Repeat on a power-of-two
// size, or clamp.
HWY_INLINE void AxisPairLanes(VF c, VI isize, VF fsize, bool repeat, VI& i0, VF& frac) {
  const DF df;
  const DI di;
  const VI last = hn::Sub(isize, hn::Set(di, 1));
  if (repeat) {
    i0 = hn::And(RepeatPow2(c, fsize, frac), last);
    return;
  }
  const VF x = TexelCoord(c, fsize, false);
  i0 = FloorIndex(x, frac);
  const auto edge = hn::Or(hn::Lt(i0, hn::Zero(di)), hn::Gt(i0, hn::Sub(isize, hn::Set(di, 2))));
  frac = hn::IfThenZeroElse(hn::RebindMask(df, edge), frac);
  i0 = hn::Min(hn::Max(i0, hn::Zero(di)), last);
}

// Any size.
HWY_INLINE void AxisPair(VF c, int32_t size, bool repeat, VI& i0, VF& frac) {
  const DF df;
  const DI di;
  const VI isize = hn::Set(di, size);
  const VF fsize = hn::Set(df, float(size));
  if (!repeat || IsPow2(size)) return AxisPairLanes(c, isize, fsize, repeat, i0, frac);
  const VF x = TexelCoord(c, fsize, true);
  i0 = FloorIndex(x, frac);
  i0 = hn::IfThenElse(hn::Lt(i0, hn::Zero(di)), hn::Add(i0, isize), i0);
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

// Byte k (0 = lowest) of each 32-bit word as an integer: the lowest by a mask, the highest by a
// shift, the middle two by one byte shuffle where the target has one (a shift and a mask before).
// A La8 word's (L, A, L, A) come out through it (Decode keeps shifts for RGBA8, see there).
template <int k>
HWY_INLINE VI WordByte(hn::Vec<DU> w) {
  static_assert(k >= 0 && k < 4);
  const DI di;
  const DU du;
  if constexpr (k == 0) {
    return hn::BitCast(di, hn::And(w, hn::Set(du, 0xFF)));
  } else if constexpr (k == 3) {
    return hn::BitCast(di, hn::ShiftRight<24>(w));
  } else {
#if HWY_TARGET == HWY_SCALAR
    return hn::BitCast(di, hn::And(hn::ShiftRight<8 * k>(w), hn::Set(du, 0xFF)));
#else
    alignas(16) static constexpr uint8_t kIndex[16] = {k,     0x80, 0x80, 0x80, 4 + k,  0x80, 0x80, 0x80,
                                                       8 + k, 0x80, 0x80, 0x80, 12 + k, 0x80, 0x80, 0x80};
    const hn::Repartition<uint8_t, DU> d8;
    return hn::BitCast(di, hn::TableLookupBytesOr0(hn::BitCast(d8, w), hn::LoadDup128(d8, kIndex)));
#endif
  }
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
  // Shifts and masks rather than WordByte's shuffles: with three channels a texel the shuffles
  // made RGBA8 and sRGB bilinear 5 % slower (texture_bench, AVX3, three alternations: 447-456
  // against 469-482 M samples/s RGBA8, 202-205 against 213-217 sRGB).
  const VI ti = hn::BitCast(di, t);
  const VI m = hn::Set(di, 0xFF);
  const VI b[3] = {hn::And(ti, m), hn::And(hn::ShiftRight<8>(ti), m), hn::And(hn::ShiftRight<16>(ti), m)};
  Decoded d;
  for (int ch = 0; ch < 3; ++ch)
    d.c[ch] = kSrgb ? hn::GatherIndex(df, srgb, b[ch]) : hn::ConvertTo(df, b[ch]);
  d.a = hn::ConvertTo(df, WordByte<3>(t));
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

// The footprint of rows y0, y1 (index offset `first` + row times `stride`) from column x0, with
// the weights ax, ay of the second column and row.
HWY_INLINE Footprint MakeFootprint(VI first, VI stride, VI x0, VI y0, VI y1, VF ax, VF ay, VF weight) {
  const DF df;
  const VF one = hn::Set(df, 1.0f);
  const VF wy1 = hn::Mul(ay, weight);
  const VF wy0 = hn::Mul(hn::Sub(one, ay), weight);
  const VF bx = hn::Sub(one, ax);
  return Footprint{hn::Add(first, hn::Add(hn::Mul(y0, stride), x0)),
                   hn::Add(first, hn::Add(hn::Mul(y1, stride), x0)),
                   {hn::Mul(bx, wy0), hn::Mul(ax, wy0), hn::Mul(bx, wy1), hn::Mul(ax, wy1)}};
}

HWY_INLINE Footprint FootprintOf(const LevelView& L, VF u, VF v, bool rep_u, bool rep_v, VF weight) {
  const DI di;
  VI x0, y0, y1;
  VF ax, ay;
  AxisPair(u, L.w, rep_u, x0, ax);
  AxisLinear(v, L.h, rep_v, y0, y1, ay);
  return MakeFootprint(hn::Zero(di), hn::Set(di, L.stride), x0, y0, y1, ax, ay, weight);
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

// The words of footprint fp on level L (FetchWord): (top, bottom) pairs for La8, the four texels
// for RGBA8.
template <bool kLa>
constexpr int kFootprintWords = kLa ? 2 : 4;

template <bool kLa>
HWY_INLINE void FetchFootprint(const LevelView& L, const Footprint& fp, hn::Vec<DU> (&word)[kFootprintWords<kLa>]) {
  if constexpr (kLa) {
    word[0] = FetchWord<true>(L, fp.top);
    word[1] = FetchWord<true>(L, fp.bottom);
  } else {
    FetchPair(L, fp.top, word[0], word[1]);
    FetchPair(L, fp.bottom, word[2], word[3]);
  }
}

// Adds footprint fp's four weighted texels to acc, in the same order for both formats.
template <bool kSrgb, bool kLa>
HWY_INLINE void TapFootprint(const hn::Vec<DU> (&word)[kFootprintWords<kLa>], const Footprint& fp, const float* srgb,
                             Acc& acc) {
  if constexpr (kLa) {
    // A word holds L, A of the left texel and L, A of the right (WordByte 0 to 3).
    const DF df;
    for (int row = 0; row < 2; ++row) {
      const hn::Vec<DU> w32 = word[row];
      const VF left = fp.w[2 * row], right = fp.w[2 * row + 1];
      acc.c[0] = hn::MulAdd(left, hn::ConvertTo(df, WordByte<0>(w32)), acc.c[0]);
      acc.c[3] = hn::MulAdd(left, hn::ConvertTo(df, WordByte<1>(w32)), acc.c[3]);
      acc.c[0] = hn::MulAdd(right, hn::ConvertTo(df, WordByte<2>(w32)), acc.c[0]);
      acc.c[3] = hn::MulAdd(right, hn::ConvertTo(df, WordByte<3>(w32)), acc.c[3]);
    }
  } else {
    for (int q = 0; q < 4; ++q) Tap<kSrgb>(word[q], fp.w[q], srgb, acc);
  }
}

// La8's luminance l into the three colour channels at lane i; a caller that wants one colour array
// passes it three times (the fur shader), and it is stored once.
HWY_INLINE void StoreLuminance(VF l, float* const out[4], size_t i) {
  const DF df;
  hn::StoreU(l, df, out[0] + i);
  if (out[1] != out[0]) hn::StoreU(l, df, out[1] + i);
  if (out[2] != out[0] && out[2] != out[1]) hn::StoreU(l, df, out[2] + i);
}

// The sample from acc, scaled, in the lanes `keep` (0 elsewhere), at out[ch] + i.
template <bool kSrgb, bool kLa>
HWY_INLINE void StoreSample(const Acc& acc, hn::Mask<DF> keep, float* const out[4], size_t i) {
  const DF df;
  const VF colour_scale = hn::Set(df, kSrgb ? 1.0f : 1.0f / 255.0f), alpha_scale = hn::Set(df, 1.0f / 255.0f);
  if constexpr (kLa) {
    StoreLuminance(hn::IfThenElseZero(keep, hn::Mul(acc.c[0], colour_scale)), out, i);
  } else {
    for (int ch = 0; ch < 3; ++ch)
      hn::StoreU(hn::IfThenElseZero(keep, hn::Mul(acc.c[ch], colour_scale)), df, out[ch] + i);
  }
  hn::StoreU(hn::IfThenElseZero(keep, hn::Mul(acc.c[3], alpha_scale)), df, out[3] + i);
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
  const size_t N = hn::Lanes(df);
  Footprint f[kLevels][kGroups];
  hn::Vec<DU> word[kLevels][kGroups][kFootprintWords<kLa>];
  bool want[kGroups];
  for (size_t g = 0; g < kGroups; ++g) want[g] = ((wanted >> (g * N)) & GroupBits()) != 0;
  for (size_t g = 0; g < kGroups; ++g) {
    if (!want[g]) continue;
    const VF uu = hn::LoadU(df, u + b + g * N), vv = hn::LoadU(df, v + b + g * N);
    for (int k = 0; k < kLevels; ++k) f[k][g] = FootprintOf(level[k], uu, vv, rep_u, rep_v, hn::Set(df, weight[k]));
  }
  for (int k = 0; k < kLevels; ++k)
    for (size_t g = 0; g < kGroups; ++g)
      if (want[g]) FetchFootprint<kLa>(level[k], f[k][g], word[k][g]);
  for (size_t g = 0; g < kGroups; ++g) {
    if (!want[g]) {
      for (int ch = 0; ch < 4; ++ch) hn::StoreU(hn::Zero(df), df, out[ch] + b + g * N);
      continue;
    }
    Acc acc;
    for (VF& c : acc.c) c = hn::Zero(df);
    for (int k = 0; k < kLevels; ++k) TapFootprint<kSrgb, kLa>(word[k][g], f[k][g], srgb, acc);
    StoreSample<kSrgb, kLa>(acc, BitsToMask(wanted, g), out, b + g * N);
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

// ---- Dense lanes: a block mask's wanted lanes packed into whole vectors ----
//
// A gather costs the same whatever its mask (16-lane gathers with 4 wanted lanes ran no faster than
// with 16 here), and a fur batch's blocks are partly covered: 70 % of their lanes are wanted on the
// furry box (3.27 M of 4.55 M a frame). Where one vector is a block (AVX-512), a chunk's wanted
// lanes are compressed into whole vectors, each lane carrying its block's level and weight,
// sampled there, and expanded back into their blocks. A lane goes through the operations of
// SampleBlock in the same order, so every sample is bit for bit the same (texture_sampling_test).
// A lane's level needs its size, level 0's shifted right k times (at least 1, as the mip chain
// halves), and its first texel, from a table of at most 16 levels (kMaxTextureSide gives 15).
// Each axis repeats on a power-of-two size or clamps (the fur's shells repeat on both, its fin
// clamps from root to tip); repeat on another size keeps the per-block path.

struct DenseLevels {
  VI width, height;  // level 0's
  VI first;          // lane k: level k's first texel, counted from level 0's
  VI top;            // the last level
  bool repeat_u, repeat_v;
};

// FootprintOf on each lane's level.
HWY_INLINE Footprint DenseFootprint(const DenseLevels& d, VI level, VF u, VF v, VF weight) {
  const DF df;
  const DI di;
  const VI one = hn::Set(di, 1);
  const VI w = hn::Max(d.width >> level, one);
  const VI h = hn::Max(d.height >> level, one);
  const VI first = hn::TableLookupLanes(d.first, hn::IndicesFromVec(di, level));
  VI x0, y0, y1;
  VF ax, ay;
  AxisPairLanes(u, w, hn::ConvertTo(df, w), d.repeat_u, x0, ax);
  AxisLinearLanes(v, h, hn::ConvertTo(df, h), d.repeat_v, y0, y1, ay);
  return MakeFootprint(first, hn::Add(w, one), x0, y0, y1, ax, ay, weight);
}

// Dense lanes [i, i + N): coordinates, level and trilinear weight per lane, on kLevels levels
// (trilinear: the level and the next, weights 1 - t and t; a lane with t = 0 adds +0 from the
// next level, which leaves its sums as SampleBlock's single level does).
template <int kLevels, bool kSrgb, bool kLa>
HWY_INLINE void SampleDenseVector(const LevelView& base, const DenseLevels& d, const float* HWY_RESTRICT u,
                                  const float* HWY_RESTRICT v, const int32_t* HWY_RESTRICT level,
                                  const float* HWY_RESTRICT t, const float* srgb, float* const out[4], size_t i) {
  const DF df;
  const DI di;
  const VF uu = hn::LoadU(df, u + i), vv = hn::LoadU(df, v + i);
  const VI l0 = hn::LoadU(di, level + i);
  Footprint f[kLevels];
  hn::Vec<DU> word[kLevels][kFootprintWords<kLa>];
  if constexpr (kLevels == 2) {
    const VF tt = hn::LoadU(df, t + i);
    f[0] = DenseFootprint(d, l0, uu, vv, hn::Sub(hn::Set(df, 1.0f), tt));
    f[1] = DenseFootprint(d, hn::Min(hn::Add(l0, hn::Set(di, 1)), d.top), uu, vv, tt);
  } else {
    f[0] = DenseFootprint(d, l0, uu, vv, hn::Set(df, 1.0f));
  }
  for (int k = 0; k < kLevels; ++k) FetchFootprint<kLa>(base, f[k], word[k]);
  Acc acc;
  for (VF& c : acc.c) c = hn::Zero(df);
  for (int k = 0; k < kLevels; ++k) TapFootprint<kSrgb, kLa>(word[k], f[k], srgb, acc);
  StoreSample<kSrgb, kLa>(acc, hn::FirstN(df, hn::Lanes(df)), out, i);
}

// The chunk's blocks [first, first + blocks * 16) through dense lanes; level[k] and weight[k] as
// SampleT computes them (level 0 and weight 0 without mipmaps).
template <int kLevels, bool kSrgb, bool kLa>
HWY_NOINLINE void SampleDenseChunk(const LevelView& base, const DenseLevels& d, const float* HWY_RESTRICT u,
                                   const float* HWY_RESTRICT v, size_t first, size_t blocks,
                                   const int32_t* level, const float* weight, const uint16_t* block_mask,
                                   const float* srgb, float* const out[4]) {
  const DF df;
  const DI di;
  const DU du;
  const size_t N = hn::Lanes(df);
  constexpr size_t kCapacity = kChunkBlocks * kBlockLanes + kBlockLanes;  // a whole vector stored past the last
  HWY_ALIGN float pu[kCapacity], pv[kCapacity], pt[kCapacity];
  HWY_ALIGN int32_t pl[kCapacity];
  HWY_ALIGN float po[4][kCapacity];
  uint32_t start[kChunkBlocks];
  size_t count = 0;
  for (size_t k = 0; k < blocks; ++k) {
    const uint32_t wanted = block_mask[first / kBlockLanes + k];
    start[k] = uint32_t(count);
    if (wanted == 0) continue;
    const auto m = BitsToMask(wanted, 0);
    const size_t b = first + k * kBlockLanes;
    hn::StoreU(hn::Compress(hn::LoadU(df, u + b), m), df, pu + count);
    hn::StoreU(hn::Compress(hn::LoadU(df, v + b), m), df, pv + count);
    hn::StoreU(hn::Set(di, level[k]), di, pl + count);
    hn::StoreU(hn::Set(df, weight[k]), df, pt + count);
    count += size_t(std::popcount(wanted));
  }
  // The last vector's lanes past `count`: in range, and their samples are never read.
  hn::StoreU(hn::Zero(df), df, pu + count);
  hn::StoreU(hn::Zero(df), df, pv + count);
  hn::StoreU(hn::Zero(di), di, pl + count);
  hn::StoreU(hn::Zero(df), df, pt + count);
  float* const packed_out[4] = {po[0], kLa ? po[0] : po[1], kLa ? po[0] : po[2], po[3]};
  for (size_t i = 0; i < count; i += N) SampleDenseVector<kLevels, kSrgb, kLa>(base, d, pu, pv, pl, pt, srgb, packed_out, i);

  // Lane l of a block takes packed lane start + (wanted lanes below l).
  const auto below = hn::Sub(hn::BitCast(du, hn::LoadU(di, kLaneBit)), hn::Set(du, 1u));
  for (size_t k = 0; k < blocks; ++k) {
    const uint32_t wanted = block_mask[first / kBlockLanes + k];
    const size_t b = first + k * kBlockLanes;
    if (wanted == 0) {
      for (int ch = 0; ch < 4; ++ch) hn::StoreU(hn::Zero(df), df, out[ch] + b);
      continue;
    }
    const auto m = BitsToMask(wanted, 0);
    const auto rank = hn::IndicesFromVec(df, hn::BitCast(di, hn::PopulationCount(hn::And(hn::Set(du, wanted), below))));
    auto expand = [&](const float* p) { return hn::IfThenElseZero(m, hn::TableLookupLanes(hn::LoadU(df, p + start[k]), rank)); };
    if constexpr (kLa) {
      StoreLuminance(expand(po[0]), out, b);
    } else {
      for (int ch = 0; ch < 3; ++ch) hn::StoreU(expand(po[ch]), df, out[ch] + b);
    }
    hn::StoreU(expand(po[3]), df, out[3] + b);
  }
}

// Whether the dense lanes apply (see above), and their level table.
HWY_INLINE bool MakeDenseLevels(const Texture& tex, const SamplerState& s, DenseLevels& d) {
  const DI di;
  if (hn::Lanes(di) != size_t(kBlockLanes) || tex.levels() > int(kBlockLanes)) return false;
  d.repeat_u = s.wrap_u == Wrap::Repeat;
  d.repeat_v = s.wrap_v == Wrap::Repeat;
  if ((d.repeat_u && !IsPow2(tex.width())) || (d.repeat_v && !IsPow2(tex.height()))) return false;
  HWY_ALIGN int32_t first[kBlockLanes] = {};
  for (int k = 0; k < tex.levels(); ++k) first[k] = int32_t(tex.level(k).offset - tex.level(0).offset);
  d.width = hn::Set(di, tex.width());
  d.height = hn::Set(di, tex.height());
  d.first = hn::Load(di, first);
  d.top = hn::Set(di, tex.levels() - 1);
  return true;
}

// Bilinear, BilinearMip and Trilinear: per chunk of blocks, their levels first (ChunkLods, so
// the loop that samples makes no calls), then each block (SampleBlock).
template <bool kSrgb, Filter kFilter, bool kLa = false>
void SampleT(const Texture& tex, const SamplerState& s, const float* HWY_RESTRICT u,
             const float* HWY_RESTRICT v, const float* lod_u, const float* lod_v, size_t lanes, float* const out[4],
             const uint16_t* block_mask) {
  if constexpr (kFilter == Filter::Nearest) {
    (void)lod_u, (void)lod_v;  // level 0 always
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
    DenseLevels dense_levels;
    const bool dense = block_mask != nullptr && MakeDenseLevels(tex, s, dense_levels);
    if constexpr (!kMipmapped) {  // level 0 for every block, as the dense lanes read it
      std::fill_n(level, kChunkBlocks, 0);
      std::fill_n(weight, kChunkBlocks, 0.0f);
    }
    for (size_t first = 0; first < lanes; first += kChunkBlocks * kBlockLanes) {
      const size_t blocks = std::min(kChunkBlocks, (lanes - first) / kBlockLanes);
      if constexpr (kMipmapped) {
        // A block outside the mask: level 0, weight 0.
        ChunkLods(lod_u + first, lod_v + first, blocks, block_mask ? block_mask + first / kBlockLanes : nullptr, base.w,
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
      if constexpr (hn::MaxLanes(DF()) == size_t(kBlockLanes)) {
        if (dense) {
          constexpr int kLevels = kFilter == Filter::Trilinear ? 2 : 1;
          SampleDenseChunk<kLevels, kSrgb, kLa>(base, dense_levels, u, v, first, blocks, level, weight, block_mask,
                                                srgb, out);
          continue;
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

void BlockLength2sImpl(const float* u, const float* v, size_t blocks, int32_t width, int32_t height, double* out) {
  for (size_t k = 0; k < blocks; ++k) out[k] = BlockLength2(u + k * kBlockLanes, v + k * kBlockLanes, width, height);
}

// lod_u, lod_v: the coordinates each block's level of detail is taken from (u, v but where
// mirroring folded them, see sample()).
void SampleImpl(const Texture& tex, const SamplerState& s, const float* u, const float* v, const float* lod_u,
                const float* lod_v, size_t lanes, float* const out[4], const uint16_t* m) {
  if (tex.format() == TexelFormat::La8) {  // always linear
    switch (s.filter) {
      case Filter::Nearest:
        return SampleT<false, Filter::Nearest, true>(tex, s, u, v, lod_u, lod_v, lanes, out, m);
      case Filter::Bilinear:
        return SampleT<false, Filter::Bilinear, true>(tex, s, u, v, lod_u, lod_v, lanes, out, m);
      case Filter::Trilinear:
        return SampleT<false, Filter::Trilinear, true>(tex, s, u, v, lod_u, lod_v, lanes, out, m);
      case Filter::BilinearMip:
        return SampleT<false, Filter::BilinearMip, true>(tex, s, u, v, lod_u, lod_v, lanes, out, m);
    }
  }
  const bool srgb = tex.encoding() == TexelEncoding::Srgb;
  switch (s.filter) {
    case Filter::Nearest:
      return srgb ? SampleT<true, Filter::Nearest>(tex, s, u, v, lod_u, lod_v, lanes, out, m)
                  : SampleT<false, Filter::Nearest>(tex, s, u, v, lod_u, lod_v, lanes, out, m);
    case Filter::Bilinear:
      return srgb ? SampleT<true, Filter::Bilinear>(tex, s, u, v, lod_u, lod_v, lanes, out, m)
                  : SampleT<false, Filter::Bilinear>(tex, s, u, v, lod_u, lod_v, lanes, out, m);
    case Filter::Trilinear:
      return srgb ? SampleT<true, Filter::Trilinear>(tex, s, u, v, lod_u, lod_v, lanes, out, m)
                  : SampleT<false, Filter::Trilinear>(tex, s, u, v, lod_u, lod_v, lanes, out, m);
    case Filter::BilinearMip:
      return srgb ? SampleT<true, Filter::BilinearMip>(tex, s, u, v, lod_u, lod_v, lanes, out, m)
                  : SampleT<false, Filter::BilinearMip>(tex, s, u, v, lod_u, lod_v, lanes, out, m);
  }
}

// fold_mirror_reference over n lanes: the same exact steps, a vector at a time (the scalar fold,
// compiled for the baseline target, called floorf per lane: about a tenth of the tiles' time of a
// furry mesh whose maps mirror).
void FoldMirrorImpl(const float* HWY_RESTRICT in, float* HWY_RESTRICT out, size_t n) {
  const DF df;
  const size_t N = hn::Lanes(df);
  const auto half = hn::Set(df, 0.5f), two = hn::Set(df, 2.0f), one = hn::Set(df, 1.0f);
  const auto fold = [&](auto c) {
    const auto a = hn::Abs(c);
    const auto t = hn::Sub(a, hn::Mul(two, hn::Floor(hn::Mul(half, a))));  // in [0, 2); 2 x is exact
    return hn::IfThenElse(hn::Gt(t, one), hn::Sub(two, t), t);
  };
  size_t i = 0;
  for (; i + N <= n; i += N) hn::StoreU(fold(hn::LoadU(df, in + i)), df, out + i);
  if (i == n) return;
  // The last lanes through a vector of their own (this Highway has no LoadN, and its MaskedLoad
  // reads a whole vector on SSE4): sample() folds whole blocks, so only a direct call of
  // fold_mirror comes here.
  HWY_ALIGN float tail[HWY_LANES(float)] = {};
  std::copy(in + i, in + n, tail);
  hn::Store(fold(hn::Load(df, tail)), df, tail);
  std::copy(tail, tail + (n - i), out + i);
}

}  // namespace HWY_NAMESPACE
}  // namespace pelt::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::raster {

HWY_EXPORT(SampleImpl);
HWY_EXPORT(BlockLodsImpl);
HWY_EXPORT(BlockLength2sImpl);
HWY_EXPORT(FoldMirrorImpl);

namespace {

// Mirrored repeat (GL_MIRRORED_REPEAT) is the kernel's clamp on coordinates folded into
// [0, 1]: c taken modulo 2, then reflected about 1. A pair of taps that straddles a mirror
// line then reads the texels the mirror gives it (the edge texel twice, as the clamp's edge
// does), so the fold costs the kernel nothing and changes no other wrap's path. The level of
// detail must still come from the coordinates as given: a block crossing a mirror line has
// its derivative turned around there (fold_mirror).
constexpr size_t kMirrorChunk = 1024;  // lanes, whole blocks
struct alignas(64) MirrorScratch {
  float u[kMirrorChunk], v[kMirrorChunk];
};
thread_local MirrorScratch tls_mirror;

void sample_mirrored(const Texture& tex, const SamplerState& state, const float* u, const float* v, size_t lanes,
                     float* const out[4], const uint16_t* block_mask) {
  MirrorScratch& s = tls_mirror;
  SamplerState folded = state;
  const bool mu = state.wrap_u == Wrap::Mirror, mv = state.wrap_v == Wrap::Mirror;
  if (mu) folded.wrap_u = Wrap::Clamp;
  if (mv) folded.wrap_v = Wrap::Clamp;
  for (size_t first = 0; first < lanes; first += kMirrorChunk) {
    const size_t n = std::min(kMirrorChunk, lanes - first);
    const float* fu = u + first;
    const float* fv = v + first;
    if (mu) {
      HWY_DYNAMIC_DISPATCH(FoldMirrorImpl)(fu, s.u, n);
      fu = s.u;
    }
    if (mv) {
      HWY_DYNAMIC_DISPATCH(FoldMirrorImpl)(fv, s.v, n);
      fv = s.v;
    }
    float* const part[4] = {out[0] + first, out[1] + first, out[2] + first, out[3] + first};
    HWY_DYNAMIC_DISPATCH(SampleImpl)(tex, folded, fu, fv, u + first, v + first, n, part,
                                     block_mask ? block_mask + first / kBlockLanes : nullptr);
  }
}

// The checks of block_lods and block_lod_length2s: throws std::invalid_argument, prefixed `fn`,
// when a size is below 1 (`sizes` names them) or, with blocks to do, a pointer is null.
// Returns whether there are blocks to do.
bool lod_blocks_to_do(const char* fn, const char* sizes, bool sizes_ok, size_t blocks, const float* u,
                      const float* v, const double* out) {
  if (!sizes_ok) throw std::invalid_argument(std::string(fn) + ": " + sizes + " must be positive");
  if (blocks == 0) return false;
  if (u == nullptr || v == nullptr || out == nullptr) throw std::invalid_argument(std::string(fn) + ": u, v or out is null");
  return true;
}

}  // namespace

// The fold is even (texel i and -1 - i mirror each other), so it starts from |c|: every step
// is then exact in float (Sterbenz), where c + 2 for a small negative c would round.
float fold_mirror_reference(float c) {
  const float a = std::fabs(c);
  const float t = a - 2.0f * std::floor(0.5f * a);  // in [0, 2)
  return t > 1.0f ? 2.0f - t : t;
}

void fold_mirror(const float* in, float* out, size_t n) {
  if (n > 0 && (in == nullptr || out == nullptr)) throw std::invalid_argument("fold_mirror: in or out is null");
  HWY_DYNAMIC_DISPATCH(FoldMirrorImpl)(in, out, n);
}

void block_lod_length2s(const float* u, const float* v, size_t blocks, int width, int height, double* out) {
  if (lod_blocks_to_do("block_lod_length2s", "width and height", width >= 1 && height >= 1, blocks, u, v, out))
    HWY_DYNAMIC_DISPATCH(BlockLength2sImpl)(u, v, blocks, width, height, out);
}

void block_lods(const float* u, const float* v, size_t blocks, int width, int height, float lod_bias, int levels,
                double* out) {
  if (lod_blocks_to_do("block_lods", "width, height and levels", width >= 1 && height >= 1 && levels >= 1, blocks,
                       u, v, out))
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
  for (const auto& [w, name] : {std::pair{state.wrap_u, "wrap_u"}, std::pair{state.wrap_v, "wrap_v"}})
    if (w != Wrap::Repeat && w != Wrap::Clamp && w != Wrap::Mirror)
      throw std::invalid_argument(std::string("sample: state.") + name + " is not a Wrap value");
  if (state.wrap_u == Wrap::Mirror || state.wrap_v == Wrap::Mirror)
    return sample_mirrored(tex, state, u, v, lanes, out, block_mask);
  HWY_DYNAMIC_DISPATCH(SampleImpl)(tex, state, u, v, u, v, lanes, out, block_mask);
}

}  // namespace pelt::raster
#endif  // HWY_ONCE
