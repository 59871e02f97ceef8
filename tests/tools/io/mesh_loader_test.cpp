#include "tools/io/mesh_loader.h"

#include <array>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sys/stat.h>

#include "tests/tools/io/mesh_checks.h"
#include "tests/tools/io/base64.h"
#include "tests/tools/io/expect_load_error.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/input_error.h"

namespace pelt::io {
namespace mesh_loader_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

using testing::expect_load_error;

std::filesystem::path data_dir() {
  const char* root = std::getenv("PELT_SOURCE_DIR");
  return std::filesystem::path(root ? root : ".") / "tools" / "data";
}

void expect_unit_normals(const Mesh& m) {
  ASSERT_EQ(m.normals.size(), m.positions.size());
  EXPECT_LT(testing::max_normal_length_error(m), 1e-5);
}

TEST(MeshLoader, BunnyObj) {
  const LoadedMesh l = load_mesh_file(data_dir() / "bunny.obj");
  EXPECT_EQ(l.mesh.vertex_count(), 1839u);
  EXPECT_EQ(l.mesh.triangle_count(), 3674u);
  EXPECT_TRUE(l.mesh.uvs.empty());
  expect_unit_normals(l.mesh);
  // Normals were computed; the file gave none to replace, so no warning.
  EXPECT_TRUE(l.warnings.empty()) << ::testing::PrintToString(l.warnings);
  for (const auto& [edge, uses] : testing::edge_use(l.mesh)) ASSERT_EQ(uses, 2);
  EXPECT_EQ(testing::winding_conflicts(l.mesh), 0);
  EXPECT_GT(testing::signed_volume(l.mesh), 0.0);
  EXPECT_FALSE(l.color_map().present());
}

TEST(MeshLoader, LeePerrySmithGlbAndObjAgree) {
  const LoadedMesh glb = load_mesh_file(data_dir() / "LeePerrySmith" / "LeePerrySmith.glb");
  const LoadedMesh obj = load_mesh_file(data_dir() / "LeePerrySmith" / "LeePerrySmith.obj");
  EXPECT_EQ(glb.mesh.triangle_count(), 17684u);
  EXPECT_EQ(glb.mesh.vertex_count(), 9279u);
  EXPECT_EQ(obj.mesh.triangle_count(), 17684u);
  EXPECT_EQ(obj.mesh.vertex_count(), 9279u);
  ASSERT_EQ(glb.mesh.uvs.size(), glb.mesh.vertex_count());
  ASSERT_EQ(obj.mesh.uvs.size(), obj.mesh.vertex_count());
  expect_unit_normals(glb.mesh);
  expect_unit_normals(obj.mesh);
  // The OBJ is a value-for-value conversion of the GLB's accessors: the same triangles'
  // corners carry the same positions, normals and uvs. The GLB's node scales y and z by
  // 1.0000001192 (one float step), which moves positions by an ulp or two.
  for (size_t k = 0; k < glb.mesh.indices.size(); k += 97) {
    const uint32_t a = glb.mesh.indices[k], b = obj.mesh.indices[k];
    EXPECT_LT(glm::distance(glb.mesh.positions[a], obj.mesh.positions[b]), 1e-6f) << k;
    EXPECT_EQ(glb.mesh.uvs[a], obj.mesh.uvs[b]) << k;
    EXPECT_NEAR(glm::dot(glb.mesh.normals[a], obj.mesh.normals[b]), 1.0f, 1e-5f) << k;
  }
  // Bounding box from the data README: +-4.28 x +-3.97 x +-2.59 (to the printed digits).
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (const auto& p : glb.mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  EXPECT_NEAR(hi.x - lo.x, 2 * 4.28, 0.02);
  EXPECT_NEAR(hi.y - lo.y, 2 * 3.97, 0.02);
  EXPECT_NEAR(hi.z - lo.z, 2 * 2.59, 0.02);
  EXPECT_FALSE(glb.color_map().present());  // the GLB's material is a plain colour
}

void expect_box_textured(const LoadedMesh& l) {
  EXPECT_EQ(l.mesh.triangle_count(), 12u);
  EXPECT_EQ(l.mesh.vertex_count(), 24u);
  ASSERT_EQ(l.mesh.uvs.size(), 24u);
  expect_unit_normals(l.mesh);
  // The file's box is [-0.5,0.5]^3 under a root matrix rotating -90 deg about X: a vertex
  // at (x, y, z) lands at (x, z, -y). The rotation maps the cube onto itself, so check a
  // normal instead: normals must stay perpendicular to their face after the transform,
  // i.e. each normal points along the axis where |position| is largest.
  for (size_t i = 0; i < l.mesh.positions.size(); ++i) {
    const glm::vec3 p = l.mesh.positions[i], n = l.mesh.normals[i];
    EXPECT_NEAR(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 0.5f, 1e-6f);
    EXPECT_NEAR(glm::dot(n, p), 0.5f, 1e-5f) << i;  // outward unit normal of a face at distance 0.5
  }
  for (size_t k = 0; k < l.mesh.indices.size(); k += 3) {
    const glm::vec3 a = l.mesh.positions[l.mesh.indices[k]], b = l.mesh.positions[l.mesh.indices[k + 1]],
                    c = l.mesh.positions[l.mesh.indices[k + 2]];
    const glm::vec3 face_n = glm::cross(b - a, c - a);
    EXPECT_GT(glm::dot(face_n, l.mesh.normals[l.mesh.indices[k]]), 0.0f) << "triangle " << k / 3;
  }
  float umax = 0;
  for (const auto& uv : l.mesh.uvs) umax = std::max(umax, uv.x);
  EXPECT_NEAR(umax, 6.0f, 1e-5f);  // repeat wrapping: u runs 0 to 6
}

TEST(MeshLoader, BoxTexturedGlbAppliesTheRootMatrix) {
  const LoadedMesh l = load_mesh_file(data_dir() / "BoxTextured.glb");
  expect_box_textured(l);
  // Only the rotation distinguishes these: the untransformed file has the face with
  // normal (0,0,1) where the transformed one has (0,-1,0)... Check the face whose uvs
  // span u in [0,6] on a known vertex: the first vertex of the file is (-0.5,-0.5,0.5)
  // with normal (0,0,1); after the -90 deg X rotation it is (-0.5,0.5,0.5), normal (0,1,0).
  EXPECT_NEAR(glm::distance(l.mesh.positions[0], glm::vec3(-0.5f, 0.5f, 0.5f)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(l.mesh.normals[0], glm::vec3(0.0f, 1.0f, 0.0f)), 0.0f, 1e-6f);
  // Embedded PNG: decoded pixels, no path.
  EXPECT_TRUE(l.color_map().path.empty());
  EXPECT_EQ(l.color_map().pixels->width, 211);
  EXPECT_EQ(l.color_map().pixels->height, 211);
  EXPECT_FALSE(l.normal_map().present());
}

TEST(MeshLoader, BoxTexturedGltfResolvesRelativeUris) {
  const auto file = data_dir() / "BoxTextured-glTF" / "BoxTextured.gltf";
  const LoadedMesh l = load_mesh_file(file);
  expect_box_textured(l);
  EXPECT_EQ(l.color_map().path, file.parent_path() / "CesiumLogoFlat.png");
  EXPECT_TRUE(std::filesystem::exists(l.color_map().path));
  const LoadedMesh glb = load_mesh_file(data_dir() / "BoxTextured.glb");
  EXPECT_EQ(l.mesh.positions, glb.mesh.positions);
  EXPECT_EQ(l.mesh.indices, glb.mesh.indices);
}

// --- bad files -------------------------------------------------------------------

// Found by fuzzing: tinygltf 2.7 hands stb_image a pointer past the buffer when an image's
// bufferView runs past the end of its buffer; the loader must refuse the file first.
TEST(MeshLoader, GlbImageBufferViewPastTheBufferIsAnError) {
  const char* root = std::getenv("PELT_SOURCE_DIR");
  ASSERT_NE(root, nullptr);
  const std::filesystem::path p = std::filesystem::path(root) /
                                  "tests/fuzz/regressions/gltf/glb_image_bufferview_past_buffer_end.glb";
  try {
    load_mesh_file(p);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(e.reason.find("images[0]: bufferView 3 runs past the end of its buffer"), std::string::npos) << e.what();
  }
}

TEST(MeshLoader, ObjNanPosition) {
  TempDir dir;
  const auto f = dir.write("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
  expect_load_error(f, "v 3", "position is NaN");
}

TEST(MeshLoader, ObjInfinitePosition) {
  TempDir dir;
  const auto f = dir.write("inf.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_load_error(f, "v 2", "position is infinite");
}

TEST(MeshLoader, ObjMalformedNumber) {
  TempDir dir;
  const auto f = dir.write("word.obj", "v 0 0 0\nvn 0 0 1\nvn 0 zero 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_load_error(f, "vn 2", "`zero` is not a number (line 3)");
}

// strtod takes hexadecimal, which tinyobjloader reads as the 0 before the `x`: `v 0x1 0 0` was
// drawn at the origin. NaN and infinity spellings stay refused by name.
TEST(MeshLoader, ObjNumbersMustBeDecimal) {
  TempDir dir;
  const std::string rest = "v 1 0 0\nv 0 1 0\nf 1 2 3\n";
  expect_load_error(dir.write("hex.obj", "v 0x1 0 0\n" + rest), "v 1", "`0x1` is not a decimal number (line 1)");
  expect_load_error(dir.write("hexp.obj", "vt 0 0\nv 0 0 -0X1p-2\n" + rest), "v 1",
                    "`-0X1p-2` is not a decimal number (line 2)");
  expect_load_error(dir.write("hexvn.obj", "vn 0 0 0x1\nv 0 0 0\n" + rest), "vn 1", "`0x1` is not a decimal number");
  expect_load_error(dir.write("inf.obj", "v -Infinity 0 0\n" + rest), "v 1", "position is infinite");
  expect_load_error(dir.write("nan.obj", "v 0 0 0\nvt nan(1) 0\n" + rest), "vt 1", "texture coordinate is NaN");
  // Every decimal form tinyobjloader reads.
  const LoadedMesh l =
      load_mesh_file(dir.write("ok.obj", "v +0 -.5e0 1.\nv 1.E+0 0 0\nv .0 10e-1 0\nf 1 2 3\n"));
  EXPECT_EQ(l.mesh.positions[0], glm::vec3(0.0f, -0.5f, 1.0f));
  EXPECT_EQ(l.mesh.positions[2], glm::vec3(0.0f, 1.0f, 0.0f));
}

// tinyobjloader fills a record's missing numbers with 0 and drops extra ones: `v 1` was the
// position (1,0,0), `vn 0 1` the normal (0,1,0). A bare `v`, which it skips, is a record too:
// it used to shift every later position, so the error named a face (`f 1: vertex index 4 out
// of range`) instead of line 1.
TEST(MeshLoader, ObjRecordsMustHaveTheirNumbers) {
  TempDir dir;
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_load_error(dir.write("v1.obj", "v 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "v 1",
                    "a position is 3 numbers (x y z), 4 (x y z w) or 6 (x y z r g b), this one has 1 (line 1)");
  expect_load_error(dir.write("v2.obj", v + "v 1 1 # z\nf 1 2 3\n"), "v 4", "this one has 2 (line 4)");
  expect_load_error(dir.write("v5.obj", v + "v 1 1 1 1 1\nf 1 2 3\n"), "v 4", "this one has 5 (line 4)");
  expect_load_error(dir.write("bare.obj", "v\n" + v + "f 2 3 4\n"), "v 1",
                    "a position is 3 numbers (x y z), 4 (x y z w) or 6 (x y z r g b), this one has 0 (line 1)");
  expect_load_error(dir.write("blank.obj", v + "v \t\nf 1 2 3\n"), "v 4", "this one has 0 (line 4)");
  expect_load_error(dir.write("vn2.obj", v + "vn 0 1\nf 1//1 2//1 3//1\n"), "vn 1",
                    "a normal is 3 numbers (x y z), this one has 2 (line 4)");
  expect_load_error(dir.write("vn4.obj", v + "vn 0 0 1 0\nf 1//1 2//1 3//1\n"), "vn 1", "this one has 4");
  expect_load_error(dir.write("vnbare.obj", v + "vn\nvn 0 0 1\nf 1//2 2//2 3//2\n"), "vn 1", "this one has 0");
  expect_load_error(dir.write("vt0.obj", v + "vt\nvt 0 0\nf 1/2 2/2 3/2\n"), "vt 1",
                    "a texture coordinate is 1 to 3 numbers (u [v [w]]), this one has 0 (line 4)");
  expect_load_error(dir.write("vt4.obj", v + "vt 0 0 0 0\nf 1/1 2/1 3/1\n"), "vt 1", "this one has 4");
  // tinyobjloader splits words at blanks only: `0\f1` is one word to it, read as 0.
  expect_load_error(dir.write("ff.obj", "v 0 0\f1 0\n" + v + "f 1 2 3\n"), "v 1", "is not a number (line 1)");

  // What tinyobjloader reads right: x y z w and x y z r g b give x y z; vt u [v [w]] gives u v
  // (v 0 when missing, as the OBJ specification says).
  const LoadedMesh l = load_mesh_file(dir.write(
      "ok.obj", "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\nvt 0.25\nvt 0.5 1\nvt 1 1 0\nf 1/1 2/2 3/3\n"));
  ASSERT_EQ(l.mesh.vertex_count(), 3u);
  EXPECT_EQ(l.mesh.positions[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(l.mesh.positions[1], glm::vec3(1, 0, 0));
  ASSERT_EQ(l.mesh.uvs.size(), 3u);
  EXPECT_EQ(l.mesh.uvs[0], glm::vec2(0.25f, 0.0f));
  EXPECT_EQ(l.mesh.uvs[1], glm::vec2(0.5f, 1.0f));
  EXPECT_EQ(l.mesh.uvs[2], glm::vec2(1.0f, 1.0f));
}

// Named by the face's record and its line (found again only for the message).
TEST(MeshLoader, ObjIndexOutOfRange) {
  TempDir dir;
  const auto f = dir.write("range.obj", "v 0 0 0\nv 1 0 0\n# a comment\nv 0 1 0\nf 1 2 3\n\nf 1 2 9\n");
  expect_load_error(f, "f 2", "vertex index 9 out of range (3 vertices) (line 7)");
}

// Faces are numbered as the file's `f` records, whatever polygons come before: the third
// record here is `f 3`, not the fourth triangle.
TEST(MeshLoader, ObjErrorsNameTheFaceRecordAfterPolygons) {
  TempDir dir;
  const auto f = dir.write("after_quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 2 3 4\nf 1 2 99\n");
  expect_load_error(f, "f 3", "vertex index 99 out of range (4 vertices)");
  const auto g = dir.write("after_hexagon.obj",
                           "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4 5 6\nf 1 2 3/7\n");
  expect_load_error(g, "f 2", "texture coordinate index 7 out of range (0 texture coordinates)");
}

// tinyobjloader's own triangulation dropped a quad with an index past the end without a
// word (the render exited 0 with a hole); pelt triangulates itself and refuses the file.
TEST(MeshLoader, ObjQuadWithAnIndexPastTheEnd) {
  TempDir dir;
  const auto f = dir.write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 2 3 99\n");
  expect_load_error(f, "f 2", "vertex index 99 out of range (4 vertices)");
}

// Corners tinyobjloader would misread: a word (read as 0), 0, a relative index reaching
// before the first record (a texture coordinate's would become "none"), past int's range.
TEST(MeshLoader, ObjCornersThatAreNotIndices) {
  TempDir dir;
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";
  expect_load_error(dir.write("word.obj", v + "f 1 2 x\n"), "f 1",
                    "`x` is not a corner (v, v/vt, v//vn or v/vt/vn) (line 5)");
  expect_load_error(dir.write("slash.obj", v + "f 1 2 3/\n"), "f 1", "`3/` is not a corner");
  expect_load_error(dir.write("four.obj", v + "f 1 2 3/1/1/1\n"), "f 1", "`3/1/1/1` is not a corner");
  expect_load_error(dir.write("zero.obj", v + "f 1 2 3\nf 0 1 2\n"), "f 2",
                    "vertex index 0: OBJ numbers its records from 1 (line 6)");
  expect_load_error(dir.write("rel.obj", v + "f -1 -2 -4\n"), "f 1",
                    "vertex index -4 out of range (3 vertices before this face) (line 5)");
  expect_load_error(dir.write("relvt.obj", v + "f 1/-2 2/-1 3/-1\n"), "f 1",
                    "texture coordinate index -2 out of range (1 texture coordinates before this face)");
  expect_load_error(dir.write("huge.obj", v + "f 1 2 99999999999\n"), "f 1", "vertex index 99999999999 out of range");
  expect_load_error(dir.write("glued.obj", v + "f 1 2 3#c\n"), "f 1", "`3#c` is not a corner");
  // tinyobjloader splits words at blanks only: it read `2\f3` as 2 and dropped the face of two.
  expect_load_error(dir.write("formfeed.obj", v + "f 1 2\f3\n"), "f 1", "is not a corner (v, v/vt, v//vn or v/vt/vn)");
  expect_load_error(dir.write("vtab.obj", v + "v 1 1 0\nf 1 2 3\v4\n"), "f 1", "is not a corner");
  // Valid forms still load: relative indices, v//vn, a leading +.
  const auto ok = dir.write("ok.obj", v + "vn 0 0 1\nf -3//1 +2//1 -1//-1\nf 1/1 2/1 3/-1\n");
  EXPECT_EQ(load_mesh_file(ok).mesh.triangle_count(), 2u);
}

// tinyobjloader counts a face's corners in a byte.
TEST(MeshLoader, ObjFaceOfMoreCornersThanTinyobjloaderCounts) {
  TempDir dir;
  std::string text, f255 = "f";
  for (int i = 0; i < 256; ++i) {
    const double a = 6.283185307179586 * i / 256;
    text += "v " + std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " 0\n";
    if (i < 255) f255.append(1, ' ').append(std::to_string(i + 1));
  }
  expect_load_error(dir.write("big.obj", text + f255 + " 256\n"), "f 1",
                    "a face has at most 255 vertices here, this one has 256 (line 257)");
  EXPECT_EQ(load_mesh_file(dir.write("ok.obj", text + f255 + "\n")).mesh.triangle_count(), 253u);
}

// An L-shaped hexagon that tinyobjloader's triangulation left with 1 of its 4 triangles
// (at this offset): all four, covering its area of 5 once.
TEST(MeshLoader, ObjPolygonIsTriangulatedWithoutHoles) {
  TempDir dir;
  const auto f = dir.write("l.obj", "v -4 1 0\nv -1 1 0\nv -1 2 0\nv -3 2 0\nv -3 4 0\nv -4 4 0\nf 1 2 3 4 5 6\n");
  const LoadedMesh l = load_mesh_file(f);
  ASSERT_EQ(l.mesh.triangle_count(), 4u);
  double area = 0.0;
  for (size_t k = 0; k < l.mesh.indices.size(); k += 3) {
    const glm::vec3 a = l.mesh.positions[l.mesh.indices[k]], b = l.mesh.positions[l.mesh.indices[k + 1]],
                    c = l.mesh.positions[l.mesh.indices[k + 2]];
    const float z = glm::cross(b - a, c - a).z;
    EXPECT_GT(z, 0.0f);  // the file's winding
    area += 0.5 * z;
  }
  EXPECT_DOUBLE_EQ(area, 5.0);
}

// tinyobjloader drops a face of one or two corners without a word; the mesh would have a
// hole where the file meant something.
TEST(MeshLoader, ObjFaceOfFewerThanThreeCorners) {
  TempDir dir;
  const auto two = dir.write("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n");
  expect_load_error(two, "f 2", "a face needs at least 3 vertices, this one has 2 (line 5)");
  const auto none = dir.write("none.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf\nf 1 2 3\n");
  expect_load_error(none, "f 1", "a face needs at least 3 vertices, this one has 0 (line 4)");
  const auto comment = dir.write("comment.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 3 # 1 2\n");
  expect_load_error(comment, "f 2", "this one has 1 (line 5)");
}

TEST(MeshLoader, ObjSomeNormalsMissing) {
  TempDir dir;
  const auto f = dir.write("some.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3\n");
  EXPECT_EQ(load_mesh_file(f).warnings,
            std::vector<std::string>{"not every vertex has a normal: all normals computed from the triangles"});
}

TEST(MeshLoader, ObjNoFaces) {
  TempDir dir;
  const auto f = dir.write("empty.obj", "v 0 0 0\nv 1 0 0\n");
  expect_load_error(f, "", "no faces");
}

TEST(MeshLoader, ObjQuadIsTriangulatedAndUvsKept) {
  TempDir dir;
  const auto f = dir.write("quad.obj",
                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                           "f 1/1/1 2/2/1 3/3/1 4/4/1\n");
  const LoadedMesh l = load_mesh_file(f);
  EXPECT_EQ(l.mesh.triangle_count(), 2u);
  EXPECT_EQ(l.mesh.vertex_count(), 4u);
  for (size_t i = 0; i < 4; ++i)  // uv = xy for this square
    EXPECT_EQ(l.mesh.uvs[i], glm::vec2(l.mesh.positions[i]));
  EXPECT_EQ(l.mesh.normals[0], glm::vec3(0, 0, 1));
  EXPECT_TRUE(l.warnings.empty());
}

TEST(MeshLoader, ObjSplitsVerticesByTriple) {
  // One position used with two different uvs: two vertices.
  TempDir dir;
  const auto f = dir.write("split.obj",
                           "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
                           "f 1/1 2/2 3/3\nf 2/2 4/4 3/4\n");
  const LoadedMesh l = load_mesh_file(f);
  EXPECT_EQ(l.mesh.vertex_count(), 5u);
  EXPECT_EQ(l.mesh.positions[2], l.mesh.positions[4]);
  EXPECT_NE(l.mesh.uvs[2], l.mesh.uvs[4]);
}

// Faces without texture coordinates beside faces with them: the uvs are kept, (0, 0) at the
// vertices that have none, which uv_missing marks and a warning names by material. Until
// 2026-11-27 every uv of the mesh was dropped. No face with uvs: none kept, nothing marked.
TEST(MeshLoader, ObjFacesWithoutUvsBesideFacesWithThem) {
  TempDir dir;
  dir.write("m.mtl", "newmtl a\nnewmtl plain\n");
  const auto f = dir.write("some.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                       "vt 0.25 0.5\nvt 0.75 0.5\nvt 0.25 1\n"
                                       "usemtl a\nf 1/1 2/2 3/3\nusemtl plain\nf 2 4 3\n");
  const LoadedMesh l = load_mesh_file(f);
  ASSERT_EQ(l.mesh.vertex_count(), 6u);
  ASSERT_EQ(l.mesh.uvs.size(), 6u);
  EXPECT_EQ(l.uv_missing, (std::vector<uint8_t>{0, 0, 0, 1, 1, 1}));
  EXPECT_EQ(l.mesh.uvs[1], glm::vec2(0.75f, 0.5f));
  EXPECT_EQ(l.mesh.uvs[4], glm::vec2(0.0f));
  EXPECT_FALSE(lacks_uv(l.mesh, l.uv_missing, 0));
  EXPECT_TRUE(lacks_uv(l.mesh, l.uv_missing, 1));
  ASSERT_EQ(l.warnings.size(), 1u);
  EXPECT_EQ(l.warnings[0], "1 of 2 triangles have no texture coordinates (faces of material `plain`): no map may be "
                           "drawn on them, and fur on the mesh cannot lay its strands by the uvs");

  // A face of another material on the same uv-less corners is named too (its vertices are the
  // first face's), and so are faces of no material.
  const auto shared = dir.write("shared.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\n"
                                              "f 1 2 3\nusemtl a\nf 1/1 2/1 4/1\nusemtl plain\nf 2 4 3\n"
                                              "usemtl a\nf 3 2 4\n");
  const LoadedMesh sh = load_mesh_file(shared);
  ASSERT_FALSE(sh.warnings.empty());
  EXPECT_NE(sh.warnings[0].find("3 of 4 triangles have no texture coordinates (faces of no material, material `plain` "
                                "and material `a`)"),
            std::string::npos)
      << sh.warnings[0];

  const auto none = dir.write("none.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2 3\n");
  const LoadedMesh n = load_mesh_file(none);
  EXPECT_TRUE(n.mesh.uvs.empty());
  EXPECT_TRUE(n.uv_missing.empty());
  EXPECT_TRUE(n.warnings.empty()) << ::testing::PrintToString(n.warnings);
}

TEST(MeshLoader, ObjMaterialTexturesResolvedRelativeToTheFile) {
  TempDir dir;
  dir.write("m.mtl", "newmtl skin\nmap_Kd tex/albedo.png\nnorm tex/normal.png\n");
  const auto f = dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl skin\nf 1 2 3\n");
  const LoadedMesh l = load_mesh_file(f);
  EXPECT_EQ(l.color_map().path, dir.path() / "tex/albedo.png");
  EXPECT_EQ(l.normal_map().path, dir.path() / "tex/normal.png");
}

// Each face keeps its material's maps: two materials naming other maps make two sets, each
// triangle in its own; materials that differ in other ways (Kd) share one set.
TEST(MeshLoader, ObjFacesKeepTheirMaterialsMaps) {
  TempDir dir;
  dir.write("m.mtl", "newmtl skin\nmap_Kd skin.png\nnewmtl eyes\nmap_Kd eyes.png\nnorm eyes_n.png\n"
                     "newmtl skin2\nmap_Kd skin.png\nKd 1 0 0\nnewmtl plain\nKd 0 1 0\n");
  const std::string v = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
  const LoadedMesh two = load_mesh_file(
      dir.write("two.obj", v + "usemtl skin\nf 1 2 3\nusemtl eyes\nf 2 4 3\nusemtl skin\nf 1 2 4\n"));
  ASSERT_EQ(two.maps.size(), 2u);
  EXPECT_EQ(two.maps[0].material, "skin");
  EXPECT_EQ(two.maps[0].color_map.path, dir.path() / "skin.png");
  EXPECT_FALSE(two.maps[0].normal_map.present());
  EXPECT_EQ(two.maps[1].material, "eyes");
  EXPECT_EQ(two.maps[1].color_map.path, dir.path() / "eyes.png");
  EXPECT_EQ(two.maps[1].normal_map.path, dir.path() / "eyes_n.png");
  EXPECT_EQ(two.triangle_maps, (std::vector<uint32_t>{0, 1, 0}));
  EXPECT_TRUE(two.warnings.empty()) << ::testing::PrintToString(two.warnings);
  // A quad is two triangles of its face's set.
  const LoadedMesh quad = load_mesh_file(dir.write("quad.obj", v + "usemtl eyes\nf 1 2 3\nusemtl skin\nf 1 2 4 3\n"));
  EXPECT_EQ(quad.triangle_maps, (std::vector<uint32_t>{0, 1, 1}));
  EXPECT_EQ(quad.maps[0].material, "eyes");
  const LoadedMesh same = load_mesh_file(dir.write("same.obj", v + "usemtl skin\nf 1 2 3\nusemtl skin2\nf 2 4 3\n"));
  ASSERT_EQ(same.maps.size(), 1u);
  EXPECT_TRUE(same.triangle_maps.empty());
  EXPECT_EQ(same.maps_of(1), 0u);
  // A material without maps beside one with them: a set without maps.
  const LoadedMesh plain = load_mesh_file(dir.write("plain.obj", v + "usemtl plain\nf 1 2 3\nusemtl skin\nf 2 4 3\n"));
  ASSERT_EQ(plain.maps.size(), 2u);
  EXPECT_FALSE(plain.maps[0].any());
  EXPECT_EQ(plain.maps[0].material, "plain");
  EXPECT_EQ(plain.triangle_maps, (std::vector<uint32_t>{0, 1}));
  EXPECT_FALSE(plain.color_map().present());  // the first face's
  // No material draws a map: no set.
  const LoadedMesh none = load_mesh_file(dir.write("none.obj", v + "usemtl plain\nf 1 2 3\n"));
  EXPECT_TRUE(none.maps.empty());
  EXPECT_TRUE(none.triangle_maps.empty());
}

// A missing library is one warning line naming where it was looked for.
TEST(MeshLoader, ObjMissingMaterialFileIsAWarning) {
  TempDir dir;
  const LoadedMesh l = load_mesh_file(dir.write("m.obj", "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  ASSERT_EQ(l.warnings.size(), 1u) << ::testing::PrintToString(l.warnings);
  EXPECT_EQ(l.warnings[0], "material library `nowhere.mtl` not found (looked for " + (dir.path() / "nowhere.mtl").string() +
                               "): its materials are not drawn");
}

TEST(MeshLoader, MissingAndUnsupportedFiles) {
  TempDir dir;
  expect_load_error(dir.path() / "nope.obj", "", "file not found");
  expect_load_error(dir.write("mesh.ply", "ply\n"), "", "unsupported mesh file extension `.ply`");
  expect_load_error(dir.path(), "", "is a folder");
}

TEST(MeshLoader, MalformedGltf) {
  TempDir dir;
  expect_load_error(dir.write("bad.gltf", "{ this is not json"), "", "malformed glTF");
  expect_load_error(dir.write("bad.glb", "glTF but not really"), "", "malformed glTF");
}

// A one-triangle glTF whose buffer is a data URI, with a chosen position and index.
std::string tiny_gltf(float x0, uint16_t i2) {
  // 3 float3 positions (36 bytes) then 3 uint16 indices (6 bytes, padded to 8).
  float pos[9] = {x0, 0, 0, 1, 0, 0, 0, 1, 0};
  uint16_t idx[4] = {0, 1, i2, 0};
  std::string bytes(reinterpret_cast<const char*>(pos), sizeof pos);
  bytes.append(reinterpret_cast<const char*>(idx), sizeof idx);
  const std::string enc = base64(bytes);
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
  "nodes":[{"mesh":0,"translation":[10,0,0],"scale":[2,2,2]}],
  "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
  "buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,)" +
         enc + R"("}],
  "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
  "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
               {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
}

// tiny_gltf's triangle twice, as two primitives of materials 0 and 1 (`materials`, a JSON
// array), with textures 0 and 1 of images a.png and b.png (copies of BoxTextured's) beside it.
std::filesystem::path two_material_gltf(const TempDir& dir, const std::string& materials) {
  const auto png = data_dir() / "BoxTextured-glTF" / "CesiumLogoFlat.png";
  std::filesystem::copy_file(png, dir.path() / "a.png");
  std::filesystem::copy_file(png, dir.path() / "b.png");
  std::string text = tiny_gltf(0.0f, 2);
  const std::string from = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)";
  text.replace(text.find(from), from.size(),
               R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0},
                                           {"attributes":{"POSITION":0},"indices":1,"material":1}]}],
                  "textures":[{"source":0},{"source":1}], "images":[{"uri":"a.png"},{"uri":"b.png"}],
                  "materials":)" + materials + ",");
  return dir.write("two.gltf", text);
}

// Each primitive keeps its material's colour texture; materials naming one image placed
// alike share a set, and one placed otherwise (KHR_texture_transform) is a set of its own.
TEST(MeshLoader, GltfPrimitivesKeepTheirMaterialsMaps) {
  TempDir dir;
  const LoadedMesh l = load_mesh_file(two_material_gltf(dir, R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
      {"pbrMetallicRoughness":{"baseColorTexture":{"index":1}}}])"));
  ASSERT_EQ(l.maps.size(), 2u);
  EXPECT_EQ(l.maps[0].color_map.path, dir.path() / "a.png");
  EXPECT_EQ(l.maps[1].color_map.path, dir.path() / "b.png");
  EXPECT_EQ(l.maps[0].material, "materials[0]");  // unnamed: its path
  EXPECT_EQ(l.triangle_maps, (std::vector<uint32_t>{0, 1}));
  EXPECT_TRUE(l.warnings.empty()) << ::testing::PrintToString(l.warnings);

  TempDir dir2;
  const LoadedMesh same = load_mesh_file(two_material_gltf(dir2, R"([{"name":"one","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
      {"name":"two","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}])"));
  ASSERT_EQ(same.maps.size(), 1u);
  EXPECT_EQ(same.maps[0].material, "one");
  EXPECT_TRUE(same.triangle_maps.empty());

  TempDir dir3;
  const LoadedMesh placed = load_mesh_file(two_material_gltf(dir3, R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
      {"pbrMetallicRoughness":{"baseColorTexture":{"index":0,
         "extensions":{"KHR_texture_transform":{"scale":[2,2]}}}}}])"));
  ASSERT_EQ(placed.maps.size(), 2u);
  EXPECT_EQ(placed.maps[0].color_map.path, placed.maps[1].color_map.path);
  EXPECT_FALSE(placed.maps[0].color_map.placement.transforms());
  EXPECT_TRUE(placed.maps[1].color_map.placement.transforms());
}

// A primitive without TEXCOORD_0 beside one with it: the same as the OBJ faces above, the
// warning naming the primitive.
TEST(MeshLoader, GltfPrimitiveWithoutUvsBesideOneWithThem) {
  TempDir dir;
  std::string text = tiny_gltf(0.0f, 2);
  const std::string from = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)";
  text.replace(text.find(from), from.size(),
               R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":2},"indices":1},
                                           {"attributes":{"POSITION":0},"indices":1}]}],)");
  const std::string accessors = R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
  // TEXCOORD_0: the positions' first 24 bytes read as three uvs (0, 0), (0, 1), (0, 0) once the
  // node's transform, which uvs do not take, is set aside.
  text.replace(text.find(accessors), accessors.size(),
               R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"},
                  {"bufferView":0,"componentType":5126,"count":3,"type":"VEC2"}]})");
  const LoadedMesh l = load_mesh_file(dir.write("some.gltf", text));
  ASSERT_EQ(l.mesh.vertex_count(), 6u);
  ASSERT_EQ(l.mesh.uvs.size(), 6u);
  EXPECT_EQ(l.uv_missing, (std::vector<uint8_t>{0, 0, 0, 1, 1, 1}));
  EXPECT_EQ(l.mesh.uvs[1], glm::vec2(0.0f, 1.0f));
  ASSERT_EQ(l.warnings.size(), 1u);
  EXPECT_EQ(l.warnings[0], "1 of 2 triangles have no texture coordinates (no TEXCOORD_0 in "
                           "meshes[0].primitives[1]): no map may be drawn on them, and fur on the mesh cannot lay "
                           "its strands by the uvs");
}

// The same mesh drawn by three nodes names its primitive once; a primitive without uvs and
// without triangles (an empty index list) decides nothing: the uvs are settled by triangles.
TEST(MeshLoader, GltfUvlessPrimitivesAreCountedByTriangles) {
  TempDir dir;
  std::string text = tiny_gltf(0.0f, 2);
  const std::string from = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)";
  const std::string accessors = R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
  text.replace(text.find(accessors), accessors.size(),
               R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"},
                  {"bufferView":0,"componentType":5126,"count":3,"type":"VEC2"},
                  {"bufferView":1,"componentType":5123,"count":0,"type":"SCALAR"}]})");
  std::string instanced = text;
  instanced.replace(instanced.find(from), from.size(),
                    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":2},"indices":1},
                                                {"attributes":{"POSITION":0},"indices":1}]}],)");
  const std::string nodes = R"("nodes":[{"mesh":0,"translation":[10,0,0],"scale":[2,2,2]}],)";
  instanced.replace(instanced.find(nodes), nodes.size(),
                    R"("nodes":[{"mesh":0},{"mesh":0,"translation":[2,0,0]},{"mesh":0,"translation":[4,0,0]}],)");
  instanced.replace(instanced.find(R"("scenes":[{"nodes":[0]}])"), 24, R"("scenes":[{"nodes":[0,1,2]}])");
  const LoadedMesh l = load_mesh_file(dir.write("instanced.gltf", instanced));
  ASSERT_EQ(l.warnings.size(), 1u) << ::testing::PrintToString(l.warnings);
  EXPECT_NE(l.warnings[0].find("3 of 6 triangles have no texture coordinates (no TEXCOORD_0 in "
                               "meshes[0].primitives[1]):"),
            std::string::npos)
      << l.warnings[0];

  std::string empty = text;
  empty.replace(empty.find(from), from.size(),
                R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":2},"indices":1},
                                            {"attributes":{"POSITION":0},"indices":3}]}],)");
  const LoadedMesh e = load_mesh_file(dir.write("empty.gltf", empty));
  EXPECT_TRUE(e.uv_missing.empty());
  EXPECT_EQ(e.mesh.uvs.size(), e.mesh.vertex_count());
  EXPECT_TRUE(e.warnings.empty()) << ::testing::PrintToString(e.warnings);
  // The other way round: the only primitive with uvs has no triangle, so no triangle has uvs.
  std::string reverse = text;
  reverse.replace(reverse.find(from), from.size(),
                  R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":2},"indices":3},
                                              {"attributes":{"POSITION":0},"indices":1}]}],)");
  const LoadedMesh r = load_mesh_file(dir.write("reverse.gltf", reverse));
  EXPECT_TRUE(r.mesh.uvs.empty());
  EXPECT_TRUE(r.uv_missing.empty());
  EXPECT_TRUE(r.warnings.empty()) << ::testing::PrintToString(r.warnings);
}

// A normalTexture is its primitive's normal map (drawn when the scene names none,
// tests/tools/render/normal_map_test.cpp), the same way.
TEST(MeshLoader, GltfNormalTextureIsThePrimitivesNormalMap) {
  TempDir dir;
  const LoadedMesh l = load_mesh_file(
      two_material_gltf(dir, R"([{"normalTexture":{"index":0}}, {"normalTexture":{"index":1}}])"));
  ASSERT_EQ(l.maps.size(), 2u);
  EXPECT_EQ(l.normal_map().path, dir.path() / "a.png");
  EXPECT_EQ(l.maps[1].normal_map.path, dir.path() / "b.png");
  EXPECT_FALSE(l.color_map().present());
  EXPECT_FALSE(l.maps[1].color_map.present());
  EXPECT_TRUE(l.warnings.empty()) << ::testing::PrintToString(l.warnings);
  // A primitive of no material beside one with a map: a set without maps.
  TempDir dir2;
  std::string text = tiny_gltf(0.0f, 2);
  const std::string from = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)";
  text.replace(text.find(from), from.size(),
               R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1},
                                           {"attributes":{"POSITION":0},"indices":1,"material":0}]}],
                  "textures":[{"source":0}], "images":[{"uri":"a.png"}],
                  "materials":[{"normalTexture":{"index":0}}],)");
  const LoadedMesh mixed = load_mesh_file(dir2.write("mixed.gltf", text));
  ASSERT_EQ(mixed.maps.size(), 2u);
  EXPECT_FALSE(mixed.maps[0].any());
  EXPECT_EQ(mixed.maps[0].material, kNoMaterial);
  ASSERT_FALSE(mixed.warnings.empty());
  EXPECT_EQ(mixed.warnings[0],
            "1 triangle of primitives without a material (meshes[0].primitives[0], ...) are drawn without the file's "
            "maps and alpha");
  EXPECT_EQ(mixed.maps[1].normal_map.path, dir2.path() / "a.png");
  EXPECT_EQ(mixed.triangle_maps, (std::vector<uint32_t>{0, 1}));
}

// Two materials drawing one embedded image share its pixels, decoded once.
TEST(MeshLoader, GltfEmbeddedImageDecodedOnceForItsSets) {
  TempDir dir;
  const auto png = data_dir() / "BoxTextured-glTF" / "CesiumLogoFlat.png";
  std::ifstream in(png, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string text = tiny_gltf(0.0f, 2);
  const std::string from = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)";
  text.replace(text.find(from), from.size(),
               R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0},
                                           {"attributes":{"POSITION":0},"indices":1,"material":1}]}],
                  "textures":[{"source":0}], "images":[{"uri":"data:image/png;base64,)" + base64(bytes) + R"("}],
                  "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
                               {"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},"normalTexture":{"index":0}}],)");
  const LoadedMesh l = load_mesh_file(dir.write("embedded.gltf", text));
  ASSERT_EQ(l.maps.size(), 2u);
  ASSERT_NE(l.maps[0].color_map.pixels, nullptr);
  EXPECT_EQ(l.maps[0].color_map.pixels, l.maps[1].color_map.pixels);
  // The normal map reads the same image linear: its own decoding.
  ASSERT_NE(l.maps[1].normal_map.pixels, nullptr);
  EXPECT_NE(l.maps[1].normal_map.pixels, l.maps[1].color_map.pixels);
}

// A required extension pelt does not read must stop the load (glTF 2.0, section 3.12); a
// used but optional one does not.
TEST(MeshLoader, GltfRequiredExtensionIsRefused) {
  TempDir dir;
  const std::string text = tiny_gltf(0.0f, 2);
  const std::string asset = R"("asset":{"version":"2.0"},)";
  ASSERT_EQ(text.find(asset), 1u);
  const std::string draco =
      R"("extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"],)";
  expect_load_error(dir.write("draco.gltf", "{" + asset + draco + text.substr(1 + asset.size())), "extensionsRequired[0]",
                    "the file needs the extension `KHR_draco_mesh_compression`, which pelt does not read");
  const std::string used = R"("extensionsUsed":["KHR_materials_emissive_strength"],)";
  EXPECT_EQ(load_mesh_file(dir.write("used.gltf", "{" + asset + used + text.substr(1 + asset.size())))
                .mesh.triangle_count(),
            1u);
  // KHR_texture_transform is read, required or not; another required one after it still stops the load.
  const std::string transform = R"("extensionsRequired":["KHR_texture_transform"],)";
  EXPECT_EQ(load_mesh_file(dir.write("transform.gltf", "{" + asset + transform + text.substr(1 + asset.size())))
                .mesh.triangle_count(),
            1u);
  const std::string both = R"("extensionsRequired":["KHR_texture_transform","KHR_draco_mesh_compression"],)";
  expect_load_error(dir.write("both.gltf", "{" + asset + both + text.substr(1 + asset.size())), "extensionsRequired[1]",
                    "`KHR_draco_mesh_compression`, which pelt does not read");
}

// asset.version names the format's major version: a glTF 1.0 file (or a future 3.0) is refused,
// a 2.x one read.
TEST(MeshLoader, GltfVersionMustBeTwo) {
  TempDir dir;
  const std::string text = tiny_gltf(0.0f, 2);
  const std::string asset = R"("asset":{"version":"2.0"},)";
  ASSERT_EQ(text.find(asset), 1u);
  for (const char* version : {"1.0", "3.0", "20"}) {
    const std::string other = std::string(R"("asset":{"version":")") + version + R"("},)";
    expect_load_error(dir.write("v.gltf", "{" + other + text.substr(1 + asset.size())), "asset.version",
                      std::string("`") + version + "`: pelt reads glTF 2.0");
  }
  const std::string minor = R"("asset":{"version":"2.1"},)";
  EXPECT_EQ(load_mesh_file(dir.write("minor.gltf", "{" + minor + text.substr(1 + asset.size()))).mesh.triangle_count(),
            1u);
}

TEST(MeshLoader, GltfTrsAndComputedNormals) {
  TempDir dir;
  const LoadedMesh l = load_mesh_file(dir.write("ok.gltf", tiny_gltf(0.0f, 2)));
  ASSERT_EQ(l.mesh.triangle_count(), 1u);
  EXPECT_EQ(l.mesh.positions[1], glm::vec3(12, 0, 0));  // scale 2 then translate 10
  EXPECT_EQ(l.mesh.normals[0], glm::vec3(0, 0, 1));
  EXPECT_TRUE(l.warnings.empty()) << ::testing::PrintToString(l.warnings);  // none given, none replaced
}

// A primitive without NORMAL gets flat normals, as the glTF specification asks (3.7.2.1): each
// triangle its own corners with its face's normal, here a quad folded along its diagonal. A
// primitive with NORMAL keeps the file's, in the same file, without a warning. Until 2026-11-26
// pelt smoothed the shared corners and replaced every given normal with a computed one.
TEST(MeshLoader, GltfPrimitivesWithoutNormalsAreFlat) {
  TempDir dir;
  // Four float3 positions: the folded quad (0,0,0) (1,0,0) (1,1,1) (0,1,0), whose diagonal
  // 0-2 joins two triangles at an angle; then the normals of the second primitive, all +z;
  // then six uint16 indices.
  const float data[24] = {0, 0, 0, 1, 0, 0, 1, 1, 1, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  std::string bytes(reinterpret_cast<const char*>(data), sizeof data);
  bytes.append(reinterpret_cast<const char*>(idx), sizeof idx);
  const std::string text = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
  "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":2},
                           {"attributes":{"POSITION":0,"NORMAL":1},"indices":2}]}],
  "buffers":[{"byteLength":108,"uri":"data:application/octet-stream;base64,)" + base64(bytes) + R"("}],
  "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":48},
                 {"buffer":0,"byteOffset":96,"byteLength":12}],
  "accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,1]},
               {"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"},
               {"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}]})";
  const LoadedMesh l = load_mesh_file(dir.write("folded.gltf", text));
  EXPECT_TRUE(l.warnings.empty()) << ::testing::PrintToString(l.warnings);
  ASSERT_EQ(l.mesh.triangle_count(), 4u);
  ASSERT_EQ(l.mesh.vertex_count(), 6u + 4u);  // the flat primitive's corners, the smooth one's four
  // The faces' normals: (1,0,0) x (1,1,1) and (1,1,1) x (0,1,0), normalised.
  const glm::vec3 expected[2] = {glm::normalize(glm::vec3(0, -1, 1)), glm::normalize(glm::vec3(-1, 0, 1))};
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = l.mesh.indices[3 * t + k];
      EXPECT_EQ(v, uint32_t(3 * t + k)) << "corners of their own";
      EXPECT_NEAR(glm::length(l.mesh.normals[v] - expected[t]), 0.0f, 1e-6f) << t << " " << k;
    }
  EXPECT_EQ(l.mesh.positions[5], glm::vec3(0, 1, 0));  // the second triangle's third corner
  for (int t = 2; t < 4; ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(l.mesh.normals[l.mesh.indices[3 * t + k]], glm::vec3(0, 0, 1));
}

TEST(MeshLoader, GltfNanPosition) {
  TempDir dir;
  expect_load_error(dir.write("nan.gltf", tiny_gltf(NAN, 2)), "meshes[0].primitives[0].attributes.POSITION[0]",
                    "position is NaN");
}

TEST(MeshLoader, GltfIndexOutOfRange) {
  TempDir dir;
  expect_load_error(dir.write("idx.gltf", tiny_gltf(0.0f, 7)), "meshes[0].primitives[0].indices[2]",
                    "index 7 out of range (3 vertices)");
}

// tiny_gltf with `from` replaced by `to` (each must occur once).
std::string edited_gltf(const std::string& from, const std::string& to, float x0 = 0.0f, uint16_t i2 = 2) {
  std::string text = tiny_gltf(x0, i2);
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

// append_triangles drops the indices a triangle list has left over, and a strip's or fan's
// one or two: the file's triangles would be drawn short without a word.
TEST(MeshLoader, GltfIndexCountMustMakeWholeTriangles) {
  TempDir dir;
  const std::string indices = R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"})";
  const std::string view = R"({"buffer":0,"byteOffset":36,"byteLength":6})";
  const std::string four = R"({"buffer":0,"byteOffset":36,"byteLength":8})";
  std::string text = edited_gltf(view, four);
  const auto count = [&](int n) {
    return R"({"bufferView":1,"componentType":5123,"count":)" + std::to_string(n) + R"(,"type":"SCALAR"})";
  };
  text.replace(text.find(indices), indices.size(), count(4));
  expect_load_error(dir.write("four.gltf", text), "accessors[1].count",
                    "4 indices do not make whole triangles: a triangle list takes a multiple of 3");
  // Without indices, POSITION's count is the primitive's.
  std::string no_indices = edited_gltf(R"("indices":1)", R"("mode":4)");
  const std::string positions = R"("count":3,"type":"VEC3")";
  no_indices.replace(no_indices.find(positions), positions.size(), R"("count":2,"type":"VEC3")");
  expect_load_error(dir.write("positions.gltf", no_indices), "accessors[0].count",
                    "2 positions (the primitive has no indices) do not make whole triangles");
  std::string strip = edited_gltf(R"("indices":1)", R"("indices":1,"mode":5)");
  strip.replace(strip.find(indices), indices.size(), count(2));
  expect_load_error(dir.write("strip.gltf", strip), "accessors[1].count",
                    "2 indices make no triangle: a strip takes at least 3");
  EXPECT_EQ(load_mesh_file(dir.write("fan.gltf", edited_gltf(R"("indices":1)", R"("indices":1,"mode":6)")))
                .mesh.triangle_count(),
            1u);
}

// A primitive's material that does not exist was ignored (drawn without its maps), as were the
// maps of a texture that does not exist when another primitive's texture was drawn.
TEST(MeshLoader, GltfMaterialAndTextureReferencesMustHold) {
  TempDir dir;
  expect_load_error(dir.write("material.gltf", edited_gltf(R"("indices":1)", R"("indices":1,"material":5)")),
                    "meshes[0].primitives[0].material", "material 5 does not exist");
  TempDir dir2;
  expect_load_error(two_material_gltf(dir2, R"([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
      {"pbrMetallicRoughness":{"baseColorTexture":{"index":7}}}])"),
                    "materials[1].pbrMetallicRoughness.baseColorTexture", "texture 7 does not exist");
}

// The triangle with TEXCOORD_0 (every uv 0.25) and, with `second_set`, TEXCOORD_1 (every uv
// 0.75), drawn with `material` (a JSON object) whose texture 0 is a.png beside it.
std::filesystem::path uv_set_gltf(const TempDir& dir, bool second_set, const std::string& material,
                                  const std::string& textures = R"("textures":[{"source":0}])") {
  std::filesystem::copy_file(data_dir() / "BoxTextured-glTF" / "CesiumLogoFlat.png", dir.path() / "a.png",
                             std::filesystem::copy_options::overwrite_existing);
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const float uv0[6] = {0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f};
  const float uv1[6] = {0.75f, 0.75f, 0.75f, 0.75f, 0.75f, 0.75f};
  const uint16_t idx[4] = {0, 1, 2, 0};
  std::string bytes(reinterpret_cast<const char*>(pos), sizeof pos);
  bytes.append(reinterpret_cast<const char*>(uv0), sizeof uv0);
  bytes.append(reinterpret_cast<const char*>(uv1), sizeof uv1);
  bytes.append(reinterpret_cast<const char*>(idx), sizeof idx);
  const std::string attributes =
      std::string(R"({"POSITION":0,"TEXCOORD_0":1)") + (second_set ? R"(,"TEXCOORD_1":2})" : "}");
  return dir.write("uv.gltf", R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
  "meshes":[{"primitives":[{"attributes":)" + attributes + R"(,"indices":3,"material":0}]}],
  "materials":[)" + material + R"(],)" + textures + R"(,"images":[{"uri":"a.png"}],
  "buffers":[{"byteLength":92,"uri":"data:application/octet-stream;base64,)" + base64(bytes) + R"("}],
  "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24},
                 {"buffer":0,"byteOffset":60,"byteLength":24},{"buffer":0,"byteOffset":84,"byteLength":6}],
  "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
               {"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"},
               {"bufferView":2,"componentType":5126,"count":3,"type":"VEC2"},
               {"bufferView":3,"componentType":5123,"count":3,"type":"SCALAR"}]})");
}

// A uri naming a folder, a pipe or a device is refused unread (tinygltf allocated a folder's
// "size", 2^63 bytes: std::bad_alloc, exit 1; it blocked on a pipe, and on /dev/zero read for
// ever), and so is a file larger than the whole memory budget.
TEST(MeshLoader, AFileAGltfNamesMustBeARegularFileWithinTheBudget) {
  const std::string color = R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})";
  for (const std::string kind : {"folder", "pipe", "device"}) {
    TempDir dir;
    const std::filesystem::path gltf = uv_set_gltf(dir, false, color);
    const std::filesystem::path png = dir.path() / "a.png";
    std::filesystem::remove(png);
    if (kind == "folder") std::filesystem::create_directory(png);
    if (kind == "pipe") {
      ASSERT_EQ(::mkfifo(png.c_str(), 0644), 0);
    }
    if (kind == "device") std::filesystem::create_symlink("/dev/zero", png);
    // Appended one piece at a time: GCC 12 saw a 2^63-byte copy in the one expression's temporaries
    // (-Wstringop-overflow, a false alarm in every build of this file).
    std::string reason = "`";
    reason += png.string();
    reason += "`, which it names, ";
    reason += kind == "folder" ? "is a folder" : "is not a regular file (a device, a pipe or a socket)";
    expect_load_error(gltf, "", reason);
  }
  TempDir dir;
  const std::filesystem::path gltf = uv_set_gltf(dir, false, color);
  Budget small;
  small.max_memory_bytes = 1000;  // CesiumLogoFlat.png is larger
  try {
    load_mesh_file(gltf, small);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.reason.find("which it names, is "), std::string::npos) << e.what();
    EXPECT_NE(e.reason.find("more than the budget of 1000 bytes"), std::string::npos) << e.what();
  }
}

// A map's texCoord names the uv set it is drawn with. TEXCOORD_0 was read whatever it named:
// a set the primitive does not have was silently replaced, and one it has was never read.
TEST(MeshLoader, GltfTexCoordNamesTheUvSet) {
  TempDir dir;
  const std::string color1 = R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":1}}})";
  expect_load_error(uv_set_gltf(dir, false, color1), "materials[0].pbrMetallicRoughness.baseColorTexture.texCoord",
                    "names TEXCOORD_1, which meshes[0].primitives[0] does not have");
  expect_load_error(uv_set_gltf(dir, false, R"({"normalTexture":{"index":0,"texCoord":1}})"),
                    "materials[0].normalTexture.texCoord", "names TEXCOORD_1");
  expect_load_error(
      uv_set_gltf(dir, true, R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":1}},
                               "normalTexture":{"index":0}})"),
      "materials[0].normalTexture.texCoord",
      "TEXCOORD_0 is not the baseColorTexture's TEXCOORD_1: pelt draws both maps with one uv set");
  const LoadedMesh one = load_mesh_file(uv_set_gltf(dir, true, color1));
  ASSERT_EQ(one.mesh.uvs.size(), 3u);
  for (const glm::vec2& uv : one.mesh.uvs) EXPECT_EQ(uv, glm::vec2(0.75f));
  EXPECT_EQ(one.color_map().path, dir.path() / "a.png");
  const LoadedMesh zero =
      load_mesh_file(uv_set_gltf(dir, true, R"({"normalTexture":{"index":0,"texCoord":0}})"));
  ASSERT_EQ(zero.mesh.uvs.size(), 3u);
  for (const glm::vec2& uv : zero.mesh.uvs) EXPECT_EQ(uv, glm::vec2(0.25f));
}

// Where a map lies: its texture's sampler's wrapS and wrapT (10497 repeat, 33071 clamp to edge,
// 33648 mirrored repeat; none: repeat) and KHR_texture_transform on its texture info (offset,
// rotation, scale, composed T R S as the extension says; its texCoord overrides the info's).
// Were ignored: a mirrored or clamped map repeated, a tiled or rotated one lay as the uvs say.
TEST(MeshLoader, GltfSamplersAndTextureTransformPlaceTheMaps) {
  TempDir dir;
  const std::string color = R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})";
  const LoadedMesh plain = load_mesh_file(uv_set_gltf(dir, false, color));
  EXPECT_EQ(plain.color_map().placement, MapPlacement{});
  const LoadedMesh wrapped = load_mesh_file(uv_set_gltf(
      dir, false, color, R"("textures":[{"source":0,"sampler":0}],"samplers":[{"wrapS":33648,"wrapT":33071}])"));
  EXPECT_EQ(wrapped.color_map().placement.wrap_u, raster::Wrap::Mirror);
  EXPECT_EQ(wrapped.color_map().placement.wrap_v, raster::Wrap::Clamp);
  EXPECT_FALSE(wrapped.color_map().placement.transforms());
  const LoadedMesh defaults = load_mesh_file(
      uv_set_gltf(dir, false, color, R"("textures":[{"source":0,"sampler":0}],"samplers":[{"magFilter":9729}])"));
  EXPECT_EQ(defaults.color_map().placement, MapPlacement{});

  const std::string transformed = R"({"normalTexture":{"index":0,"extensions":{"KHR_texture_transform":
      {"offset":[0.5,0.25],"rotation":1.5707963267948966,"scale":[2,4]}}}})";
  const LoadedMesh t = load_mesh_file(uv_set_gltf(dir, false, transformed));
  // u' = 2 cos(r) u + 4 sin(r) v + 0.5, v' = -2 sin(r) u + 4 cos(r) v + 0.25
  const std::array<float, 6> want{0.0f, 4.0f, 0.5f, -2.0f, 0.0f, 0.25f};
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(t.normal_map().placement.m[size_t(k)], want[size_t(k)], 1e-6) << k;
  EXPECT_EQ(t.normal_map().placement.wrap_u, raster::Wrap::Repeat);

  // The extension's texCoord picks the uv set.
  const LoadedMesh set1 = load_mesh_file(uv_set_gltf(
      dir, true, R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":0,
                   "extensions":{"KHR_texture_transform":{"texCoord":1}}}}})"));
  ASSERT_EQ(set1.mesh.uvs.size(), 3u);
  EXPECT_EQ(set1.mesh.uvs[0], glm::vec2(0.75f));
  expect_load_error(uv_set_gltf(dir, false, R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0,
                                  "extensions":{"KHR_texture_transform":{"texCoord":1}}}}})"),
                    "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform.texCoord",
                    "names TEXCOORD_1");

  // Malformed: named by their JSON path.
  const std::string base = "materials[0].normalTexture.extensions.KHR_texture_transform";
  const auto with = [&](const std::string& ext) {
    return uv_set_gltf(dir, false, R"({"normalTexture":{"index":0,"extensions":{"KHR_texture_transform":)" + ext + "}}}");
  };
  expect_load_error(with(R"({"offset":[1]})"), base + ".offset", "expected an array of 2 numbers");
  expect_load_error(with(R"({"scale":[1,"2"]})"), base + ".scale[1]", "expected a number, got a string");
  expect_load_error(with(R"({"rotation":"90"})"), base + ".rotation", "expected a number");
  expect_load_error(with(R"({"offset":[1e300,0]})"), base + ".offset[0]", "too large");
  expect_load_error(with(R"({"texCoord":-1})"), base + ".texCoord", "must be in [0, ");
  expect_load_error(with("[1]"), base, "expected an object");
  expect_load_error(with(R"({"scale":[1,0]})"), base + ".scale[1]", "a scale of 0");
  expect_load_error(with(R"({"scale":[1e-50,1]})"), base + ".scale[0]", "a scale of 1e-50 shrinks the map");
  // A sampler index past the samplers drew the map with the default repeat, without a word.
  expect_load_error(uv_set_gltf(dir, false, color, R"("textures":[{"source":0,"sampler":3}],"samplers":[{}])"),
                    "textures[0].sampler", "sampler 3 does not exist (the file has 1)");
  expect_load_error(uv_set_gltf(dir, false, color, R"("textures":[{"source":0,"sampler":0}])"),
                    "textures[0].sampler", "sampler 0 does not exist (the file has 0)");
  expect_load_error(uv_set_gltf(dir, false, color,
                                R"("textures":[{"source":0,"sampler":0}],"samplers":[{"wrapS":33333}])"),
                    "samplers[0].wrapS", "33333 is no wrap mode");
  expect_load_error(uv_set_gltf(dir, false, color,
                                R"("textures":[{"source":0,"sampler":0}],"samplers":[{"wrapT":-1}])"),
                    "samplers[0].wrapT", "must be in [0, ");
}

// What a drawn material asks for that pelt does not draw is said, once per material: a base
// colour factor's colour (the scene's colour is used), emission. A material at its defaults,
// or whose factor differs in alpha alone, says nothing; MASK and BLEND are drawn.
TEST(MeshLoader, GltfMaterialFieldsNotDrawnAreNamed) {
  TempDir dir;
  const LoadedMesh plain = load_mesh_file(uv_set_gltf(dir, false, R"({"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,1]}})"));
  EXPECT_TRUE(plain.warnings.empty()) << ::testing::PrintToString(plain.warnings);
  // An emissive texture without a factor emits nothing (the factor is [0, 0, 0] unless given), and
  // the factor's alpha means nothing to an opaque material.
  const LoadedMesh dark = load_mesh_file(uv_set_gltf(
      dir, false, R"({"emissiveTexture":{"index":0},"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.5]}})"));
  EXPECT_TRUE(dark.warnings.empty()) << ::testing::PrintToString(dark.warnings);
  const LoadedMesh l = load_mesh_file(uv_set_gltf(
      dir, false, R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorFactor":[0.5,1,1,1]},"emissiveFactor":[0,0.2,0]})"));
  ASSERT_EQ(l.warnings.size(), 2u) << ::testing::PrintToString(l.warnings);
  EXPECT_EQ(l.warnings[0], "materials[0].pbrMetallicRoughness.baseColorFactor [0.5, 1, 1, 1] is not applied to the "
                           "colour: the scene's material colour is the albedo (times the map)");
  EXPECT_EQ(l.warnings[1], "materials[0] emits light (emissiveFactor), which pelt does not draw");
}

// alphaMode MASK and BLEND are the set's alpha, with alphaCutoff and the factor's alpha (until
// 2026-11-27 warned of and drawn opaque); OPAQUE keeps the defaults whatever the factor says.
TEST(MeshLoader, GltfAlphaModesAreTheSetsAlpha) {
  TempDir dir;
  const LoadedMesh mask = load_mesh_file(uv_set_gltf(
      dir, false, R"({"alphaMode":"MASK","alphaCutoff":0.3,"pbrMetallicRoughness":{"baseColorTexture":{"index":0},
                      "baseColorFactor":[1,1,1,0.8]}})"));
  ASSERT_EQ(mask.maps.size(), 1u);
  EXPECT_EQ(mask.maps[0].alpha_mode, AlphaMode::mask);
  EXPECT_EQ(mask.maps[0].alpha_cutoff, 0.3f);
  EXPECT_EQ(mask.maps[0].alpha_factor, 0.8f);
  const LoadedMesh cutoff = load_mesh_file(uv_set_gltf(dir, false, R"({"alphaMode":"MASK"})"));
  ASSERT_EQ(cutoff.maps.size(), 1u);  // no map, but alpha: a set
  EXPECT_EQ(cutoff.maps[0].alpha_cutoff, 0.5f);  // the specification's default
  const LoadedMesh blend = load_mesh_file(uv_set_gltf(
      dir, false, R"({"alphaMode":"BLEND","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.25]}})"));
  ASSERT_EQ(blend.maps.size(), 1u);
  EXPECT_EQ(blend.maps[0].alpha_mode, AlphaMode::blend);
  EXPECT_EQ(blend.maps[0].alpha_factor, 0.25f);
  const LoadedMesh opaque = load_mesh_file(uv_set_gltf(
      dir, false, R"({"alphaMode":"OPAQUE","alphaCutoff":0.9,"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.25]}})"));
  EXPECT_TRUE(opaque.maps.empty());
}

// The alpha fields are read as written: a word that is no mode, a cutoff outside [0, 1] (above
// 1 nothing would be drawn) and a factor outside [0, 1] are refused, naming the field.
TEST(MeshLoader, GltfAlphaFieldsAreChecked) {
  TempDir dir;
  expect_load_error(uv_set_gltf(dir, false, R"({"alphaMode":"CUTOUT"})"), "materials[0].alphaMode",
                    "\"CUTOUT\" is no alpha mode: OPAQUE, MASK or BLEND");
  expect_load_error(uv_set_gltf(dir, false, R"({"alphaMode":"MASK","alphaCutoff":1.5})"), "materials[0].alphaCutoff",
                    "1.5 is no cutoff: a number from 0 to 1");
  expect_load_error(uv_set_gltf(dir, false, R"({"alphaCutoff":-0.5})"), "materials[0].alphaCutoff",
                    "-0.5 is no cutoff");
  // Above 1 on a material that does not cut out: valid, and not drawn.
  EXPECT_TRUE(load_mesh_file(uv_set_gltf(dir, false, R"({"alphaMode":"BLEND","alphaCutoff":1.5})")).warnings.empty());
  expect_load_error(uv_set_gltf(dir, false, R"({"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,2]}})"),
                    "materials[0].pbrMetallicRoughness.baseColorFactor[3]", "2 is outside [0, 1]");
  expect_load_error(uv_set_gltf(dir, false, R"({"pbrMetallicRoughness":{"baseColorFactor":[1,1,1]}})"),
                    "materials[0].pbrMetallicRoughness.baseColorFactor", "must be an array of 4 numbers");
}

// tinygltf reads an optional integer it cannot take as absent and keeps -1 where -1 means
// absent: `"mode": -1` was drawn as triangles, `"byteOffset": -4` read from offset 0.
TEST(MeshLoader, GltfIntegerFieldsAreCheckedAsWritten) {
  TempDir dir;
  expect_load_error(dir.write("mode.gltf", edited_gltf(R"("indices":1)", R"("indices":1,"mode":-1)")),
                    "meshes[0].primitives[0].mode", "must be in [0, 6], got -1");
  expect_load_error(dir.write("mode7.gltf", edited_gltf(R"("indices":1)", R"("indices":1,"mode":7)")),
                    "meshes[0].primitives[0].mode", "must be in [0, 6], got 7");
  const std::string accessor = R"({"bufferView":0,)";
  expect_load_error(dir.write("offset.gltf", edited_gltf(accessor, R"({"bufferView":0,"byteOffset":-4,)")),
                    "accessors[0].byteOffset", "must not be negative, got -4");
  expect_load_error(dir.write("float.gltf", edited_gltf(accessor, R"({"bufferView":0,"byteOffset":4.0,)")),
                    "accessors[0].byteOffset", "expected an integer, got 4.0");
  expect_load_error(dir.write("view.gltf", edited_gltf(R"("byteOffset":36,)", R"("byteOffset":-36,)")),
                    "bufferViews[1].byteOffset", "must not be negative, got -36");
  expect_load_error(dir.write("material.gltf", edited_gltf(R"("indices":1)", R"("indices":1,"material":-1)")),
                    "meshes[0].primitives[0].material", "must be in [0, 2147483647], got -1");
  // tinygltf would truncate this one to 0.
  expect_load_error(dir.write("wide.gltf", edited_gltf(R"("indices":1)", R"("indices":4294967297)")),
                    "meshes[0].primitives[0].indices", "must be in [0, 2147483647], got 4294967297");
  expect_load_error(dir.write("mesh.gltf", edited_gltf(R"({"mesh":0,)", R"({"mesh":"0",)")), "nodes[0].mesh",
                    "expected an integer, got a string");
  // Given as written, the same fields load.
  EXPECT_EQ(load_mesh_file(dir.write("ok.gltf", edited_gltf(accessor, R"({"bufferView":0,"byteOffset":0,)")))
                .mesh.triangle_count(),
            1u);
}

// tinygltf reads an index list up to the first element it cannot take (a fraction, a string)
// and drops the rest, ignores a list that is not an array, and wraps an index past int's range:
// `"children": [1, 4294967297]` drew node 1 twice, `"nodes": [0, 1.5]` dropped the 1.5.
TEST(MeshLoader, GltfIndexListsAreCheckedAsWritten) {
  TempDir dir;
  // Node 0 a parent of `children` (JSON), node 1 the triangle's.
  const auto parent = [](const std::string& children) {
    return edited_gltf(R"("nodes":[{"mesh":0,)", R"("nodes":[{"children":)" + children + R"(},{"mesh":0,)");
  };
  EXPECT_EQ(load_mesh_file(dir.write("parent.gltf", parent("[1]"))).mesh.triangle_count(), 1u);
  expect_load_error(dir.write("wrapped.gltf", parent("[1, 4294967297]")), "nodes[0].children[1]",
                    "must be in [0, 2147483647], got 4294967297");
  expect_load_error(dir.write("cycle.gltf", parent("[-4294967296]")), "nodes[0].children[0]",
                    "must be in [0, 2147483647], got -4294967296");
  expect_load_error(dir.write("negative.gltf", parent("[1, -1]")), "nodes[0].children[1]",
                    "must be in [0, 2147483647], got -1");
  expect_load_error(dir.write("fraction.gltf", parent("[1.5, 1]")), "nodes[0].children[0]",
                    "expected an integer, got 1.5");
  expect_load_error(dir.write("string.gltf", parent(R"([1, "1"])")), "nodes[0].children[1]",
                    "expected an integer, got a string");
  expect_load_error(dir.write("scalar.gltf", parent("1")), "nodes[0].children",
                    "expected an array of indices, got a number");
  const std::string scene = R"("scenes":[{"nodes":[0]}])";
  expect_load_error(dir.write("scene_wrapped.gltf", edited_gltf(scene, R"("scenes":[{"nodes":[4294967296]}])")),
                    "scenes[0].nodes[0]", "must be in [0, 2147483647], got 4294967296");
  expect_load_error(dir.write("scene_fraction.gltf", edited_gltf(scene, R"("scenes":[{"nodes":[0, 1.5]}])")),
                    "scenes[0].nodes[1]", "expected an integer, got 1.5");
  expect_load_error(dir.write("scene_string.gltf", edited_gltf(scene, R"("scenes":[{"nodes":["0"]}])")),
                    "scenes[0].nodes[0]", "expected an integer, got a string");
  expect_load_error(dir.write("scene_object.gltf", edited_gltf(scene, R"("scenes":[{"nodes":{"0":0}}])")),
                    "scenes[0].nodes", "expected an array of indices, got an object");
  // A primitive's attributes are indices too: POSITION 4294967296 was read as accessor 0.
  expect_load_error(dir.write("attribute.gltf", edited_gltf(R"("POSITION":0)", R"("POSITION":4294967296)")),
                    "meshes[0].primitives[0].attributes.POSITION", "must be in [0, 2147483647], got 4294967296");
  // The default scene's index, a lone integer, was checked already; no test named it.
  expect_load_error(
      dir.write("scene_index.gltf", edited_gltf(R"("scene":0,)", R"("scene":-4294967296,)")), "scene",
      "must be in [0, 2147483647], got -4294967296");
}

// tinyGLTF's triangle as a GLB of header version `version`, its JSON the only chunk.
std::string tiny_glb(uint32_t version) {
  std::string json = tiny_gltf(0.0f, 2);
  json.resize((json.size() + 3) / 4 * 4, ' ');
  const auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  return "glTF" + u32(version) + u32(uint32_t(20 + json.size())) + u32(uint32_t(json.size())) + "JSON" + json;
}

// tinygltf reads any GLB header version as glTF 2.0's layout.
TEST(MeshLoader, GlbVersionMustBeTwo) {
  TempDir dir;
  expect_load_error(dir.write("v1.glb", tiny_glb(1)), "header.version",
                    "GLB version 1: pelt reads glTF 2.0 binaries (version 2)");
  expect_load_error(dir.write("v3.glb", tiny_glb(3)), "header.version", "GLB version 3");
  EXPECT_EQ(load_mesh_file(dir.write("v2.glb", tiny_glb(2))).mesh.triangle_count(), 1u);
}

TEST(MeshLoader, ValidateMeshNamesTheElement) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2};
  EXPECT_NO_THROW(validate_mesh(m, "m"));
  m.positions[1].y = INFINITY;
  try {
    validate_mesh(m, "m");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "m: vertex 1: position is infinite");
  }
  m.positions[1].y = 0;
  m.indices[2] = 3;
  try {
    validate_mesh(m, "m");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "m: triangle 0: index 3 out of range (3 vertices)");
  }
  m.indices.clear();
  EXPECT_THROW(validate_mesh(m, "m"), InputError);
}

}  // namespace mesh_loader_test
}  // namespace pelt::io
