// Maps drawn where their mesh file places them (io::MapPlacement): MTL's -s, -o and -clamp on an
// OBJ (whose v the renderer flips), a normal map's tangent frame taken from its own placed uvs,
// and sample_placed against the sampler at the transformed coordinates.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "raster/config.h"
#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/image_io.h"
#include "tools/render/texture_sampling.h"

namespace pelt::render::test {
namespace {

// A quad in the y = 0 plane seen from straight above, its uvs scaled by `uv_scale` (u by
// uv_scale[0], v by uv_scale[1]), its material `mtl` (one `newmtl m`).
io::Scene quad_scene(const SceneDir& dir, const std::string& stem, const std::string& mtl, const float uv_scale[2],
                     const std::string& material_type = "unlit") {
  dir.write(stem + ".mtl", "newmtl m\n" + mtl + "\n");
  std::string obj = "mtllib " + stem + ".mtl\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nv -1 0 -1\n";
  const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const auto& t : uv) obj += "vt " + std::to_string(t[0] * uv_scale[0]) + " " + std::to_string(t[1] * uv_scale[1]) + "\n";
  obj += "vn 0 1 0\nusemtl m\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
  dir.write(stem + ".obj", obj);
  const std::string lights = material_type == "unlit"
                                 ? R"([{"type": "ambient", "intensity": 1}])"
                                 : R"([{"type": "directional", "direction": [0.6, 0.8, 0.2], "intensity": 1}])";
  return dir.scene(R"({"pelt": 1, "image": {"width": 48, "height": 48, "background": [0, 0, 0]},
      "camera": {"eye": [0, 3, 0.001], "target": [0, 0, 0], "fovy_deg": 40},
      "lights": )" + lights + R"(,
      "objects": [{"mesh": ")" + (dir.path() / (stem + ".obj")).string() + R"(",
                   "material": {"type": ")" + material_type + R"(", "color": [1, 1, 1]}}]})");
}

void write_random_map(const SceneDir& dir, const std::string& name, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> px(16 * 16 * 3);
  for (uint8_t& b : px) b = uint8_t(rng());
  io::write_image_atomic(dir.path() / name, 16, 16, 3, io::PixelType::u8, px.data());
}

float max_difference(const FrameImage& a, const FrameImage& b) {
  float d = 0.0f;
  for (size_t i = 0; i < a.color.size() && i < b.color.size(); ++i) d = std::max(d, std::abs(a.color[i] - b.color[i]));
  return d;
}

// `map_Kd -s 2 3 -o 0.25 0.3` draws what uvs scaled and offset that way draw (OBJ's v counts
// from the bottom: the placement is flipped with the uvs). The same uvs without the options
// draw a different picture, so the comparison can fail.
TEST(MapPlacement, MtlScaleAndOffsetDrawWhatScaledUvsDraw) {
  SceneDir dir;
  write_random_map(dir, "tex.png", 3);
  const float one[2] = {1, 1}, scaled[2] = {2, 3};
  const FrameImage placed = render_at(quad_scene(dir, "placed", "map_Kd -s 2 3 -o 0.25 0.3 tex.png", one), {});
  // The offset, added to every vertex's uv instead: scaled uvs then shifted.
  dir.write("shifted.mtl", "newmtl m\nmap_Kd tex.png\n");
  std::string obj = "mtllib shifted.mtl\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nv -1 0 -1\n";
  const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const auto& t : uv)
    obj += "vt " + std::to_string(t[0] * scaled[0] + 0.25f) + " " + std::to_string(t[1] * scaled[1] + 0.3f) + "\n";
  obj += "vn 0 1 0\nusemtl m\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
  dir.write("shifted.obj", obj);
  const io::Scene shifted_scene = dir.scene(R"({"pelt": 1, "image": {"width": 48, "height": 48, "background": [0, 0, 0]},
      "camera": {"eye": [0, 3, 0.001], "target": [0, 0, 0], "fovy_deg": 40},
      "lights": [{"type": "ambient", "intensity": 1}],
      "objects": [{"mesh": ")" + (dir.path() / "shifted.obj").string() + R"(",
                   "material": {"type": "unlit", "color": [1, 1, 1]}}]})");
  const FrameImage shifted = render_at(shifted_scene, {});
  const FrameImage plain = render_at(quad_scene(dir, "plain", "map_Kd tex.png", one), {});
  EXPECT_LT(max_difference(placed, shifted), 2e-3f);
  EXPECT_GT(max_difference(placed, plain), 0.2f);
}

// The loader reads `.OBJ` as OBJ, and so must the renderer's flip of v (it compared the
// extension with `.obj` alone: an upper-case OBJ drew its maps upside down).
TEST(MapPlacement, AnUpperCaseObjIsFlippedLikeAnyObj) {
  SceneDir dir;
  write_random_map(dir, "tex.png", 5);
  const float one[2] = {1, 1};
  const io::Scene lower = quad_scene(dir, "q", "map_Kd tex.png", one);
  std::filesystem::copy_file(dir.path() / "q.obj", dir.path() / "Q.OBJ");
  io::Scene upper = lower;
  upper.objects[0].mesh_path = dir.path() / "Q.OBJ";
  upper.objects[0].mesh = upper.objects[0].mesh_path.string();
  EXPECT_TRUE(same_pixels(render_at(lower, {}), render_at(upper, {})));
}

// `-clamp on`: past the uvs' [0, 1] the edge texels stretch; repeated, the map would come back.
// A map of three columns, red, blue and green, drawn on uvs from -1 to 2 with the nearest texel:
// the quad's outer thirds are red and green, and only the middle third shows blue.
TEST(MapPlacement, MtlClampStretchesTheEdgeTexels) {
  SceneDir dir;
  const uint8_t px[9] = {255, 0, 0, 0, 0, 255, 0, 255, 0};
  io::write_image_atomic(dir.path() / "cols.png", 3, 1, 3, io::PixelType::u8, px);
  const float three[2] = {3, 1};
  // uvs 0..3 offset by -1: u from -1 to 2.
  io::Quality q;
  io::set_knob(q, "filter", "nearest");
  const FrameImage clamped = render_at(quad_scene(dir, "c", "map_Kd -o -1 0 -clamp on cols.png", three), q);
  const FrameImage repeated = render_at(quad_scene(dir, "r", "map_Kd -o -1 0 cols.png", three), q);
  int blue_clamped = 0, blue_repeated = 0;
  for (size_t p = 0; p + 3 < clamped.color.size(); p += 4) {
    blue_clamped += clamped.color[p + 2] > 0.5f;
    blue_repeated += repeated.color[p + 2] > 0.5f;
  }
  EXPECT_GT(blue_clamped, 50);
  EXPECT_GT(blue_repeated, 2 * blue_clamped);  // a blue stripe in each of the three repeats
  // The left edge of the quad (u near -1) is red when clamped.
  const int row = 24;
  int first = 0;
  while (first < 48 && clamped.color[(size_t(row) * 48 + size_t(first)) * 4] + clamped.color[(size_t(row) * 48 + size_t(first)) * 4 + 1] +
                           clamped.color[(size_t(row) * 48 + size_t(first)) * 4 + 2] < 0.5f)
    ++first;
  ASSERT_LT(first, 48);
  const float* left = &clamped.color[(size_t(row) * 48 + size_t(first) + 1) * 4];
  EXPECT_GT(left[0], 0.5f);
  EXPECT_LT(left[2], 0.5f);
}

// A normal map placed mirrored (`norm -s -1 1`) turns its tangent frame with it: it lights the
// quad as the same map on uvs mirrored in the file does, bit for bit. With the frame of the
// unplaced uvs its x component would tilt the normals the other way.
TEST(MapPlacement, ANormalMapsTangentFrameFollowsItsPlacement) {
  SceneDir dir;
  std::vector<uint8_t> px;
  for (int i = 0; i < 16; ++i) px.insert(px.end(), {230, 150, 200});  // tilted toward +u and +v
  io::write_image_atomic(dir.path() / "n.png", 4, 4, 3, io::PixelType::u8, px.data());
  const float one[2] = {1, 1}, mirrored[2] = {-1, 1};
  const FrameImage placed = render_at(quad_scene(dir, "p", "norm -s -1 1 n.png", one, "lambert"), {});
  const FrameImage in_file = render_at(quad_scene(dir, "f", "norm n.png", mirrored, "lambert"), {});
  const FrameImage unplaced = render_at(quad_scene(dir, "u", "norm n.png", one, "lambert"), {});
  EXPECT_TRUE(same_pixels(placed, in_file)) << max_difference(placed, in_file);
  EXPECT_GT(max_difference(placed, unplaced), 0.05f);
}

// sample_placed samples the sampler at the placement's transform of every lane, wrapped as it
// says, across chunks of the batch size and with a block mask, at both precisions.
TEST(MapPlacement, SamplePlacedSamplesTheTransformedCoordinates) {
  std::mt19937 rng(11);
  std::vector<uint8_t> texels(32 * 16 * 4);
  for (uint8_t& b : texels) b = uint8_t(rng());
  raster::Texture tex;
  ASSERT_FALSE(raster::Texture::from_rgba8(32, 16, texels.data(), raster::TexelEncoding::Srgb, tex).has_value());
  const size_t lanes = raster::kMaxBatchLanes + 48;
  std::vector<float> u(lanes), v(lanes), tu(lanes), tv(lanes);
  std::uniform_real_distribution<float> coord(-2.0f, 3.0f);
  for (size_t i = 0; i < lanes; ++i) {
    u[i] = coord(rng);
    v[i] = coord(rng);
  }
  std::vector<uint16_t> mask(lanes / 16);
  for (uint16_t& m : mask) m = uint16_t(rng() | 1u);
  io::MapPlacement p;
  p.wrap_u = raster::Wrap::Mirror;
  p.wrap_v = raster::Wrap::Clamp;
  p.m = {0.5f, -1.25f, 0.125f, 2.0f, 0.75f, -0.5f};
  for (size_t i = 0; i < lanes; ++i) {
    tu[i] = p.m[0] * u[i] + p.m[1] * v[i] + p.m[2];
    tv[i] = p.m[3] * u[i] + p.m[4] * v[i] + p.m[5];
  }
  for (const bool dbl : {false, true})
    for (const uint16_t* m : {static_cast<const uint16_t*>(nullptr), static_cast<const uint16_t*>(mask.data())}) {
      std::vector<float> a(4 * lanes), b(4 * lanes);
      float* const pa[4] = {&a[0], &a[lanes], &a[2 * lanes], &a[3 * lanes]};
      float* const pb[4] = {&b[0], &b[lanes], &b[2 * lanes], &b[3 * lanes]};
      sample_placed(tex, p, raster::Filter::Trilinear, u.data(), v.data(), lanes, pa, dbl, m);
      const raster::SamplerState s{raster::Filter::Trilinear, p.wrap_u, p.wrap_v, 0.0f};
      sample_texture(tex, s, tu.data(), tv.data(), lanes, pb, dbl, m);
      EXPECT_TRUE(a == b) << "double " << dbl << " mask " << (m != nullptr);
    }
}

}  // namespace
}  // namespace pelt::render::test
