// A colour map's alpha is drawn by no material: its colours are read and filtered as stored,
// whatever the alpha beside them (the texture builder's alpha-weighted mips and its fill of
// transparent texels are for blended textures; on a colour map they changed the colours).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/image_io.h"

namespace pelt::render::test {
namespace {

// An unlit plane seen from straight above, its colour the map `file` (trilinear unless `filter`).
io::Scene unlit_plane(const SceneDir& dir, const std::string& file) {
  return dir.scene(R"({"pelt": 1, "image": {"width": 32, "height": 24, "background": [0, 0, 1]},
      "camera": {"eye": [0, 3, 0.001], "target": [0, 0, 0], "fovy_deg": 40},
      "lights": [{"type": "ambient", "intensity": 1}],
      "objects": [{"mesh": "plane:1", "material": {"type": "unlit", "color": [1, 1, 1], "color_map": ")" +
                   (dir.path() / file).string() + R"("}}]})");
}

FrameImage draw(const io::Scene& scene, const char* filter) {
  io::Quality q;
  io::set_knob(q, "filter", filter);
  return render_at(scene, q);
}

// Half the map red and opaque, half green and fully transparent, drawn with the nearest texel:
// the green half shows (its texels took the red neighbours' colour).
TEST(ColorMapAlpha, TransparentTexelsKeepTheirColour) {
  SceneDir dir;
  std::vector<uint8_t> px;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const bool red = x < 4;
      px.insert(px.end(), {uint8_t(red ? 255 : 0), uint8_t(red ? 0 : 255), 0, uint8_t(red ? 255 : 0)});
    }
  io::write_image_atomic(dir.path() / "half.png", 8, 8, 4, io::PixelType::u8, px.data());
  const FrameImage img = draw(unlit_plane(dir, "half.png"), "nearest");
  int red = 0, green = 0, other = 0;
  for (size_t p = 0; p + 3 < img.color.size(); p += 4) {
    const float r = img.color[p], g = img.color[p + 1], b = img.color[p + 2];
    if (b > 0.5f) continue;  // the background
    if (r > 0.99f && g < 0.01f) ++red;
    else if (g > 0.99f && r < 0.01f) ++green;
    else ++other;
    EXPECT_EQ(img.color[p + 3], 1.0f);  // drawn opaque, as before
  }
  EXPECT_GT(red, 100);
  EXPECT_GT(green, 100);
  EXPECT_EQ(other, 0);
}

// Columns of red (alpha 1) and green (alpha 8/255) minified: the average is yellow, as the same
// map's opaque version gives (the alpha-weighted mips made it red).
TEST(ColorMapAlpha, MinifiedColoursAverageWhateverTheAlpha) {
  SceneDir dir;
  std::vector<uint8_t> faint, opaque;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool red = x % 2 == 0;
      faint.insert(faint.end(), {uint8_t(red ? 255 : 0), uint8_t(red ? 0 : 255), 0, uint8_t(red ? 255 : 8)});
      opaque.insert(opaque.end(), {uint8_t(red ? 255 : 0), uint8_t(red ? 0 : 255), 0, 255});
    }
  io::write_image_atomic(dir.path() / "faint.png", 64, 64, 4, io::PixelType::u8, faint.data());
  io::write_image_atomic(dir.path() / "opaque.png", 64, 64, 4, io::PixelType::u8, opaque.data());
  const FrameImage a = draw(unlit_plane(dir, "faint.png"), "trilinear");
  const FrameImage b = draw(unlit_plane(dir, "opaque.png"), "trilinear");
  ASSERT_EQ(a.color.size(), b.color.size());
  EXPECT_TRUE(a.color == b.color);
  const size_t centre = (size_t{12} * 32 + 16) * 4;
  EXPECT_NEAR(a.color[centre], a.color[centre + 1], 0.02f);  // yellow: as much red as green
}

}  // namespace
}  // namespace pelt::render::test
