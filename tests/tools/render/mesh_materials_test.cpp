// A mesh file whose materials name several maps: each face is drawn with its own material's
// maps (io::LoadedMesh::maps), as the same faces split into one object per material draw them;
// the id AOV still numbers the triangles as the whole mesh does; fur that reads the colour map
// takes one map or is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/tools/render/render_test_scenes.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"

namespace pelt::render::test {
namespace {

// Four triangles of a 2 x 2 patch in the y = 0 plane, seen from above: two of material `a`,
// two of `b`, taking turns (a b a b) so that the parts interleave in the file.
const char* const kPatch =
    "v -1 0 1\nv 0 0 1\nv 1 0 1\nv -1 0 -1\nv 0 0 -1\nv 1 0 -1\n"
    "vt 0 0\nvt 0.5 0\nvt 1 0\nvt 0 1\nvt 0.5 1\nvt 1 1\nvn 0 1 0\n";
const char* const kFaces[4] = {"f 1/1/1 2/2/1 5/5/1", "f 2/2/1 3/3/1 6/6/1", "f 1/1/1 5/5/1 4/4/1",
                               "f 2/2/1 6/6/1 5/5/1"};

// The patch with each face's material `usemtl`-ed as `materials` says (a name, or "" for none).
std::string patch_obj(const std::string& mtllib, const std::vector<std::string>& materials) {
  std::string obj = (mtllib.empty() ? "" : "mtllib " + mtllib + "\n") + std::string(kPatch);
  for (size_t f = 0; f < 4; ++f) obj += (materials[f].empty() ? "" : "usemtl " + materials[f] + "\n") + kFaces[f] + "\n";
  return obj;
}

// m.mtl (`mtl`, defining materials a and b), both.obj (the patch, its faces a b a b), and a.obj
// and b.obj (each material's faces alone: one object per material).
void write_patch(const SceneDir& dir, const std::string& mtl) {
  dir.write("m.mtl", mtl);
  dir.write("both.obj", patch_obj("m.mtl", {"a", "b", "a", "b"}));
  dir.write("a.obj", "mtllib m.mtl\n" + std::string(kPatch) + "usemtl a\n" + kFaces[0] + "\n" + kFaces[2] + "\n");
  dir.write("b.obj", "mtllib m.mtl\n" + std::string(kPatch) + "usemtl b\n" + kFaces[1] + "\n" + kFaces[3] + "\n");
}

io::Scene scene_of(const SceneDir& dir, const std::vector<std::string>& meshes, const std::string& material_type,
                   const std::string& extra = "") {
  std::string objects;
  for (const std::string& m : meshes)
    objects += std::string(objects.empty() ? "" : ",") + R"({"mesh": ")" +
               (m.find(':') != std::string::npos ? m : (dir.path() / m).string()) +
               R"(", "material": {"type": ")" + material_type + R"(", "color": [1, 1, 1]})" + extra + "}";
  const std::string lights = material_type == "unlit"
                                 ? R"([{"type": "ambient", "intensity": 1}])"
                                 : R"([{"type": "directional", "direction": [0.6, 0.8, 0.2], "intensity": 1}])";
  return dir.scene(R"({"pelt": 1, "image": {"width": 48, "height": 48, "background": [0, 0, 0]},
      "camera": {"eye": [0, 3, 0.001], "target": [0, 0, 0], "fovy_deg": 50},
      "lights": )" + lights + R"(, "objects": [)" + objects + "]}");
}

void write_flat_map(const SceneDir& dir, const std::string& name, uint8_t r, uint8_t g, uint8_t b) {
  std::vector<uint8_t> px;
  for (int i = 0; i < 16; ++i) px.insert(px.end(), {r, g, b});
  io::write_image_atomic(dir.path() / name, 4, 4, 3, io::PixelType::u8, px.data());
}

// Pixels whose colour is mostly channel c.
int pixels_of(const FrameImage& img, int c) {
  int n = 0;
  for (size_t p = 0; p + 3 < img.color.size(); p += 4)
    n += img.color[p + size_t(c)] > 0.5f && img.color[p + size_t((c + 1) % 3)] < 0.2f &&
         img.color[p + size_t((c + 2) % 3)] < 0.2f;
  return n;
}

// Faces of two materials with two colour maps draw both (until 2026-11-27 the first face's map
// covered the whole mesh): the same pixels as the faces split into two objects, one per material.
TEST(MeshMaterials, EachFaceDrawsItsOwnMaterialsColourMap) {
  SceneDir dir;
  write_flat_map(dir, "red.png", 255, 0, 0);
  write_flat_map(dir, "blue.png", 0, 0, 255);
  write_patch(dir, "newmtl a\nmap_Kd red.png\nnewmtl b\nmap_Kd blue.png\n");
  const FrameImage both = render_at(scene_of(dir, {"both.obj"}, "unlit"), {});
  const FrameImage split = render_at(scene_of(dir, {"a.obj", "b.obj"}, "unlit"), {});
  EXPECT_TRUE(same_pixels(both, split));
  EXPECT_GT(pixels_of(both, 0), 300);  // red on the left half
  EXPECT_GT(pixels_of(both, 2), 300);  // blue on the right
}

// Normal maps placed two ways (`norm -s -1 1` mirrors one) light each part with its own tangent
// frame: bit for bit what one object per material draws, lit (lambert) with a colour map too.
TEST(MeshMaterials, EachPartHasItsOwnNormalMapAndTangentFrame) {
  SceneDir dir;
  std::vector<uint8_t> px;
  for (int i = 0; i < 16; ++i) px.insert(px.end(), {230, 150, 200});  // tilted toward +u and +v
  io::write_image_atomic(dir.path() / "n.png", 4, 4, 3, io::PixelType::u8, px.data());
  write_flat_map(dir, "grey.png", 180, 180, 180);
  write_patch(dir, "newmtl a\nmap_Kd grey.png\nnorm n.png\nnewmtl b\nmap_Kd grey.png\nnorm -s -1 1 n.png\n");
  const FrameImage both = render_at(scene_of(dir, {"both.obj"}, "lambert"), {});
  const FrameImage split = render_at(scene_of(dir, {"a.obj", "b.obj"}, "lambert"), {});
  EXPECT_TRUE(same_pixels(both, split));
  // The mirrored map lights its half otherwise: the halves differ, so the comparison can fail.
  const size_t left = (24 * 48 + 12) * 4, right = (24 * 48 + 36) * 4;
  EXPECT_GT(std::abs(both.color[left] - both.color[right]), 0.02f);
}

// The id AOV numbers the triangles as the whole mesh does, whatever parts draw them.
TEST(MeshMaterials, TheIdAovNumbersTrianglesAsTheFileDoes) {
  SceneDir dir;
  write_flat_map(dir, "red.png", 255, 0, 0);
  write_flat_map(dir, "blue.png", 0, 0, 255);
  write_patch(dir, "newmtl a\nmap_Kd red.png\nnewmtl b\nmap_Kd blue.png\n");
  dir.write("plain.obj", patch_obj("", {"", "", "", ""}));
  RenderSettings rs;
  rs.aov = Aov::id;
  const auto ids = [&](const std::string& mesh) {
    SceneRenderer r(scene_of(dir, {mesh}, "unlit"), rs);
    FrameImage img;
    FrameStats st;
    r.render(0, img, st);
    return img.id;
  };
  const std::vector<uint32_t> parts = ids("both.obj"), whole = ids("plain.obj");
  EXPECT_EQ(parts, whole);
  // The background and every triangle of the patch show.
  std::vector<uint32_t> seen(parts);
  std::sort(seen.begin(), seen.end());
  seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
  EXPECT_EQ(seen, (std::vector<uint32_t>{0, 1, 2, 3, 4}));
}

// Fur that reads the colour map takes each face's (until 2026-11-27 faces of two colour maps were
// refused): red strands over the red material, blue over the blue, and the scene's colour map,
// which covers every part, red everywhere. Two files of the same texels draw the same pixels as
// one file named by both materials (each lane samples its map as it would alone), and faces of a
// material without a map grow untinted strands beside tinted ones.
TEST(MeshMaterials, FurTakesEachFacesColourMap) {
  SceneDir dir;
  write_flat_map(dir, "red.png", 255, 0, 0);
  write_flat_map(dir, "red2.png", 255, 0, 0);
  write_flat_map(dir, "blue.png", 0, 0, 255);
  write_patch(dir, "newmtl a\nmap_Kd red.png\nnewmtl b\nmap_Kd blue.png\n");
  const std::string fur =
      R"(, "fur": {"shells": 4, "texture_size": 16, "use_color_map": true, "root_color": [1, 1, 1],
                   "tip_color": [1, 1, 1]})";
  const FrameImage both = render_at(scene_of(dir, {"both.obj"}, "unlit", fur), {});
  EXPECT_GT(pixels_of(both, 0), 300);
  EXPECT_GT(pixels_of(both, 2), 300);
  io::Scene with_scene_map = scene_of(dir, {"both.obj"}, "unlit", fur);
  with_scene_map.objects[0].material.color_map = dir.path() / "red.png";
  const FrameImage red = render_at(with_scene_map, {});
  EXPECT_EQ(pixels_of(red, 2), 0);  // the scene's red map everywhere
  EXPECT_GT(pixels_of(red, 0), 600);

  // Every fin, in each order (the layer order hands each layer's fin draw its part of the quads'
  // maps), per-pixel lighting and the double references: both maps, the fins' too.
  for (const io::SortQuality sort : {io::SortQuality::none, io::SortQuality::layer, io::SortQuality::tile,
                                     io::SortQuality::surface, io::SortQuality::exact})
    for (const io::Precision precision : {io::Precision::simd, io::Precision::double_precision}) {
      io::Quality q;
      q.sort = sort;
      q.fins = fur::FinMode::all;
      q.precision = precision;
      for (const FurLighting lighting : {FurLighting::vertex, FurLighting::pixel}) {
        const FrameImage img = render_at(scene_of(dir, {"both.obj"}, "unlit", fur), q, 2, lighting);
        EXPECT_GT(pixels_of(img, 0), 300) << int(sort) << " " << int(precision) << " " << int(lighting);
        EXPECT_GT(pixels_of(img, 2), 300) << int(sort) << " " << int(precision) << " " << int(lighting);
      }
    }

  dir.write("m.mtl", "newmtl a\nmap_Kd red.png\nnewmtl b\nmap_Kd red2.png\n");
  const FrameImage two_files = render_at(scene_of(dir, {"both.obj"}, "unlit", fur), {});
  dir.write("m.mtl", "newmtl a\nmap_Kd red.png\nnewmtl b\nmap_Kd red.png\n");
  const FrameImage one_file = render_at(scene_of(dir, {"both.obj"}, "unlit", fur), {});
  EXPECT_TRUE(same_pixels(two_files, one_file));
  EXPECT_GT(pixels_of(one_file, 0), 600);

  dir.write("m.mtl", "newmtl a\nmap_Kd red.png\nnewmtl b\n");
  const FrameImage half = render_at(scene_of(dir, {"both.obj"}, "unlit", fur), {});
  int white = 0;
  for (size_t p = 0; p + 3 < half.color.size(); p += 4)
    white += half.color[p] > 0.5f && half.color[p + 1] > 0.5f && half.color[p + 2] > 0.5f;
  EXPECT_GT(pixels_of(half, 0), 200);
  EXPECT_GT(white, 200);
}

// The scene's map replaces the file's on every face: faces whose materials differed only in that
// map draw alike, as one part (one draw, one tangent frame for a normal map over them all), and
// a normal map the scene names lights the patch as it lights the mesh without materials.
TEST(MeshMaterials, TheScenesMapsJoinThePartsTheyMakeAlike) {
  SceneDir dir;
  write_flat_map(dir, "red.png", 255, 0, 0);
  write_flat_map(dir, "blue.png", 0, 0, 255);
  std::vector<uint8_t> px;
  for (int i = 0; i < 16; ++i) px.insert(px.end(), {230, 150, 200});
  io::write_image_atomic(dir.path() / "n.png", 4, 4, 3, io::PixelType::u8, px.data());
  write_patch(dir, "newmtl a\nmap_Kd red.png\nnewmtl b\nmap_Kd blue.png\n");
  dir.write("plain.obj", patch_obj("", {"", "", "", ""}));
  io::Scene both = scene_of(dir, {"both.obj"}, "lambert");
  both.objects[0].material.color_map = dir.path() / "red.png";
  both.objects[0].material.normal_map = dir.path() / "n.png";
  io::Scene plain = both;
  plain.objects[0].mesh_path = dir.path() / "plain.obj";
  plain.objects[0].mesh = plain.objects[0].mesh_path.string();
  RenderSettings rs;
  const SceneRenderer joined(both, rs);
  ASSERT_EQ(joined.maps_drawn(0).size(), 1u);
  EXPECT_EQ(joined.maps_drawn(0)[0].triangles, 4u);
  EXPECT_TRUE(same_pixels(render_at(both, {}), render_at(plain, {})));
  // Only the colour map named by the scene: the normal maps (none) agree, one part again.
  both.objects[0].material.normal_map.clear();
  EXPECT_EQ(SceneRenderer(both, rs).maps_drawn(0).size(), 1u);
  // Without the scene's maps, two parts.
  both.objects[0].material.color_map.clear();
  EXPECT_EQ(SceneRenderer(both, rs).maps_drawn(0).size(), 2u);
}

}  // namespace
}  // namespace pelt::render::test
