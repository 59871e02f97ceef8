// Normal mapping kernel (normal_map.h). One source compiled per Highway target; the entry point
// validates once and dispatches once per call. The model and its rules are the reference's
// (normal_map_reference.cpp); the header states the bounds and the precision.

#include <cstdint>
#include <stdexcept>

#include "shading/normal_map.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shading/normal_map_kernels.cc"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "shading/vec3-inl.h"

#ifndef PELT_SHADING_NORMAL_MAP_KERNELS_ONCE
#define PELT_SHADING_NORMAL_MAP_KERNELS_ONCE
namespace pelt::shading::normal_map_detail {
// |T orthogonalised|^2 below this fraction of |T|^2 (T within about 7 degrees of +-N): the lane
// is evaluated in double. Above it, two float passes keep every output within 3 ulps of |out|
// (of a unit vector: 2^-23 |out|) of the reference; below it the error grows as 1 / sin(T, N).
inline constexpr float kPreciseSin2 = 1.0f / 64.0f;
}  // namespace pelt::shading::normal_map_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace pelt::shading::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace normal_map {

using namespace vec3;

// A power of two that brings v's largest |component| into [1, 4) (a denormal one into
// [2^-22, 2)): 2^-e for the exponent e of that component, capped at 2^-126 so that it stays a
// normal float. Multiplying by it is exact, and the direction rules are scale-free, so it only
// keeps the squares below from overflowing (|v| > 1e19) or underflowing (|v| < 1e-19).
HWY_INLINE V Pow2Scale(D d, const V3& v) {
  const hn::RebindToSigned<D> di;
  const V a = hn::Max(hn::Max(hn::Abs(v.x), hn::Abs(v.y)), hn::Abs(v.z));
  const auto exponent = hn::And(hn::BitCast(di, a), hn::Set(di, 0x7F800000));
  return hn::BitCast(d, hn::Sub(hn::Set(di, 254 << 23), hn::Min(exponent, hn::Set(di, 253 << 23))));
}

// `lanes` (those the float path flagged as ill-conditioned) evaluated again by the reference and
// patched into `out`. The reference then also decides their degenerate case: a T along N passes
// N through exactly where the reference does, whatever the float roundings left of T.
HWY_NOINLINE void PreciseLanes(D d, M lanes, V3& out, const NormalMapSoA& s, size_t i) {
  constexpr size_t kMax = hn::MaxLanes(D());
  HWY_ALIGN float o[3][kMax];
  HWY_ALIGN int32_t flag[kMax];
  const hn::RebindToSigned<D> di;
  hn::Store(out.x, d, o[0]);
  hn::Store(out.y, d, o[1]);
  hn::Store(out.z, d, o[2]);
  hn::Store(hn::VecFromMask(di, hn::RebindMask(di, lanes)), di, flag);
  for (size_t k = 0; k < hn::Lanes(d); ++k) {
    if (!flag[k]) continue;
    const size_t j = i + k;
    const NormalMapSoA one{1,
                           {s.normal[0] + j, s.normal[1] + j, s.normal[2] + j},
                           {s.tangent[0] + j, s.tangent[1] + j, s.tangent[2] + j, s.tangent[3] + j},
                           {s.texel[0] + j, s.texel[1] + j, s.texel[2] + j}};
    float* const dst[3] = {o[0] + k, o[1] + k, o[2] + k};
    perturb_normals_reference(one, dst);
  }
  out = {hn::Load(d, o[0]), hn::Load(d, o[1]), hn::Load(d, o[2])};
}

// Lanes [i, i + Lanes(d)) of `s` into `out`.
HWY_INLINE void PerturbVector(D d, const NormalMapSoA& s, size_t i, float* const out[3]) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V3 n = LoadU3(d, s.normal, i);
  const V3 t = LoadU3(d, s.tangent, i);
  const V3 ns = Scale(n, Pow2Scale(d, n));
  const V3 ts0 = Scale(t, Pow2Scale(d, t));

  const V nn = Dot(ns, ns);  // 0 only for N = 0: a scaled non-zero N has a component >= 2^-22
  const M has_n = hn::Gt(nn, zero);
  const V inv_n = hn::IfThenElseZero(has_n, hn::Div(one, hn::Sqrt(hn::IfThenElse(has_n, nn, one))));
  // Its own division, not inv_n squared: the passes below then wait for a division only, not
  // for the square root too (measured 5-10% faster on AVX2).
  const V inv_nn = hn::IfThenElseZero(has_n, hn::Div(one, hn::IfThenElse(has_n, nn, one)));
  // Twice: the first pass's roundings (T.N, 1/|N|^2, k N) leave a component along N of a few ulps
  // of |T|, which turns a T near N noticeably; the second pass removes it (worst error on the
  // random test 13 ulps of |out| with one pass, 3 with two).
  V3 ts = ts0;
  for (int pass = 0; pass < 2; ++pass) {
    const V k = hn::Mul(Dot(ts, ns), inv_nn);
    ts = {hn::Sub(ts.x, hn::Mul(k, ns.x)), hn::Sub(ts.y, hn::Mul(k, ns.y)), hn::Sub(ts.z, hn::Mul(k, ns.z))};
  }
  const V tt = Dot(ts, ts);
  const M precise = hn::Lt(tt, hn::Mul(hn::Set(d, normal_map_detail::kPreciseSin2), Dot(ts0, ts0)));
  const M has_t = hn::Gt(tt, zero);
  const V inv_t = hn::Div(one, hn::Sqrt(hn::IfThenElse(has_t, tt, one)));
  const V3 tu = Scale(ts, inv_t), nu = Scale(ns, inv_n);
  V3 b = Cross(nu, tu);
  const M flip = hn::Lt(hn::LoadU(d, s.tangent[3] + i), zero);
  b = Select(flip, V3{hn::Neg(b.x), hn::Neg(b.y), hn::Neg(b.z)}, b);
  V m[3];
  for (int c = 0; c < 3; ++c) {
    const V tex = Clamp(hn::LoadU(d, s.texel[c] + i), zero, one);
    m[c] = hn::Sub(hn::Add(tex, tex), one);
  }
  V3 r = {hn::Add(hn::Add(hn::Mul(m[0], tu.x), hn::Mul(m[1], b.x)), hn::Mul(m[2], nu.x)),
          hn::Add(hn::Add(hn::Mul(m[0], tu.y), hn::Mul(m[1], b.y)), hn::Mul(m[2], nu.y)),
          hn::Add(hn::Add(hn::Mul(m[0], tu.z), hn::Mul(m[1], b.z)), hn::Mul(m[2], nu.z))};
  r = Select(has_t, r, n);
  if (HWY_UNLIKELY(!hn::AllFalse(d, precise))) PreciseLanes(d, precise, r, s, i);
  hn::StoreU(r.x, d, out[0] + i);
  hn::StoreU(r.y, d, out[1] + i);
  hn::StoreU(r.z, d, out[2] + i);
}

}  // namespace normal_map

void PerturbNormalsBatch(const NormalMapSoA& s, float* const out[3]) {
  using namespace normal_map;
  const D d;
  const size_t N = hn::Lanes(d);
  size_t i = 0;
  for (; i + N <= s.n; i += N) PerturbVector(d, s, i, out);
  if (i == s.n) return;
  // The last partial vector through zero-padded copies (a zero frame passes through as zero and
  // is never flagged): no load or store past n.
  constexpr size_t kMax = hn::MaxLanes(D());
  HWY_ALIGN float in[10][kMax] = {};
  HWY_ALIGN float res[3][kMax];
  const size_t valid = s.n - i;
  const float* const src[10] = {s.normal[0],  s.normal[1],  s.normal[2], s.tangent[0], s.tangent[1],
                                s.tangent[2], s.tangent[3], s.texel[0], s.texel[1],   s.texel[2]};
  for (int a = 0; a < 10; ++a)
    for (size_t k = 0; k < valid; ++k) in[a][k] = src[a][i + k];
  const NormalMapSoA tail{N, {in[0], in[1], in[2]}, {in[3], in[4], in[5], in[6]}, {in[7], in[8], in[9]}};
  float* const tail_out[3] = {res[0], res[1], res[2]};
  PerturbVector(d, tail, 0, tail_out);
  for (int c = 0; c < 3; ++c)
    for (size_t k = 0; k < valid; ++k) out[c][i + k] = res[c][k];
}

}  // namespace pelt::shading::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::shading {

HWY_EXPORT(PerturbNormalsBatch);

void perturb_normals(const NormalMapSoA& in, float* const out[3]) {
  if (auto e = validate_batch(in, out)) throw std::invalid_argument(e->message());
  HWY_DYNAMIC_DISPATCH(PerturbNormalsBatch)(in, out);
}

}  // namespace pelt::shading
#endif  // HWY_ONCE
