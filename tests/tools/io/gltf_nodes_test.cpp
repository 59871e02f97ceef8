// glTF nodes beyond a plain transform: a node scaled to nothing (how files hide one), a
// transform that flattens its mesh, skins (the mesh placed by its joints, the node's own
// transform ignored, as the specification asks), morph targets at their default weights, and
// node matrices the specification does not allow.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "tests/tools/io/base64.h"
#include "tests/tools/io/expect_load_error.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/input_error.h"
#include "tools/io/mesh_loader.h"

namespace pelt::io {
namespace {

using testing::expect_load_error;
namespace fs = std::filesystem;

constexpr int kFloat = 5126, kUnsignedByte = 5121, kUnsignedShort = 5123;

// One buffer, a bufferView and an accessor per block of data; the rest of the file (nodes,
// meshes, skins) is given as JSON.
struct GltfFile {
  std::string bytes;
  std::vector<std::string> views, accessors;

  template <class T>
  int add(const std::vector<T>& data, int component, const char* type, bool normalized = false) {
    while (bytes.size() % 4 != 0) bytes.push_back('\0');
    const size_t offset = bytes.size(), size = data.size() * sizeof(T);
    bytes.append(reinterpret_cast<const char*>(data.data()), size);
    const int components = std::string(type) == "SCALAR" ? 1
                           : std::string(type) == "VEC2" ? 2
                           : std::string(type) == "VEC3" ? 3
                           : std::string(type) == "VEC4" ? 4
                                                         : 16;
    views.push_back(R"({"buffer":0,"byteOffset":)" + std::to_string(offset) + R"(,"byteLength":)" +
                    std::to_string(size) + "}");
    accessors.push_back(R"({"bufferView":)" + std::to_string(views.size() - 1) + R"(,"componentType":)" +
                        std::to_string(component) + R"(,"count":)" + std::to_string(data.size() / components) +
                        R"(,"type":")" + type + "\"" + (normalized ? R"(,"normalized":true)" : "") + "}");
    return static_cast<int>(accessors.size() - 1);
  }

  std::string text(const std::string& rest) const {
    auto list = [](const std::vector<std::string>& items) {
      std::string out;
      for (const std::string& s : items) out += (out.empty() ? "" : ",") + s;
      return "[" + out + "]";
    };
    return R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":)" + std::to_string(bytes.size()) +
           R"(,"uri":"data:application/octet-stream;base64,)" + base64(bytes) + R"("}],"bufferViews":)" +
           list(views) + R"(,"accessors":)" + list(accessors) + "," + rest + "}";
  }
};

// The triangle (-1,-1,0) (1,-1,0) (0,1,0) with the given normal at every corner: accessors 0 and 1.
GltfFile triangle(glm::vec3 normal) {
  GltfFile f;
  f.add(std::vector<float>{-1, -1, 0, 1, -1, 0, 0, 1, 0}, kFloat, "VEC3");
  f.add(std::vector<float>{normal.x, normal.y, normal.z, normal.x, normal.y, normal.z, normal.x, normal.y, normal.z},
        kFloat, "VEC3");
  return f;
}

void expect_near(glm::vec3 a, glm::vec3 b, const std::string& what) {
  EXPECT_LT(glm::length(a - b), 1e-5f) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") against (" << b.x
                                       << ", " << b.y << ", " << b.z << ")";
}

// A node scaled to 0 is hidden: nothing of it is drawn, nothing of it sizes the mesh, and the
// file's normals stay the file's. Until 2026-11-27 its inverse transpose was infinite, so every
// normal of the file was recomputed (a lit triangle turned from N.L 0.8 to 1), and its
// collapsed corners stretched the bounds and uv area that size the fur.
TEST(GltfNodes, ANodeScaledToNothingIsNotDrawn) {
  TempDir dir;
  const glm::vec3 n = glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f));
  const std::string rest = R"("scene":0,"scenes":[{"nodes":[0,1]}],
    "nodes":[{"mesh":0},{"mesh":0,"translation":[20,0,0],"scale":[0,0,0]}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1}}]}])";
  const LoadedMesh l = load_mesh_file(dir.write("hidden.gltf", triangle(n).text(rest)));
  ASSERT_EQ(l.mesh.triangle_count(), 1u);
  ASSERT_EQ(l.mesh.vertex_count(), 3u);
  for (uint32_t v = 0; v < 3; ++v) {
    expect_near(l.mesh.normals[v], n, "the file's normal");
    EXPECT_LT(l.mesh.positions[v].x, 2.0f);
  }
  ASSERT_EQ(l.warnings.size(), 1u);
  EXPECT_EQ(l.warnings[0], "nodes[1] is scaled to a point or a line: not drawn");
  // A hidden level of detail of several nodes is one warning.
  const std::string many = R"("scene":0,"scenes":[{"nodes":[0,1]}],
    "nodes":[{"mesh":0},{"scale":[0,0,0],"children":[2,3,4]},{"mesh":0},{"mesh":0},{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1}}]}])";
  const LoadedMesh lod = load_mesh_file(dir.write("lod.gltf", triangle(n).text(many)));
  EXPECT_EQ(lod.mesh.triangle_count(), 1u);
  ASSERT_EQ(lod.warnings.size(), 1u) << ::testing::PrintToString(lod.warnings);
  EXPECT_EQ(lod.warnings[0], "nodes[2] and 2 more nodes are scaled to a point or a line: not drawn");
}

// A scale of 0 along one axis flattens the mesh into a plane: its normals are the plane's,
// from the flattened faces, and the other nodes keep theirs.
TEST(GltfNodes, AFlattenedNodeTakesItsFacesNormals) {
  TempDir dir;
  const glm::vec3 n = glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f));
  const std::string rest = R"("scene":0,"scenes":[{"nodes":[0,1]}],
    "nodes":[{"mesh":0},{"mesh":0,"translation":[5,0,0],"rotation":[0.3826834,0,0,0.9238795],"scale":[1,1,0]}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1}}]}])";
  const LoadedMesh l = load_mesh_file(dir.write("flat.gltf", triangle(n).text(rest)));
  EXPECT_TRUE(l.warnings.empty()) << ::testing::PrintToString(l.warnings);
  ASSERT_EQ(l.mesh.triangle_count(), 2u);
  for (uint32_t k = 0; k < 3; ++k) expect_near(l.mesh.normals[l.mesh.indices[k]], n, "the first node's");
  // The second node squashes z (the triangle's own plane, so it keeps its shape), then turns it
  // 45 degrees about x: its normal is (0, -1, 1) / sqrt(2), whatever the file's normal says.
  const glm::vec3 plane = glm::normalize(glm::vec3(0.0f, -1.0f, 1.0f));
  for (uint32_t k = 3; k < 6; ++k) {
    const glm::vec3 got = l.mesh.normals[l.mesh.indices[k]];
    EXPECT_GT(glm::dot(got, plane), 1.0f - 1e-5f) << got.x << " " << got.y << " " << got.z;
  }
}

// A skinned mesh is placed by its joints (their world transforms times their inverse bind
// matrices, blended by the vertex's weights, normalised), and its node's own transform is
// ignored. Until 2026-11-27 the skin was ignored and the node's transform applied.
TEST(GltfNodes, ASkinPlacesTheMeshByItsJoints) {
  TempDir dir;
  GltfFile f = triangle(glm::vec3(0, 0, 1));
  const int joints = f.add(std::vector<uint8_t>{0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0}, kUnsignedByte, "VEC4");
  // Vertex 0 on joint 0, vertex 1 half on each (weights 100 and 100 of 255, normalised), vertex
  // 2 on joint 1.
  const int weights =
      f.add(std::vector<uint8_t>{255, 0, 0, 0, 100, 100, 0, 0, 255, 0, 0, 0}, kUnsignedByte, "VEC4", true);
  // Joint 1 was bound at (0, 0, 2): its inverse bind matrix moves it back.
  const int ibm = f.add(std::vector<float>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,  //
                                           1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -2, 1},
                        kFloat, "MAT4");
  const std::string rest = R"("scene":0,"scenes":[{"nodes":[0,1]}],
    "nodes":[{"mesh":0,"skin":0,"translation":[100,0,0]},
             {"translation":[0,5,0],"children":[2]},
             {"translation":[0,0,2],"rotation":[0,0,0.7071068,0.7071068]}],
    "skins":[{"joints":[1,2],"inverseBindMatrices":)" +
                           std::to_string(ibm) + R"(}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"JOINTS_0":)" +
                           std::to_string(joints) + R"(,"WEIGHTS_0":)" + std::to_string(weights) + "}}]}]";
  const LoadedMesh l = load_mesh_file(dir.write("skin.gltf", f.text(rest)));
  EXPECT_TRUE(l.warnings.empty()) << ::testing::PrintToString(l.warnings);
  ASSERT_EQ(l.mesh.vertex_count(), 3u);
  // Joint 0 moves by (0, 5, 0). Joint 1 (world: up 5, out 2, turned 90 degrees about z) undoes
  // its bind (back 2 in z), turns, and moves by (0, 5, 2): (x, y, z) -> (-y, x + 5, z).
  expect_near(l.mesh.positions[0], glm::vec3(-1, 4, 0), "vertex 0, on joint 0");
  expect_near(l.mesh.positions[2], glm::vec3(-1, 5, 0), "vertex 2, on joint 1");
  expect_near(l.mesh.positions[1], 0.5f * (glm::vec3(1, 4, 0) + glm::vec3(1, 6, 0)), "vertex 1, half each");
  expect_near(l.mesh.normals[0], glm::vec3(0, 0, 1), "a normal on joint 0");
  expect_near(l.mesh.normals[2], glm::vec3(0, 0, 1), "a normal turned about z");
}

TEST(GltfNodes, ASkinsMistakesAreNamed) {
  TempDir dir;
  auto skinned = [&](const std::vector<uint8_t>& joint_ids, const std::vector<float>& weights,
                     const std::string& skin, const char* name) {
    GltfFile f = triangle(glm::vec3(0, 0, 1));
    const int j = f.add(joint_ids, kUnsignedByte, "VEC4");
    const int w = f.add(weights, kFloat, "VEC4");
    const std::string rest = R"("scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0,"skin":)" + skin +
                             R"(},{}],"skins":[{"joints":[1]}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0,"JOINTS_0":)" +
                             std::to_string(j) + R"(,"WEIGHTS_0":)" + std::to_string(w) + "}}]}]";
    return dir.write(name, f.text(rest));
  };
  const std::vector<uint8_t> zeros(12, 0);
  const std::vector<float> ones = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  EXPECT_EQ(load_mesh_file(skinned(zeros, ones, "0", "ok.gltf")).mesh.triangle_count(), 1u);
  expect_load_error(skinned({0, 0, 0, 0, 3, 0, 0, 0, 0, 0, 0, 0}, ones, "0", "range.gltf"),
                    "meshes[0].primitives[0].attributes.JOINTS_0[1]", "joint 3 out of range (the skin has 1)");
  expect_load_error(skinned(zeros, {1, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0}, "0", "unweighted.gltf"),
                    "meshes[0].primitives[0].attributes.WEIGHTS_0[1]", "the vertex has no joint weight");
  expect_load_error(skinned(zeros, {1, 0, 0, 0, -1, 0, 0, 0, 1, 0, 0, 0}, "0", "negative.gltf"),
                    "meshes[0].primitives[0].attributes.WEIGHTS_0[1]", "must be finite and >= 0");
  expect_load_error(skinned(zeros, ones, "4", "noskin.gltf"), "nodes[0].skin", "skin 4 does not exist");
}

// Morph targets are drawn at the mesh's default weights, or the node's own where it has them
// (until 2026-11-27 they were ignored); their normals too.
TEST(GltfNodes, MorphTargetsTakeTheirDefaultWeights) {
  TempDir dir;
  GltfFile f = triangle(glm::vec3(0, 0, 1));
  const int shift = f.add(std::vector<float>{2, 0, 0, 2, 0, 0, 2, 0, 0}, kFloat, "VEC3");
  const int lift = f.add(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}, kFloat, "VEC3");
  const int tilt = f.add(std::vector<float>{1, 0, -1, 1, 0, -1, 1, 0, -1}, kFloat, "VEC3");
  const std::string targets = R"("targets":[{"POSITION":)" + std::to_string(shift) + R"(},{"POSITION":)" +
                              std::to_string(lift) + R"(,"NORMAL":)" + std::to_string(tilt) + "}]";
  const std::string rest = R"("scene":0,"scenes":[{"nodes":[0,1]}],
    "nodes":[{"mesh":0},{"mesh":0,"weights":[0,1]}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1},)" +
                           targets + R"(}],"weights":[0.5,0.25]}])";
  const LoadedMesh l = load_mesh_file(dir.write("morph.gltf", f.text(rest)));
  ASSERT_EQ(l.mesh.vertex_count(), 6u);
  expect_near(l.mesh.positions[0], glm::vec3(0, -1, 0.25f), "the mesh's weights");
  expect_near(l.mesh.normals[0], glm::normalize(glm::vec3(0.25f, 0, 0.75f)), "a normal at the mesh's weights");
  expect_near(l.mesh.positions[3], glm::vec3(-1, -1, 1), "the node's weights");
  expect_near(l.mesh.normals[3], glm::normalize(glm::vec3(1, 0, 0)), "a normal at the node's weights");
  expect_load_error(dir.write("count.gltf", f.text(R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0},)" + targets + R"(}],"weights":[1]}])")),
                    "meshes[0].weights", "1 weights for the 2 morph targets of meshes[0].primitives[0]");
}

// A node has a matrix or translation, rotation and scale, never both (tinygltf keeps the
// matrix and drops the rest without a word), and its matrix is affine.
TEST(GltfNodes, NodeMatricesTheSpecificationForbidsAreRefused) {
  TempDir dir;
  const GltfFile f = triangle(glm::vec3(0, 0, 1));
  auto with_node = [&](const std::string& node, const char* name) {
    return dir.write(name, f.text(R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[)" + node +
                                  R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}])"));
  };
  const std::string identity = "[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]";
  EXPECT_EQ(load_mesh_file(with_node(R"({"mesh":0,"matrix":)" + identity + "}", "ok.gltf")).mesh.triangle_count(), 1u);
  expect_load_error(with_node(R"({"mesh":0,"matrix":)" + identity + R"(,"translation":[3,0,0]})", "both.gltf"),
                    "nodes[0].translation", "a node has a matrix or translation, rotation and scale, not both");
  expect_load_error(with_node(R"({"mesh":0,"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,4]})", "w.gltf"),
                    "nodes[0].matrix", "must be 0, 0, 0, 1");
  // An exporter's float rounding of the last row is taken as the 1 it means.
  EXPECT_EQ(load_mesh_file(with_node(R"({"mesh":0,"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,0.99999994]})",
                                     "rounded.gltf"))
                .mesh.triangle_count(),
            1u);
}

// A joint's inverse bind matrix is affine too (its w was dropped without a word).
TEST(GltfNodes, AnInverseBindMatrixMustBeAffine) {
  TempDir dir;
  GltfFile f = triangle(glm::vec3(0, 0, 1));
  const int joints = f.add(std::vector<uint8_t>(12, 0), kUnsignedByte, "VEC4");
  const int weights = f.add(std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kFloat, "VEC4");
  const int ibm = f.add(std::vector<float>{1, 0, 0, 0.5f, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, kFloat, "MAT4");
  const std::string rest = R"("scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0,"skin":0},{}],
    "skins":[{"joints":[1],"inverseBindMatrices":)" + std::to_string(ibm) + R"(}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0,"JOINTS_0":)" + std::to_string(joints) +
                           R"(,"WEIGHTS_0":)" + std::to_string(weights) + "}}]}]";
  expect_load_error(dir.write("ibm.gltf", f.text(rest)), "skins[0].inverseBindMatrices[0]", "must be 0, 0, 0, 1");
}

// Morph targets cost vertices x targets: bounded by 3 x --max-faces vertex values, so a small
// file of many targets sharing one accessor is refused rather than running for hours.
TEST(GltfNodes, MorphWorkIsBudgeted) {
  TempDir dir;
  GltfFile f = triangle(glm::vec3(0, 0, 1));
  const int delta = f.add(std::vector<float>(9, 0.001f), kFloat, "VEC3");
  std::string targets, weights;
  for (int t = 0; t < 40; ++t) {
    targets += std::string(t ? "," : "") + R"({"POSITION":)" + std::to_string(delta) + "}";
    weights += std::string(t ? "," : "") + "1";
  }
  const fs::path file = dir.write("morphs.gltf", f.text(R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
    "meshes":[{"primitives":[{"attributes":{"POSITION":0},"targets":[)" + targets + R"(]}],"weights":[)" + weights + "]}]"));
  EXPECT_NEAR(load_mesh_file(file).mesh.positions[0].x, -1.0f + 40 * 0.001f, 1e-5f);
  Budget small;
  small.max_faces = 20;  // 60 vertex values; 40 targets of 3 vertices move 120
  try {
    load_mesh_file(file, small);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.reason.find("morph targets and skins move 63 vertex values or more, more than the budget of 60 (3 x "
                            "--max-faces; raise it with --max-faces)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace pelt::io
