// SIMD shading kernels. One source compiled per Highway target; the entry points in pelt::shading
// validate once and dispatch once per call. Every formula mirrors skin_reference.cpp (double
// precision); comments there state the terms' bounds and the deviations from the paper.

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "shading/skin_kernels.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shading/skin_kernels.cc"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "hwy/contrib/math/math-inl.h"
#include "shading/vec3-inl.h"

#ifndef PELT_SHADING_SKIN_KERNELS_ONCE
#define PELT_SHADING_SKIN_KERNELS_ONCE
namespace pelt::shading::detail {
// Per-call constants, computed in scalar code before dispatch.
struct LightSums {
  float all[3];      // sum of every light's colour (the paper's fake epidermis uses no direction)
  float ambient[3];  // sum of the ambient lights' colours
};
enum class Basic : int { unlit, lambert, blinn };

// A non-ambient light as the kernels read it, prepared once per call in scalar code before
// dispatch: renormalising a directional light in double (a square root and three divisions)
// inside the kernels sat on the critical path of every lane vector, and the compiler cannot
// hoist it there (the output stores may alias the Light array as far as it knows).
struct KernelLight {
  float vec[3];  // kernel_light_vector: unit direction to the light, or the point light's position
  bool point;
  float color[3];
  float sebum[3];  // skin only: Opacity Specularity SheenColor color, the sebum layer per unit lobe
};
}  // namespace pelt::shading::detail
#endif

HWY_BEFORE_NAMESPACE();
namespace pelt::shading::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using namespace vec3;

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
// At Eta = 1 (`eta_one`) the cosine is c itself: c^2 underflows below c = 1e-19 (to zero under
// flush-to-zero, gradually to zero at 4e-23 without) and would turn a grazing view into total
// internal reflection. Above that sqrt(c * c) is c exactly, so the shortcut changes no result.
HWY_INLINE V RefractCos(D d, V c, V eta2m1, V inv_eta2, bool eta_one, M& ok) {
  if (eta_one) {
    ok = hn::Gt(c, hn::Zero(d));
    return c;
  }
  const V k = hn::Mul(hn::Add(hn::Mul(c, c), eta2m1), inv_eta2);
  ok = hn::Gt(k, hn::Zero(d));
  return hn::Sqrt(hn::Max(k, hn::Zero(d)));
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

// 2^-e for x in [2^e, 2^(e+1)) with 0 <= x < 2^127, and 2^127 for zero or subnormal x: the
// exact scale that brings a normal x into [1, 2).
HWY_INLINE V InversePowerOfTwo(D d, V x) {
  const hn::RebindToSigned<D> di;
  const auto exponent = hn::And(hn::BitCast(di, x), hn::Set(di, 0x7F800000));
  return hn::BitCast(d, hn::Sub(hn::Set(di, 254 << 23), exponent));
}

// Unpolarised Fresnel transmittance 1 - F = num / den for c in [0, 1] with refracted cosine ct
// (ok false on total internal reflection, where the caller sets the result to 0), clamped to
// [0, 1] by the caller. Evaluated as 2 eta c ct (1/(c + eta ct)^2 + 1/(eta c + ct)^2) (1 - r^2
// factored), which keeps its relative precision at grazing angles where 1 - F would cancel,
// with the two fractions over the common denominator (c + eta ct)^2 (eta c + ct)^2, so one
// division; returned as a fraction so that the caller may share that division with another.
// The denominators vanish only where ct = 0, i.e. where !ok: those lanes get den = 1.
// num and den are of degree 4 in (c, ct), so c and ct are first scaled by the power of two that
// brings the larger into [1, 2): at Eta = 1 and c = 1e-10 both would otherwise underflow (16 c^4)
// to 0/0, which the caller's clamp turns into 0 instead of 1. A power of two scales every
// rounding exactly, so where nothing underflowed the ratio keeps its bits.
HWY_INLINE void FresnelKtParts(D d, V c_in, V ct_in, M ok, V eta, V& num, V& den) {
  const V scale = InversePowerOfTwo(d, hn::Max(c_in, ct_in));
  const V c = hn::Mul(c_in, scale), ct = hn::Mul(ct_in, scale);
  const V one = hn::Set(d, 1.0f);
  const V ds = hn::IfThenElse(ok, hn::MulAdd(eta, ct, c), one);
  const V dp = hn::IfThenElse(ok, hn::MulAdd(eta, c, ct), one);
  const V ds2 = hn::Mul(ds, ds), dp2 = hn::Mul(dp, dp);
  den = hn::Mul(ds2, dp2);
  num = hn::Mul(hn::Mul(hn::Add(eta, eta), hn::Mul(c, ct)), hn::Add(ds2, dp2));
}

// The shading frame of lanes i.. (ref::make_frame's rules: a degenerate normal becomes the view
// direction and vice versa, both degenerate give +z; the normal is turned toward the viewer),
// into separate vectors: GCC copied V3 aggregates through the stack in 64-bit pieces
// (store-forwarding stalls in every lane vector).
HWY_INLINE void LaneFrame(D d, const SurfaceSoA& s, size_t i, const float eye[3], V& nx, V& ny, V& nz, V& vx,
                          V& vy, V& vz, V& co, M& flipped) {
  const V px = hn::Load(d, s.pos[0] + i), py = hn::Load(d, s.pos[1] + i), pz = hn::Load(d, s.pos[2] + i);
  const V ax = hn::Load(d, s.normal[0] + i), ay = hn::Load(d, s.normal[1] + i), az = hn::Load(d, s.normal[2] + i);
  const V bx = hn::Sub(hn::Set(d, eye[0]), px), by = hn::Sub(hn::Set(d, eye[1]), py),
          bz = hn::Sub(hn::Set(d, eye[2]), pz);
  const V lo = hn::Set(d, kDegenerateNormal2), hi = hn::Set(d, FLT_MAX), one = hn::Set(d, 1.0f);
  const V la = hn::MulAdd(az, az, hn::MulAdd(ay, ay, hn::Mul(ax, ax)));
  const V lb = hn::MulAdd(bz, bz, hn::MulAdd(by, by, hn::Mul(bx, bx)));
  const M n_ok = hn::And(hn::Ge(la, lo), hn::Le(la, hi));
  const M v_ok = hn::And(hn::Ge(lb, lo), hn::Le(lb, hi));
  // Two divisions, not one shared by both lengths: a rounding more in |N| moves R.V by a few
  // 1e-7, which a Phong exponent of 200 amplifies past the 1e-4 tolerance.
  const V ia = hn::Div(one, hn::Sqrt(Clamp(la, lo, hi)));
  const V ib = hn::Div(one, hn::Sqrt(Clamp(lb, lo, hi)));
  const V n0x = hn::Mul(ax, ia), n0y = hn::Mul(ay, ia), n0z = hn::Mul(az, ia);
  const V v0x = hn::Mul(bx, ib), v0y = hn::Mul(by, ib), v0z = hn::Mul(bz, ib);
  const V zero = hn::Zero(d);
  vx = hn::IfThenElse(v_ok, v0x, hn::IfThenElseZero(n_ok, n0x));
  vy = hn::IfThenElse(v_ok, v0y, hn::IfThenElseZero(n_ok, n0y));
  vz = hn::IfThenElse(v_ok, v0z, hn::IfThenElse(n_ok, n0z, one));
  const V n1x = hn::IfThenElse(n_ok, n0x, vx), n1y = hn::IfThenElse(n_ok, n0y, vy),
          n1z = hn::IfThenElse(n_ok, n0z, vz);
  flipped = hn::Lt(hn::MulAdd(n1z, vz, hn::MulAdd(n1y, vy, hn::Mul(n1x, vx))), zero);
  nx = hn::IfThenElse(flipped, hn::Neg(n1x), n1x);
  ny = hn::IfThenElse(flipped, hn::Neg(n1y), n1y);
  nz = hn::IfThenElse(flipped, hn::Neg(n1z), n1z);
  co = Clamp(hn::MulAdd(nz, vz, hn::MulAdd(ny, vy, hn::Mul(nx, vx))), zero, one);
}

// Unit direction from lanes i.. to a point light at (px, py, pz); a light at the shaded point
// (or beyond float range) shines along n.
HWY_INLINE void PointLightDir(D d, const SurfaceSoA& s, size_t i, V px, V py, V pz, V nx, V ny, V nz, V& Lx,
                              V& Ly, V& Lz) {
  const V lo2 = hn::Set(d, kDegenerateNormal2), hi2 = hn::Set(d, FLT_MAX);
  const V dx = hn::Sub(px, hn::Load(d, s.pos[0] + i)), dy = hn::Sub(py, hn::Load(d, s.pos[1] + i)),
          dz = hn::Sub(pz, hn::Load(d, s.pos[2] + i));
  const V l2 = hn::MulAdd(dz, dz, hn::MulAdd(dy, dy, hn::Mul(dx, dx)));
  const M ok = hn::And(hn::Ge(l2, lo2), hn::Le(l2, hi2));
  const V inv = hn::Div(hn::Set(d, 1.0f), hn::Sqrt(Clamp(l2, lo2, hi2)));
  Lx = hn::IfThenElse(ok, hn::Mul(dx, inv), nx);
  Ly = hn::IfThenElse(ok, hn::Mul(dy, inv), ny);
  Lz = hn::IfThenElse(ok, hn::Mul(dz, inv), nz);
}

// 1/x and 1/y from ONE division of x y where both factors are in (0, 2^20] and the product is at
// least 2^-96 in every lane (the pairwise products are then normal floats, and the reciprocals
// carry two roundings more than separate divisions: a few 1e-7 relative); otherwise two. Used
// where the division is off the light loop's latency chains: merging the three divisions of the
// dermis term per light this way was measured slower, because it serialises them behind the
// last one's inputs (sqrt of the phase base).
HWY_INLINE void Reciprocals2(D d, V x, V y, V& rx, V& ry) {
  const V one = hn::Set(d, 1.0f);
  const V xy = hn::Mul(x, y);
  if (HWY_LIKELY(hn::AllTrue(d, hn::Ge(xy, hn::Set(d, 0x1p-96f))))) {
    const V r = hn::Div(one, xy);
    rx = hn::Mul(y, r);
    ry = hn::Mul(x, r);
  } else {
    rx = hn::Div(one, x);
    ry = hn::Div(one, y);
  }
}

void ShadeSkinBatch(const SkinParams& p, const detail::KernelLight* lights, size_t light_count,
                    const detail::LightSums& sums, const float eye[3], const SurfaceSoA& s,
                    const ShadeOutSoA& o) {
  const D d;
  const size_t N = hn::Lanes(d);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const float eta = p.Eta;
  const V veta = hn::Set(d, eta);
  const V eta2m1 = hn::Set(d, float((double(eta) - 1.0) * (double(eta) + 1.0)));
  const V inv_eta2 = hn::Set(d, float(1.0 / (double(eta) * eta)));
  const bool eta_one = eta == 1.0f;
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
  const bool ss_on = p.single_scattering != SingleScattering::off;
  const bool ss_correct = p.single_scattering == SingleScattering::correct;
  const bool efres = p.fresnel == Fresnel::efresnel;
  const MultipleScattering mode = p.multiple_scattering;
  const bool blur = mode == MultipleScattering::normal_blur;
  const double fdr_raw = -1.440 / (double(eta) * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
  const double fdr = std::fmin(std::fmax(fdr_raw, 0.0), 0.99);
  const float dipole_A = float((1.0 + fdr) / (1.0 - fdr));

  // Colour factors of each layer, Opacity included: the light loop sums colour x weight per
  // channel and the per-lane factors (albedo, Kt_out, Rd) multiply the sums once afterwards.
  const double op = p.Opacity, ms = p.MultipleScatteringCoeff;
  // pi / eta^2 for the `correct` dermis (a BRDF per steradian in pelt's no-1/pi light units, and
  // the radiance leaving the layer divided by eta^2), 1 for the paper's listing, which is kept in
  // its own units; see shade_skin_pixel.
  const double dermis_units = ss_correct ? std::numbers::pi / (double(eta) * eta) : 1.0;
  float amb_k[3], epi_k[3], derm_k[3], blur_w[3], blur_1mw[3];
  for (int c = 0; c < 3; ++c) {
    amb_k[c] = float(op * p.AmbientCoeff * sums.ambient[c] * p.SkinColor[c]);
    epi_k[c] = float(mode == MultipleScattering::paper ? op * ms * p.DiffusionColor[c] * sums.all[c]
                     : blur                            ? op * ms * p.DiffusionColor[c]
                                                       : op * ms);
    derm_k[c] = float(op * dermis_units * p.SingleScatteringCoeff * p.SkinColor[c]);
    blur_w[c] = p.normal_blur_mix[c];
    blur_1mw[c] = 1.0f - p.normal_blur_mix[c];
  }
  const V lo2 = hn::Set(d, kDegenerateNormal2), hi2 = hn::Set(d, FLT_MAX);

  // The lanes are shaded in blocks, in three passes over the block: the frame and the
  // transmission out per lane, then each light over every lane vector, then the layers. One
  // pass of every stage over a lane vector was a single chain of several hundred instructions
  // (two square roots and a division, then per light a square root, a division and expm1 after
  // one another), longer than the out-of-order window, so the core idled on latency; a loop over
  // the lanes for one light has short iterations that are independent of one another and
  // overlap. The per-lane values between the passes live in this block's scratch (L1).
  constexpr size_t kBlock = 64;
  enum : int { kNx, kNy, kNz, kVx, kVy, kVz, kCo, kCot, kVtx, kVty, kVtz, kKtOut, kKtOutExact, kFake,
               kSebum, kDerm = kSebum + 3, kEpi = kDerm + 3, kBlur = kEpi + 3, kArrays = kBlur + 9 };
  HWY_ALIGN float scratch[kArrays][kBlock];
  auto at = [&](int k, size_t j) { return scratch[k] + j; };

  for (size_t base = 0; base < s.n; base += kBlock) {
    const size_t count = std::min(kBlock, s.n - base);  // a multiple of 16, hence of N

    for (size_t j = 0; j < count; j += N) {
      const size_t i = base + j;
      V nx, ny, nz, vx, vy, vz, co;
      M flipped;
      LaneFrame(d, s, i, eye, nx, ny, nz, vx, vy, vz, co, flipped);
      if (blur)
        for (int c = 0; c < 3; ++c) {
          const V bx = hn::Load(d, s.blurred_normal[c][0] + i), by = hn::Load(d, s.blurred_normal[c][1] + i),
                  bz = hn::Load(d, s.blurred_normal[c][2] + i);
          const V l2 = hn::MulAdd(bz, bz, hn::MulAdd(by, by, hn::Mul(bx, bx)));
          const M ok = hn::And(hn::Ge(l2, lo2), hn::Le(l2, hi2));
          const V inv = hn::IfThenElseZero(ok, hn::Div(one, hn::Sqrt(Clamp(l2, lo2, hi2))));
          const V flip = hn::IfThenElse(flipped, hn::Neg(inv), inv);
          hn::Store(hn::IfThenElse(ok, hn::Mul(bx, flip), nx), d, at(kBlur + 3 * c, j));
          hn::Store(hn::IfThenElse(ok, hn::Mul(by, flip), ny), d, at(kBlur + 3 * c + 1, j));
          hn::Store(hn::IfThenElse(ok, hn::Mul(bz, flip), nz), d, at(kBlur + 3 * c + 2, j));
        }
      M out_ok;
      const V cot = RefractCos(d, co, eta2m1, inv_eta2, eta_one, out_ok);
      V kt_out_exact = zero, kt_out = one, fake = zero;
      if (ss_correct || mode == MultipleScattering::reference) {
        V num, den, rden;
        FresnelKtParts(d, co, cot, out_ok, veta, num, den);
        if (mode == MultipleScattering::paper)
          Reciprocals2(d, den, hn::Max(hn::Add(co, hn::Set(d, p.ClampCoeff)), hn::Set(d, kClampFloor)), rden, fake);
        else
          rden = hn::Div(one, den);
        kt_out_exact = hn::IfThenElseZero(out_ok, Clamp(hn::Mul(num, rden), zero, one));
        if (ss_correct) kt_out = efres ? EfresnelKt(d, kt_out_exact) : kt_out_exact;
      } else if (mode == MultipleScattering::paper) {
        fake = hn::Div(one, hn::Max(hn::Add(co, hn::Set(d, p.ClampCoeff)), hn::Set(d, kClampFloor)));
      }
      hn::Store(nx, d, at(kNx, j));
      hn::Store(ny, d, at(kNy, j));
      hn::Store(nz, d, at(kNz, j));
      hn::Store(vx, d, at(kVx, j));
      hn::Store(vy, d, at(kVy, j));
      hn::Store(vz, d, at(kVz, j));
      hn::Store(co, d, at(kCo, j));
      // cot > 0 exactly where the view ray refracts out (out_ok): the light pass re-derives it.
      hn::Store(cot, d, at(kCot, j));
      // Tangential part of V, shared by every light's phase angle.
      hn::Store(hn::NegMulAdd(co, nx, vx), d, at(kVtx, j));
      hn::Store(hn::NegMulAdd(co, ny, vy), d, at(kVty, j));
      hn::Store(hn::NegMulAdd(co, nz, vz), d, at(kVtz, j));
      hn::Store(kt_out, d, at(kKtOut, j));
      hn::Store(kt_out_exact, d, at(kKtOutExact, j));
      hn::Store(fake, d, at(kFake, j));
    }
    // The sums over the lights start at zero: one contiguous clear (stores of zero in the loop
    // above were turned into a `rep stos` per array and block, a tenth of the kernel's time).
    const bool epi_sums = blur || mode == MultipleScattering::reference;
    std::memset(scratch[kSebum], 0, size_t(epi_sums ? kBlur - kSebum : kEpi - kSebum) * sizeof(scratch[0]));

    for (size_t k = 0; k < light_count; ++k) {
      const detail::KernelLight* sl = &lights[k];
      const V cl[3] = {hn::Set(d, sl->color[0]), hn::Set(d, sl->color[1]), hn::Set(d, sl->color[2])};
      const V sheen[3] = {hn::Set(d, sl->sebum[0]), hn::Set(d, sl->sebum[1]), hn::Set(d, sl->sebum[2])};
      const bool point = sl->point;
      const V Lx0 = hn::Set(d, sl->vec[0]), Ly0 = hn::Set(d, sl->vec[1]), Lz0 = hn::Set(d, sl->vec[2]);

      for (size_t j = 0; j < count; j += N) {
        const size_t i = base + j;
        const V nx = hn::Load(d, at(kNx, j)), ny = hn::Load(d, at(kNy, j)), nz = hn::Load(d, at(kNz, j));
        V Lx = Lx0, Ly = Ly0, Lz = Lz0;
        if (point) PointLightDir(d, s, i, Lx0, Ly0, Lz0, nx, ny, nz, Lx, Ly, Lz);
        const V ci = Clamp(hn::MulAdd(nz, Lz, hn::MulAdd(ny, Ly, hn::Mul(nx, Lx))), hn::Set(d, -1.0f), one);
        if (blur)
          for (int c = 0; c < 3; ++c) {
            const V nbl = hn::MulAdd(hn::Load(d, at(kBlur + 3 * c + 2, j)), Lz,
                                     hn::MulAdd(hn::Load(d, at(kBlur + 3 * c + 1, j)), Ly,
                                                hn::Mul(hn::Load(d, at(kBlur + 3 * c, j)), Lx)));
            const V lit = hn::MulAdd(hn::Set(d, blur_1mw[c]), hn::Max(ci, zero),
                                     hn::Mul(hn::Set(d, blur_w[c]), hn::Max(nbl, zero)));
            hn::Store(hn::MulAdd(cl[c], lit, hn::Load(d, at(kEpi + c, j))), d, at(kEpi + c, j));
          }
        const M lit = hn::Gt(ci, zero);
        if (hn::AllFalse(d, lit)) continue;

        const V vx = hn::Load(d, at(kVx, j)), vy = hn::Load(d, at(kVy, j)), vz = hn::Load(d, at(kVz, j));
        const V co = hn::Load(d, at(kCo, j));
        const V LdotV = hn::MulAdd(Lz, vz, hn::MulAdd(Ly, vy, hn::Mul(Lx, vx)));
        V lobe;
        if (p.specular == Specular::phong) {
          lobe = SpecularLobe(d, hn::Sub(hn::Mul(hn::Add(ci, ci), co), LdotV), power, int_power);
        } else {
          // |L + V| from the summed vector, not 2 + 2 L.V, which cancels at grazing angles.
          const V hx = hn::Add(Lx, vx), hy = hn::Add(Ly, vy), hz = hn::Add(Lz, vz);
          const V h2 = hn::MulAdd(hz, hz, hn::MulAdd(hy, hy, hn::Mul(hx, hx)));
          const M h_ok = hn::Gt(h2, hn::Set(d, 1e-30f));
          const V nh = hn::MulAdd(nz, hz, hn::MulAdd(ny, hy, hn::Mul(nx, hx)));
          const V sh = hn::Div(nh, hn::Sqrt(hn::IfThenElse(h_ok, h2, one)));
          lobe = hn::IfThenElseZero(h_ok, SpecularLobe(d, sh, power, int_power));
        }
        lobe = hn::IfThenElseZero(lit, lobe);
        for (int c = 0; c < 3; ++c)
          hn::Store(hn::MulAdd(sheen[c], lobe, hn::Load(d, at(kSebum + c, j))), d, at(kSebum + c, j));

        if (!ss_on && mode != MultipleScattering::reference) continue;
        const V cip = hn::Max(ci, zero);
        M in_ok;
        const V cit = RefractCos(d, cip, eta2m1, inv_eta2, eta_one, in_ok);
        const M lit_in = hn::And(lit, in_ok);
        V fnum, fden;
        FresnelKtParts(d, cip, cit, lit_in, veta, fnum, fden);
        const V kt_in_exact = hn::IfThenElseZero(lit_in, Clamp(hn::Div(fnum, fden), zero, one));
        if (mode == MultipleScattering::reference) {
          const V w = hn::Mul(cip, kt_in_exact);
          for (int c = 0; c < 3; ++c)
            hn::Store(hn::MulAdd(cl[c], w, hn::Load(d, at(kEpi + c, j))), d, at(kEpi + c, j));
        }
        if (!ss_on) continue;
        V kt_in = one;
        if (ss_correct) kt_in = efres ? EfresnelKt(d, kt_in_exact) : kt_in_exact;
        const V cot = hn::Load(d, at(kCot, j));
        // 1 -+ cos(theta) of the refracted directions from the difference or sum of the unit
        // vectors: t_o -+ t_i = (V_t +- L_t) / eta + (co_t +- ci_t) n, so 1 -+ cos = abs(t_o -+ t_i)^2 / 2
        // (well conditioned at both phase peaks, unlike 1 - a dot product).
        const V ltx = hn::NegMulAdd(ci, nx, Lx), lty = hn::NegMulAdd(ci, ny, Ly), ltz = hn::NegMulAdd(ci, nz, Lz);
        const V vtx = hn::Load(d, at(kVtx, j)), vty = hn::Load(d, at(kVty, j)), vtz = hn::Load(d, at(kVtz, j));
        V b;
        if (paper_phase || g >= 0.0) {
          const V sx = hn::Add(ltx, vtx), sy = hn::Add(lty, vty), sz = hn::Add(ltz, vtz);
          const V cc = hn::Add(cit, cot);
          const V s2 = hn::MulAdd(sz, sz, hn::MulAdd(sy, sy, hn::Mul(sx, sx)));
          const V omc = Clamp(hn::Mul(hn::Set(d, 0.5f), hn::MulAdd(s2, inv_eta2, hn::Mul(cc, cc))), zero,
                              hn::Set(d, 2.0f));  // 1 - cos(theta)
          if (paper_phase) {
            // 1 - g^2 - 2 g cos = 1 - g^2 - 2 g + 2 g (1 - cos)
            b = hn::Max(hn::MulAdd(hg_2g, omc, hn::Sub(hg_1mg2, hg_2g)), hg_floor);
          } else {
            b = hn::MulAdd(hg_2ag, omc, hg_floor);
          }
        } else {
          const V dx = hn::Sub(vtx, ltx), dy = hn::Sub(vty, lty), dz = hn::Sub(vtz, ltz);
          const V cd2 = hn::Sub(cot, cit);
          const V d2 = hn::MulAdd(dz, dz, hn::MulAdd(dy, dy, hn::Mul(dx, dx)));
          const V opc = Clamp(hn::Mul(hn::Set(d, 0.5f), hn::MulAdd(d2, inv_eta2, hn::Mul(cd2, cd2))), zero,
                              hn::Set(d, 2.0f));  // 1 + cos(theta)
          b = hn::MulAdd(hg_2ag, opc, hg_floor);
        }
        // 1/ci + 1/co as (ci + co) / (ci co) with both floored at 1e-20 (their product is then
        // >= 1e-40, a float denormal, so it is floored at FLT_MIN instead: the exponent is
        // clamped at -100 anyway, where 1 - exp is 1 in float).
        const V cim = hn::Max(cit, tiny), com = hn::Max(cot, tiny);
        const V sum_inv = hn::Div(hn::Add(cim, com), hn::Max(hn::Mul(cim, com), hn::Set(d, FLT_MIN)));
        const V arg = hn::Max(hn::Neg(hn::Mul(thickness, sum_inv)), hn::Set(d, -100.0f));
        // phase x geometry: hg_k / (b^1.5 max(ci + co, 1e-20)), divided while expm1 runs.
        const V den = hn::Mul(hn::Mul(b, hn::Sqrt(b)), hn::Max(hn::Add(cit, cot), tiny));
        const V ph_geom = hn::Mul(hn::Neg(hn::Expm1(d, arg)), hn::Div(hg_k, den));
        const M ok = hn::And(lit_in, hn::Gt(cot, zero));
        const V w = hn::IfThenElseZero(ok, hn::Mul(hn::Mul(cip, kt_in), ph_geom));
        for (int c = 0; c < 3; ++c)
          hn::Store(hn::MulAdd(cl[c], w, hn::Load(d, at(kDerm + c, j))), d, at(kDerm + c, j));
      }
    }

    for (size_t j = 0; j < count; j += N) {
      const size_t i = base + j;
      const V kt_out = hn::Load(d, at(kKtOut, j));
      V rgb[3], sebum[3], epi[3], dermis[3];
      for (int c = 0; c < 3; ++c) {
        const V A = Clamp(hn::Load(d, s.albedo[c] + i), zero, one);
        const V k = hn::Set(d, epi_k[c]);
        const V acc = hn::Load(d, at(kEpi + c, j));
        switch (mode) {
          case MultipleScattering::off:
            epi[c] = zero;
            break;
          case MultipleScattering::paper:
            epi[c] = hn::Mul(hn::Mul(k, A), hn::Load(d, at(kFake, j)));
            break;
          case MultipleScattering::normal_blur:
            epi[c] = hn::Mul(hn::Mul(k, A), acc);
            break;
          case MultipleScattering::reference: {
            const V rd = DipoleRd(d, hn::Mul(hn::Set(d, p.DiffusionColor[c]), A), dipole_A);
            epi[c] = hn::Mul(hn::Mul(hn::Mul(k, hn::Load(d, at(kKtOutExact, j))), rd), acc);
            break;
          }
        }
        sebum[c] = hn::Load(d, at(kSebum + c, j));
        dermis[c] = hn::Mul(hn::Mul(hn::Mul(hn::Set(d, derm_k[c]), A), kt_out), hn::Load(d, at(kDerm + c, j)));
        rgb[c] = hn::Add(hn::MulAdd(hn::Set(d, amb_k[c]), A, sebum[c]), hn::Add(epi[c], dermis[c]));
      }
      StoreLayer(d, o.rgb, i, rgb);
      hn::Store(hn::Set(d, p.Opacity), d, o.alpha + i);
      StoreLayer(d, o.sebum, i, sebum);
      StoreLayer(d, o.epidermis, i, epi);
      StoreLayer(d, o.dermis, i, dermis);
    }
  }
}

void ShadeBasicBatch(detail::Basic kind, const BasicParams& p, const detail::KernelLight* lights,
                     size_t light_count, const detail::LightSums& sums, const float eye[3], const SurfaceSoA& s,
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
      V nx, ny, nz, vx, vy, vz, co;
      M flipped;
      LaneFrame(d, s, i, eye, nx, ny, nz, vx, vy, vz, co, flipped);
      V irr[3], spec[3];
      for (int c = 0; c < 3; ++c) {
        irr[c] = hn::Set(d, sums.ambient[c]);
        spec[c] = zero;
      }
      for (size_t li = 0; li < light_count; ++li) {
        const detail::KernelLight& l = lights[li];
        V Lx = hn::Set(d, l.vec[0]), Ly = hn::Set(d, l.vec[1]), Lz = hn::Set(d, l.vec[2]);
        if (l.point) PointLightDir(d, s, i, Lx, Ly, Lz, nx, ny, nz, Lx, Ly, Lz);
        const V ci = Clamp(hn::MulAdd(nz, Lz, hn::MulAdd(ny, Ly, hn::Mul(nx, Lx))), hn::Set(d, -1.0f), one);
        const M lit = hn::Gt(ci, zero);
        const V cip = hn::Max(ci, zero);
        V lobe = zero;
        if (kind == detail::Basic::blinn) {
          const V hx = hn::Add(Lx, vx), hy = hn::Add(Ly, vy), hz = hn::Add(Lz, vz);
          const V h2 = hn::MulAdd(hz, hz, hn::MulAdd(hy, hy, hn::Mul(hx, hx)));
          const M h_ok = hn::And(lit, hn::Gt(h2, hn::Set(d, 1e-30f)));
          const V nh = hn::MulAdd(nz, hz, hn::MulAdd(ny, hy, hn::Mul(nx, hx)));
          const V sh = hn::Div(nh, hn::Sqrt(hn::IfThenElse(h_ok, h2, one)));
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

// The call's non-ambient lights as the kernels read them: up to 16 on the stack (a frame's
// calls allocate nothing), more on the heap.
class PreparedLights {
 public:
  PreparedLights(const Light* lights, size_t count, const SkinParams* skin) {
    detail::KernelLight* out = inline_.data();
    size_t direct = 0;
    for (size_t i = 0; i < count; ++i) direct += lights[i].type != Light::Type::Ambient;
    if (direct > inline_.size()) {
      heap_.resize(direct);
      out = heap_.data();
    }
    for (size_t i = 0; i < count; ++i) {
      const Light& l = lights[i];
      if (l.type == Light::Type::Ambient) continue;
      detail::KernelLight& k = out[size_++];
      k.point = l.type == Light::Type::Point;
      kernel_light_vector(l, k.vec);
      for (int c = 0; c < 3; ++c) {
        k.color[c] = l.color[c];
        k.sebum[c] = skin ? float(double(skin->Opacity) * skin->Specularity * skin->SheenColor[c] * l.color[c]) : 0.0f;
      }
    }
    data_ = out;
  }
  const detail::KernelLight* data() const { return data_; }
  size_t size() const { return size_; }

 private:
  std::array<detail::KernelLight, 16> inline_;
  std::vector<detail::KernelLight> heap_;
  const detail::KernelLight* data_ = nullptr;
  size_t size_ = 0;
};

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
  const PreparedLights prepared(lights, light_count, &params);
  HWY_DYNAMIC_DISPATCH(ShadeSkinBatch)(params, prepared.data(), prepared.size(), sum_lights(lights, light_count), eye,
                                       surface, out);
}

void shade_unlit(const Light* lights, size_t light_count, const float eye[3], const SurfaceSoA& surface,
                 const ShadeOutSoA& out) {
  check_common(lights, light_count, eye, surface, out, false);
  const PreparedLights prepared(lights, light_count, nullptr);
  HWY_DYNAMIC_DISPATCH(ShadeBasicBatch)(detail::Basic::unlit, BasicParams{}, prepared.data(), prepared.size(),
                                        sum_lights(lights, light_count), eye, surface, out);
}

void shade_lambert(const Light* lights, size_t light_count, const float eye[3], const SurfaceSoA& surface,
                   const ShadeOutSoA& out) {
  check_common(lights, light_count, eye, surface, out, false);
  const PreparedLights prepared(lights, light_count, nullptr);
  HWY_DYNAMIC_DISPATCH(ShadeBasicBatch)(detail::Basic::lambert, BasicParams{}, prepared.data(), prepared.size(),
                                        sum_lights(lights, light_count), eye, surface, out);
}

void shade_blinn(const BasicParams& params, const Light* lights, size_t light_count, const float eye[3],
                 const SurfaceSoA& surface, const ShadeOutSoA& out) {
  throw_if(validate(params));
  check_common(lights, light_count, eye, surface, out, false);
  const PreparedLights prepared(lights, light_count, nullptr);
  HWY_DYNAMIC_DISPATCH(ShadeBasicBatch)(detail::Basic::blinn, params, prepared.data(), prepared.size(),
                                        sum_lights(lights, light_count), eye, surface, out);
}

}  // namespace pelt::shading
#endif  // HWY_ONCE
