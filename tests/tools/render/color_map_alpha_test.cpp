// A colour map's alpha is drawn by no material: its colours are read and filtered as stored,
// whatever the alpha beside them (the texture builder's alpha-weighted mips and its fill of
// transparent texels are for blended textures; on a colour map they changed the colours).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <filesystem>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/tools/io/base64.h"
#include "tests/tools/io/linear_png.h"
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

// A colour map's PNG that says it holds linear values is drawn so (about 0.5 for its 128s,
// not sRGB's 0.216), when the scene or an MTL names it; a glTF's, as sRGB, since the glTF
// specification tells loaders to ignore a PNG's gamma.
TEST(ColorMapAlpha, APngDeclaredLinearIsHonouredButWhereAGltfNamesIt) {
  SceneDir dir;
  io::write_linear_png(dir.path() / "linear.png");
  const size_t centre = (size_t{12} * 32 + 16) * 4;
  const FrameImage scene_named = draw(unlit_plane(dir, "linear.png"), "bilinear");
  EXPECT_NEAR(scene_named.color[centre], 0.502f, 0.002f);
  // The same map named by a glTF quad that fills the view.
  const float pos[12] = {-2, 0, 2, 2, 0, 2, 2, 0, -2, -2, 0, -2};
  const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
  const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  std::string bytes(reinterpret_cast<const char*>(pos), sizeof pos);
  bytes.append(reinterpret_cast<const char*>(uv), sizeof uv);
  bytes.append(reinterpret_cast<const char*>(idx), sizeof idx);
  dir.write("quad.gltf", R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,"material":0}]}],
    "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],"textures":[{"source":0}],
    "images":[{"uri":"linear.png"}],
    "buffers":[{"byteLength":92,"uri":"data:application/octet-stream;base64,)" + io::base64(bytes) + R"("}],
    "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":32},
                   {"buffer":0,"byteOffset":80,"byteLength":12}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-2,0,-2],"max":[2,0,2]},
                 {"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"},
                 {"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}]})");
  const io::Scene gltf = dir.scene(R"({"pelt": 1, "image": {"width": 32, "height": 24, "background": [0, 0, 1]},
      "camera": {"eye": [0, 3, 0.001], "target": [0, 0, 0], "fovy_deg": 40},
      "lights": [{"type": "ambient", "intensity": 1}],
      "objects": [{"mesh": ")" + (dir.path() / "quad.gltf").string() + R"(",
                   "material": {"type": "unlit", "color": [1, 1, 1], "double_sided": true}}]})");
  const FrameImage gltf_named = draw(gltf, "bilinear");
  EXPECT_NEAR(gltf_named.color[centre], 0.216f, 0.002f);
}

}  // namespace
}  // namespace pelt::render::test
