// The batch interface's contract: validation errors name the field, optional outputs, layer sums.
#include <stdexcept>

#include "shading/skin_kernels.h"
#include "tests/shading/batch_harness.h"

namespace pelt::shading {
namespace skin_kernels_api_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

using testing::Inputs;
using testing::Outputs;

Inputs facing_plane(size_t n) {
  Inputs in(n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      in.pos(c)[i] = c == 0 ? 0.01f * float(i) : 0.0f;
      in.normal(c)[i] = c == 2 ? 1.0f : 0.0f;
      in.albedo(c)[i] = 0.5f + 0.1f * float(c);
    }
  return in;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ShadingApi, ErrorsNameTheField) {
  Inputs in = facing_plane(16);
  Outputs out(16);
  const float eye[3] = {0, 0, 5};
  const Light light{Light::Type::Directional, {0, 0, 1}, {1, 1, 1}};
  SkinParams p;
  p.Opacity = 2.0f;
  EXPECT_EQ(error_of([&] { shade_skin(p, &light, 1, eye, in.soa(), out.soa()); }).rfind("Opacity:", 0), 0u);
  EXPECT_EQ(error_of([&] { shade_skin_reference(p, &light, 1, eye, in.soa(), out.soa()); }).rfind("Opacity:", 0), 0u);

  SurfaceSoA s = in.soa();
  s.n = 20;
  EXPECT_EQ(error_of([&] { shade_lambert(&light, 1, eye, s, out.soa()); }).rfind("n:", 0), 0u);
  s = in.soa();
  s.albedo[1] += 1;  // misaligned
  EXPECT_EQ(error_of([&] { shade_lambert(&light, 1, eye, s, out.soa()); }).rfind("albedo[1]:", 0), 0u);

  Light bad = light;
  bad.color[2] = -1.0f;
  EXPECT_EQ(error_of([&] { shade_lambert(&bad, 1, eye, in.soa(), out.soa()); }).rfind("lights[0].color[2]:", 0), 0u);
  // light.h: each colour channel in [0, 1e6] (the kernels' float sums stay finite below it).
  bad = light;
  bad.color[1] = 1e6f;
  EXPECT_NO_THROW(shade_lambert(&bad, 1, eye, in.soa(), out.soa()));
  bad.color[1] = 1.5e6f;
  EXPECT_EQ(error_of([&] { shade_lambert(&bad, 1, eye, in.soa(), out.soa()); }).rfind("lights[0].color[1]:", 0), 0u);
  bad = light;
  bad.vec[0] = bad.vec[1] = bad.vec[2] = 0.0f;
  EXPECT_EQ(error_of([&] { shade_lambert(&bad, 1, eye, in.soa(), out.soa()); }).rfind("lights[0].vec:", 0), 0u);

  SkinParams nb;
  nb.multiple_scattering = MultipleScattering::normal_blur;
  s = in.soa();
  s.blurred_normal[0][2] = nullptr;
  EXPECT_EQ(error_of([&] { shade_skin(nb, &light, 1, eye, s, out.soa()); }).rfind("blurred_normal[0][z]:", 0), 0u);

  BasicParams bp;
  bp.shininess = 0.0f;
  EXPECT_EQ(error_of([&] { shade_blinn(bp, &light, 1, eye, in.soa(), out.soa()); }).rfind("shininess:", 0), 0u);
}

TEST(ShadingApi, LayersAreOptionalAndSumToRgb) {
  const size_t n = 32;
  Inputs in = facing_plane(n);
  const float eye[3] = {0.5f, 0.2f, 3};
  const Light lights[3] = {{Light::Type::Directional, {0.3f, 0.1f, 1}, {1, 0.9f, 0.8f}},
                           {Light::Type::Point, {1, 1, 1}, {0.5f, 0.5f, 0.5f}},
                           {Light::Type::Ambient, {0, 0, 0}, {0.2f, 0.2f, 0.2f}}};
  SkinParams p;
  p.Opacity = 0.75f;
  Outputs full(n), bare(n);
  shade_skin(p, lights, 3, eye, in.soa(), full.soa());
  ShadeOutSoA o = bare.soa();
  for (int c = 0; c < 3; ++c) o.sebum[c] = o.epidermis[c] = o.dermis[c] = nullptr;
  bare.out[5][0] = -7.0f;  // a layer buffer the call must not touch
  shade_skin(p, lights, 3, eye, in.soa(), o);
  EXPECT_EQ(bare.at(5, 0), -7.0f);
  for (size_t i = 0; i < n; ++i) {
    EXPECT_EQ(full.at(3, i), 0.75f);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(full.at(c, i), bare.at(c, i));
      const double ambient = 0.75 * p.AmbientCoeff * p.SkinColor[c] * in.albedo(c)[i] * 0.2;
      const double layers = full.at(4 + c, i) + full.at(7 + c, i) + full.at(10 + c, i);
      EXPECT_NEAR(full.at(c, i), ambient + layers, 1e-6 * (1 + full.at(c, i)));
      EXPECT_GT(full.at(10 + c, i), 0.0f) << "the default dermis is lit";
    }
  }
}

TEST(ShadingApi, LambertWhiteFacingUnitLightIsOne) {
  Inputs in = facing_plane(16);
  for (size_t i = 0; i < 16; ++i)
    for (int c = 0; c < 3; ++c) in.albedo(c)[i] = 1.0f;
  const float eye[3] = {0, 0, 5};
  const Light light{Light::Type::Directional, {0, 0, 2}, {1, 1, 1}};
  Outputs out(16);
  shade_lambert(&light, 1, eye, in.soa(), out.soa());
  for (size_t i = 0; i < 16; ++i)
    for (int c = 0; c < 4; ++c) EXPECT_EQ(out.at(c, i), 1.0f);
}

}  // namespace skin_kernels_api_test
}  // namespace pelt::shading
