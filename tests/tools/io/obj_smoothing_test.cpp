// An OBJ's smoothing groups (`s N`, `s off`) decide its computed normals: a position's copies in
// one group share a normal, two groups meet at a hard edge, a face in no group is flat. Before,
// pelt ignored them and smoothed every such file whole.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/tools/io/expect_load_error.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/mesh_loader.h"

namespace pelt::io {
namespace {

using testing::expect_load_error;

// A roof: two square slopes meeting at a ridge (x from 0 to 1 at y = 1), the first facing
// (0, 1, -1), the second (0, 1, 1). `first` and `second` are written before each face's `f`
// record (an `s` record, or nothing); `vt`: texture coordinates with a seam along the ridge.
std::string roof(const std::string& first, const std::string& second, bool vt = false) {
  std::string s = "v 0 1 0\nv 1 1 0\nv 0 0 -1\nv 1 0 -1\nv 0 0 1\nv 1 0 1\n";
  if (!vt) return s + first + "f 1 2 4 3\n" + second + "f 5 6 2 1\n";
  s += "vt 0 1\nvt 1 1\nvt 0 0\nvt 1 0\nvt 0 0.5\nvt 1 0.5\n";
  return s + first + "f 1/1 2/2 4/4 3/3\n" + second + "f 5/3 6/4 2/6 1/5\n";
}

// The roof with one `vn` record, named at every corner of its first face (group 1); the second
// face's record as given (group 2).
std::string roof_with_normal(const std::string& vn, const std::string& second_face) {
  return std::string("v 0 1 0\nv 1 1 0\nv 0 0 -1\nv 1 0 -1\nv 0 0 1\nv 1 0 1\nvn ")
      .append(vn)
      .append("\ns 1\nf 1//1 2//1 4//1 3//1\ns 2\n")
      .append(second_face)
      .append("\n");
}

const glm::vec3 kFirst = glm::normalize(glm::vec3(0, 1, -1)), kSecond = glm::normalize(glm::vec3(0, 1, 1));

// The face normal of every vertex that only faces of that normal use, by side (z < 0: the first
// slope; z > 0: the second; the ridge, z = 0, is checked by the caller).
void expect_flat_slopes(const Mesh& m) {
  for (size_t i = 0; i < m.vertex_count(); ++i) {
    if (m.positions[i].z == 0.0f) continue;
    const glm::vec3 want = m.positions[i].z < 0.0f ? kFirst : kSecond;
    EXPECT_LT(glm::distance(m.normals[i], want), 1e-6f) << "vertex " << i;
  }
}

TEST(ObjSmoothingGroups, TwoGroupsMeetAtAHardEdge) {
  TempDir dir;
  const LoadedMesh l = load_mesh_file(dir.write("hard.obj", roof("s 1\n", "s 2\n")));
  ASSERT_EQ(l.mesh.vertex_count(), 8u);  // the ridge's two vertices, once in each group
  expect_flat_slopes(l.mesh);
  for (size_t i = 0; i < 8; ++i) {
    if (l.mesh.positions[i].z != 0.0f) continue;
    // A ridge copy takes the normal of the face that names it.
    bool first_face = false;
    for (size_t c = 0; c < 6; ++c) first_face |= l.mesh.indices[c] == i;
    EXPECT_LT(glm::distance(l.mesh.normals[i], first_face ? kFirst : kSecond), 1e-6f) << "vertex " << i;
  }
  EXPECT_TRUE(l.warnings.empty());
}

// One group, or no `s` record at all (pelt's way before groups: a scan such as the bunny has
// none), smooths across the ridge: the same vertices and normals either way.
TEST(ObjSmoothingGroups, OneGroupSmoothsAsAFileWithoutGroups) {
  TempDir dir;
  const LoadedMesh grouped = load_mesh_file(dir.write("one.obj", roof("s 1\n", "")));
  const LoadedMesh plain = load_mesh_file(dir.write("none.obj", roof("", "")));
  ASSERT_EQ(grouped.mesh.vertex_count(), 6u);
  EXPECT_EQ(grouped.mesh.positions, plain.mesh.positions);
  EXPECT_EQ(grouped.mesh.indices, plain.mesh.indices);
  EXPECT_EQ(grouped.mesh.normals, plain.mesh.normals);
  for (size_t i = 0; i < 2; ++i) {  // the ridge leans toward neither slope's normal alone
    EXPECT_GT(grouped.mesh.normals[i].y, 0.9f);
    EXPECT_LT(std::abs(grouped.mesh.normals[i].z), 0.5f);
  }
}

// `s off` and `s 0` (the specification's two spellings), and a face before the file's first `s`
// record, are in no group: flat, each face its own copies of its corners.
TEST(ObjSmoothingGroups, FacesInNoGroupAreFlat) {
  TempDir dir;
  for (const auto& [name, first, second] :
       std::vector<std::array<std::string, 3>>{{"off.obj", "s off\n", ""},
                                              {"zero.obj", "s 0\n", ""},
                                              {"before.obj", "", "s 3\n"},
                                              {"between.obj", "s 1\n", "s off\n"}}) {
    const LoadedMesh l = load_mesh_file(dir.write(name, roof(first, second)));
    EXPECT_EQ(l.mesh.vertex_count(), 8u) << name;
    expect_flat_slopes(l.mesh);
    size_t flat_ridge = 0;
    for (size_t i = 0; i < l.mesh.vertex_count(); ++i)
      if (l.mesh.positions[i].z == 0.0f)
        flat_ridge += glm::distance(l.mesh.normals[i], kFirst) < 1e-6f ||
                      glm::distance(l.mesh.normals[i], kSecond) < 1e-6f;
    EXPECT_EQ(flat_ridge, 4u) << name;
  }
}

// Within a group, the copies a texture seam makes still share one normal (per position, as
// without groups); across groups they do not.
TEST(ObjSmoothingGroups, ASeamInsideAGroupStaysSmooth) {
  TempDir dir;
  const LoadedMesh one = load_mesh_file(dir.write("seam.obj", roof("s 1\n", "", true)));
  ASSERT_EQ(one.mesh.vertex_count(), 8u);  // split by the texture seam along the ridge
  std::vector<glm::vec3> ridge;
  for (size_t i = 0; i < one.mesh.vertex_count(); ++i)
    if (one.mesh.positions[i] == glm::vec3(0, 1, 0)) ridge.push_back(one.mesh.normals[i]);
  ASSERT_EQ(ridge.size(), 2u);
  EXPECT_EQ(ridge[0], ridge[1]);
  EXPECT_GT(ridge[0].y, 0.9f);

  const LoadedMesh two = load_mesh_file(dir.write("seam2.obj", roof("s 1\n", "s 2\n", true)));
  ASSERT_EQ(two.mesh.vertex_count(), 8u);
  expect_flat_slopes(two.mesh);
  ridge.clear();
  for (size_t i = 0; i < two.mesh.vertex_count(); ++i)
    if (two.mesh.positions[i] == glm::vec3(0, 1, 0)) ridge.push_back(two.mesh.normals[i]);
  ASSERT_EQ(ridge.size(), 2u);
  EXPECT_LT(glm::distance(ridge[0], kFirst), 1e-6f);  // the first face names its copy first
  EXPECT_LT(glm::distance(ridge[1], kSecond), 1e-6f);
}

// CRLF files, and a lone carriage return (tinyobjloader ends a line there too): every `s` record
// is checked as tinyobjloader reads it, none hides inside a comment's line.
TEST(ObjSmoothingGroups, LineEndsAsTinyobjloaderReadsThem) {
  TempDir dir;
  std::string crlf;
  for (const char c : roof("s 1\n", "s 2\n")) {
    if (c == '\n') crlf.push_back('\r');
    crlf.push_back(c);
  }
  const LoadedMesh l = load_mesh_file(dir.write("crlf.obj", crlf));
  EXPECT_EQ(l.mesh.vertex_count(), 8u);
  expect_flat_slopes(l.mesh);
  expect_load_error(dir.write("bare_crlf.obj", roof("s\r\n", "")), "s 1", "needs `off` or a group number");
  expect_load_error(dir.write("lone_cr.obj", roof("# a note\rs foo\n", "")), "s 1", "`foo` is not a smoothing group");
  // `s` after the last face changes nothing.
  std::string after = roof("s 1\n", "");
  after.append("s 2\n");
  EXPECT_EQ(load_mesh_file(dir.write("after.obj", after)).mesh.vertex_count(), 6u);
}

// A file that gives some normals: all are computed (with the loader's warning), within the groups.
TEST(ObjSmoothingGroups, MixedNormalsAreComputedWithinTheGroups) {
  TempDir dir;
  const LoadedMesh l = load_mesh_file(dir.write("mixed.obj", roof_with_normal("0 1 0", "f 5 6 2 1")));
  EXPECT_EQ(l.warnings,
            std::vector<std::string>{"not every vertex has a normal: all normals computed from the triangles"});
  ASSERT_EQ(l.mesh.vertex_count(), 8u);
  expect_flat_slopes(l.mesh);
  // A zero-length given normal has them all computed too, and the groups still decide.
  const LoadedMesh z = load_mesh_file(dir.write("zero.obj", roof_with_normal("0 0 0", "f 5//1 6//1 2//1 1//1")));
  ASSERT_EQ(z.mesh.vertex_count(), 8u);
  expect_flat_slopes(z.mesh);
  for (size_t i = 0; i < 8; ++i) {
    if (z.mesh.positions[i].z != 0.0f) continue;
    EXPECT_TRUE(glm::distance(z.mesh.normals[i], kFirst) < 1e-6f || glm::distance(z.mesh.normals[i], kSecond) < 1e-6f)
        << i;
  }
}

// The file's own normals win: groups only decide normals that pelt computes.
TEST(ObjSmoothingGroups, GivenNormalsAreKept) {
  TempDir dir;
  const LoadedMesh l = load_mesh_file(dir.write("given.obj", roof_with_normal("0 1 0", "f 5//1 6//1 2//1 1//1")));
  EXPECT_EQ(l.mesh.vertex_count(), 6u);
  for (const glm::vec3& n : l.mesh.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));
}

// tinyobjloader reads any word, and a negative number, as group 0 without a word: the faces
// after it would be flat by accident.
TEST(ObjSmoothingGroups, AMalformedGroupIsAnError) {
  TempDir dir;
  expect_load_error(dir.write("on.obj", roof("s on\n", "")), "s 1", "`on` is not a smoothing group");
  expect_load_error(dir.write("neg.obj", roof("s 1\n", "s -2\n")), "s 2", "`-2` is not a smoothing group");
  expect_load_error(dir.write("two.obj", roof("s 1 2\n", "")), "s 1", "`1 2` is not a smoothing group");
  // tinyobjloader reads the group into an int and a negative one as 0: past INT_MAX it would be off.
  expect_load_error(dir.write("big.obj", roof("s 2147483648\n", "")), "s 1", "up to 2147483647");
  EXPECT_EQ(load_mesh_file(dir.write("max.obj", roof("s 2147483647\n", "s 1\n"))).mesh.vertex_count(), 8u);
  expect_load_error(dir.write("bare.obj", roof("s\n", "")), "s 1", "needs `off` or a group number");
  expect_load_error(dir.write("line.obj", roof("s 1\n", "s one\n")), "s 2", "(line 9)");
  // A comment after the group is not part of it; `+` as an index allows.
  const LoadedMesh l = load_mesh_file(dir.write("comment.obj", roof("s +1 # left\n", "s 2\t# right\n")));
  EXPECT_EQ(l.mesh.vertex_count(), 8u);
}

}  // namespace
}  // namespace pelt::io
