// Mesh utilities: tangent frames for normal maps.
#include "raster/mesh.h"
#include "tests/raster/test_meshes.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace pelt {
namespace {

using test::unit_square;

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
