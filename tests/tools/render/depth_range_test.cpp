// A near plane tiny beside the scene's distances: window depth (about 1 - near / distance)
// rounds to the far plane's 1 for every surface. The surfaces are still drawn (raster::kClearDepth),
// and the renderer says that depth cannot order them there; a usual near and far say nothing.
#include <gtest/gtest.h>

#include <string>

#include "tests/tools/render/render_test_scenes.h"

namespace pelt::render::test {
namespace {

std::string box_with_depth_range(const char* near, const char* far) {
  return std::string(R"({"pelt": 1, "image": {"width": 128, "height": 96, "background": [0, 0, 0]},
      "camera": {"eye": [3, 4, 50], "target": [0, 0, 0], "near": )") +
         near + R"(, "far": )" + far + R"(},
      "objects": [{"mesh": "box:2", "transform": {"scale": 10}, "material": {"type": "unlit", "color": [1, 1, 1]}}]})";
}

size_t lit_pixels(const std::string& json, std::vector<std::string>& warnings) {
  SceneDir dir;
  RenderSettings rs;
  rs.threads = 2;
  SceneRenderer r(dir.scene(json), rs);
  warnings = r.warnings();
  FrameImage img;
  FrameStats st;
  r.render(0, img, st);
  size_t lit = 0;
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p) lit += img.color[4 * p] > 0.5f;
  return lit;
}

TEST(DepthRange, ASurfaceBeyondTheDepthReachIsDrawnAndTheSceneWarned) {
  std::vector<std::string> usual_warnings, tiny_warnings;
  // The nearest plane a scene may have (raster::kMinW), its reach 2^24 x 1e-6 short of the box.
  const size_t usual = lit_pixels(box_with_depth_range("1", "1000"), usual_warnings);
  const size_t tiny = lit_pixels(box_with_depth_range("1e-6", "1000"), tiny_warnings);
  EXPECT_GT(usual, 3000u);
  EXPECT_EQ(tiny, usual);  // before kClearDepth: 0, the box gone
  EXPECT_TRUE(usual_warnings.empty());
  ASSERT_EQ(tiny_warnings.size(), 1u);
  EXPECT_NE(tiny_warnings[0].find("(camera.near): surfaces farther than about 16.8 scene units (2^24 x near) all take "
                                  "the far plane's depth"),
            std::string::npos)
      << tiny_warnings[0];
}

}  // namespace
}  // namespace pelt::render::test
