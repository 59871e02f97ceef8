// Kernel vs double reference on random inputs, for every compiled Highway target.
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "shading/skin_kernels.h"
#include "shading/skin_reference.h"
#include "tests/shading/batch_harness.h"
#include "tests/shading/random_inputs.h"

namespace pelt::shading {
namespace skin_kernels_random_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

using testing::Inputs;
using testing::Outputs;

using testing::random_eye;
using testing::random_lights;
using testing::Rng;

SkinParams random_params(Rng& r) {
  SkinParams p;
  for (int c = 0; c < 3; ++c) {
    p.SkinColor[c] = r.uni(0, 1);
    p.SheenColor[c] = r.uni(0, 1);
    p.DiffusionColor[c] = r.uni(0, 1);
    p.normal_blur_mix[c] = r.uni(0, 1);
  }
  p.Opacity = r.uni(0, 1);
  p.AmbientCoeff = r.uni(0, 1);
  p.Thickness = r.pick(8) == 0 ? 0.0f : r.logu(1e-3f, 1e3f);
  p.Eta = r.pick(4) == 0 ? r.uni(0.25f, 1.0f) : r.uni(1.0f, 4.0f);
  p.SingleScatteringCoeff = r.uni(0, 20);
  p.MultipleScatteringCoeff = r.uni(0, 2);
  p.ClampCoeff = r.uni(0, 2);
  p.Power = r.logu(1, 256);
  p.Specularity = r.uni(0, 2);
  p.g = r.uni(-1, 1);
  p.single_scattering = static_cast<SingleScattering>(r.pick(3));
  p.multiple_scattering = static_cast<MultipleScattering>(r.pick(4));
  p.fresnel = static_cast<Fresnel>(r.pick(2));
  p.phase = static_cast<Phase>(r.pick(2));
  p.specular = static_cast<Specular>(r.pick(2));
  return p;
}

void random_surface(Rng& r, Inputs& in) {
  for (size_t i = 0; i < in.n; ++i) {
    float nrm[3];
    r.unit(nrm);
    const float len = r.logu(1e-3f, 1e3f);
    for (int c = 0; c < 3; ++c) {
      in.pos(c)[i] = r.uni(-1, 1);
      in.normal(c)[i] = nrm[c] * len;
      in.albedo(c)[i] = r.uni(-0.2f, 1.2f);  // outside [0, 1]: masked-off lanes' extrapolation
    }
    for (int ch = 0; ch < 3; ++ch)
      for (int c = 0; c < 3; ++c) in.blurred(ch, c)[i] = nrm[c] + r.uni(-0.5f, 0.5f);
  }
}

// One batch: random lights, eye and surface for `p`, the kernel on every target against the
// reference (the jitter criterion for ill-conditioned outputs, batch_harness.h).
void expect_random_batch_matches(Rng& r, const SkinParams& p, Inputs& in, const std::string& name) {
  const size_t n = in.n;
  const std::vector<Light> lights = random_lights(r);
  float eye[3];
  random_eye(r, eye);
  random_surface(r, in);
  Outputs ref(n);
  shade_skin_reference(p, lights.data(), lights.size(), eye, in.soa(), ref.soa());
  std::string trace = name;
  trace += " ss ";
  trace += to_string(p.single_scattering);
  trace += " ms ";
  trace += to_string(p.multiple_scattering);
  SCOPED_TRACE(trace);
  auto describe = [&](size_t i) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "n %.9g %.9g %.9g p %.9g %.9g %.9g eye %.9g %.9g %.9g", in.normal(0)[i],
                  in.normal(1)[i], in.normal(2)[i], in.pos(0)[i], in.pos(1)[i], in.pos(2)[i], eye[0], eye[1], eye[2]);
    std::string s = buf;
    std::snprintf(buf, sizeof buf, " | fr %d ph %d sp %d ss %d ms %d th %.9g g %.9g eta %.9g P %.9g op %.9g",
                  int(p.fresnel), int(p.phase), int(p.specular), int(p.single_scattering),
                  int(p.multiple_scattering), p.Thickness, p.g, p.Eta, p.Power, p.Opacity);
    s += buf;
    for (const Light& l : lights) {
      std::snprintf(buf, sizeof buf, " L%d %.9g %.9g %.9g", int(l.type), l.vec[0], l.vec[1], l.vec[2]);
      s += buf;
    }
    return s;
  };
  auto jittered = [&](size_t i, int k, int trial) {
    std::mt19937 jr(uint32_t(i * 977 + trial));
    auto jit = [&](float v) {
      const float ulps = float(std::uniform_int_distribution<int>(-4, 4)(jr));
      return double(v) + double(ulps) * std::fabs(double(v)) * 0x1p-24;
    };
    ref::Sample smp{};
    for (int c = 0; c < 3; ++c) {
      smp.pos[c] = jit(in.pos(c)[i]);
      smp.normal[c] = jit(in.normal(c)[i]);
      smp.albedo[c] = in.albedo(c)[i];
      for (int a = 0; a < 3; ++a) smp.blurred_normal[c][a] = jit(in.blurred(c, a)[i]);
    }
    std::vector<Light> lj = lights;
    for (Light& l : lj)
      for (float& v : l.vec) v = float(jit(v));
    const double e[3] = {jit(eye[0]), jit(eye[1]), jit(eye[2])};
    const ref::Shaded r = ref::shade_skin_pixel(p, lj.data(), lj.size(), e, smp);
    const double all[13] = {r.rgb[0],       r.rgb[1],       r.rgb[2],       r.alpha,     r.sebum[0],
                            r.sebum[1],     r.sebum[2],     r.epidermis[0], r.epidermis[1], r.epidermis[2],
                            r.dermis[0],    r.dermis[1],    r.dermis[2]};
    return all[k];
  };
  testing::expect_matches_reference_all_targets(
      ref, n, [&](Outputs& out) { shade_skin(p, lights.data(), lights.size(), eye, in.soa(), out.soa()); }, 13,
      describe, jittered);
}

TEST(SkinKernels, MatchesReferenceOnAMillionRandomInputs) {
  Rng r(0x5eed);
  const size_t n = 16384;
  const int batches = 64;  // 1,048,576 lanes, each batch with its own parameters and lights
  Inputs in(n);
  for (int b = 0; b < batches; ++b) expect_random_batch_matches(r, random_params(r), in, "batch " + std::to_string(b));
  std::printf("outputs that passed by the jitter criterion (all targets): %zu of %zu\n",
              testing::total_conditioned(), size_t(batches) * n * 13 * hwy::SupportedAndGeneratedTargets().size());
}

// The sebum lobe's other path: an integer Power (the default, 20) is raised by repeated
// squaring, any other through Exp and Log (skin_kernels.cc, SpecularLobe). random_params's
// powers are almost never integers, so the million lanes above test only Exp and Log; here
// every switch combination in turn with integer powers over the whole range [1, 256], odd and
// even, on a lane count that ends in a partial 64-lane block (the kernel's passes).
TEST(SkinKernels, IntegerPowersMatchReferenceOnRandomInputs) {
  Rng r(0x1a7e);
  Inputs in(64 * 15 + 48);
  const float powers[] = {1.0f, 2.0f, 3.0f, 7.0f, 20.0f, 33.0f, 128.0f, 255.0f, 256.0f};
  int k = 0;
  for (int ss = 0; ss < 3; ++ss)
    for (int ms = 0; ms < 4; ++ms)
      for (int sp = 0; sp < 2; ++sp) {
        SkinParams p = random_params(r);
        p.single_scattering = static_cast<SingleScattering>(ss);
        p.multiple_scattering = static_cast<MultipleScattering>(ms);
        p.specular = static_cast<Specular>(sp);
        p.fresnel = static_cast<Fresnel>(k % 2);
        p.phase = static_cast<Phase>(k / 2 % 2);
        p.Power = powers[k++ % std::size(powers)];
        // A bright sheen, so that the lobe is most of rgb.
        p.Specularity = 2.0f;
        expect_random_batch_matches(r, p, in, "Power " + std::to_string(p.Power));
      }
}

// The three basic materials on `batches` batches of random lanes, Blinn's shininess from
// `shininess(r)`.
void expect_basic_batches_match(Rng& r, size_t n, int batches, const std::function<float(Rng&)>& shininess) {
  Inputs in(n);
  for (int b = 0; b < batches; ++b) {
    const std::vector<Light> lights = random_lights(r);
    float eye[3];
    r.unit(eye);
    for (float& e : eye) e *= 4.0f;
    random_surface(r, in);
    BasicParams bp;
    for (float& s : bp.specular) s = r.uni(0, 2);
    bp.shininess = shininess(r);
    SCOPED_TRACE("shininess " + std::to_string(bp.shininess));
    Outputs ref_unlit(n), ref_lambert(n), ref_blinn(n);
    shade_unlit_reference(lights.data(), lights.size(), eye, in.soa(), ref_unlit.soa());
    shade_lambert_reference(lights.data(), lights.size(), eye, in.soa(), ref_lambert.soa());
    shade_blinn_reference(bp, lights.data(), lights.size(), eye, in.soa(), ref_blinn.soa());
    testing::expect_matches_reference_all_targets(
        ref_unlit, n, [&](Outputs& o) { shade_unlit(lights.data(), lights.size(), eye, in.soa(), o.soa()); }, 4);
    testing::expect_matches_reference_all_targets(
        ref_lambert, n, [&](Outputs& o) { shade_lambert(lights.data(), lights.size(), eye, in.soa(), o.soa()); },
        4);
    testing::expect_matches_reference_all_targets(
        ref_blinn, n, [&](Outputs& o) { shade_blinn(bp, lights.data(), lights.size(), eye, in.soa(), o.soa()); },
        4);
  }
}

TEST(BasicKernels, MatchReferenceOnRandomInputs) {
  Rng r(0xba51c);
  expect_basic_batches_match(r, 16384, 8, [](Rng& g) { return g.logu(1, 256); });
}

// Blinn's integer shininess (the default, 32) takes SpecularLobe's repeated squaring, which the
// random shininess above never does: integer exponents over [1, 256], odd and even.
TEST(BasicKernels, IntegerShininessMatchesReferenceOnRandomInputs) {
  Rng r(0x5417);
  int k = 0;
  const float shininess[] = {1.0f, 2.0f, 3.0f, 7.0f, 32.0f, 77.0f, 255.0f, 256.0f};
  expect_basic_batches_match(r, 1024 + 16, int(std::size(shininess)),
                             [&](Rng&) { return shininess[k++ % std::size(shininess)]; });
}

}  // namespace skin_kernels_random_test
}  // namespace pelt::shading
