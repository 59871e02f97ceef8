// Meshes some of whose faces have texture coordinates and others none (io::LoadedMesh::uv_missing):
// the faces with uvs draw their maps, the others draw none, and fur lays its strands by the box
// mapping. Until 2026-11-27 one face without uvs dropped every uv of the mesh, and a map on any
// face of it was refused.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "tests/tools/render/render_test_scenes.h"
#include "tests/tools/render/two_quads_gltf.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"

namespace pelt::render::test {
namespace partial_uvs_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

// Two quads facing +z: at the back (z = -0.5, larger, so it frames the other) one of material
// `back`, in front one of material `front`. `back_uvs` / `front_uvs`: whether each quad's faces
// give texture coordinates.
std::string two_quads_obj(bool back_uvs, bool front_uvs, bool with_mtl = true) {
  std::string s = with_mtl ? "mtllib m.mtl\n" : "";
  s += "v -2 -2 -0.5\nv 2 -2 -0.5\nv 2 2 -0.5\nv -2 2 -0.5\n";
  s += "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n";
  s += "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
  const auto quad = [](int first, bool uvs) {
    // Appended piece by piece: GCC 12's -Wstringop-overflow misreads `"/" + std::to_string(..)` here.
    std::string f = "f";
    for (int k = 0; k < 4; ++k) {
      f.append(" ").append(std::to_string(first + k));
      if (uvs) f.append("/").append(std::to_string(k + 1));
    }
    return f.append("\n");
  };
  s.append(with_mtl ? "usemtl back\n" : "").append(quad(1, back_uvs));
  s.append(with_mtl ? "usemtl front\n" : "").append(quad(5, front_uvs));
  return s;
}

// front.ppm: 2 x 1 texels, red then blue, so a pixel's colour says which half of the uvs it reads.
void write_files(const SceneDir& dir, const std::string& obj) {
  dir.write("quads.obj", obj);
  dir.write("m.mtl", "newmtl back\nnewmtl front\nmap_Kd front.ppm\n");
  dir.write("front.ppm", "P3\n2 1\n255\n255 0 0 0 0 255\n");
}

io::Scene quads_scene(const SceneDir& dir, const std::string& mesh, const std::string& object_extra = "",
                      const std::string& material = R"({"type": "unlit", "color": [1, 1, 1]})") {
  return front_view_scene(dir, mesh, material, object_extra);
}

struct Counts {
  int red = 0, blue = 0, white = 0;
};
Counts count(const FrameImage& img) {
  Counts c;
  for (size_t p = 0; p + 3 < img.color.size(); p += 4) {
    const float r = img.color[p], g = img.color[p + 1], b = img.color[p + 2];
    c.red += r > 0.99f && g < 0.01f && b < 0.01f;
    c.blue += r < 0.01f && g < 0.01f && b > 0.99f;
    c.white += r > 0.99f && g > 0.99f && b > 0.99f;
  }
  return c;
}

// Nearest texels: a pixel is red or blue, never between.
io::Quality nearest() {
  io::Quality q;
  q.filter = raster::Filter::Nearest;
  return q;
}

std::string error_of(const io::Scene& scene) {
  try {
    SceneRenderer r(scene, RenderSettings{});
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// Mesh `partial` (the back quad without uvs) draws the front quad's map, red and blue, beside the
// back quad's white, the same pixels as mesh `all` (both quads with uvs).
void expect_map_beside_plain(const SceneDir& dir, const std::string& partial, const std::string& all) {
  const FrameImage img = render_at(quads_scene(dir, partial), nearest());
  const Counts c = count(img);
  EXPECT_GT(c.red, 300);
  EXPECT_GT(c.blue, 300);
  EXPECT_GT(c.white, 1000);
  EXPECT_TRUE(same_pixels(img, render_at(quads_scene(dir, all), nearest())));
}

// The front quad's map is drawn at its own uvs (red and blue halves) beside the back quad, which
// has none and draws no map (white): the same pixels as when the back quad has uvs it does not use.
TEST(PartialUvs, ObjFacesWithUvsDrawTheirMapBesideFacesWithout) {
  SceneDir dir;
  write_files(dir, two_quads_obj(false, true));
  dir.write("all.obj", two_quads_obj(true, true));
  expect_map_beside_plain(dir, "quads.obj", "all.obj");
}

// glTF: a primitive without TEXCOORD_0 beside one whose material's baseColorTexture reads its uvs.
const std::string kFront = R"({"name":"front","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})";

TEST(PartialUvs, GltfPrimitiveWithoutTexcoordBesideAMappedOne) {
  SceneDir dir;
  const uint8_t px[8] = {255, 0, 0, 255, 0, 0, 255, 255};
  io::write_image_atomic(dir.path() / "front.png", 2, 1, 4, io::PixelType::u8, px);
  dir.write("partial.gltf", two_quads_gltf(kFront, false));
  dir.write("all.gltf", two_quads_gltf(kFront));
  expect_map_beside_plain(dir, "partial.gltf", "all.gltf");
}

// A map on the faces without uvs would read one texel there: refused, naming who asks for it.
TEST(PartialUvs, AMapOnFacesWithoutUvsIsRefused) {
  SceneDir dir;
  write_files(dir, two_quads_obj(true, false));  // the mapped quad has none
  EXPECT_NE(error_of(quads_scene(dir, "quads.obj"))
                .find("objects[0].mesh: a color_map needs texture coordinates, and 2 triangles of mesh `" +
                      (dir.path() / "quads.obj").string() +
                      "` that it is drawn on have none (faces of material `front`, which names the map)"),
            std::string::npos);
  // The scene's map covers every face, those without uvs too: named by their material, not by
  // the first material of the part the scene's map joins them in.
  write_files(dir, two_quads_obj(true, false));
  const std::string scene_map = R"({"type": "unlit", "color_map": ")" + (dir.path() / "front.ppm").string() + "\"}";
  EXPECT_NE(error_of(quads_scene(dir, "quads.obj", "", scene_map))
                .find("objects[0].material.color_map: a color_map needs texture coordinates, and 2 triangles of mesh `" +
                      (dir.path() / "quads.obj").string() + "` that it is drawn on have none (faces of material `front`)"),
            std::string::npos);
}

// The fur grows by the box mapping, as on the same mesh without any uvs; what would read the
// uvs is refused, naming its field.
TEST(PartialUvs, FurLaysItsStrandsByTheBoxMapping) {
  SceneDir dir;
  dir.write("partial.obj", two_quads_obj(false, true, false));
  dir.write("none.obj", two_quads_obj(false, false, false));
  const std::string fur = R"(, "fur": {"shells": 8, "texture_size": 32, "length": 0.3})";
  const std::string lambert = R"({"type": "lambert", "color": [0.4, 0.3, 0.2]})";
  const FrameImage partial = render_at(quads_scene(dir, "partial.obj", fur, lambert), {});
  EXPECT_TRUE(same_pixels(partial, render_at(quads_scene(dir, "none.obj", fur, lambert), {})));
  int furred = 0;  // the fur is drawn, not dropped
  for (size_t p = 0; p + 3 < partial.color.size(); p += 4) furred += partial.color[p] > 0.0f;
  EXPECT_GT(furred, 1000);

  const auto refused = [&](const std::string& fur_block) {
    return error_of(quads_scene(dir, "partial.obj", R"(, "fur": {"shells": 4, "texture_size": 32, )" + fur_block + "}",
                                lambert));
  };
  EXPECT_NE(refused(R"("texture_coordinates": "mesh")")
                .find("objects[0].fur.texture_coordinates: \"mesh\" lays the strands on the mesh's texture "
                      "coordinates, and 2 triangles of mesh `"),
            std::string::npos);
  EXPECT_NE(refused(R"("comb": {"field": "uv"})").find("objects[0].fur.comb.field: \"uv\" combs along the mesh's "),
            std::string::npos);
  // Without a colour map the fur says what it misses, not that the uvs would not do.
  EXPECT_NE(refused(R"("use_color_map": true)").find("objects[0].fur.use_color_map: true needs a colour map"),
            std::string::npos);
  write_files(dir, two_quads_obj(false, true));  // the front quad's map, on faces with uvs
  EXPECT_NE(error_of(quads_scene(dir, "quads.obj", R"(, "fur": {"shells": 4, "use_color_map": true})", lambert))
                .find("objects[0].fur.use_color_map: true reads the colour map at the mesh's texture coordinates"),
            std::string::npos);
  const uint8_t grey[4] = {128, 128, 128, 255};
  io::write_image_atomic(dir.path() / "len.png", 1, 1, 4, io::PixelType::u8, grey);
  EXPECT_NE(refused(R"("length_map": ")" + (dir.path() / "len.png").string() + "\"")
                .find("objects[0].fur.length_map: a length map is read at the mesh's texture coordinates, and 2 "
                      "triangles of mesh `"),
            std::string::npos);
}

}  // namespace partial_uvs_test
}  // namespace pelt::render::test
