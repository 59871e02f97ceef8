// Tangent-space normal maps: a constant map tilts the shading normal by exactly the
// decoded texel in the vertex tangent frame, a flat map changes (almost) nothing, and a
// mesh without texture coordinates is refused with the field named.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <vector>

#include <glm/geometric.hpp>

#include "raster/mesh.h"
#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/builtin_meshes.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/render/budget_check.h"

namespace pelt::render::test {
namespace normal_map_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

// A 4 x 4 map of one texel value.
void write_map(const std::filesystem::path& path, uint8_t r, uint8_t g, uint8_t b) {
  std::vector<uint8_t> px(4 * 4 * 3);
  for (size_t i = 0; i < px.size(); i += 3) px[i] = r, px[i + 1] = g, px[i + 2] = b;
  io::write_image_atomic(path, 4, 4, 3, io::PixelType::u8, px.data());
}

// The plane seen from straight above, lit from `light` (unit, toward the light).
std::string plane_scene(const std::string& material_extra, glm::vec3 light) {
  char buf[768];
  std::snprintf(buf, sizeof buf, R"({"pelt": 1, "image": {"width": 24, "height": 18},
      "camera": {"eye": [0, 4, 0.001], "target": [0, 0, 0], "fovy_deg": 20},
      "lights": [{"type": "directional", "direction": [%.9g, %.9g, %.9g]}],
      "objects": [{"mesh": "plane:2", "transform": {"scale": 3},
                   "material": {"type": "lambert", "color": [1, 1, 1]%s}}]})",
                light.x, light.y, light.z, material_extra.c_str());
  return buf;
}

TEST(NormalMap, ConstantMapTiltsTheNormalInTheTangentFrame) {
  SceneDir dir;
  const uint8_t r = 210, g = 90, b = 200;
  write_map(dir.path() / "n.png", r, g, b);
  // The expected shading normal, from the plane's own tangent frame.
  const Mesh plane = io::make_builtin_mesh("plane:2");
  const glm::vec4 t = compute_vertex_tangents(plane)[0];
  const glm::vec3 N(0, 1, 0), T(t), B = t.w * glm::cross(N, T);
  const glm::vec3 m(2.0f * r / 255.0f - 1.0f, 2.0f * g / 255.0f - 1.0f, 2.0f * b / 255.0f - 1.0f);
  const glm::vec3 n = glm::normalize(m.x * T + m.y * B + m.z * N);
  const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.8f, -0.4f));
  const double want = std::max(0.0f, glm::dot(n, light));
  const double flat = light.y;  // without the map
  io::Quality q;
  ASSERT_FALSE(io::set_knob(q, "filter", "bilinear"));
  const FrameImage img =
      render_at(dir.scene(plane_scene(R"(, "normal_map": "n.png")", light)), q);
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
    ASSERT_NEAR(img.color[4 * p], want, 2e-5) << "pixel " << p;
  EXPECT_GT(std::abs(want - flat), 0.05);  // the map really tilts it
}

TEST(NormalMap, FlatMapMatchesNoMap) {
  SceneDir dir;
  write_map(dir.path() / "flat.png", 128, 128, 255);  // (0.004, 0.004, 1): 8-bit's nearest to +z
  const glm::vec3 light = glm::normalize(glm::vec3(0.5f, 0.7f, 0.2f));
  const FrameImage with = render_at(dir.scene(plane_scene(R"(, "normal_map": "flat.png")", light)), {});
  const FrameImage without = render_at(dir.scene(plane_scene("", light)), {});
  EXPECT_LT(image_rmse(with.color, without.color), 0.01);
  EXPECT_GT(image_rmse(with.color, without.color), 0.0);  // the map was applied
}

TEST(NormalMap, CountedInTheMemoryEstimate) {
  SceneDir dir;
  write_map(dir.path() / "n.png", 128, 128, 255);
  const io::Scene s = dir.scene(plane_scene(R"(, "normal_map": "n.png")", glm::vec3(0, 1, 0)));
  const MemoryEstimate e = estimate_memory(s, io::load_scene_meshes(s), 0, 0, 1, 1);
  size_t found = 0;
  for (const MemoryPart& p : e.parts)
    if (p.field == "objects[0].material.normal_map") {
      ++found;
      EXPECT_GE(p.bytes, 4u * 4u * 4u * sizeof(float));  // at least the 4 x 4 map as float RGBA
    }
  EXPECT_EQ(found, 1u);
  RenderSettings rs;
  SceneRenderer r(s, rs);
  EXPECT_GE(e.renderer_total(), r.memory_estimate());
}

// A square of two triangles in the y = 0 plane, facing up, with uvs, its material from m.mtl.
void write_square_obj(const std::filesystem::path& dir, const std::string& mtl) {
  std::ofstream(dir / "m.mtl") << mtl;
  std::ofstream(dir / "sq.obj") << "mtllib m.mtl\nv -1.5 0 1.5\nv 1.5 0 1.5\nv 1.5 0 -1.5\nv -1.5 0 -1.5\n"
                                   "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 1 0\nusemtl a\n"
                                   "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
}

std::string square_scene(const std::string& material_extra, glm::vec3 light) {
  std::string s = plane_scene(material_extra, light);
  const std::string from = R"("mesh": "plane:2", "transform": {"scale": 3})", to = R"("mesh": "sq.obj")";
  s.replace(s.find(from), from.size(), to);
  return s;
}

// A normal map the mesh file names (MTL `norm`; glTF normalTexture goes the same way) is
// drawn as the scene's `normal_map` would draw the same image; the scene's wins over it.
TEST(NormalMap, TheMeshFilesMapIsDrawnWhenTheSceneNamesNone) {
  SceneDir dir;
  write_map(dir.path() / "n.png", 210, 90, 200);
  write_map(dir.path() / "other.png", 128, 128, 255);  // flat: close to no map
  write_square_obj(dir.path(), "newmtl a\nnorm n.png\n");
  const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.8f, -0.4f));
  const FrameImage from_mesh = render_at(dir.scene(square_scene("", light)), {});
  const FrameImage from_scene = render_at(dir.scene(square_scene(R"(, "normal_map": "n.png")", light)), {});
  const FrameImage other = render_at(dir.scene(square_scene(R"(, "normal_map": "other.png")", light)), {});
  write_square_obj(dir.path(), "newmtl a\n");
  const FrameImage none = render_at(dir.scene(square_scene("", light)), {});
  EXPECT_EQ(from_mesh.color, from_scene.color);
  EXPECT_GT(image_rmse(from_mesh.color, none.color), 0.05);  // the map was drawn
  EXPECT_GT(image_rmse(other.color, from_mesh.color), 0.05);  // the scene's map replaced it
}

// `bump` is as often a height map: not drawn, and said so.
TEST(NormalMap, AnMtlBumpMapIsNotDrawnButNamed) {
  SceneDir dir;
  write_map(dir.path() / "h.png", 210, 90, 200);
  write_square_obj(dir.path(), "newmtl a\nbump h.png\n");
  const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.8f, -0.4f));
  const io::Scene s = dir.scene(square_scene("", light));
  SceneRenderer r(s, RenderSettings{});
  ASSERT_EQ(r.warnings().size(), 1u);
  EXPECT_NE(r.warnings()[0].find("material `a` names a bump map `h.png` that is not drawn"), std::string::npos)
      << r.warnings()[0];
  const FrameImage with_bump = render_at(s, {});
  write_square_obj(dir.path(), "newmtl a\n");
  EXPECT_EQ(with_bump.color, render_at(dir.scene(square_scene("", light)), {}).color);
}

// The mesh's map is counted like the scene's, under the mesh's field.
TEST(NormalMap, TheMeshFilesMapIsCountedInTheMemoryEstimate) {
  SceneDir dir;
  write_map(dir.path() / "n.png", 128, 128, 255);
  write_square_obj(dir.path(), "newmtl a\nnorm n.png\n");
  const io::Scene s = dir.scene(square_scene("", glm::vec3(0, 1, 0)));
  const MemoryEstimate e = estimate_memory(s, io::load_scene_meshes(s), 0, 0, 1, 1);
  size_t found = 0;
  for (const MemoryPart& p : e.parts)
    if (p.field == "objects[0].mesh" && p.what.find("normal map n.png") != std::string::npos) {
      ++found;
      EXPECT_GE(p.bytes, 4u * 4u * 4u * sizeof(float));
    }
  EXPECT_EQ(found, 1u);
}

TEST(NormalMap, MeshWithoutUvsIsRefused) {
  SceneDir dir;
  write_map(dir.path() / "n.png", 128, 128, 255);
  std::ofstream(dir.path() / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const io::Scene s = dir.scene(R"({"pelt": 1, "image": {"width": 8, "height": 8},
      "objects": [{"mesh": "tri.obj", "material": {"type": "lambert", "normal_map": "n.png"}}]})");
  try {
    SceneRenderer r(s, RenderSettings{});
    FAIL() << "accepted a normal map on a mesh without uvs";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.field, "objects[0].material.normal_map") << e.what();
    EXPECT_NE(e.reason.find("needs texture coordinates"), std::string::npos) << e.what();
  }
}

}  // namespace normal_map_test
}  // namespace pelt::render::test
