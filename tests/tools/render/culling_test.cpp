// Single-sided materials (the default, "double_sided": false) cull back faces; double-sided
// ones draw both sides. The plane's front faces +y, so a camera below it sees its back.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "tests/tools/render/render_test_scenes.h"

namespace pelt::render::test {
namespace {

std::string plane_seen_from(float eye_y, bool double_sided) {
  char buf[640];
  std::snprintf(buf, sizeof buf, R"({"pelt": 1, "image": {"width": 16, "height": 12, "background": [0, 0, 0]},
      "camera": {"eye": [0, %g, 0.001], "target": [0, 0, 0], "fovy_deg": 20},
      "lights": [{"type": "ambient"}],
      "objects": [{"mesh": "plane:2", "transform": {"scale": 3},
                   "material": {"type": "unlit", "color": [1, 0.5, 0.25], "double_sided": %s}}]})",
                eye_y, double_sided ? "true" : "false");
  return buf;
}

struct Drawn {
  size_t lit_pixels = 0;
  uint64_t triangles = 0, triangles_culled = 0;
};

Drawn render_plane(float eye_y, bool double_sided) {
  SceneDir dir;
  RenderSettings rs;
  rs.threads = 2;
  SceneRenderer r(dir.scene(plane_seen_from(eye_y, double_sided)), rs);
  FrameImage img;
  FrameStats st;
  r.render(0, img, st);
  Drawn d;
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p) d.lit_pixels += img.color[4 * p] > 0.5f;
  d.triangles = st.triangles();
  d.triangles_culled = st.raster.triangles_culled;
  return d;
}

TEST(Culling, SingleSidedDrawsOnlyTheFront) {
  const size_t pixels = 16 * 12;
  const Drawn front = render_plane(4.0f, false);
  EXPECT_EQ(front.lit_pixels, pixels);  // the plane fills the view
  EXPECT_EQ(front.triangles_culled, 0u);
  const Drawn back = render_plane(-4.0f, false);
  EXPECT_EQ(back.lit_pixels, 0u);
  EXPECT_GT(back.triangles, 0u);
  EXPECT_EQ(back.triangles_culled, back.triangles);  // every triangle, as back-facing
}

TEST(Culling, DoubleSidedDrawsBothSides) {
  const size_t pixels = 16 * 12;
  EXPECT_EQ(render_plane(4.0f, true).lit_pixels, pixels);
  const Drawn back = render_plane(-4.0f, true);
  EXPECT_EQ(back.lit_pixels, pixels);
  EXPECT_EQ(back.triangles_culled, 0u);
}

}  // namespace
}  // namespace pelt::render::test
