// A glTF material's alpha drawn (io::AlphaMode): MASK cuts the surface out where the base colour
// map's alpha times the factor's is below alphaCutoff, so what lies behind shows and the id AOV
// sees it; BLEND blends the surface over it. Until 2026-11-27 both were drawn opaque.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "tests/tools/render/render_test_scenes.h"
#include "tests/tools/render/two_quads_gltf.h"
#include "tools/io/image_io.h"
#include "tools/render/budget_check.h"

namespace pelt::render::test {
namespace alpha_materials_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

// front.png: 4 x 4 green texels whose alpha is `alpha` (x, y).
template <class Alpha>
void write_front(const SceneDir& dir, Alpha alpha) {
  std::vector<uint8_t> px;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) px.insert(px.end(), {0, 255, 0, alpha(x, y)});
  io::write_image_atomic(dir.path() / "front.png", 4, 4, 4, io::PixelType::u8, px.data());
}

const std::string kUnlitWhite = R"({"type": "unlit", "color": [1, 1, 1]})";

// Mesh file `mesh` of dir seen from +z, unlit, with nearest texels where the scene's quality holds.
io::Scene mesh_scene(const SceneDir& dir, const std::string& mesh, const std::string& material = kUnlitWhite,
                     const std::string& object_extra = "") {
  return front_view_scene(dir, mesh, material, object_extra, R"("filter": "nearest")");
}

io::Scene quads_scene(const SceneDir& dir, const std::string& front, const std::string& material = kUnlitWhite,
                      const std::string& object_extra = "") {
  dir.write("quads.gltf", two_quads_gltf(front));
  return mesh_scene(dir, "quads.gltf", material, object_extra);
}

const std::string kTextured = R"("pbrMetallicRoughness":{"baseColorTexture":{"index":0}})";

struct Counts {
  int green = 0, white = 0, other = 0;
};
Counts count(const FrameImage& img) {
  Counts c;
  for (size_t p = 0; p + 3 < img.color.size(); p += 4) {
    const float r = img.color[p], g = img.color[p + 1], b = img.color[p + 2];
    if (r < 0.01f && g > 0.99f && b < 0.01f) ++c.green;
    else if (r > 0.99f && g > 0.99f && b > 0.99f) ++c.white;
    else if (r + g + b > 0.0f) ++c.other;
  }
  return c;
}

// MASK over a checker of alpha 0 and 1: the front quad is green where the alpha is 1 and shows
// the back quad (white) where it is 0, about half each; opaque, the front quad hides it all.
TEST(AlphaMaterials, MaskCutsTheSurfaceOut) {
  SceneDir dir;
  write_front(dir, [](int x, int y) { return uint8_t((x + y) % 2 ? 255 : 0); });
  const Counts mask = count(render_at(quads_scene(dir, R"({"alphaMode":"MASK",)" + kTextured + "}"), {}));
  const Counts opaque = count(render_at(quads_scene(dir, "{" + kTextured + "}"), {}));
  EXPECT_GT(mask.green, 150);
  EXPECT_GT(mask.white, opaque.white + 150);  // the holes
  EXPECT_EQ(mask.other, 0);                   // no blend of the two: cut, not blended
  EXPECT_NEAR(double(mask.green), double(opaque.green) / 2.0, double(opaque.green) / 8.0);
}

// The cutoff and the factor's alpha decide: alpha 0.4 everywhere is cut at the default 0.5 but
// kept at 0.3, and kept at 0.3 with a factor of 0.5 (0.2) is cut again.
TEST(AlphaMaterials, TheCutoffAndTheFactorDecide) {
  SceneDir dir;
  write_front(dir, [](int, int) { return uint8_t(102); });  // 0.4
  const auto green = [&](const std::string& material) {
    return count(render_at(quads_scene(dir, material), {})).green;
  };
  EXPECT_EQ(green(R"({"alphaMode":"MASK",)" + kTextured + "}"), 0);
  EXPECT_GT(green(R"({"alphaMode":"MASK","alphaCutoff":0.3,)" + kTextured + "}"), 300);
  EXPECT_EQ(green(R"({"alphaMode":"MASK","alphaCutoff":0.3,"pbrMetallicRoughness":{"baseColorTexture":{"index":0},
                      "baseColorFactor":[1,1,1,0.5]}})"),
            0);
}

// A MASK part that every texel of its map fails (alpha 0.4 at the default cutoff 0.5) is not drawn:
// its triangles are not submitted, where they were set up and shaded for every pixel they cover
// only to be discarded; the frame is the back quad's alone, as when the cut keeps nothing of the
// front quad's pixels. A part the test keeps somewhere (cutoff 0.3) is still drawn.
TEST(AlphaMaterials, APartCutAwayWholeIsNotDrawn) {
  SceneDir dir;
  write_front(dir, [](int, int) { return uint8_t(102); });  // 0.4
  const auto drawn = [&](const std::string& material) {
    SceneRenderer r(quads_scene(dir, material), RenderSettings{});
    FrameImage img;
    FrameStats st;
    r.render(0, img, st);
    return std::pair{st.raster.triangles_submitted, count(img)};
  };
  const auto [gone_triangles, gone] = drawn(R"({"alphaMode":"MASK",)" + kTextured + "}");
  const auto [kept_triangles, kept] = drawn(R"({"alphaMode":"MASK","alphaCutoff":0.3,)" + kTextured + "}");
  EXPECT_EQ(gone_triangles, 2u);  // the back quad's
  EXPECT_EQ(kept_triangles, 4u);
  EXPECT_EQ(gone.green, 0);
  EXPECT_EQ(gone.white, kept.white + kept.green);  // the back quad shows wherever the front one was
  EXPECT_EQ(gone.other, 0);
}

// The id AOV sees through the holes: the back quad's triangles (ids 1, 2) where the front's are
// cut out, the front's (3, 4) elsewhere.
TEST(AlphaMaterials, TheIdAovSeesThroughTheHoles) {
  SceneDir dir;
  write_front(dir, [](int x, int y) { return uint8_t((x + y) % 2 ? 255 : 0); });
  RenderSettings rs;
  rs.aov = Aov::id;
  SceneRenderer r(quads_scene(dir, R"({"alphaMode":"MASK",)" + kTextured + "}"), rs);
  FrameImage img;
  FrameStats st;
  r.render(0, img, st);
  int back = 0, front = 0;
  for (int y = 16; y < 48; ++y)  // inside the front quad
    for (int x = 16; x < 48; ++x) {
      const uint32_t id = img.id[size_t(y) * 64 + size_t(x)];
      back += id == 1 || id == 2;
      front += id == 3 || id == 4;
    }
  EXPECT_GT(back, 200);
  EXPECT_GT(front, 200);
}

// BLEND: alpha 0.5 green over the white back quad gives (0.5, 1, 0.5); the back quad is drawn
// under it (the blended part writes no depth).
TEST(AlphaMaterials, BlendBlendsOverWhatLiesBehind) {
  SceneDir dir;
  write_front(dir, [](int, int) { return uint8_t(128); });
  const FrameImage img = render_at(quads_scene(dir, R"({"alphaMode":"BLEND",)" + kTextured + "}"), {});
  const float* mid = &img.color[(size_t(32) * 64 + 32) * 4];
  const float a = 128.0f / 255.0f;
  EXPECT_NEAR(mid[0], 1.0f - a, 1e-3f);
  EXPECT_NEAR(mid[1], 1.0f, 1e-3f);
  EXPECT_NEAR(mid[2], 1.0f - a, 1e-3f);
  EXPECT_EQ(count(img).green, 0);
}

// The OBJ twin of two_quads_gltf.h: a white back quad (material `back`) and a front one of
// material `glass`, whose MTL statements are `glass` (a green 1 x 1 map g.ppm is there to name).
io::Scene glass_quads(const SceneDir& dir, const std::string& glass) {
  dir.write("q.obj", "mtllib q.mtl\nv -2 -2 -0.5\nv 2 -2 -0.5\nv 2 2 -0.5\nv -2 2 -0.5\n"
                     "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "usemtl back\nf 1/1 2/2 3/3 4/4\nusemtl glass\nf 5/1 6/2 7/3 8/4\n");
  dir.write("q.mtl", "newmtl back\nnewmtl glass\n" + glass);
  dir.write("g.ppm", "P3\n1 1\n255\n0 255 0\n");
  return mesh_scene(dir, "q.obj");
}

// An OBJ material's `d` blends its faces as BLEND does: a green map at d 0.25 over the white back
// quad gives (0.75, 1, 0.75). Until 2026-11-27 it was drawn opaque, with a warning.
TEST(AlphaMaterials, ObjDissolveBlendsOverWhatLiesBehind) {
  SceneDir dir;
  const FrameImage img = render_at(glass_quads(dir, "d 0.25\nmap_Kd g.ppm\n"), {});
  const float* mid = &img.color[(size_t(32) * 64 + 32) * 4];
  EXPECT_NEAR(mid[0], 0.75f, 1e-3f);
  EXPECT_NEAR(mid[1], 1.0f, 1e-3f);
  EXPECT_NEAR(mid[2], 0.75f, 1e-3f);
  const float* corner = &img.color[(size_t(4) * 64 + 4) * 4];  // the back quad alone: white
  EXPECT_EQ(corner[0], 1.0f);
}

// An OBJ material's `map_d` blends its faces by the map as `d` does by its value: a green map with a
// dissolve of 64/255 over the white back quad, and the files it read are the scene's inputs (an
// output may not overwrite them). Until 2026-11-28 map_d was warned of and drawn opaque.
TEST(AlphaMaterials, ObjDissolveMapBlendsOverWhatLiesBehind) {
  SceneDir dir;
  dir.write("a.pgm", "P2\n1 1\n255\n64\n");
  const io::Scene s = glass_quads(dir, "map_Kd g.ppm\nmap_d a.pgm\n");
  const FrameImage img = render_at(s, {});
  const float* mid = &img.color[(size_t(32) * 64 + 32) * 4];
  const float a = 64.0f / 255.0f;
  EXPECT_NEAR(mid[0], 1.0f - a, 1e-3f);
  EXPECT_NEAR(mid[1], 1.0f, 1e-3f);
  EXPECT_NEAR(mid[2], 1.0f - a, 1e-3f);
  const std::vector<std::filesystem::path> inputs = SceneRenderer(s, RenderSettings{}).input_files();
  for (const char* f : {"g.ppm", "a.pgm"})
    EXPECT_NE(std::find(inputs.begin(), inputs.end(), dir.path() / f), inputs.end()) << f;
  // The memory estimate names the image by its files (it had said "embedded colour map").
  const MemoryEstimate e = estimate_memory(s, io::load_scene_meshes(s), 0, 0, 1, 1);
  EXPECT_TRUE(std::any_of(e.parts.begin(), e.parts.end(), [](const MemoryPart& p) {
    return p.what.rfind("colour map g.ppm with its map_d a.pgm, 1 x 1 texels", 0) == 0;
  }));
}

// On a translucent skin (Opacity below 1, every part blended) MASK still cuts: the front quad's
// pixels are the back quad's alone where its alpha is below the cutoff, and the cutoff moves
// the cut (a review found it blended by the map's alpha, the cutoff unread).
TEST(AlphaMaterials, MaskCutsATranslucentSkinToo) {
  SceneDir dir;
  write_front(dir, [](int x, int) { return uint8_t(x * 85); });  // alpha 0, 1/3, 2/3, 1 by column
  const std::string skin = R"({"type": "skin", "skin": {"Opacity": 0.5}})";
  const auto at = [&](float cutoff) {
    char material[160];
    std::snprintf(material, sizeof material, R"({"alphaMode":"MASK","alphaCutoff":%g,%s})", double(cutoff),
                  kTextured.c_str());
    return render_at(quads_scene(dir, material, skin), {});
  };
  const FrameImage low = at(0.2f), high = at(0.8f), all = at(1.0f);
  // Column 1 (alpha 1/3) of the front quad: kept at 0.2, cut at 0.8; column 0 cut in both.
  const size_t row = 32, col0 = 19, col1 = 27;
  const auto px = [&](const FrameImage& img, size_t x) { return &img.color[(row * 64 + x) * 4]; };
  EXPECT_GT(std::abs(px(low, col1)[1] - px(high, col1)[1]), 0.02f);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(px(low, col0)[c], px(high, col0)[c]) << c;
    EXPECT_EQ(px(high, col1)[c], px(all, col1)[c]) << c;  // cut: the back quad alone
  }
}

// Fur reads one colour map without its alpha: parts that read one image, one of them with its
// alpha (MASK) and one without, give the fur that image (a review found it refused).
TEST(AlphaMaterials, FurTakesTheColourOfAMapACutOutAlsoReads) {
  SceneDir dir;
  write_front(dir, [](int x, int y) { return uint8_t((x + y) % 2 ? 255 : 0); });
  const std::string back_textured = R"({"name":"back",)" + kTextured + "}";
  std::string gltf = two_quads_gltf(R"({"alphaMode":"MASK",)" + kTextured + "}");
  const std::string from = R"("materials":[{"name":"back"},)";
  gltf.replace(gltf.find(from), from.size(), R"("materials":[)" + back_textured + ",");
  dir.write("quads.gltf", gltf);
  const io::Scene s = dir.scene(R"({"pelt": 1, "image": {"width": 64, "height": 64},
      "camera": {"eye": [0, 0, 4], "target": [0, 0, 0], "fovy_deg": 40},
      "lights": [{"type": "ambient", "intensity": 1}],
      "objects": [{"mesh": ")" + (dir.path() / "quads.gltf").string() + R"(",
                   "material": {"type": "lambert"},
                   "fur": {"shells": 4, "texture_size": 16, "use_color_map": true}}]})");
  RenderSettings rs;
  const SceneRenderer r(s, rs);
  ASSERT_EQ(r.maps_drawn(0).size(), 2u);
  EXPECT_EQ(r.maps_drawn(0)[1].alpha_mode, io::AlphaMode::mask);
}

// The same image on any thread count, cut-outs and blends included.
TEST(AlphaMaterials, OneAndTwoThreadsAgree) {
  SceneDir dir;
  write_front(dir, [](int x, int y) { return uint8_t((x * 3 + y * 5) % 4 * 85); });
  for (const char* mode : {"MASK", "BLEND"}) {
    const io::Scene s = quads_scene(dir, std::string(R"({"alphaMode":")") + mode + "\"," + kTextured + "}");
    EXPECT_TRUE(same_pixels(render_at(s, {}, 1), render_at(s, {}, 2))) << mode;
  }
}

}  // namespace alpha_materials_test
}  // namespace pelt::render::test
