// The hard cases of issue 4, one test each: kernel vs double reference on every compiled Highway
// target and every model switch combination, and every output finite, non-negative and within
// its term's stated bound (skin_reference.h).
#include <array>
#include <cmath>
#include <vector>

#include "shading/skin_kernels.h"
#include "shading/skin_reference.h"
#include "tests/shading/batch_harness.h"

namespace pelt::shading {
namespace skin_hard_cases_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

using testing::Inputs;
using testing::Outputs;

struct Lane {
  std::array<float, 3> pos;
  std::array<float, 3> normal;
};

struct Case {
  std::vector<Light> lights;
  std::array<float, 3> eye;
  std::vector<Lane> lanes;
};

Light directional(double x, double y, double z, float c = 1.0f) {
  return Light{Light::Type::Directional, {float(x), float(y), float(z)}, {c, 0.8f * c, 0.6f * c}};
}
Light point(float x, float y, float z, float c = 1.0f) {
  return Light{Light::Type::Point, {x, y, z}, {c, 0.8f * c, 0.6f * c}};
}
Light ambient(float c = 0.3f) { return Light{Light::Type::Ambient, {0, 0, 0}, {c, c, c}}; }

// Light at incidence cosine c to the +z normal, in the xz plane.
Light at_cos(double c) { return directional(std::sqrt(std::max(0.0, 1.0 - c * c)), 0.0, c); }

// Every combination of the model switches that exercises a term.
std::vector<SkinParams> all_modes(const SkinParams& base) {
  std::vector<SkinParams> out;
  for (auto ss : {SingleScattering::paper, SingleScattering::correct})
    for (auto fr : {Fresnel::exact, Fresnel::efresnel})
      for (auto ph : {Phase::correct, Phase::paper})
        for (auto ms : {MultipleScattering::paper, MultipleScattering::normal_blur, MultipleScattering::reference})
          for (auto sp : {Specular::phong, Specular::blinn}) {
            SkinParams p = base;
            p.single_scattering = ss;
            p.fresnel = fr;
            p.phase = ph;
            p.multiple_scattering = ms;
            p.specular = sp;
            out.push_back(p);
          }
  return out;
}

// Upper bounds of each layer per channel, from the terms' stated bounds (skin_reference.h):
// sebum <= Op Specularity Sheen sum(Cl); epidermis <= Op C_d I_ms sum(Cl) / kClampFloor (paper),
// Op C_d I_ms sum(Cl) (normal_blur, reference); dermis <= pi Op SSC a sum(Cl) p_max 2 (eta + 1/eta)
// / eta^2 with exact or efresnel transmission (pi: the light units; 1/eta^2: the radiance leaving
// the layer), and Op SSC a sum(Cl) p_max eta for the
// paper's Kt = 1 when eta >= 1 (the listing's units, no pi; for eta < 1 the paper's term grows
// without bound at the critical angle: finite only).
struct Bounds {
  double sebum[3], epidermis[3], dermis[3];
};

Bounds bounds(const SkinParams& p, const std::vector<Light>& lights, const float albedo[3]) {
  double direct[3] = {0, 0, 0}, all[3] = {0, 0, 0};
  for (const Light& l : lights)
    for (int c = 0; c < 3; ++c) {
      all[c] += l.color[c];
      if (l.type != Light::Type::Ambient) direct[c] += l.color[c];
    }
  const double pmax = p.phase == Phase::correct ? ref::hg_bound(p.g) : ref::hg_paper_bound(p.g);
  const double eta = p.Eta;
  double geom = ref::kPi * 2.0 * (eta + 1.0 / eta) / (eta * eta);
  if (p.single_scattering == SingleScattering::paper) geom = eta >= 1.0 ? eta : INFINITY;
  Bounds b{};
  for (int c = 0; c < 3; ++c) {
    const double A = std::clamp(double(albedo[c]), 0.0, 1.0);
    const double cd = p.DiffusionColor[c] * A, a = p.SkinColor[c] * A;
    b.sebum[c] = p.Opacity * p.Specularity * p.SheenColor[c] * direct[c];
    b.epidermis[c] = p.multiple_scattering == MultipleScattering::paper
                         ? p.Opacity * cd * p.MultipleScatteringCoeff * all[c] / kClampFloor
                         : p.Opacity * cd * p.MultipleScatteringCoeff * direct[c];
    b.dermis[c] = p.Opacity * p.SingleScatteringCoeff * a * direct[c] * pmax * geom;
  }
  return b;
}

void expect_within_bounds(const SkinParams& p, const Case& cs, Inputs& in, const Outputs& o, const char* who) {
  for (size_t i = 0; i < in.n; ++i) {
    const float albedo[3] = {in.albedo(0)[i], in.albedo(1)[i], in.albedo(2)[i]};
    const Bounds b = bounds(p, cs.lights, albedo);
    for (int k = 0; k < 13; ++k) {
      const double v = o.at(k, i);
      ASSERT_TRUE(std::isfinite(v) && v >= 0.0) << who << " lane " << i << " " << testing::output_name(k) << " = " << v;
    }
    for (int c = 0; c < 3; ++c) {
      const double slack = 1.0 + 1e-4;
      EXPECT_LE(o.at(4 + c, i), b.sebum[c] * slack + 1e-6) << who << " sebum lane " << i;
      EXPECT_LE(o.at(7 + c, i), b.epidermis[c] * slack + 1e-6) << who << " epidermis lane " << i;
      EXPECT_LE(o.at(10 + c, i), b.dermis[c] * slack + 1e-6) << who << " dermis lane " << i;
    }
  }
}

// Runs one hard case for every switch combination; `extra` adds case-specific checks on the
// reference outputs.
void run_case(const SkinParams& base, const Case& cs,
              const std::function<void(const SkinParams&, Inputs&, const Outputs&)>& extra = {}) {
  const size_t n = ((cs.lanes.size() + 15) / 16) * 16;
  Inputs in(n);
  for (size_t i = 0; i < n; ++i) {
    const Lane& l = cs.lanes[i % cs.lanes.size()];
    for (int c = 0; c < 3; ++c) {
      in.pos(c)[i] = l.pos[c];
      in.normal(c)[i] = l.normal[c];
      in.albedo(c)[i] = 0.2f + 0.05f * float((i + c) % 16);
      // Blurred normals: the normal tilted toward +x by a channel-dependent amount.
      for (int ch = 0; ch < 3; ++ch) in.blurred(ch, c)[i] = l.normal[c] + (c == 0 ? 0.1f * float(3 - ch) : 0.0f);
    }
  }
  for (const SkinParams& p : all_modes(base)) {
    ASSERT_FALSE(validate(p).has_value()) << validate(p)->message();
    std::string trace = "ss ";
    trace += to_string(p.single_scattering);
    trace += " fresnel ";
    trace += to_string(p.fresnel);
    trace += " phase ";
    trace += to_string(p.phase);
    trace += " ms ";
    trace += to_string(p.multiple_scattering);
    trace += " spec ";
    trace += to_string(p.specular);
    SCOPED_TRACE(trace);
    Outputs ref(n);
    shade_skin_reference(p, cs.lights.data(), cs.lights.size(), cs.eye.data(), in.soa(), ref.soa());
    expect_within_bounds(p, cs, in, ref, "reference");
    if (extra) extra(p, in, ref);
    testing::expect_matches_reference_all_targets(ref, n, [&](Outputs& out) {
      shade_skin(p, cs.lights.data(), cs.lights.size(), cs.eye.data(), in.soa(), out.soa());
      expect_within_bounds(p, cs, in, out, "kernel");
    });
  }
}

// 16 points on the z = 0 plane with normal +z.
std::vector<Lane> plane_lanes() {
  std::vector<Lane> lanes;
  for (int i = 0; i < 16; ++i) lanes.push_back({{0.1f * float(i % 4), 0.1f * float(i / 4), 0.0f}, {0, 0, 1}});
  return lanes;
}

TEST(SkinHardCases, CosIZeroTinyAndNegative) {
  for (double c : {0.0, 1e-7, -1e-7, -0.4}) {
    SCOPED_TRACE("cos_i " + std::to_string(c));
    Case cs{{at_cos(c)}, {1.0f, 2.0f, 5.0f}, plane_lanes()};
    run_case(SkinParams{}, cs, [&](const SkinParams&, Inputs& in, const Outputs& ref) {
      if (c > 0.0) return;
      for (size_t i = 0; i < in.n; ++i)
        for (int ch = 0; ch < 3; ++ch) {
          EXPECT_EQ(ref.at(4 + ch, i), 0.0f) << "no sebum from a light at or behind the horizon";
          EXPECT_EQ(ref.at(10 + ch, i), 0.0f) << "no dermis from a light at or behind the horizon";
        }
    });
  }
}

TEST(SkinHardCases, CosOZeroTinyAndNegative) {
  for (double c : {0.0, 1e-7, -1e-7, -0.4}) {
    SCOPED_TRACE("cos_o " + std::to_string(c));
    const double s = std::sqrt(1.0 - c * c);
    std::vector<Lane> lanes(16, Lane{{0, 0, 0}, {0, 0, 1}});
    Case cs{{at_cos(0.6), ambient()}, {float(-5.0 * s), 0.0f, float(5.0 * c)}, lanes};
    run_case(SkinParams{}, cs);
  }
}

TEST(SkinHardCases, GAtAndNearPlusMinusOne) {
  for (float g : {-1.0f, -0.999999f, 0.0f, 0.999999f, 1.0f}) {
    SCOPED_TRACE("g " + std::to_string(g));
    SkinParams p;
    p.g = g;
    for (float eta : {1.4f, 1.0f}) {
      p.Eta = eta;
      Case cs{{at_cos(0.8), at_cos(1.0), point(0.3f, -0.2f, 0.05f)}, {-0.5f, 0.3f, 4.0f}, plane_lanes()};
      run_case(p, cs);
    }
    // The phase functions themselves at the peaks: finite and at most their bounds.
    for (double ct : {-1.0, 1.0}) {
      EXPECT_TRUE(std::isfinite(ref::hg_phase(ct, g)));
      EXPECT_LE(ref::hg_phase(ct, g), ref::hg_bound(g) * (1 + 1e-12));
      EXPECT_LE(ref::hg_phase_paper(ct, g), ref::hg_paper_bound(g) * (1 + 1e-12));
    }
  }
}

TEST(SkinHardCases, CosThetaPlusMinusOneExactly) {
  SkinParams p;
  p.Eta = 1.0f;  // no bending, so the refracted directions are the outside ones
  // Light and view both along the normal: t_i = -n, t_o = n, cos(theta) = -1.
  Case back{{at_cos(1.0)}, {0.0f, 0.0f, 5.0f}, std::vector<Lane>(16, Lane{{0, 0, 0}, {0, 0, 1}})};
  run_case(p, back);
  // Grazing light from +x and grazing view toward -x: t_i = t_o, cos(theta) = +1 (and cos_i = 0).
  Case fwd{{directional(1, 0, 0)}, {-5.0f, 0.0f, 0.0f}, std::vector<Lane>(16, Lane{{0, 0, 0}, {0, 0, 1}})};
  run_case(p, fwd);
  for (float g : {-0.9f, 0.0f, 0.8f}) {
    const double a = std::fabs(g);
    const double peak = (1 + a) / (4 * ref::kPi * (1 - a) * (1 - a));
    EXPECT_NEAR(ref::hg_phase(g >= 0 ? 1.0 : -1.0, g), peak, 1e-12 * peak);
  }
}

TEST(SkinHardCases, EtaOne) {
  SkinParams p;
  p.Eta = 1.0f;
  for (double c : {1e-7, 0.3, 1.0}) EXPECT_NEAR(ref::fresnel_exact(c, 1.0), 0.0, 1e-12);
  EXPECT_EQ(ref::fresnel_exact(0.0, 1.0), 1.0);
  Case cs{{at_cos(0.5), at_cos(1e-3), ambient()}, {2.0f, -1.0f, 3.0f}, plane_lanes()};
  run_case(p, cs);
}

TEST(SkinHardCases, EtaBelowOneWithTotalInternalReflection) {
  SkinParams p;
  p.Eta = 0.7f;  // critical cosine sqrt(1 - 0.49) = 0.714
  EXPECT_EQ(ref::fresnel_exact(0.5, 0.7), 1.0);
  double ct;
  EXPECT_FALSE(ref::refract_cos(0.5, 0.7, ct));
  // Light beyond the critical angle: no dermis; view beyond it: no dermis from any light.
  Case light_tir{{at_cos(0.5)}, {0.5f, 0.2f, 5.0f}, plane_lanes()};
  run_case(p, light_tir, [](const SkinParams&, Inputs& in, const Outputs& ref) {
    for (size_t i = 0; i < in.n; ++i)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(ref.at(10 + c, i), 0.0f);
  });
  Case view_tir{{at_cos(0.9)}, {-5.0f, 0.0f, 2.0f}, std::vector<Lane>(16, Lane{{0, 0, 0}, {0, 0, 1}})};
  run_case(p, view_tir, [](const SkinParams&, Inputs& in, const Outputs& ref) {
    for (size_t i = 0; i < in.n; ++i)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(ref.at(10 + c, i), 0.0f);
  });
  Case lit{{at_cos(0.95), at_cos(0.75)}, {0.2f, 0.1f, 5.0f}, plane_lanes()};
  run_case(p, lit);
}

TEST(SkinHardCases, ThicknessZeroAndHuge) {
  SkinParams p;
  p.Thickness = 0.0f;
  Case cs{{at_cos(0.7), at_cos(1e-7)}, {1.0f, 0.5f, 4.0f}, plane_lanes()};
  run_case(p, cs, [](const SkinParams&, Inputs& in, const Outputs& ref) {
    for (size_t i = 0; i < in.n; ++i)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(ref.at(10 + c, i), 0.0f) << "an empty layer scatters nothing";
  });
  p.Thickness = 1e6f;
  run_case(p, cs);
  // Semi-infinite limit of the term: a p / (ci + co).
  EXPECT_NEAR(ref::single_scattering(0.5, 0.25, 0.1, 0.8, 1e6), 0.8 * 0.1 / 0.75, 1e-15);
}

TEST(SkinHardCases, ZeroLengthAndDenormalNormals) {
  // Degenerate normals are replaced by the view direction: every such lane must equal a lane
  // whose normal is the view direction.
  const float eye[3] = {0.0f, 0.0f, 5.0f};
  std::vector<Lane> lanes = {
      {{0, 0, 0}, {0, 0, 0}},           {{0, 0, 0}, {1e-40f, 0, 0}},       {{0, 0, 0}, {1e-45f, 1e-45f, 1e-45f}},
      {{0, 0, 0}, {-1e-39f, 2e-39f, 0}}, {{0, 0, 0}, {0, 0, 1}},  // the view direction itself
  };
  Case cs{{at_cos(0.6), point(1.0f, 1.0f, 1.0f), ambient()}, {eye[0], eye[1], eye[2]}, lanes};
  run_case(SkinParams{}, cs);
  // Direct equality with the facing lane under one albedo.
  Inputs in(16);
  for (size_t i = 0; i < 16; ++i) {
    const Lane& l = lanes[i % lanes.size()];
    for (int c = 0; c < 3; ++c) {
      in.pos(c)[i] = l.pos[c];
      in.normal(c)[i] = l.normal[c];
      in.albedo(c)[i] = 0.7f;
    }
  }
  for (const SkinParams& p : all_modes(SkinParams{})) {
    if (p.multiple_scattering == MultipleScattering::normal_blur) continue;
    Outputs out(16);
    shade_skin(p, cs.lights.data(), cs.lights.size(), eye, in.soa(), out.soa());
    for (size_t i = 0; i < 16; ++i)
      for (int k = 0; k < 13; ++k) EXPECT_EQ(out.at(k, i), out.at(k, 4)) << "lane " << i << " output " << k;
  }
}

TEST(SkinHardCases, PointLightAtTheShadedPoint) {
  // The light sits exactly on the surface point: it shines along the normal, like a directional
  // light along +z.
  Case cs{{point(0.25f, 0.5f, 0.0f)}, {0.3f, 0.1f, 5.0f}, std::vector<Lane>(16, Lane{{0.25f, 0.5f, 0.0f}, {0, 0, 1}})};
  run_case(SkinParams{}, cs, [&](const SkinParams& p, Inputs& in, const Outputs& ref) {
    Outputs along(in.n);
    const Light d = directional(0, 0, 1);
    shade_skin_reference(p, &d, 1, cs.eye.data(), in.soa(), along.soa());
    for (size_t i = 0; i < in.n; ++i)
      for (int k = 0; k < 13; ++k) EXPECT_NEAR(ref.at(k, i), along.at(k, i), 1e-6 * (1 + along.at(k, i)));
  });
}

TEST(SkinHardCases, ClampCoeffZeroWithGrazingView) {
  SkinParams p;
  p.ClampCoeff = 0.0f;
  Case cs{{at_cos(0.5), ambient(0.5f)}, {5.0f, 0.0f, 0.0f}, std::vector<Lane>(16, Lane{{0, 0, 0}, {0, 0, 1}})};
  run_case(p, cs, [](const SkinParams& q, Inputs& in, const Outputs& ref) {
    if (q.multiple_scattering != MultipleScattering::paper) return;
    // |I.N| + l_c = 0 is floored at kClampFloor.
    for (size_t i = 0; i < in.n; ++i) {
      const double cl_sum = 1.0 + 0.5;  // red channel of both lights
      const double expect = q.Opacity * q.DiffusionColor[0] * in.albedo(0)[i] * q.MultipleScatteringCoeff *
                            cl_sum / kClampFloor;
      EXPECT_NEAR(ref.at(7, i), expect, 1e-5 * expect);
    }
  });
}

// More non-ambient lights than the entry points prepare on the stack (16): they are prepared
// on the heap instead and must shade like fewer lights do.
TEST(SkinHardCases, MoreLightsThanTheKernelCaches) {
  std::vector<Light> lights;
  for (int k = 0; k < 21; ++k) {
    const double a = 0.3 * k;
    if (k % 7 == 3) lights.push_back(ambient(0.05f));
    else if (k % 5 == 4) lights.push_back(point(float(std::cos(a)), float(std::sin(a)), 0.6f, 0.2f));
    else lights.push_back(directional(0.6 * std::cos(a), 0.6 * std::sin(a), 0.8, 0.15f));
  }
  Case cs{lights, {0.4f, -0.3f, 4.0f}, plane_lanes()};
  run_case(SkinParams{}, cs);
}

// Eta = 1 and a view a hair above the horizon: exact Fresnel transmission is 1 at every angle,
// but the outgoing fraction's 16 c^4 / 16 c^4 underflowed to 0/0 (then clamped to 0) for
// cos_o <= 1e-10, and c^2 in the refracted cosine underflows below 1e-19, dropping the dermis and
// the reference epidermis. Down to 1e-7 the denominator times the floored |I.N| + ClampCoeff was
// also below 2^-96, where the shared division of the two would lose precision.
TEST(SkinHardCases, EtaOneGrazingViewKeepsItsTransmission) {
  SkinParams p;
  p.Eta = 1.0f;
  p.ClampCoeff = 0.0f;
  for (double c : {1e-30, 1e-20, 1e-12, 1e-11, 1e-10, 1e-7, 1e-5, 3e-3}) {
    SCOPED_TRACE(::testing::Message() << "cos_o " << c);
    const double s = std::sqrt(1.0 - c * c);
    Case cs{{at_cos(0.6), ambient()}, {float(-5.0 * s), 0.0f, float(5.0 * c)},
            std::vector<Lane>(16, Lane{{0, 0, 0}, {0, 0, 1}})};
    run_case(p, cs);
  }
}

TEST(BasicHardCases, DegenerateNormalsGrazingAndCoincidentLights) {
  const float eye[3] = {5.0f, 0.0f, 0.0f};  // grazing view of the +z plane
  std::vector<Lane> lanes = {{{0, 0, 0}, {0, 0, 0}}, {{0, 0, 0}, {1e-40f, 0, 0}}, {{0, 0, 0}, {0, 0, 1}},
                             {{0, 0, 0}, {0, 0, -1}}};
  const std::vector<Light> lights = {at_cos(0.0), at_cos(-1e-7), point(0, 0, 0), ambient()};
  Inputs in(16);
  for (size_t i = 0; i < 16; ++i)
    for (int c = 0; c < 3; ++c) {
      in.pos(c)[i] = lanes[i % 4].pos[c];
      in.normal(c)[i] = lanes[i % 4].normal[c];
      in.albedo(c)[i] = 0.1f * float(i % 10);
    }
  BasicParams bp;
  bp.shininess = 256.0f;
  Outputs r1(16), r2(16), r3(16);
  shade_unlit_reference(lights.data(), lights.size(), eye, in.soa(), r1.soa());
  shade_lambert_reference(lights.data(), lights.size(), eye, in.soa(), r2.soa());
  shade_blinn_reference(bp, lights.data(), lights.size(), eye, in.soa(), r3.soa());
  testing::expect_matches_reference_all_targets(
      r1, 16, [&](Outputs& o) { shade_unlit(lights.data(), lights.size(), eye, in.soa(), o.soa()); }, 4);
  testing::expect_matches_reference_all_targets(
      r2, 16, [&](Outputs& o) { shade_lambert(lights.data(), lights.size(), eye, in.soa(), o.soa()); }, 4);
  testing::expect_matches_reference_all_targets(
      r3, 16, [&](Outputs& o) { shade_blinn(bp, lights.data(), lights.size(), eye, in.soa(), o.soa()); }, 4);
}

}  // namespace skin_hard_cases_test
}  // namespace pelt::shading
