// Fur lighting kernels (fur_lighting.h). One source compiled per Highway target; the entry points
// validate once, prepare the lights once, and dispatch once per call. Every formula mirrors
// fur_lighting_reference.cpp (double precision), which is the specification.

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "shading/fur_lighting.h"
#include "shading/param_checks.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shading/fur_lighting.cc"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "hwy/contrib/math/math-inl.h"
#include "shading/vec3-inl.h"

#ifndef PELT_SHADING_FUR_LIGHTING_ONCE
#define PELT_SHADING_FUR_LIGHTING_ONCE
namespace pelt::shading::fur_detail {

// A non-ambient light as the kernel reads it: directional vectors already unit.
struct PreparedLight {
  bool point;
  float vec[3];  // unit direction to the light, or the point light's position
  float raw[3];  // the light's vector as given (PreciseLight normalises it again, in double)
  float color[3];
};

// Lanes evaluated again in double (PreciseLight): |T|^2 |L + V|^2, |N.L| and sin^2(T, L) below
// these.
inline constexpr float kBacklitHalf2 = 0.04f;
inline constexpr float kGrazingNdl = 0.01f;
inline constexpr float kParallelSin2 = 1e-4f;

// The per-call constants, computed in scalar code before dispatch.
struct Plan {
  const PreparedLight* lights;
  size_t light_count;
  float ambient[3];  // sum of the ambient lights' colours
  float eye[3];
  float ao_root, diffuse, specular, wrap;
  // sin^shininess = (sin^2)^exponent with exponent = shininess / 2 = whole + (half ? 0.5 : 0)
  // when shininess is an integer (repeated squaring, and a square root for the half), else
  // exp(exponent log(sin^2)).
  bool integer_path;
  uint32_t whole;
  bool half;
  float exponent;
  double shininess_half;  // the exact exponent, for the double path
  float lobe_min_sin2;  // sin^2 below this gives a lobe under kFurLobeFloor: flushed to 0
};

}  // namespace pelt::shading::fur_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace pelt::shading::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace fur {

using namespace vec3;

HWY_INLINE V3 Add3(const V3& a, const V3& b) { return {hn::Add(a.x, b.x), hn::Add(a.y, b.y), hn::Add(a.z, b.z)}; }
HWY_INLINE V3 Broadcast3(D d, const float v[3]) { return {hn::Set(d, v[0]), hn::Set(d, v[1]), hn::Set(d, v[2])}; }
HWY_INLINE V Clamp01(D d, V x) { return hn::Min(hn::Max(x, hn::Zero(d)), hn::Set(d, 1.0f)); }

// Unit v where `ok` (the header's degeneracy rule); other lanes are garbage for the caller to
// replace. 1/sqrt from Sqrt and Div (about an ulp), not the approximate reciprocal square root:
// the lobe's exponent (up to 256 on sin^2) magnifies any error in V's length past the tolerance.
HWY_INLINE V3 Normalize(D d, const V3& v, M& ok) {
  const V len2 = Dot(v, v);
  ok = hn::And(hn::Ge(len2, hn::Set(d, kDegenerateNormal2)), hn::Le(len2, hn::Set(d, FLT_MAX)));
  const V safe = hn::IfThenElse(ok, len2, hn::Set(d, 1.0f));
  return Scale(v, hn::Div(hn::Set(d, 1.0f), hn::Sqrt(safe)));
}

// (sin^2)^exponent for sin^2 in [0, 1], 0 below the flush threshold (so never a denormal:
// every partial product is >= the final value >= about kFurLobeFloor).
HWY_INLINE V Lobe(D d, V sin2, const fur_detail::Plan& plan) {
  const M keep = hn::Ge(sin2, hn::Set(d, plan.lobe_min_sin2));
  const V s = hn::IfThenElse(keep, sin2, hn::Set(d, 1.0f));
  V r;
  if (plan.integer_path) {
    r = plan.half ? hn::Sqrt(s) : hn::Set(d, 1.0f);
    V base = s;
    for (uint32_t k = plan.whole; k != 0;) {
      if (k & 1u) r = hn::Mul(r, base);
      k >>= 1;
      if (k != 0) base = hn::Mul(base, base);
    }
  } else {
    r = hn::Exp(d, hn::Mul(hn::Set(d, plan.exponent), hn::Log(d, s)));
  }
  return hn::IfThenElseZero(keep, r);
}

// The ill-conditioned corners of the model, where float rounding of an input direction (about
// 1e-7 absolute) would cost more than the 1e-4 relative tolerance:
//   - backlit: |L + V| < 0.2 (the fragment seen almost against the light). H is then a short
//     difference of two unit vectors; the rounding of their lengths turns it by up to
//     1e-7 / |L + V| radians, which a lobe raised to 256 magnifies past 1e-4;
//   - grazing: |N.L| < 0.01 (the terminator), where N.L's absolute error is a relative one;
//   - parallel: sin^2(T, L) < 1e-4 (the strand along the light), likewise for sin(T, L).
// Called only for vectors with such a lane (about 1-3% of random lanes, a thin band on a real
// surface): the flagged lanes' term for this light is evaluated again in double precision, as
// the reference does, and `dif` and `spc` are patched in place. Only backlit lanes recompute the
// lobe (scalar pow); the others keep the float `lobe`, which is well conditioned there.
HWY_NOINLINE void PreciseLight(D d, M lanes, M backlit, V& dif, V& spc, V lobe, const V3& t,
                               const FurSurfaceSoA& s, size_t i, const fur_detail::PreparedLight& l,
                               const fur_detail::Plan& plan) {
  constexpr size_t kMax = hn::MaxLanes(D());
  HWY_ALIGN float dif_a[kMax], spc_a[kMax], lobe_a[kMax], tx[kMax], ty[kMax], tz[kMax];
  HWY_ALIGN int32_t flag[kMax], back[kMax];
  const hn::RebindToSigned<D> di;
  hn::Store(dif, d, dif_a);
  hn::Store(spc, d, spc_a);
  hn::Store(lobe, d, lobe_a);
  hn::Store(t.x, d, tx);
  hn::Store(t.y, d, ty);
  hn::Store(t.z, d, tz);
  hn::Store(hn::VecFromMask(di, hn::RebindMask(di, lanes)), di, flag);
  hn::Store(hn::VecFromMask(di, hn::RebindMask(di, backlit)), di, back);
  const size_t n = hn::Lanes(d);
  for (size_t k = 0; k < n; ++k) {
    if (!flag[k]) continue;
    using Vec3 = std::array<double, 3>;
    auto dot = [](const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    auto sin2 = [&](const Vec3& a, const Vec3& b) {
      const Vec3 c = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
      const double cc = dot(c, c), ab = dot(a, b);
      return cc / (ab * ab + cc);
    };
    auto unit = [&](Vec3 v, Vec3& out) {  // the header's degeneracy rule
      const double len2 = dot(v, v);
      if (!(len2 >= double(kDegenerateNormal2) && len2 <= double(FLT_MAX))) return false;
      const double inv = 1.0 / std::sqrt(len2);
      out = {v[0] * inv, v[1] * inv, v[2] * inv};
      return true;
    };
    const Vec3 p = {s.pos[0][i + k], s.pos[1][i + k], s.pos[2][i + k]};
    Vec3 N{}, V{}, T{}, L{};
    const bool n_ok = unit({s.normal[0][i + k], s.normal[1][i + k], s.normal[2][i + k]}, N);
    const bool v_ok = unit({plan.eye[0] - p[0], plan.eye[1] - p[1], plan.eye[2] - p[2]}, V);
    if (!v_ok) V = {0.0, 0.0, 0.0};
    const Vec3 fallback = n_ok ? N : v_ok ? V : Vec3{0.0, 0.0, 1.0};
    if (!unit({s.tangent[0][i + k], s.tangent[1][i + k], s.tangent[2][i + k]}, T)) T = {tx[k], ty[k], tz[k]};
    if (!unit(l.point ? Vec3{l.raw[0] - p[0], l.raw[1] - p[1], l.raw[2] - p[2]} : Vec3{l.raw[0], l.raw[1], l.raw[2]},
              L))
      L = fallback;
    const double ndl = n_ok ? std::max(std::min(dot(N, L), 1.0), 0.0) : 1.0;
    const double wrap = plan.wrap;
    dif_a[k] = float(double(plan.diffuse) * std::sqrt(sin2(T, L)) * (wrap + (1.0 - wrap) * ndl));
    const Vec3 h = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double lob = lobe_a[k];
    if (dot(h, h) < double(kDegenerateHalf2)) {
      lob = 0.0;
    } else if (back[k]) {
      lob = std::pow(sin2(T, h), plan.shininess_half);
      if (lob < double(kFurLobeFloor)) lob = 0.0;
    }
    spc_a[k] = float(double(plan.specular) * lob * ndl);
  }
  dif = hn::Load(d, dif_a);
  spc = hn::Load(d, spc_a);
}

}  // namespace fur

// Called once per shade_fur call on the whole batch.
void ShadeFurBatch(const fur_detail::Plan& plan, const FurSurfaceSoA& s, const FurOutSoA& o) {
  using namespace fur;
  const D d;
  const size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V ao_root = hn::Set(d, plan.ao_root);
  const V kd = hn::Set(d, plan.diffuse), ks = hn::Set(d, plan.specular);
  const V wrap = hn::Set(d, plan.wrap), one_minus_wrap = hn::Set(d, 1.0f - plan.wrap);
  const V half_min = hn::Set(d, kDegenerateHalf2);
  const V backlit_half = hn::Set(d, fur_detail::kBacklitHalf2);
  const V grazing_ndl = hn::Set(d, fur_detail::kGrazingNdl);
  const V parallel_sin2 = hn::Set(d, fur_detail::kParallelSin2);
  const V3 eye = Broadcast3(d, plan.eye);

  for (size_t i = 0; i < s.n; i += N) {
    const V3 pos = Load3(d, s.pos, i);
    M n_ok, v_ok, t_ok;
    const V3 n = Normalize(d, Load3(d, s.normal, i), n_ok);
    V3 v = Normalize(d, {hn::Sub(eye.x, pos.x), hn::Sub(eye.y, pos.y), hn::Sub(eye.z, pos.z)}, v_ok);
    v = Select(v_ok, v, V3{zero, zero, zero});
    const V3 fallback = Select(n_ok, n, Select(v_ok, v, V3{zero, zero, one}));
    const V3 t_unit = Normalize(d, Load3(d, s.tangent, i), t_ok);
    const V3 t = Select(t_ok, t_unit, fallback);
    const V3 t_x_v = Cross(t, v);
    const V t_d_v = Dot(t, v);

    V diff[3] = {zero, zero, zero}, spec[3] = {zero, zero, zero};
    for (size_t li = 0; li < plan.light_count; ++li) {
      const fur_detail::PreparedLight& l = plan.lights[li];
      V3 L = Broadcast3(d, l.vec);
      if (l.point) {
        M l_ok;
        const V3 to_light = Normalize(d, {hn::Sub(L.x, pos.x), hn::Sub(L.y, pos.y), hn::Sub(L.z, pos.z)}, l_ok);
        L = Select(l_ok, to_light, fallback);
      }
      const V ndl_raw = Dot(n, L);
      const V ndl = hn::IfThenElse(n_ok, hn::Max(ndl_raw, zero), one);
      const V3 t_x_l = Cross(t, L);
      const V t_d_l = Dot(t, L);
      // T and L are unit within a few ulps, so |T x L|^2 is sin^2 without the scale division the
      // lobe needs (the diffuse term is linear in it: a few ulps stay a few ulps).
      const V sin2_l = hn::Min(Dot(t_x_l, t_x_l), one);
      V dif = hn::Mul(hn::Mul(kd, hn::Sqrt(sin2_l)), hn::Add(wrap, hn::Mul(one_minus_wrap, ndl)));

      // T x H and T.H up to the scale of H = L + V, from the per-fragment T x V and T.V.
      const V3 t_x_h = Add3(t_x_l, t_x_v);
      const V t_d_h = hn::Add(t_d_l, t_d_v);
      const V sin2_h_num = Dot(t_x_h, t_x_h);
      const V den_h = hn::Add(hn::Mul(t_d_h, t_d_h), sin2_h_num);  // |T|^2 |L + V|^2
      const M h_ok = hn::Ge(den_h, half_min);
      const V sin2_h = hn::Min(hn::Div(sin2_h_num, hn::IfThenElse(h_ok, den_h, one)), one);
      const V lobe = hn::IfThenElseZero(h_ok, Lobe(d, sin2_h, plan));
      V spc = hn::Mul(hn::Mul(ks, lobe), ndl);
      const M backlit = hn::And(hn::Lt(den_h, backlit_half), v_ok);
      const M grazing = hn::And(hn::Lt(hn::Abs(ndl_raw), grazing_ndl), n_ok);
      const M precise = hn::Or(backlit, hn::Or(grazing, hn::Lt(sin2_l, parallel_sin2)));
      if (HWY_UNLIKELY(!hn::AllFalse(d, precise))) PreciseLight(d, precise, backlit, dif, spc, lobe, t, s, i, l, plan);
      for (int c = 0; c < 3; ++c) {
        const V col = hn::Set(d, l.color[c]);
        diff[c] = hn::Add(diff[c], hn::Mul(col, dif));
        spec[c] = hn::Add(spec[c], hn::Mul(col, spc));
      }
    }
    // lerp(ao_root, 1, h) as h + (1 - h) ao_root: exactly ao_root at 0 and exactly 1 at 1.
    const V h = Clamp01(d, hn::Load(d, s.height + i));
    const V ao = hn::Add(h, hn::Mul(hn::Sub(one, h), ao_root));
    for (int c = 0; c < 3; ++c) {
      const V tex = Clamp01(d, hn::Load(d, s.texel[c] + i));
      const V lit = hn::Add(hn::Mul(tex, hn::Add(hn::Set(d, plan.ambient[c]), diff[c])), spec[c]);
      hn::Store(hn::Mul(ao, lit), d, o.rgba[c] + i);
    }
    hn::Store(Clamp01(d, hn::Load(d, s.texel[3] + i)), d, o.rgba[3] + i);
  }
}

// Called once per shade_fur_match_llvmpipe call; `light` is unit.
void ShadeFurLlvmpipeBatch(const float light[3], const FurSurfaceSoA& s, const FurOutSoA& o) {
  using namespace fur;
  const D d;
  const size_t N = hn::Lanes(d);
  const V one = hn::Set(d, 1.0f);
  const V3 L = Broadcast3(d, light);
  const V k0 = hn::Set(d, 0.35f), k1 = hn::Set(d, 0.65f);
  for (size_t i = 0; i < s.n; i += N) {
    M n_ok;
    const V3 n = Normalize(d, Load3(d, s.normal, i), n_ok);
    const V ndl = hn::IfThenElse(n_ok, hn::Max(Dot(n, L), hn::Zero(d)), one);
    const V k = hn::Add(k0, hn::Mul(k1, ndl));
    for (int c = 0; c < 3; ++c) hn::Store(hn::Mul(Clamp01(d, hn::Load(d, s.texel[c] + i)), k), d, o.rgba[c] + i);
    hn::Store(Clamp01(d, hn::Load(d, s.texel[3] + i)), d, o.rgba[3] + i);
  }
}

}  // namespace pelt::shading::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::shading {

HWY_EXPORT(ShadeFurBatch);
HWY_EXPORT(ShadeFurLlvmpipeBatch);

namespace {

using checks::fmt;
using checks::pointer;
using checks::range;

void throw_if(const std::optional<ParamError>& e) {
  if (e) throw std::invalid_argument(e->message());
}

// Lights kept on the stack up to this count: no allocation for any ordinary scene.
constexpr size_t kInlineLights = 16;

}  // namespace

std::optional<ParamError> validate(const FurLightParams& p) {
  if (auto e = range("ambient_occlusion_root", p.ambient_occlusion_root, 0.0, 1.0)) return e;
  if (auto e = range("diffuse", p.diffuse, 0.0, 100.0)) return e;
  if (auto e = range("specular", p.specular, 0.0, 100.0)) return e;
  if (auto e = range("shininess", p.shininess, 1.0, 512.0)) return e;
  if (auto e = range("backlight_wrap", p.backlight_wrap, 0.0, 1.0)) return e;
  return std::nullopt;
}

std::optional<ParamError> validate_batch(const FurSurfaceSoA& s, const FurOutSoA& o, bool needs_strand) {
  if (s.n % 16 != 0) return ParamError{"n", "must be a multiple of 16, got " + std::to_string(s.n)};
  static constexpr const char* kXyz[3] = {"x", "y", "z"};
  for (int c = 0; c < 3; ++c) {
    const auto named = [c](const char* what) { return [=] { return std::string(what) + "[" + kXyz[c] + "]"; }; };
    if (needs_strand) {
      if (auto e = pointer(named("pos"), s.pos[c])) return e;
      if (auto e = pointer(named("tangent"), s.tangent[c])) return e;
    }
    if (auto e = pointer(named("normal"), s.normal[c])) return e;
  }
  if (needs_strand)
    if (auto e = pointer("height", s.height)) return e;
  for (int c = 0; c < 4; ++c)
    if (auto e = pointer([c] { return "texel[" + std::to_string(c) + "]"; }, s.texel[c])) return e;
  for (int c = 0; c < 4; ++c)
    if (auto e = pointer([c] { return "rgba[" + std::to_string(c) + "]"; }, o.rgba[c])) return e;
  return std::nullopt;
}

std::optional<ParamError> validate_light_dir(const float light_dir[3]) {
  if (!light_dir) return ParamError{"light_dir", "must not be null"};
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(light_dir[c]))
      return ParamError{"light_dir[" + std::to_string(c) + "]", "must be finite, got " + fmt(light_dir[c])};
  const double len2 = double(light_dir[0]) * light_dir[0] + double(light_dir[1]) * light_dir[1] +
                      double(light_dir[2]) * light_dir[2];
  if (!(len2 > 1e-12)) return ParamError{"light_dir", "must be a non-zero direction"};
  return std::nullopt;
}

void shade_fur(const FurLightParams& params, const Light* lights, size_t light_count, const float eye[3],
               const FurSurfaceSoA& surface, const FurOutSoA& out) {
  throw_if(validate(params));
  throw_if(validate_lights(lights, light_count));
  if (!eye) throw std::invalid_argument("eye: must not be null");
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(eye[c])) throw std::invalid_argument("eye[" + std::to_string(c) + "]: must be finite");
  throw_if(validate_batch(surface, out, true));

  std::array<fur_detail::PreparedLight, kInlineLights> inline_lights;
  std::vector<fur_detail::PreparedLight> many;
  fur_detail::PreparedLight* prepared = inline_lights.data();
  if (light_count > kInlineLights) {
    many.resize(light_count);
    prepared = many.data();
  }
  fur_detail::Plan plan{};
  for (size_t i = 0; i < light_count; ++i) {
    const Light& l = lights[i];
    if (l.type == Light::Type::Ambient) {
      for (int c = 0; c < 3; ++c) plan.ambient[c] += l.color[c];
      continue;
    }
    fur_detail::PreparedLight& p = prepared[plan.light_count++];
    p.point = l.type == Light::Type::Point;
    kernel_light_vector(l, p.vec);
    for (int c = 0; c < 3; ++c) {
      p.raw[c] = l.vec[c];
      p.color[c] = l.color[c];
    }
  }
  plan.lights = prepared;
  for (int c = 0; c < 3; ++c) plan.eye[c] = eye[c];
  plan.ao_root = params.ambient_occlusion_root;
  plan.diffuse = params.diffuse;
  plan.specular = params.specular;
  plan.wrap = params.backlight_wrap;
  const double exponent = double(params.shininess) * 0.5;
  plan.exponent = float(exponent);
  plan.shininess_half = exponent;
  plan.integer_path = params.shininess == std::floor(params.shininess);
  plan.whole = uint32_t(std::floor(exponent));
  plan.half = exponent != std::floor(exponent);
  // sin2^exponent < kFurLobeFloor below this; never below FLT_MIN, so sin2 itself is normal.
  plan.lobe_min_sin2 = float(std::fmax(std::pow(double(kFurLobeFloor), 1.0 / exponent), double(FLT_MIN)));
  HWY_DYNAMIC_DISPATCH(ShadeFurBatch)(plan, surface, out);
}

void shade_fur_match_llvmpipe(const float light_dir[3], const FurSurfaceSoA& surface, const FurOutSoA& out) {
  throw_if(validate_light_dir(light_dir));
  throw_if(validate_batch(surface, out, false));
  const double len = std::sqrt(double(light_dir[0]) * light_dir[0] + double(light_dir[1]) * light_dir[1] +
                               double(light_dir[2]) * light_dir[2]);
  const float unit[3] = {float(light_dir[0] / len), float(light_dir[1] / len), float(light_dir[2] / len)};
  HWY_DYNAMIC_DISPATCH(ShadeFurLlvmpipeBatch)(unit, surface, out);
}

}  // namespace pelt::shading
#endif  // HWY_ONCE
