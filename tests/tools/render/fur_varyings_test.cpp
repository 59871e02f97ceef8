// Grey per-vertex fur light travels as one diffuse and one specular varying instead of three
// each: the same image from half the interpolation, and only when the light really is grey.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/scene.h"
#include "tools/render/scene_renderer.h"

namespace pelt::render::test {
namespace {

struct Frame {
  FrameImage image;
  int varyings = 0;
};

Frame render_fur(const std::string& ambient, bool grey_allowed) {
  std::string json = furry_box_scene(R"("fins": "all", "gravity": {}, "wind": {})", 3);
  const std::string tinted = R"("color": [0.3, 0.3, 0.35])";
  json.replace(json.find(tinted), tinted.size(), ambient);
  const io::Scene scene = io::parse_scene(json, "fur_varyings.json");
  RenderSettings rs;
  rs.threads = 2;
  rs.fur_grey_varyings = grey_allowed;
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

TEST(FurVaryings, ColouredLightKeepsThreeChannels) {
  const Frame tinted = render_fur(R"("color": [0.3, 0.3, 0.35])", true);
  EXPECT_EQ(tinted.varyings, 8);
  const Frame forced = render_fur(R"("color": [0.3, 0.3, 0.35])", false);
  EXPECT_EQ(0, std::memcmp(tinted.image.color.data(), forced.image.color.data(),
                           tinted.image.color.size() * sizeof(float)));
}

}  // namespace
}  // namespace pelt::render::test
