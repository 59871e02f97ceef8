// SIMD shading kernels. One source compiled per Highway target; the entry points in pelt::shading
// validate once and dispatch once per call. Every formula mirrors skin_reference.cpp (double
// precision); comments there state the terms' bounds and the deviations from the paper.

#include <cfloat>
#include <cmath>
#include <stdexcept>

#include "shading/skin_kernels.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shading/skin_kernels.cc"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "hwy/contrib/math/math-inl.h"

#ifndef PELT_SHADING_SKIN_KERNELS_ONCE
#define PELT_SHADING_SKIN_KERNELS_ONCE
namespace pelt::shading::detail {
// Per-call constants, computed in scalar code before dispatch.
struct LightSums {
  float all[3];      // sum of every light's colour (the paper's fake epidermis uses no direction)
  float ambient[3];  // sum of the ambient lights' colours
};
enum class Basic : int { unlit, lambert, blinn };
}  // namespace pelt::shading::detail
#endif

HWY_BEFORE_NAMESPACE();
namespace pelt::shading::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

struct V3 {
  V x, y, z;
};

HWY_INLINE V Dot(const V3& a, const V3& b) {
  return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}
HWY_INLINE V3 Select(M m, const V3& a, const V3& b) {
  return {hn::IfThenElse(m, a.x, b.x), hn::IfThenElse(m, a.y, b.y), hn::IfThenElse(m, a.z, b.z)};
}
HWY_INLINE V3 Load3(D d, const float* const p[3], size_t i) {
  return {hn::Load(d, p[0] + i), hn::Load(d, p[1] + i), hn::Load(d, p[2] + i)};
}
HWY_INLINE V Clamp(V x, V lo, V hi) { return hn::Min(hn::Max(x, lo), hi); }

// Normalises v; `ok` is false where |v|^2 < kDegenerateNormal2 or overflowed (those lanes of the
// result are garbage and must be replaced by the caller).
HWY_INLINE V3 Normalize(D d, const V3& v, M& ok) {
  const V len2 = Dot(v, v);
  ok = hn::And(hn::Ge(len2, hn::Set(d, kDegenerateNormal2)), hn::Le(len2, hn::Set(d, FLT_MAX)));
  const V inv = hn::Div(hn::Set(d, 1.0f), hn::Sqrt(hn::Max(len2, hn::Set(d, kDegenerateNormal2))));
  return {hn::Mul(v.x, inv), hn::Mul(v.y, inv), hn::Mul(v.z, inv)};
}

struct Frame {
  V3 n, v;
  M flipped;
  V co;
};

// Same rules as ref::make_frame: a degenerate normal becomes the view direction and vice versa,
// both degenerate give +z; the normal is turned toward the viewer.
HWY_INLINE Frame MakeFrame(D d, const SurfaceSoA& s, size_t i, const float eye[3]) {
  const V3 p = Load3(d, s.pos, i);
  M n_ok, v_ok;
  const V3 n0 = Normalize(d, Load3(d, s.normal, i), n_ok);
  const V3 v0 = Normalize(d, {hn::Sub(hn::Set(d, eye[0]), p.x), hn::Sub(hn::Set(d, eye[1]), p.y),
                              hn::Sub(hn::Set(d, eye[2]), p.z)},
                          v_ok);
  const V3 z = {hn::Zero(d), hn::Zero(d), hn::Set(d, 1.0f)};
  const V3 v1 = Select(v_ok, v0, Select(n_ok, n0, z));
  const V3 n1 = Select(n_ok, n0, v1);
  Frame f;
  f.flipped = hn::Lt(Dot(n1, v1), hn::Zero(d));
  f.n = {hn::IfThenElse(f.flipped, hn::Neg(n1.x), n1.x), hn::IfThenElse(f.flipped, hn::Neg(n1.y), n1.y),
         hn::IfThenElse(f.flipped, hn::Neg(n1.z), n1.z)};
  f.v = v1;
  f.co = Clamp(Dot(f.n, f.v), hn::Zero(d), hn::Set(d, 1.0f));
  return f;
}

// Unit direction to a non-ambient light; a point light at the shaded point shines along n.
HWY_INLINE V3 LightDir(D d, const Light& l, const SurfaceSoA& s, size_t i, const V3& n) {
  if (l.type == Light::Type::Directional) {
    const double len = std::sqrt(double(l.vec[0]) * l.vec[0] + double(l.vec[1]) * l.vec[1] +
                                 double(l.vec[2]) * l.vec[2]);
    return {hn::Set(d, float(l.vec[0] / len)), hn::Set(d, float(l.vec[1] / len)),
            hn::Set(d, float(l.vec[2] / len))};
  }
  const V3 p = Load3(d, s.pos, i);
  M ok;
  const V3 L = Normalize(d, {hn::Sub(hn::Set(d, l.vec[0]), p.x), hn::Sub(hn::Set(d, l.vec[1]), p.y),
                             hn::Sub(hn::Set(d, l.vec[2]), p.z)},
                         ok);
  return Select(ok, L, n);
}

// s^power for s in (0, 1], 0 for s <= 0. An integer power (int_power >= 0; the defaults,
// Power 20 and shininess 32, are) takes repeated squaring: a handful of multiplies
// instead of Log and Exp, the costliest part of the sebum and Blinn terms.
HWY_INLINE V SpecularLobe(D d, V s, V power, int int_power) {
  const M pos = hn::Gt(s, hn::Zero(d));
  const V sc = hn::Min(hn::IfThenElse(pos, s, hn::Set(d, 1.0f)), hn::Set(d, 1.0f));
  if (int_power >= 0) {
    V result = hn::Set(d, 1.0f), base = sc;
    for (int n = int_power; n > 0; n >>= 1) {
      if (n & 1) result = hn::Mul(result, base);
      if (n > 1) base = hn::Mul(base, base);
    }
    return hn::IfThenElseZero(pos, result);
  }
  return hn::IfThenElseZero(pos, hn::Exp(d, hn::Mul(power, hn::Log(d, sc))));
}

// The exponent as an integer when it is one (the loop above), else -1.
inline int IntegerPower(float power) {
  return (power >= 0.0f && power <= 1024.0f && power == float(int(power))) ? int(power) : -1;
}

// Refracted cosine; `ok` false on total internal reflection. k = (c^2 + eta^2 - 1) / eta^2.
HWY_INLINE V RefractCos(D d, V c, V eta2m1, V inv_eta2, M& ok) {
  const V k = hn::Mul(hn::Add(hn::Mul(c, c), eta2m1), inv_eta2);
  ok = hn::Gt(k, hn::Zero(d));
  return hn::Sqrt(hn::Max(k, hn::Zero(d)));
}

// Unpolarised Fresnel transmittance 1 - F for c in [0, 1] with refracted cosine ct (ok false on
// total internal reflection, where the result is 0).
// Evaluated as 2 eta c ct (1/(c + eta ct)^2 + 1/(eta c + ct)^2) (1 - r^2 factored), which keeps
// its relative precision at grazing angles where 1 - F would cancel.
HWY_INLINE V FresnelKt(D d, V c, V ct, M ok, V eta) {
  const V one = hn::Set(d, 1.0f);
  // The denominators vanish only where ct = 0, i.e. where !ok; those lanes are replaced below.
  const V ds = hn::IfThenElse(ok, hn::Add(c, hn::Mul(eta, ct)), one);
  const V dp = hn::IfThenElse(ok, hn::Add(hn::Mul(eta, c), ct), one);
  const V ds2 = hn::Mul(ds, ds), dp2 = hn::Mul(dp, dp);
  const V sum = hn::Div(hn::Add(ds2, dp2), hn::Mul(ds2, dp2));  // 1/ds^2 + 1/dp^2
  const V kt = hn::Mul(hn::Mul(hn::Mul(hn::Set(d, 2.0f), eta), hn::Mul(c, ct)), sum);
  return hn::IfThenElseZero(ok, Clamp(kt, hn::Zero(d), one));
}

// Transmittance after Pharr's efresnel boost, 1 - smoothstep(0, 0.5, F), from the exact
// transmittance Kt = 1 - F. Uses 1 - smoothstep(t) = smoothstep(1 - t), with 1 - t = 2 Kt - 1:
// subtracting a smoothstep near 1 from 1 would lose the small result to cancellation.
HWY_INLINE V EfresnelKt(D d, V kt) {
  const V u = Clamp(hn::Sub(hn::Add(kt, kt), hn::Set(d, 1.0f)), hn::Zero(d), hn::Set(d, 1.0f));
  return hn::Mul(hn::Mul(u, u), hn::Sub(hn::Set(d, 3.0f), hn::Add(u, u)));
}

// Dipole total diffuse reflectance for reduced albedo alpha in [0, 1] (A precomputed per call).
HWY_INLINE V DipoleRd(D d, V alpha, float A) {
  const V s = hn::Sqrt(hn::Mul(hn::Set(d, 3.0f), hn::Sub(hn::Set(d, 1.0f), alpha)));
  const V e1 = hn::Exp(d, hn::Mul(hn::Set(d, float(-4.0 / 3.0 * A)), s));
  const V e2 = hn::Exp(d, hn::Neg(s));
  return hn::Mul(hn::Mul(hn::Mul(hn::Set(d, 0.5f), alpha), hn::Add(hn::Set(d, 1.0f), e1)), e2);
}

HWY_INLINE void StoreLayer(D d, float* const dst[3], size_t i, const V v[3]) {
  for (int c = 0; c < 3; ++c)
    if (dst[c]) hn::Store(v[c], d, dst[c] + i);
}

void ShadeSkinBatch(const SkinParams& p, const Light* lights, size_t light_count,
                    const detail::LightSums& sums, const float eye[3], const SurfaceSoA& s,
                    const ShadeOutSoA& o) {
  const D d;
  const size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const float eta = p.Eta;
  const V veta = hn::Set(d, eta);
  const V eta2m1 = hn::Set(d, float((double(eta) - 1.0) * (double(eta) + 1.0)));
  const V inv_eta2 = hn::Set(d, float(1.0 / (double(eta) * eta)));
  const double g = std::fmin(std::fmax(double(p.g), -double(kMaxAbsG)), double(kMaxAbsG));
  const double ag = std::fabs(g);
  const V hg_floor = hn::Set(d, float((1.0 - ag) * (1.0 - ag)));
  const V hg_2ag = hn::Set(d, float(2.0 * ag));
  const V hg_2g = hn::Set(d, float(2.0 * g));
  const V hg_1mg2 = hn::Set(d, float((1.0 - g) * (1.0 + g)));
  const bool paper_phase = p.phase == Phase::paper;
  const V hg_k = hn::Set(d, float(paper_phase ? (1.0 - g) * (1.0 + g)
                                               : (1.0 - g) * (1.0 + g) / (4.0 * 3.14159265358979323846)));
  const V thickness = hn::Set(d, p.Thickness);
  const V tiny = hn::Set(d, 1e-20f);
  const V power = hn::Set(d, p.Power);
  const int int_power = IntegerPower(p.Power);
  const V ms = hn::Set(d, p.MultipleScatteringCoeff);
  const bool ss_on = p.single_scattering != SingleScattering::off;
  const bool ss_correct = p.single_scattering == SingleScattering::correct;
  const bool efres = p.fresnel == Fresnel::efresnel;
  const MultipleScattering mode = p.multiple_scattering;
  const double fdr_raw = -1.440 / (double(eta) * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
  const double fdr = std::fmin(std::fmax(fdr_raw, 0.0), 0.99);
  const float dipole_A = float((1.0 + fdr) / (1.0 - fdr));

  for (size_t base = 0; base < s.n; base += 16) {
    for (size_t i = base; i < base + 16; i += N) {
      const Frame f = MakeFrame(d, s, i, eye);
      V A[3], a[3], cd[3];
      for (int c = 0; c < 3; ++c) {
        A[c] = Clamp(hn::Load(d, s.albedo[c] + i), zero, one);
        a[c] = hn::Mul(hn::Set(d, p.SkinColor[c]), A[c]);
        cd[c] = hn::Mul(hn::Set(d, p.DiffusionColor[c]), A[c]);
      }
      V3 nb[3] = {f.n, f.n, f.n};
      if (mode == MultipleScattering::normal_blur)
        for (int c = 0; c < 3; ++c) {
          M ok;
          const V3 b = Normalize(d, Load3(d, s.blurred_normal[c], i), ok);
          const V3 bf = {hn::IfThenElse(f.flipped, hn::Neg(b.x), b.x),
                         hn::IfThenElse(f.flipped, hn::Neg(b.y), b.y),
                         hn::IfThenElse(f.flipped, hn::Neg(b.z), b.z)};
          nb[c] = Select(ok, bf, f.n);
        }
      M out_ok;
      const V cot = RefractCos(d, f.co, eta2m1, inv_eta2, out_ok);
      const V kt_out_exact = FresnelKt(d, f.co, cot, out_ok, veta);
      V kt_out = one;
      if (ss_correct) kt_out = efres ? EfresnelKt(d, kt_out_exact) : kt_out_exact;
      V rd[3] = {zero, zero, zero};
      if (mode == MultipleScattering::reference)
        for (int c = 0; c < 3; ++c) rd[c] = DipoleRd(d, cd[c], dipole_A);

      V sebum[3] = {zero, zero, zero}, epi[3] = {zero, zero, zero}, dermis[3] = {zero, zero, zero};
      if (mode == MultipleScattering::paper) {
        const V fake = hn::Div(ms, hn::Max(hn::Add(f.co, hn::Set(d, p.ClampCoeff)), hn::Set(d, kClampFloor)));
        for (int c = 0; c < 3; ++c) epi[c] = hn::Mul(hn::Mul(cd[c], hn::Set(d, sums.all[c])), fake);
      }

      for (size_t li = 0; li < light_count; ++li) {
        const Light& l = lights[li];
        if (l.type == Light::Type::Ambient) continue;
        const V cl[3] = {hn::Set(d, l.color[0]), hn::Set(d, l.color[1]), hn::Set(d, l.color[2])};
        const V3 L = LightDir(d, l, s, i, f.n);
        const V ci = Clamp(Dot(f.n, L), hn::Set(d, -1.0f), one);
        if (mode == MultipleScattering::normal_blur)
          for (int c = 0; c < 3; ++c) {
            const V w = hn::Set(d, p.normal_blur_mix[c]);
            const V lit = hn::Add(hn::Mul(hn::Sub(one, w), hn::Max(ci, zero)),
                                  hn::Mul(w, hn::Max(Dot(nb[c], L), zero)));
            epi[c] = hn::Add(epi[c], hn::Mul(hn::Mul(hn::Mul(cd[c], ms), cl[c]), lit));
          }
        const M lit = hn::Gt(ci, zero);
        if (hn::AllFalse(d, lit)) continue;

        const V LdotV = Dot(L, f.v);
        V lobe;
        if (p.specular == Specular::phong) {
          lobe = SpecularLobe(d, hn::Sub(hn::Mul(hn::Add(ci, ci), f.co), LdotV), power, int_power);
        } else {
          // |L + V| from the summed vector, not 2 + 2 L.V, which cancels at grazing angles.
          const V3 H = {hn::Add(L.x, f.v.x), hn::Add(L.y, f.v.y), hn::Add(L.z, f.v.z)};
          const V h2 = Dot(H, H);
          const M h_ok = hn::Gt(h2, hn::Set(d, 1e-30f));
          const V sh = hn::Div(Dot(f.n, H), hn::Sqrt(hn::IfThenElse(h_ok, h2, one)));
          lobe = hn::IfThenElseZero(h_ok, SpecularLobe(d, sh, power, int_power));
        }
        lobe = hn::IfThenElseZero(lit, lobe);
        for (int c = 0; c < 3; ++c)
          sebum[c] = hn::Add(sebum[c], hn::Mul(hn::Set(d, p.Specularity * p.SheenColor[c]), hn::Mul(cl[c], lobe)));

        const V cip = hn::Max(ci, zero);
        M in_ok;
        const V cit = RefractCos(d, cip, eta2m1, inv_eta2, in_ok);
        const V kt_in_exact = FresnelKt(d, cip, cit, in_ok, veta);
        if (mode == MultipleScattering::reference) {
          const V w = hn::IfThenElseZero(lit, hn::Mul(hn::Mul(ms, cip), hn::Mul(kt_in_exact, kt_out_exact)));
          for (int c = 0; c < 3; ++c) epi[c] = hn::Add(epi[c], hn::Mul(hn::Mul(cl[c], w), rd[c]));
        }
        if (!ss_on) continue;
        V kt_in = one;
        if (ss_correct) kt_in = efres ? EfresnelKt(d, kt_in_exact) : kt_in_exact;
        // 1 -+ cos(theta) of the refracted directions from the difference or sum of the unit
        // vectors: t_o -+ t_i = (V_t +- L_t) / eta + (co_t +- ci_t) n, so 1 -+ cos = abs(t_o -+ t_i)^2 / 2
        // (well conditioned at both phase peaks, unlike 1 - a dot product).
        const V3 Lt = {hn::Sub(L.x, hn::Mul(ci, f.n.x)), hn::Sub(L.y, hn::Mul(ci, f.n.y)),
                       hn::Sub(L.z, hn::Mul(ci, f.n.z))};
        const V3 Vt = {hn::Sub(f.v.x, hn::Mul(f.co, f.n.x)), hn::Sub(f.v.y, hn::Mul(f.co, f.n.y)),
                       hn::Sub(f.v.z, hn::Mul(f.co, f.n.z))};
        V b;
        if (paper_phase || g >= 0.0) {
          const V3 sum = {hn::Add(Lt.x, Vt.x), hn::Add(Lt.y, Vt.y), hn::Add(Lt.z, Vt.z)};
          const V cc = hn::Add(cit, cot);
          const V omc = Clamp(hn::Mul(hn::Set(d, 0.5f), hn::Add(hn::Mul(Dot(sum, sum), inv_eta2), hn::Mul(cc, cc))),
                              zero, hn::Set(d, 2.0f));  // 1 - cos(theta)
          if (paper_phase) {
            // 1 - g^2 - 2 g cos = 1 - g^2 - 2 g + 2 g (1 - cos)
            b = hn::Max(hn::Add(hn::Sub(hg_1mg2, hg_2g), hn::Mul(hg_2g, omc)), hg_floor);
          } else {
            b = hn::Add(hg_floor, hn::Mul(hg_2ag, omc));
          }
        } else {
          const V3 dif = {hn::Sub(Vt.x, Lt.x), hn::Sub(Vt.y, Lt.y), hn::Sub(Vt.z, Lt.z)};
          const V cd2 = hn::Sub(cot, cit);
          const V opc = Clamp(hn::Mul(hn::Set(d, 0.5f), hn::Add(hn::Mul(Dot(dif, dif), inv_eta2), hn::Mul(cd2, cd2))),
                              zero, hn::Set(d, 2.0f));  // 1 + cos(theta)
          b = hn::Add(hg_floor, hn::Mul(hg_2ag, opc));
        }
        // 1/ci + 1/co as (ci + co) / (ci co) with both floored at 1e-20 (their product is then
        // >= 1e-40, a float denormal, so it is floored at FLT_MIN instead: the exponent is
        // clamped at -100 anyway, where 1 - exp is 1 in float).
        const V cim = hn::Max(cit, tiny), com = hn::Max(cot, tiny);
        const V sum_inv = hn::Div(hn::Add(cim, com), hn::Max(hn::Mul(cim, com), hn::Set(d, FLT_MIN)));
        const V arg = hn::Max(hn::Neg(hn::Mul(thickness, sum_inv)), hn::Set(d, -100.0f));
        const V att = hn::Neg(hn::Expm1(d, arg));
        // phase x geometry in one division: hg_k att / (b^1.5 max(ci + co, 1e-20)).
        const V den = hn::Mul(hn::Mul(b, hn::Sqrt(b)), hn::Max(hn::Add(cit, cot), tiny));
        const V ph_geom = hn::Div(hn::Mul(hg_k, att), den);
        const M ok = hn::And(lit, hn::And(in_ok, out_ok));
        const V w = hn::IfThenElseZero(
            ok, hn::Mul(hn::Mul(hn::Mul(hn::Set(d, p.SingleScatteringCoeff), cip), hn::Mul(kt_in, kt_out)), ph_geom));
        for (int c = 0; c < 3; ++c) dermis[c] = hn::Add(dermis[c], hn::Mul(hn::Mul(cl[c], w), a[c]));
      }

      const V op = hn::Set(d, p.Opacity);
      V rgb[3];
      for (int c = 0; c < 3; ++c) {
        sebum[c] = hn::Mul(sebum[c], op);
        epi[c] = hn::Mul(epi[c], op);
        dermis[c] = hn::Mul(dermis[c], op);
        const V amb = hn::Mul(hn::Mul(hn::Set(d, p.AmbientCoeff * sums.ambient[c]), a[c]), op);
        rgb[c] = hn::Add(hn::Add(amb, sebum[c]), hn::Add(epi[c], dermis[c]));
      }
      StoreLayer(d, o.rgb, i, rgb);
      hn::Store(op, d, o.alpha + i);
      StoreLayer(d, o.sebum, i, sebum);
      StoreLayer(d, o.epidermis, i, epi);
      StoreLayer(d, o.dermis, i, dermis);
    }
  }
}

void ShadeBasicBatch(detail::Basic kind, const BasicParams& p, const Light* lights, size_t light_count,
                     const detail::LightSums& sums, const float eye[3], const SurfaceSoA& s,
                     const ShadeOutSoA& o) {
  const D d;
  const size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V shininess = hn::Set(d, p.shininess);
  const int int_shininess = IntegerPower(p.shininess);
  for (size_t base = 0; base < s.n; base += 16) {
    for (size_t i = base; i < base + 16; i += N) {
      V A[3], rgb[3];
      for (int c = 0; c < 3; ++c) A[c] = Clamp(hn::Load(d, s.albedo[c] + i), zero, one);
      if (kind == detail::Basic::unlit) {
        StoreLayer(d, o.rgb, i, A);
        hn::Store(one, d, o.alpha + i);
        continue;
      }
      const Frame f = MakeFrame(d, s, i, eye);
      V irr[3], spec[3];
      for (int c = 0; c < 3; ++c) {
        irr[c] = hn::Set(d, sums.ambient[c]);
        spec[c] = zero;
      }
      for (size_t li = 0; li < light_count; ++li) {
        const Light& l = lights[li];
        if (l.type == Light::Type::Ambient) continue;
        const V3 L = LightDir(d, l, s, i, f.n);
        const V ci = Clamp(Dot(f.n, L), hn::Set(d, -1.0f), one);
        const M lit = hn::Gt(ci, zero);
        const V cip = hn::Max(ci, zero);
        V lobe = zero;
        if (kind == detail::Basic::blinn) {
          const V3 H = {hn::Add(L.x, f.v.x), hn::Add(L.y, f.v.y), hn::Add(L.z, f.v.z)};
          const V h2 = Dot(H, H);
          const M h_ok = hn::And(lit, hn::Gt(h2, hn::Set(d, 1e-30f)));
          const V sh = hn::Div(Dot(f.n, H), hn::Sqrt(hn::IfThenElse(h_ok, h2, one)));
          lobe = hn::IfThenElseZero(h_ok, SpecularLobe(d, sh, shininess, int_shininess));
        }
        for (int c = 0; c < 3; ++c) {
          const V cl = hn::Set(d, l.color[c]);
          irr[c] = hn::Add(irr[c], hn::Mul(cl, cip));
          spec[c] = hn::Add(spec[c], hn::Mul(hn::Mul(cl, hn::Set(d, p.specular[c])), lobe));
        }
      }
      for (int c = 0; c < 3; ++c) rgb[c] = hn::Add(hn::Mul(A[c], irr[c]), spec[c]);
      StoreLayer(d, o.rgb, i, rgb);
      hn::Store(one, d, o.alpha + i);
    }
  }
}

}  // namespace pelt::shading::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::shading {

HWY_EXPORT(ShadeSkinBatch);
HWY_EXPORT(ShadeBasicBatch);

namespace {

void throw_if(const std::optional<ParamError>& e) {
  if (e) throw std::invalid_argument(e->message());
}

detail::LightSums sum_lights(const Light* lights, size_t count) {
  detail::LightSums s{};
  for (size_t i = 0; i < count; ++i)
    for (int c = 0; c < 3; ++c) {
      s.all[c] += lights[i].color[c];
      if (lights[i].type == Light::Type::Ambient) s.ambient[c] += lights[i].color[c];
    }
  return s;
}

void check_common(const Light* lights, size_t count, const float eye[3], const SurfaceSoA& s,
                  const ShadeOutSoA& o, bool needs_blurred) {
  throw_if(validate_lights(lights, count));
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(eye[c])) throw std::invalid_argument("eye[" + std::to_string(c) + "]: must be finite");
  throw_if(validate_batch(s, o, needs_blurred));
}

}  // namespace

void shade_skin(const SkinParams& params, const Light* lights, size_t light_count, const float eye[3],
                const SurfaceSoA& surface, const ShadeOutSoA& out) {
  throw_if(validate(params));
  check_common(lights, light_count, eye, surface, out,
               params.multiple_scattering == MultipleScattering::normal_blur);
  const detail::LightSums sums = sum_lights(lights, light_count);
  HWY_DYNAMIC_DISPATCH(ShadeSkinBatch)(params, lights, light_count, sums, eye, surface, out);
}

void shade_unlit(const Light* lights, size_t light_count, const float eye[3], const SurfaceSoA& surface,
                 const ShadeOutSoA& out) {
  check_common(lights, light_count, eye, surface, out, false);
  HWY_DYNAMIC_DISPATCH(ShadeBasicBatch)(detail::Basic::unlit, BasicParams{}, lights, light_count,
                                        sum_lights(lights, light_count), eye, surface, out);
}

void shade_lambert(const Light* lights, size_t light_count, const float eye[3], const SurfaceSoA& surface,
                   const ShadeOutSoA& out) {
  check_common(lights, light_count, eye, surface, out, false);
  HWY_DYNAMIC_DISPATCH(ShadeBasicBatch)(detail::Basic::lambert, BasicParams{}, lights, light_count,
                                        sum_lights(lights, light_count), eye, surface, out);
}

void shade_blinn(const BasicParams& params, const Light* lights, size_t light_count, const float eye[3],
                 const SurfaceSoA& surface, const ShadeOutSoA& out) {
  throw_if(validate(params));
  check_common(lights, light_count, eye, surface, out, false);
  HWY_DYNAMIC_DISPATCH(ShadeBasicBatch)(detail::Basic::blinn, params, lights, light_count,
                                        sum_lights(lights, light_count), eye, surface, out);
}

}  // namespace pelt::shading
#endif  // HWY_ONCE
