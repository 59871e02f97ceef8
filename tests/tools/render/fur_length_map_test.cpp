// fur.length_map: the fur's length per vertex from an image, bare where it is 0.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/render/length_map.h"

namespace pelt::render::test {
namespace fur_length_map_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

// A sphere (uvs: u round it, v from pole to pole), furry with gravity and wind, seen side on.
std::string sphere_scene(const std::string& fur) {
  return R"({"pelt": 1, "image": {"width": 96, "height": 72, "background": [0.05, 0.05, 0.08]},
  "camera": {"eye": [0, 1.2, 3.0], "target": [0, 0, 0], "fovy_deg": 45},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}, {"type": "ambient", "color": [0.3, 0.3, 0.35]}],
  "objects": [{"mesh": "sphere:24", "material": {"type": "lambert", "color": [0.6, 0.3, 0.2]})" +
         (fur.empty() ? "" : R"(, "fur": {"shells": 8, "texture_size": 64, "fins": "all", "gravity": {}, "wind": {})" +
                                  (fur == "{}" ? std::string() : ", " + fur) + "}") +
         "}]}";
}

// An 8 x 8 map, `left` on the columns u < 0.5 and `right` on the others.
void write_map(const SceneDir& dir, const std::string& name, uint8_t left, uint8_t right) {
  std::vector<uint8_t> px;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) px.push_back(x < 4 ? left : right);
  io::write_image_atomic(dir.path() / name, 8, 8, 1, io::PixelType::u8, px.data());
}

struct Frame {
  FrameImage image;
  FrameStats stats;
};

Frame render(const io::Scene& scene, int threads = 2) {
  RenderSettings rs;
  rs.threads = threads;
  SceneRenderer r(scene, rs);
  Frame f;
  r.render(0, f.image, f.stats);
  return f;
}

// A map of 0 everywhere grows no fur at all: not a fragment blended, the image of the bare sphere.
TEST(FurLengthMap, ABlackMapGrowsNoFur) {
  SceneDir dir;
  write_map(dir, "black.png", 0, 0);
  const Frame bare = render(dir.scene(sphere_scene(R"("length_map": "black.png")")));
  EXPECT_EQ(bare.stats.raster.fragments_blended, 0u);
  EXPECT_TRUE(same_pixels(bare.image, render(dir.scene(sphere_scene(""))).image));
}

// Half the map at 0: fur on the other half only, so two complementary maps share the full fur's
// fragments between them (the faces along the border, tapering, grow some in both: measured 1.04 of
// the full fur's); every pixel finite under gravity and wind (the bare chains have no length to
// bend); the same image on any thread count.
TEST(FurLengthMap, HalfABlackMapGrowsFurOnTheOtherHalfOnly) {
  SceneDir dir;
  write_map(dir, "half.png", 0, 255);
  write_map(dir, "other.png", 255, 0);
  const io::Scene half = dir.scene(sphere_scene(R"("length_map": "half.png")"));
  const Frame a = render(half);
  const Frame b = render(dir.scene(sphere_scene(R"("length_map": "other.png")")));
  const Frame full = render(dir.scene(sphere_scene("{}")));
  for (float c : a.image.color) ASSERT_TRUE(std::isfinite(c));
  const double fa = double(a.stats.raster.fragments_blended), fb = double(b.stats.raster.fragments_blended),
               ff = double(full.stats.raster.fragments_blended);
  EXPECT_GT(fa, 0.0);
  EXPECT_GT(fb, 0.0);
  EXPECT_NEAR((fa + fb) / ff, 1.0, 0.2) << fa << " + " << fb << " of " << ff;
  EXPECT_TRUE(same_pixels(a.image, render(half, 1).image));
  EXPECT_TRUE(same_pixels(a.image, render(half, 3).image));
}

// The map is read at the file's own precision: a float map's 0.001 is short fur, not bare skin (8
// bits would have made it 0), and a vertex at a texel centre reads that texel exactly.
TEST(FurLengthMap, ValuesKeepTheFilesPrecision) {
  SceneDir dir;
  const float texels[4] = {0.001f, 0.3333f, 0.5f, 0.999f};
  io::write_image_atomic(dir.path() / "fine.exr", 2, 2, 1, io::PixelType::f32, texels);
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  m.uvs = {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.25f, 0.75f}, {0.75f, 0.75f}};  // the texel centres
  m.indices = {0, 1, 2, 1, 3, 2};
  const std::vector<float> scale = read_length_map(dir.path() / "fine.exr", m, "quad", "s.json", "f", io::Budget{});
  ASSERT_EQ(scale.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(scale[i], texels[i]) << "vertex " << i;
  // Half-way between two texels, and wrapped round the edge (u = 0 lies between the last and first).
  m.uvs = {{0.5f, 0.25f}, {0.0f, 0.25f}, {0.25f, 0.5f}, {1.0f, 0.75f}};
  const std::vector<float> mid = read_length_map(dir.path() / "fine.exr", m, "quad", "s.json", "f", io::Budget{});
  EXPECT_FLOAT_EQ(mid[0], (0.001f + 0.3333f) / 2);
  EXPECT_FLOAT_EQ(mid[1], (0.001f + 0.3333f) / 2);
  EXPECT_FLOAT_EQ(mid[2], (0.001f + 0.5f) / 2);
  EXPECT_FLOAT_EQ(mid[3], (0.5f + 0.999f) / 2);
  // Uvs that cover no area read one line of the map everywhere: refused by field.
  m.uvs = {{0.1f, 0.5f}, {0.2f, 0.5f}, {0.3f, 0.5f}, {0.4f, 0.5f}};
  try {
    read_length_map(dir.path() / "fine.exr", m, "quad", "s.json", "objects[0].fur.length_map", io::Budget{});
    FAIL() << "read";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.field, "objects[0].fur.length_map");
    EXPECT_NE(e.reason.find("cover no area"), std::string::npos) << e.reason;
  }
}

// Only the first channel is read, so the others may hold anything: a NaN in g no longer refuses
// the map (it was named as a bad texel of a channel no one reads).
TEST(FurLengthMap, OnlyTheFirstChannelIsChecked) {
  SceneDir dir;
  const float nan = std::nanf("");
  const float texels[12] = {0.25f, nan, 0.0f, 0.5f, nan, 1.0f, 0.75f, 0.0f, nan, 1.0f, nan, nan};
  io::write_image_atomic(dir.path() / "rgb.exr", 2, 2, 3, io::PixelType::f32, texels);
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  m.uvs = {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.25f, 0.75f}, {0.75f, 0.75f}};
  m.indices = {0, 1, 2, 1, 3, 2};
  const std::vector<float> scale = read_length_map(dir.path() / "rgb.exr", m, "quad", "s.json", "f", io::Budget{});
  ASSERT_EQ(scale.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(scale[size_t(i)], texels[3 * i]) << "vertex " << i;
}

TEST(FurLengthMap, BadMapsAreRefusedNamingTheFieldOrTheFile) {
  SceneDir dir;
  // Not found: at parse time, by field.
  try {
    dir.scene(sphere_scene(R"("length_map": "missing.png")"));
    FAIL() << "parsed";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.field, "objects[0].fur.length_map");
    EXPECT_NE(e.reason.find("not found"), std::string::npos) << e.reason;
  }
  // A first channel outside [0, 1]: the image and its texel.
  const float texels[4] = {0.5f, 2.0f, 0.25f, 0.0f};
  io::write_image_atomic(dir.path() / "over.exr", 2, 2, 1, io::PixelType::f32, texels);
  try {
    render(dir.scene(sphere_scene(R"("length_map": "over.exr")")));
    FAIL() << "rendered";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.file, (dir.path() / "over.exr").string());
    EXPECT_NE(e.reason.find("texel (1, 0) of the first channel is 2"), std::string::npos) << e.reason;
    EXPECT_NE(e.reason.find("objects[0].fur.length_map"), std::string::npos) << e.reason;
  }
  // A mesh without texture coordinates: by field.
  write_map(dir, "half.png", 0, 255);
  {
    std::FILE* f = std::fopen((dir.path() / "tetra.obj").c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", f);
    std::fclose(f);
  }
  std::string json = sphere_scene(R"("length_map": "half.png")");
  json.replace(json.find("sphere:24"), 9, "tetra.obj");
  try {
    render(dir.scene(json));
    FAIL() << "rendered";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.field, "objects[0].fur.length_map");
    EXPECT_NE(e.reason.find("has none"), std::string::npos) << e.reason;
  }
}

}  // namespace fur_length_map_test
}  // namespace pelt::render::test
