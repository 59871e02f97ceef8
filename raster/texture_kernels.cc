// The texture sampler, written once with Highway and compiled for every target; dispatched
// once per sample() call. See raster/texture.h for the contract.
//
// Per vector of lanes: texel coordinates and wrapped integer indices per axis, one 32-bit
// gather per texel (RGBA8), bytes unpacked with shifts (sRGB colour through a gather from
// the 256-float table), accumulated alpha-weighted and plain, divided once at the end.
// The level pair of trilinear is chosen per 4x4 block in scalar code, so every gather of a
// vector reads one level whose base and width are scalars.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/texture_kernels.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <cmath>
#include <stdexcept>

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
  const uint32_t* texels;
  int32_t w, h;
};

LevelView View(const Texture& tex, int k) {
  const MipLevel& L = tex.level(k);
  return LevelView{tex.level_texels(k), L.width, L.height};
}

struct Acc {
  VF pm[3];     // sum of w * a * c
  VF plain[3];  // sum of w * c
  VF alpha;     // sum of w * a (a in bytes)
};

// The two texel indices around coordinate c along an axis of `size` texels and the weight
// of the second. Repeat: c is wrapped to [0, 1] first (exact for c >= 0), so x lies in
// [-0.5, size - 0.5] and only i0 = -1 and i1 = size need wrapping. The float clamps change
// no finite in-range value; they give NaN and huge inputs a defined index (x86 and scalar
// Min/Max return the second operand for NaN).
HWY_INLINE void AxisLinear(VF c, int32_t size, bool repeat, VI& i0, VI& i1, VF& frac) {
  const DF df;
  const DI di;
  const VF fsize = hn::Set(df, float(size));
  const VI isize = hn::Set(di, size);
  VF x;
  if (repeat) {
    c = hn::Sub(c, hn::Floor(c));
    x = hn::Sub(hn::Mul(c, fsize), hn::Set(df, 0.5f));
    x = hn::Max(hn::Min(x, hn::Set(df, float(size) - 0.5f)), hn::Set(df, -0.5f));
  } else {
    x = hn::Sub(hn::Mul(c, fsize), hn::Set(df, 0.5f));
    x = hn::Max(hn::Min(x, hn::Set(df, float(size) + 1.0f)), hn::Set(df, -2.0f));
  }
  const VF xf = hn::Floor(x);
  frac = hn::Sub(x, xf);
  i0 = hn::ConvertTo(di, xf);
  i1 = hn::Add(i0, hn::Set(di, 1));
  if (repeat) {
    i0 = hn::IfThenElse(hn::Lt(i0, hn::Zero(di)), hn::Add(i0, isize), i0);
    i1 = hn::IfThenElse(hn::Ge(i1, isize), hn::Sub(i1, isize), i1);
  } else {
    const VI last = hn::Set(di, size - 1);
    i0 = hn::Min(hn::Max(i0, hn::Zero(di)), last);
    i1 = hn::Min(hn::Max(i1, hn::Zero(di)), last);
  }
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
    return hn::IfThenElse(hn::Ge(i, isize), hn::Sub(i, isize), i);
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
HWY_INLINE Decoded Fetch(const uint32_t* texels, VI idx, const float* srgb) {
  const DF df;
  const DI di;
  const DU du;
  const auto t = hn::GatherIndex(du, texels, idx);
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
HWY_INLINE void Tap(const uint32_t* texels, VI idx, VF w, const float* srgb, Acc& acc) {
  const Decoded d = Fetch<kSrgb>(texels, idx, srgb);
  const VF wa = hn::Mul(w, d.a);
  for (int ch = 0; ch < 3; ++ch) {
    acc.pm[ch] = hn::MulAdd(wa, d.c[ch], acc.pm[ch]);
    acc.plain[ch] = hn::MulAdd(w, d.c[ch], acc.plain[ch]);
  }
  acc.alpha = hn::Add(acc.alpha, wa);
}

template <bool kSrgb>
HWY_INLINE void Bilinear(const LevelView& L, VF u, VF v, bool rep_u, bool rep_v, VF weight,
                         const float* srgb, Acc& acc) {
  const DF df;
  const DI di;
  VI x0, x1, y0, y1;
  VF ax, ay;
  AxisLinear(u, L.w, rep_u, x0, x1, ax);
  AxisLinear(v, L.h, rep_v, y0, y1, ay);
  const VI stride = hn::Set(di, L.w);
  const VI r0 = hn::Mul(y0, stride), r1 = hn::Mul(y1, stride);
  const VF one = hn::Set(df, 1.0f);
  const VF wy1 = hn::Mul(ay, weight);
  const VF wy0 = hn::Mul(hn::Sub(one, ay), weight);
  const VF bx = hn::Sub(one, ax);
  Tap<kSrgb>(L.texels, hn::Add(r0, x0), hn::Mul(bx, wy0), srgb, acc);
  Tap<kSrgb>(L.texels, hn::Add(r0, x1), hn::Mul(ax, wy0), srgb, acc);
  Tap<kSrgb>(L.texels, hn::Add(r1, x0), hn::Mul(bx, wy1), srgb, acc);
  Tap<kSrgb>(L.texels, hn::Add(r1, x1), hn::Mul(ax, wy1), srgb, acc);
}

template <bool kSrgb, Filter kFilter>
void SampleT(const Texture& tex, const SamplerState& s, const float* HWY_RESTRICT u,
             const float* HWY_RESTRICT v, size_t lanes, float* const out[4]) {
  const DF df;
  const size_t N = hn::Lanes(df);
  const bool rep_u = s.wrap_u == Wrap::Repeat, rep_v = s.wrap_v == Wrap::Repeat;
  const float* srgb = srgb8_to_linear_table();
  const VF colour_scale = hn::Set(df, kSrgb ? 1.0f : 1.0f / 255.0f);
  const VF alpha_scale = hn::Set(df, 1.0f / 255.0f);
  const LevelView base = View(tex, 0);
  const double top = tex.levels() - 1;

  for (size_t b = 0; b < lanes; b += kBlockLanes) {
    LevelView L0 = base, L1 = base;
    float t = 0.0f;
    if constexpr (kFilter == Filter::Trilinear) {
      const double lambda = block_lod(u + b, v + b, base.w, base.h) + double(s.lod_bias);
      const double clamped = lambda > 0.0 ? std::min(lambda, top) : 0.0;
      const int l0 = int(clamped);
      L0 = View(tex, l0);
      t = float(clamped - l0);
      if (t > 0.0f) L1 = View(tex, std::min(l0 + 1, tex.levels() - 1));
    }
    for (size_t i = b; i < b + kBlockLanes; i += N) {
      const VF uu = hn::LoadU(df, u + i), vv = hn::LoadU(df, v + i);
      if constexpr (kFilter == Filter::Nearest) {
        const VI xi = AxisNearest(uu, base.w, rep_u);
        const VI yi = AxisNearest(vv, base.h, rep_v);
        const VI idx = hn::Add(hn::Mul(yi, hn::Set(DI(), base.w)), xi);
        const Decoded d = Fetch<kSrgb>(base.texels, idx, srgb);
        for (int ch = 0; ch < 3; ++ch) hn::StoreU(hn::Mul(d.c[ch], colour_scale), df, out[ch] + i);
        hn::StoreU(hn::Mul(d.a, alpha_scale), df, out[3] + i);
        continue;
      }
      Acc acc;
      for (int ch = 0; ch < 3; ++ch) acc.pm[ch] = acc.plain[ch] = hn::Zero(df);
      acc.alpha = hn::Zero(df);
      if (t > 0.0f) {
        Bilinear<kSrgb>(L0, uu, vv, rep_u, rep_v, hn::Set(df, 1.0f - t), srgb, acc);
        Bilinear<kSrgb>(L1, uu, vv, rep_u, rep_v, hn::Set(df, t), srgb, acc);
      } else {
        Bilinear<kSrgb>(L0, uu, vv, rep_u, rep_v, hn::Set(df, 1.0f), srgb, acc);
      }
      const auto opaque_part = hn::Gt(acc.alpha, hn::Zero(df));
      const VF inv = hn::Div(colour_scale, acc.alpha);  // inf where alpha is 0: not selected
      for (int ch = 0; ch < 3; ++ch) {
        const VF c = hn::IfThenElse(opaque_part, hn::Mul(acc.pm[ch], inv),
                                    hn::Mul(acc.plain[ch], colour_scale));
        hn::StoreU(c, df, out[ch] + i);
      }
      hn::StoreU(hn::Mul(acc.alpha, alpha_scale), df, out[3] + i);
    }
  }
}

void SampleImpl(const Texture& tex, const SamplerState& s, const float* u, const float* v,
                size_t lanes, float* const out[4]) {
  const bool srgb = tex.encoding() == TexelEncoding::Srgb;
  switch (s.filter) {
    case Filter::Nearest:
      return srgb ? SampleT<true, Filter::Nearest>(tex, s, u, v, lanes, out)
                  : SampleT<false, Filter::Nearest>(tex, s, u, v, lanes, out);
    case Filter::Bilinear:
      return srgb ? SampleT<true, Filter::Bilinear>(tex, s, u, v, lanes, out)
                  : SampleT<false, Filter::Bilinear>(tex, s, u, v, lanes, out);
    case Filter::Trilinear:
      return srgb ? SampleT<true, Filter::Trilinear>(tex, s, u, v, lanes, out)
                  : SampleT<false, Filter::Trilinear>(tex, s, u, v, lanes, out);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace pelt::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::raster {

HWY_EXPORT(SampleImpl);

void sample(const Texture& tex, const SamplerState& state, const float* u, const float* v,
            size_t lanes, float* const out[4]) {
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
      state.filter != Filter::Trilinear)
    throw std::invalid_argument("sample: state.filter is not a Filter value");
  HWY_DYNAMIC_DISPATCH(SampleImpl)(tex, state, u, v, lanes, out);
}

}  // namespace pelt::raster
#endif  // HWY_ONCE
