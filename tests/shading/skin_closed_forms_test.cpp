// Closed-form values of the skin layers for single, hand-computed configurations, checked on the
// double reference and on the kernels of every compiled target. The random and hard-case tests
// compare the kernels with the reference, so a slip made the same way in both passes them; these
// pin each term to its textbook formula instead (Fresnel from the angle forms, Snell's refracted
// cosines in Hanrahan-Krueger, Phong's mirror direction, the normal-blur mix, the fake
// epidermis's ambient lights, the dipole epidermis's reciprocity).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "shading/skin_kernels.h"
#include "shading/skin_reference.h"
#include "tests/shading/batch_harness.h"
#include "tests/shading/skin_test_params.h"

namespace pelt::shading {
namespace skin_closed_forms_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

using ref::kPi;

struct Dir {
  double x, y, z;
};

// Unit direction in the xz plane at `deg` degrees from +z, toward +x for positive angles.
Dir tilted(double deg) {
  const double r = deg * kPi / 180.0;
  return {std::sin(r), 0.0, std::cos(r)};
}

// Fresnel reflectance of unpolarised light from the angle forms (Hecht): an independent route to
// the value that ref::fresnel_exact and the kernels compute from cosines.
double fresnel_angles(double theta_i, double eta) {
  if (theta_i == 0.0) {
    const double r = (eta - 1.0) / (eta + 1.0);
    return r * r;
  }
  const double theta_t = std::asin(std::sin(theta_i) / eta);
  const double rs = -std::sin(theta_i - theta_t) / std::sin(theta_i + theta_t);
  const double rp = std::tan(theta_i - theta_t) / std::tan(theta_i + theta_t);
  return 0.5 * (rs * rs + rp * rp);
}

double smoothstep_to_half(double x) {
  const double t = std::clamp(x / 0.5, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// One shading point at the origin with the given normal, blurred normal (every channel) and
// albedo 1, seen from far along `view`: the reference's layer (k as in testing::Outputs: 4 sebum,
// 7 epidermis, 10 dermis, + channel) and the same from the kernels on every target, 16 equal lanes.
// The reference is held to 1e-6: the light's direction reaches it as floats.
struct Point {
  Dir normal{0, 0, 1};
  Dir blurred{0, 0, 1};
  Dir view{0, 0, 1};
};

double reference_layer(const SkinParams& p, const std::vector<Light>& lights, const Point& pt, int k) {
  ref::Sample s{};
  s.normal[0] = pt.normal.x, s.normal[1] = pt.normal.y, s.normal[2] = pt.normal.z;
  for (int c = 0; c < 3; ++c) {
    s.albedo[c] = 1.0;
    s.blurred_normal[c][0] = pt.blurred.x, s.blurred_normal[c][1] = pt.blurred.y, s.blurred_normal[c][2] = pt.blurred.z;
  }
  const double eye[3] = {10.0 * pt.view.x, 10.0 * pt.view.y, 10.0 * pt.view.z};
  const ref::Shaded o = ref::shade_skin_pixel(p, lights.data(), lights.size(), eye, s);
  const double* layers[4] = {o.rgb, o.sebum, o.epidermis, o.dermis};
  return k == 3 ? o.alpha : layers[(k < 3 ? 0 : (k - 1) / 3)][k < 3 ? k : (k - 1) % 3];
}

void expect_layer(const SkinParams& p, const std::vector<Light>& lights, const Point& pt, int k, double want,
                  double rel) {
  EXPECT_NEAR(reference_layer(p, lights, pt, k), want, 1e-6 * want + 1e-15)
      << "reference " << testing::output_name(k);
  testing::Inputs in(16);
  for (size_t i = 0; i < 16; ++i) {
    const double n[3] = {pt.normal.x, pt.normal.y, pt.normal.z}, b[3] = {pt.blurred.x, pt.blurred.y, pt.blurred.z};
    for (int c = 0; c < 3; ++c) {
      in.normal(c)[i] = float(n[c]);
      in.albedo(c)[i] = 1.0f;
      for (int ch = 0; ch < 3; ++ch) in.blurred(ch, c)[i] = float(b[c]);
    }
  }
  const float eye[3] = {float(10.0 * pt.view.x), float(10.0 * pt.view.y), float(10.0 * pt.view.z)};
  testing::for_each_target([&](int64_t) {
    testing::Outputs out(16);
    shade_skin(p, lights.data(), lights.size(), eye, in.soa(), out.soa());
    for (size_t i = 0; i < 16; i += 5)
      EXPECT_NEAR(out.at(k, i), want, rel * want + 1e-7) << "kernel " << testing::output_name(k) << " lane " << i;
  });
}

Light directional(const Dir& d, float c = 1.0f) {
  return Light{Light::Type::Directional, {float(d.x), float(d.y), float(d.z)}, {c, c, c}};
}

// Kills the mutants that swap the cosines of one polarisation (r_s computed as r_p or the
// reverse): both still give R(0) = ((eta-1)/(eta+1))^2 and the same value from both sides of
// the interface, which is all the older tests asked. Brewster's angle separates them: r_p = 0
// there, so F = r_s^2 / 2 exactly.
TEST(SkinClosedForms, FresnelMatchesTheAngleFormsAndBrewstersAngle) {
  for (double eta : {1.33, 1.4, 2.0})
    for (double deg = 0.0; deg < 90.0; deg += 7.5) {
      const double th = deg * kPi / 180.0;
      EXPECT_NEAR(ref::fresnel_exact(std::cos(th), eta), fresnel_angles(th, eta), 1e-12) << eta << " " << deg;
    }
  const double eta = 1.5, tb = std::atan(eta);  // Brewster
  const double ct = std::sqrt(1.0 - std::sin(tb) * std::sin(tb) / (eta * eta));
  const double rs = (std::cos(tb) - eta * ct) / (std::cos(tb) + eta * ct);
  EXPECT_NEAR(ref::fresnel_exact(std::cos(tb), eta), 0.5 * rs * rs, 1e-12);
  EXPECT_NEAR(ref::fresnel_exact(std::cos(tb), eta), 0.0739, 1e-4);  // the textbook R at Brewster, glass
}

// Pharr's efresnel is smoothstep(0, 0.5, Kr): half way at Kr = 0.25, saturated from Kr = 0.5.
TEST(SkinClosedForms, EfresnelIsASmoothstepUpToOneHalf) {
  EXPECT_DOUBLE_EQ(ref::efresnel(0.25), 0.5);
  EXPECT_DOUBLE_EQ(ref::efresnel(0.125), 0.15625);
  EXPECT_DOUBLE_EQ(ref::efresnel(0.5), 1.0);
  EXPECT_DOUBLE_EQ(ref::efresnel(0.75), 1.0);
}

// Hanrahan-Krueger single scattering at Eta = 1.4 with an isotropic phase (g = 0: 1/(4 pi)),
// where the refracted cosines differ from the outside ones:
//   dermis = (pi / eta^2) SSC Cl cos_i Kt_i Kt_o a (1/(4 pi)) (1 - exp(-d (1/ct_i + 1/ct_o))) / (ct_i + ct_o)
// with ct = sqrt(1 - sin^2 / eta^2) (Snell) and Kt = 1 - F, or 1 - smoothstep(0, 0.5, F) for
// efresnel; 1/eta^2 for the radiance leaving the layer. Every earlier closed-form dermis test ran
// at Eta = 1.
TEST(SkinClosedForms, DermisUsesTheRefractedCosinesAndBothTransmissions) {
  const double eta = double(1.4f), d = 0.5;
  for (Fresnel fr : {Fresnel::exact, Fresnel::efresnel})
    for (auto [li, vi] : {std::pair{0.0, 0.0}, {60.0, -30.0}, {75.0, 40.0}, {20.0, 80.0}}) {
      SCOPED_TRACE(std::string(to_string(fr)) + " light " + std::to_string(li) + " view " + std::to_string(vi));
      SkinParams p = testing::bare_skin();
      p.single_scattering = SingleScattering::correct;
      p.fresnel = fr;
      p.g = 0.0f;
      p.Eta = float(eta);
      p.Thickness = float(d);
      const double ti = li * kPi / 180.0, to = std::fabs(vi) * kPi / 180.0;
      const double cti = std::sqrt(1.0 - std::sin(ti) * std::sin(ti) / (eta * eta));
      const double cto = std::sqrt(1.0 - std::sin(to) * std::sin(to) / (eta * eta));
      const double Fi = fresnel_angles(ti, eta), Fo = fresnel_angles(to, eta);
      const double kti = fr == Fresnel::exact ? 1.0 - Fi : 1.0 - smoothstep_to_half(Fi);
      const double kto = fr == Fresnel::exact ? 1.0 - Fo : 1.0 - smoothstep_to_half(Fo);
      const double want = kPi / (eta * eta) * std::cos(ti) * kti * kto * (1.0 / (4.0 * kPi)) *
                          -std::expm1(-d * (1.0 / cti + 1.0 / cto)) / (cti + cto);
      Point pt;
      pt.view = tilted(vi);
      expect_layer(p, {directional(tilted(li))}, pt, 10, want, 2e-5);
    }
}

// README, listing bug 3: the paper's Kr is <= 0 everywhere and efresnel maps it to 0, so the
// `paper` dermis transmits Kt = 1 in and out at every angle, whatever `fresnel` says, and (item 6)
// takes no factor pi. With its phase at g = 0 equal to 1, at Eta = 1.4:
//   dermis = SSC Cl cos_i a (1 - exp(-d (1/ct_i + 1/ct_o))) / (ct_i + ct_o).
// PaperDermisIsTheListingsArithmetic runs at Eta = 1, where exact Fresnel also gives Kt = 1.
TEST(SkinClosedForms, PaperDermisTransmitsEverythingAtEta14) {
  const double eta = double(1.4f), d = 0.5;
  for (Fresnel fr : {Fresnel::exact, Fresnel::efresnel}) {
    SkinParams p = testing::bare_skin();
    p.single_scattering = SingleScattering::paper;
    p.phase = Phase::paper;
    p.fresnel = fr;
    p.g = 0.0f;
    p.Thickness = float(d);
    p.SingleScatteringCoeff = 2.0f;
    const double ti = 70.0 * kPi / 180.0, to = 35.0 * kPi / 180.0;
    const double cti = std::sqrt(1.0 - std::sin(ti) * std::sin(ti) / (eta * eta));
    const double cto = std::sqrt(1.0 - std::sin(to) * std::sin(to) / (eta * eta));
    const double want = 2.0 * std::cos(ti) * -std::expm1(-d * (1.0 / cti + 1.0 / cto)) / (cti + cto);
    Point pt;
    pt.view = tilted(-35.0);
    expect_layer(p, {directional(tilted(70.0))}, pt, 10, want, 2e-5);
  }
}

// Forward scattering for g > 0. Light and view along the normal make the refracted directions
// exactly opposite (cos theta = -1), so the dermis carries the phase function's backward value
// (1 - g) / (4 pi (1 + g)^2): with g = 0.5 it is 27 times smaller than with g = -0.5.
TEST(SkinClosedForms, PositiveGScattersForwardSoItsBackscatterIsDim) {
  const double eta = double(1.4f), d = 0.5, kt = 1.0 - std::pow((eta - 1) / (eta + 1), 2);
  for (double g : {0.5, -0.5, 0.8}) {
    SkinParams p = testing::bare_skin();
    p.single_scattering = SingleScattering::correct;
    p.g = float(g);
    p.Thickness = float(d);
    const double back = (1 - g * g) / (4 * kPi * std::pow(1 + g * g + 2 * g, 1.5));
    const double want = kPi / (eta * eta) * kt * kt * back * -std::expm1(-2.0 * d) / 2.0;
    expect_layer(p, {directional({0, 0, 1})}, Point{}, 10, want, 2e-5);
  }
  EXPECT_NEAR(ref::hg_phase(-1.0, 0.5) / ref::hg_phase(-1.0, -0.5), 1.0 / 27.0, 1e-12);
  EXPECT_NEAR(ref::hg_phase(0.3, 0.0), 1.0 / (4.0 * kPi), 1e-15);
}

// Phong sebum: Specularity SheenColor Cl (R.V)^Power with R = 2 (N.L) N - L, the mirror of L.
// At the mirror direction the lobe is 1; 10 degrees off it, cos(10 deg)^Power.
TEST(SkinClosedForms, PhongSebumPeaksAtTheMirrorDirection) {
  SkinParams p = testing::bare_skin();
  p.Specularity = 0.5f;
  p.SheenColor[1] = 0.4f;
  p.Power = 20.0f;
  const Light l = directional(tilted(40.0), 2.0f);
  for (double off : {0.0, 10.0, -25.0}) {
    Point pt;
    pt.view = tilted(-40.0 + off);
    const double lobe = std::pow(std::cos(off * kPi / 180.0), 20.0);
    expect_layer(p, {l}, pt, 4, 0.5 * 2.0 * lobe, 1e-4);
    expect_layer(p, {l}, pt, 5, 0.5 * 0.4 * 2.0 * lobe, 1e-4);
  }
  p.Power = 7.0f;  // also the kernels' path for an integer power: the exponent is the parameter
  Point pt;
  pt.view = tilted(-30.0);
  expect_layer(p, {l}, pt, 4, 0.5 * 2.0 * std::pow(std::cos(10.0 * kPi / 180.0), 7.0), 1e-4);
}

// Blinn-Phong: the lobe is (N.H)^Power with H the UNIT half vector of L and V. Light 40 degrees
// one side of the normal and view on it (or 60 and -20) put H 20 degrees off N: cos(20)^Power.
TEST(SkinClosedForms, BlinnSebumUsesTheUnitHalfVector) {
  SkinParams p = testing::bare_skin();
  p.specular = Specular::blinn;
  p.Specularity = 0.5f;
  p.Power = 20.0f;
  const double lobe = std::pow(std::cos(20.0 * kPi / 180.0), 20.0);
  for (auto [li, vi] : {std::pair{40.0, 0.0}, {60.0, -20.0}}) {
    Point pt;
    pt.view = tilted(vi);
    expect_layer(p, {directional(tilted(li))}, pt, 4, 0.5 * lobe, 1e-4);
  }
}

// The basic Blinn material of the same form: rgb = Cl (albedo N.L + specular (N.H)^shininess),
// here with albedo 0, so the specular term alone.
TEST(SkinClosedForms, BasicBlinnUsesTheUnitHalfVector) {
  BasicParams bp;
  for (float& s : bp.specular) s = 0.5f;
  bp.shininess = 32.0f;
  const Light l = directional(tilted(40.0));
  const double want = 0.5 * std::pow(std::cos(20.0 * kPi / 180.0), 32.0);
  ref::Sample s{};
  s.normal[2] = 1.0;
  const double eye_d[3] = {0.0, 0.0, 10.0};
  EXPECT_NEAR(ref::shade_blinn_pixel(bp, &l, 1, eye_d, s).rgb[0], want, 1e-6 * want);
  testing::Inputs in(16);
  for (size_t i = 0; i < 16; ++i) in.normal(2)[i] = 1.0f;
  const float eye[3] = {0.0f, 0.0f, 10.0f};
  testing::for_each_target([&](int64_t) {
    testing::Outputs out(16);
    shade_blinn(bp, &l, 1, eye, in.soa(), out.soa());
    EXPECT_NEAR(out.at(0, 7), want, 1e-4 * want);
  });
}

// The paper's epidermis is "used like an ambient component", per light with no direction and
// (README) ambient lights included: an ambient light alone gives C_d I_ms Cl / (abs(I.N) + l_c).
TEST(SkinClosedForms, FakeEpidermisIsLitByAmbientLightsToo) {
  SkinParams p = testing::bare_skin();
  p.multiple_scattering = MultipleScattering::paper;
  p.MultipleScatteringCoeff = 0.25f;
  p.ClampCoeff = 0.5f;
  p.DiffusionColor[0] = 0.9f;
  p.Opacity = 0.8f;
  const Light amb{Light::Type::Ambient, {0, 0, 0}, {0.6f, 0.6f, 0.6f}};
  Point pt;
  pt.view = tilted(60.0);
  const double want = 0.8 * 0.9 * 0.25 * 0.6 / (0.5 + 0.5);
  expect_layer(p, {amb}, pt, 7, want, 1e-5);
  // With a directional light as well, each light adds its own share.
  expect_layer(p, {amb, directional(tilted(-20.0), 0.4f)}, pt, 7, want * (0.6 + 0.4) / 0.6, 1e-5);
}

// README (Opacity): the shading functions return rgb and every layer premultiplied by Opacity
// (RenderMan's Ci = Oi * ...), so halving Opacity halves each of them, in every epidermis model.
TEST(SkinClosedForms, EveryLayerIsPremultipliedByOpacity) {
  const std::vector<Light> lights = {directional(tilted(30.0)), {Light::Type::Ambient, {0, 0, 0}, {0.2f, 0.2f, 0.2f}}};
  Point pt;
  pt.view = tilted(-20.0);
  for (MultipleScattering ms : {MultipleScattering::paper, MultipleScattering::normal_blur, MultipleScattering::reference}) {
    SCOPED_TRACE(std::string(to_string(ms)));
    SkinParams p;
    p.multiple_scattering = ms;
    SkinParams half = p;
    half.Opacity = 0.5f;
    for (int k : {0, 4, 7, 10}) {
      const double full = reference_layer(p, lights, pt, k);
      ASSERT_GT(full, 0.0) << testing::output_name(k);
      expect_layer(half, lights, pt, k, 0.5 * full, 1e-5);
    }
    expect_layer(half, lights, pt, 3, 0.5, 0.0);
  }
}

// Normal blur: C_d I_ms Cl ((1 - w) max(0, N.L) + w max(0, N_blur.L)), w = normal_blur_mix[c].
TEST(SkinClosedForms, NormalBlurMixWeighsTheBlurredNormal) {
  SkinParams p = testing::bare_skin();
  p.multiple_scattering = MultipleScattering::normal_blur;
  p.DiffusionColor[0] = 0.8f;
  p.DiffusionColor[1] = 0.5f;
  p.DiffusionColor[2] = 0.3f;
  p.normal_blur_mix[0] = 0.9f;
  p.normal_blur_mix[1] = 0.25f;
  p.normal_blur_mix[2] = 0.0f;
  Point pt;
  pt.blurred = tilted(90.0);  // +x
  pt.view = tilted(-10.0);
  const Light l = directional(tilted(30.0));  // N.L = cos 30, N_blur.L = 1/2
  for (int c = 0; c < 3; ++c) {
    const double w = p.normal_blur_mix[c];
    expect_layer(p, {l}, pt, 7 + c, p.DiffusionColor[c] * ((1 - w) * std::cos(kPi / 6) + w * 0.5), 1e-5);
  }
}

// Seen from behind, the normal is turned toward the viewer, and the blurred normals with it: a
// blurred normal equal to the normal then changes nothing, whatever the mix.
TEST(SkinClosedForms, BlurredNormalsTurnWithTheNormalSeenFromBehind) {
  SkinParams p = testing::bare_skin();
  p.multiple_scattering = MultipleScattering::normal_blur;
  for (float& w : p.normal_blur_mix) w = 0.75f;
  Point pt;
  pt.normal = pt.blurred = {0, 0, -1};
  pt.view = tilted(20.0);
  const Light l = directional(tilted(-50.0));
  for (int c = 0; c < 3; ++c) expect_layer(p, {l}, pt, 7 + c, std::cos(50.0 * kPi / 180.0), 1e-5);
}

// The dipole epidermis (flat-surface limit): I_ms Cl cos_i Kt(cos_i) Rd Kt(cos_o). As a BRDF
// times cos_i it must be reciprocal: the value over cos_i is the same with light and view
// exchanged. Both transmissions are also pinned to the angle-form Fresnel.
TEST(SkinClosedForms, DipoleEpidermisIsReciprocalAndTransmitsBothWays) {
  SkinParams p = testing::bare_skin();
  p.multiple_scattering = MultipleScattering::reference;
  p.DiffusionColor[0] = 0.7f;
  const double eta = p.Eta, rd = ref::dipole_total_rd(0.7f, eta);
  for (auto [a, b] : {std::pair{20.0, 70.0}, {0.0, 55.0}, {80.0, 35.0}}) {
    const double ta = a * kPi / 180.0, tb = b * kPi / 180.0;
    const double want = std::cos(ta) * (1 - fresnel_angles(ta, eta)) * rd * (1 - fresnel_angles(tb, eta));
    Point ab, ba;
    ab.view = tilted(-b);
    ba.view = tilted(-a);
    expect_layer(p, {directional(tilted(a))}, ab, 7, want, 1e-5);
    const double fwd = reference_layer(p, {directional(tilted(a))}, ab, 7) / std::cos(ta);
    const double rev = reference_layer(p, {directional(tilted(b))}, ba, 7) / std::cos(tb);
    EXPECT_NEAR(fwd, rev, 1e-6 * fwd) << a << " <-> " << b;
  }
}

}  // namespace skin_closed_forms_test
}  // namespace pelt::shading
