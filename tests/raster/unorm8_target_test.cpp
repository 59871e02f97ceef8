// The RGBA8 target (RenderTarget::color8): every byte is unorm8 of the float colour the same
// render gives, on every target, in covered, partial edge and empty tiles, with colours
// outside [0, 1] and NaN, into a 16-byte aligned plane and one that is not even 4-byte aligned;
// and the byte plane alone gives the same bytes as beside the float plane.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "tests/raster/render_helpers.h"
#include "tests/raster/test_shaders.h"

namespace pelt::raster::test {
namespace {

TEST(Unorm8, RoundsHalfUpClampsAndMapsNanToZero) {
  for (int k = 0; k < 256; ++k) {
    EXPECT_EQ(unorm8(float(k) / 255.0f), k);
    if (k < 255) {
      EXPECT_EQ(unorm8((float(k) + 0.25f) / 255.0f), k);
      EXPECT_EQ(unorm8((float(k) + 0.75f) / 255.0f), k + 1);
    }
  }
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(unorm8(-0.0f), 0);
  EXPECT_EQ(unorm8(-1.0f), 0);
  EXPECT_EQ(unorm8(-inf), 0);
  EXPECT_EQ(unorm8(1.5f), 255);
  EXPECT_EQ(unorm8(inf), 255);
  EXPECT_EQ(unorm8(std::numeric_limits<float>::quiet_NaN()), 0);
}

TEST(Unorm8Target, IsTheFloatColourQuantisedOnEveryTarget) {
  // 131 x 77: 3 x 2 tiles, the last column 3 pixels and the last row 13 wide (not a whole block).
  constexpr int kW = 131, kH = 77;
  constexpr size_t kPixels = size_t(kW) * kH;
  // An opaque ramp whose colours run from -0.2 to 1.2 (both clamps), a translucent triangle over
  // it, and an opaque triangle with a NaN colour; the right part of the image is left empty.
  const std::vector<glm::vec3> pos = {{-1.0f, -1.0f, 0.5f}, {0.6f, -1.0f, 0.5f}, {-1.0f, 1.0f, 0.5f},
                                      {-0.9f, -0.8f, 0.2f}, {0.5f, 0.1f, 0.2f},  {-0.2f, 0.9f, 0.2f},
                                      {0.1f, 0.5f, 0.1f},   {0.4f, 0.5f, 0.1f},  {0.1f, 0.9f, 0.1f}};
  const std::vector<float> var = {-0.2f, 0.3f, 1.2f, 1.2f, -0.2f, 0.5f, 0.6f, 1.2f, -0.2f,
                                  0.9f,  0.1f, 0.4f, 0.2f, 0.8f,  0.0f, 0.5f, 0.5f, 1.0f,
                                  0.0f,  0.0f, 0.0f, 0.0f, 0.0f,  0.0f, 0.0f, 0.0f, 0.0f};
  const std::vector<uint32_t> ramp = {0, 1, 2}, over = {3, 4, 5}, bad = {6, 7, 8};
  const VaryingShader opaque_shader, glass_shader(0.4f);
  const ConstantShader nan_shader({std::nanf(""), 0.5f, 0.25f, 1.0f});
  DrawCall d[3];
  for (DrawCall& c : d) {
    c.positions = pos.data();
    c.vertex_count = uint32_t(pos.size());
    c.varyings = var.data();
    c.varying_count = 3;
    c.triangle_count = 1;
  }
  d[0].indices = ramp.data();
  d[0].shader = &opaque_shader;
  d[1].indices = bad.data();
  d[1].shader = &nan_shader;
  d[2].indices = over.data();
  d[2].shader = &glass_shader;
  d[2].state.blend = BlendMode::AlphaOver;
  d[2].state.depth_write = false;
  RenderOptions opt;
  opt.background = glm::vec4(0.25f, 0.5f, 0.75f, 0.125f);
  // 16-byte aligned, then not even 4-byte aligned.
  for (const size_t at : {size_t{16}, size_t{1}}) {
    for_each_target([&](const std::string& target) {
      std::vector<float> colour(kPixels * 4, -1.0f);
      std::vector<uint8_t> bytes(kPixels * 4 + 32, 7), alone(kPixels * 4 + 32, 7);
      Renderer r(2);
      RenderTarget both{kW, kH, colour.data()};
      both.color8 = bytes.data() + at;
      r.render({d, 3}, opt, both, nullptr);
      RenderTarget only{kW, kH};
      only.color8 = alone.data() + at;
      r.render({d, 3}, opt, only, nullptr);
      size_t clamped = 0, nan = 0;
      for (size_t i = 0; i < kPixels * 4; ++i) {
        ASSERT_EQ(bytes[i + at], unorm8(colour[i])) << target << " at " << at << " pixel " << i / 4 << " channel "
                                                    << i % 4 << ": " << colour[i];
        clamped += colour[i] < 0.0f || colour[i] > 1.0f;
        nan += std::isnan(colour[i]);
      }
      EXPECT_EQ(alone, bytes) << target;
      EXPECT_GT(clamped, 100u) << target;  // the test reaches both clamps...
      EXPECT_GT(nan, 10u) << target;       // ...and NaN
      EXPECT_EQ(bytes[at - 1], 7) << target;  // nothing written before the plane
      EXPECT_EQ(bytes[at + kPixels * 4], 7) << target;  // nor after it
      const size_t last = kPixels - 1;  // the bottom-right pixel: an empty tile's background
      for (int k = 0; k < 4; ++k) EXPECT_EQ(bytes[at + 4 * last + size_t(k)], unorm8(opt.background[k])) << target;
    });
  }
}

}  // namespace
}  // namespace pelt::raster::test
