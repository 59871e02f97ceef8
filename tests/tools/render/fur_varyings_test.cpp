// Grey per-vertex fur light travels as one diffuse and one specular varying instead of three
// each: the same image from half the interpolation, and only when the light really is grey.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "raster/renderer.h"
#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/builtin_meshes.h"
#include "tools/io/scene.h"
#include "tools/render/fur_object.h"
#include "tools/render/fur_shader.h"
#include "tools/render/scene_renderer.h"

namespace pelt::render::test {
namespace fur_varyings_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

struct Frame {
  FrameImage image;
  int varyings = 0;
};

Frame render_fur(const std::string& ambient, bool grey_allowed, FurLighting lighting = FurLighting::vertex) {
  std::string json = furry_box_scene(R"("fins": "all", "gravity": {}, "wind": {})", 3);
  const std::string tinted = R"("color": [0.3, 0.3, 0.35])";
  json.replace(json.find(tinted), tinted.size(), ambient);
  const io::Scene scene = io::parse_scene(json, "fur_varyings.json");
  RenderSettings rs;
  rs.threads = 2;
  rs.fur_grey_varyings = grey_allowed;
  rs.fur_lighting = lighting;
  SceneRenderer r(scene, rs);
  Frame f;
  FrameStats st;
  for (int frame = 0; frame < 3; ++frame) r.render(frame, f.image, st);
  f.varyings = r.fur_varying_count(0);
  return f;
}

TEST(FurVaryings, GreyLightTakesHalfTheVaryingsAndGivesTheSameImage) {
  const std::string white = R"("color": [0.3, 0.3, 0.3])";
  const Frame grey = render_fur(white, true), rgb = render_fur(white, false);
  EXPECT_EQ(grey.varyings, 4);
  EXPECT_EQ(rgb.varyings, 8);
  ASSERT_EQ(grey.image.color.size(), rgb.image.color.size());
  EXPECT_EQ(0, std::memcmp(grey.image.color.data(), rgb.image.color.data(), grey.image.color.size() * sizeof(float)));
}

// Kajiya-Kay per fragment (FurPixelVaryings) draws the same fur as per vertex, shells and fins
// with their tints, up to the lighting's interpolation: every pixel finite, the same coverage
// (alpha), and the mean colour within 2 % (measured: 0.3 %).
TEST(FurVaryings, PerPixelLightingDrawsTheSameFur) {
  const std::string white = R"("color": [0.3, 0.3, 0.3])";
  const Frame vertex = render_fur(white, true), pixel = render_fur(white, true, FurLighting::pixel);
  ASSERT_EQ(vertex.image.color.size(), pixel.image.color.size());
  double mean_vertex[3] = {}, mean_pixel[3] = {};
  for (size_t i = 0; i < pixel.image.color.size(); ++i) {
    ASSERT_TRUE(std::isfinite(pixel.image.color[i])) << i;
    if (i % 4 == 3) {
      ASSERT_EQ(pixel.image.color[i], vertex.image.color[i]) << "alpha of pixel " << i / 4;
      continue;
    }
    mean_vertex[i % 4] += vertex.image.color[i];
    mean_pixel[i % 4] += pixel.image.color[i];
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(mean_pixel[c] / mean_vertex[c], 1.0, 0.02) << "channel " << c;
  }
}

TEST(FurVaryings, ColouredLightKeepsThreeChannels) {
  const Frame tinted = render_fur(R"("color": [0.3, 0.3, 0.35])", true);
  EXPECT_EQ(tinted.varyings, 8);
  const Frame forced = render_fur(R"("color": [0.3, 0.3, 0.35])", false);
  EXPECT_EQ(0, std::memcmp(tinted.image.color.data(), forced.image.color.data(),
                           tinted.image.color.size() * sizeof(float)));
}

// The varying layout follows the light from frame to frame: an object lit white and then
// coloured draws exactly what an object lit coloured from the start draws (its uvs move
// with the layout's stride), and back.
TEST(FurVaryings, SwitchingBetweenGreyAndColouredLightMovesTheWholeRecord) {
  const Mesh box = io::make_builtin_mesh("box:3");
  fur::FurParams params;
  params.shells = 8;
  params.texture_size = 32;
  const shading::Light sun{shading::Light::Type::Directional, {0.3f, 0.8f, 0.5f}, {1.0f, 1.0f, 1.0f}};
  const std::vector<shading::Light> white = {sun, {shading::Light::Type::Ambient, {0, 0, 0}, {0.3f, 0.3f, 0.3f}}};
  const std::vector<shading::Light> coloured = {sun, {shading::Light::Type::Ambient, {0, 0, 0}, {0.3f, 0.2f, 0.4f}}};
  FurFrame f;
  f.sort = FurSort::none;
  f.eye = glm::vec3(3.0f, 2.0f, 4.0f);
  f.clip_from_world = glm::perspective(glm::radians(45.0f), 1.0f, 1.0f, 20.0f) *
                      glm::lookAt(f.eye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
  auto draw = [&](FurObject& o, const std::vector<shading::Light>& lights) {
    FrameStats st;
    o.update(f, lights, st);
    std::vector<raster::DrawCall> draws;
    o.append_draws(draws);
    std::vector<float> color(64 * 64 * 4), depth(64 * 64);
    std::vector<uint32_t> id(64 * 64);
    raster::Renderer r(1);
    r.render(draws, {}, raster::RenderTarget{64, 64, color.data(), depth.data(), id.data()}, nullptr);
    return std::make_pair(o.varying_count(), color);
  };
  FrameStats setup;
  FurObject switched(box, params, {}, FurOrigin{"switched", ""}, setup),
      fresh_coloured(box, params, {}, FurOrigin{"coloured", ""}, setup),
      fresh_white(box, params, {}, FurOrigin{"white", ""}, setup);
  EXPECT_EQ(draw(switched, white).first, 4);
  const auto to_coloured = draw(switched, coloured), coloured_only = draw(fresh_coloured, coloured);
  EXPECT_EQ(to_coloured.first, 8);
  EXPECT_EQ(to_coloured.second, coloured_only.second);
  const auto back = draw(switched, white), white_only = draw(fresh_white, white);
  EXPECT_EQ(back.first, 4);
  EXPECT_EQ(back.second, white_only.second);
}

// Shells are always luminance-alpha: a shell draw without its per-layer tint is a set-up error,
// not an RGBA fallback.
TEST(FurVaryings, AShellShaderNeedsItsTint) {
  FurShaderSetup su;
  EXPECT_THROW(FurShader{su}, std::invalid_argument);
  su.fins = true;
  EXPECT_NO_THROW(FurShader{su});
  const glm::vec3 tint(1.0f);
  su.fins = false;
  su.shell_tint = &tint;
  EXPECT_NO_THROW(FurShader{su});
}

}  // namespace fur_varyings_test
}  // namespace pelt::render::test
