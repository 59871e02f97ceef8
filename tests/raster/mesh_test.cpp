// Mesh utilities: computed normals, tangent frames for normal maps.
#include "raster/mesh.h"
#include "tests/raster/test_meshes.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace pelt {
namespace {

using test::unit_square;

// Two triangles folded along the edge x = 0, each with its own copies of the fold's two
// vertices (as a file splits them): 0-2 face (-1, 1, 0)/sqrt2, 3-5 face (1, 1, 0)/sqrt2.
Mesh folded_pair() {
  Mesh m;
  m.positions = {{0, 1, 0}, {0, 1, 1}, {-1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 1, 1}};
  m.indices = {0, 2, 1, 3, 5, 4};
  return m;
}

TEST(MeshNormals, SmoothingKeysNarrowTheCopiesThatShare) {
  const glm::vec3 left = glm::normalize(glm::vec3(-1, 1, 0)), right = glm::normalize(glm::vec3(1, 1, 0));
  Mesh shared = folded_pair();
  compute_vertex_normals(shared, NormalSharing::per_position);
  EXPECT_LT(glm::distance(shared.normals[0], glm::vec3(0, 1, 0)), 1e-6f);  // both faces' sum
  EXPECT_EQ(shared.normals[0], shared.normals[3]);

  Mesh apart = folded_pair();
  compute_vertex_normals(apart, NormalSharing::per_position, std::vector<uint64_t>{7, 7, 7, 9, 9, 9});
  for (uint32_t i = 0; i < 6; ++i) EXPECT_LT(glm::distance(apart.normals[i], i < 3 ? left : right), 1e-6f) << i;

  // Equal keys share as without keys; keys that differ only in their upper half still differ.
  Mesh same = folded_pair();
  compute_vertex_normals(same, NormalSharing::per_position, std::vector<uint64_t>(6, 1));
  EXPECT_EQ(same.normals, shared.normals);
  Mesh high = folded_pair();
  const uint64_t h = uint64_t{1} << 32;
  compute_vertex_normals(high, NormalSharing::per_position, std::vector<uint64_t>{h, h, h, h | 1, h | 1, h | 1});
  EXPECT_EQ(high.normals, apart.normals);

  // Keys never widen sharing: per vertex, the copies keep their own faces' normals.
  Mesh per_vertex = folded_pair();
  compute_vertex_normals(per_vertex, NormalSharing::per_vertex, std::vector<uint64_t>(6, 1));
  EXPECT_EQ(per_vertex.normals, apart.normals);
}

TEST(MeshNormals, SmoothingKeysMustCoverEveryVertex) {
  Mesh m = folded_pair();
  EXPECT_THROW(compute_vertex_normals(m, NormalSharing::per_position, std::vector<uint64_t>{1, 2}),
               std::invalid_argument);
}

TEST(MeshTangents, TangentAlongUBitangentTowardTheImageTop) {
  for (const glm::vec4& t : compute_vertex_tangents(unit_square())) {
    EXPECT_NEAR(glm::distance(glm::vec3(t), glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
    EXPECT_EQ(t.w, 1.0f);
    const glm::vec3 b = t.w * glm::cross(glm::vec3(0, 1, 0), glm::vec3(t));
    EXPECT_NEAR(glm::distance(b, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
  }
}

TEST(MeshTangents, MirroredUvsFlipTheHandedness) {
  Mesh m = unit_square();
  for (glm::vec2& uv : m.uvs) uv.x = 1.0f - uv.x;  // u now runs along -x
  for (const glm::vec4& t : compute_vertex_tangents(m)) {
    EXPECT_NEAR(glm::distance(glm::vec3(t), glm::vec3(-1, 0, 0)), 0.0f, 1e-6f);
    EXPECT_EQ(t.w, -1.0f);
    const glm::vec3 b = t.w * glm::cross(glm::vec3(0, 1, 0), glm::vec3(t));
    EXPECT_NEAR(glm::distance(b, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);  // still the image's top
  }
}

TEST(MeshTangents, TangentIsOrthogonalToASlantedNormal) {
  Mesh m = unit_square();
  m.normals.assign(4, glm::normalize(glm::vec3(1, 1, 0)));
  for (const glm::vec4& t : compute_vertex_tangents(m)) {
    EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(glm::vec3(t), m.normals[0]), 0.0f, 1e-6f);
  }
}

TEST(MeshTangents, DegenerateOrMissingUvsStillGiveAUnitOrthogonalFrame) {
  Mesh m = unit_square();
  m.uvs.assign(4, {0.5f, 0.5f});
  for (const glm::vec4& t : compute_vertex_tangents(m)) {
    EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(glm::vec3(t), glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
    EXPECT_EQ(t.w, 1.0f);
  }
  m.uvs.clear();
  m.normals[2] = {0, 0, 0};  // a zero normal too
  for (const glm::vec4& t : compute_vertex_tangents(m)) {
    EXPECT_TRUE(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z));
    EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
  }
}

}  // namespace
}  // namespace pelt
