#include "tools/io/polygon_triangulation.h"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <gtest/gtest.h>

namespace pelt::io {
namespace {

using Poly = std::vector<glm::vec3>;

std::vector<uint32_t> triangulate(const Poly& p) {
  std::vector<uint32_t> out;
  triangulate_polygon(p, out);
  return out;
}

// Twice the signed area, in the z = 0 plane, of a polygon and of a triangle of it.
double polygon_area2(const Poly& p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const glm::dvec3 u(p[i]), v(p[(i + 1) % p.size()]);
    a += u.x * v.y - u.y * v.x;
  }
  return a;
}
double triangle_area2(const Poly& p, uint32_t a, uint32_t b, uint32_t c) {
  const glm::dvec3 u = glm::dvec3(p[b]) - glm::dvec3(p[a]), v = glm::dvec3(p[c]) - glm::dvec3(p[a]);
  return u.x * v.y - u.y * v.x;
}

// Every polygon gets size - 2 triangles of its own corners, none repeating a corner.
void expect_complete(const Poly& p, const std::vector<uint32_t>& t) {
  ASSERT_EQ(t.size(), 3 * (p.size() - 2));
  for (size_t k = 0; k < t.size(); k += 3) {
    for (int c = 0; c < 3; ++c) ASSERT_LT(t[k + c], p.size());
    EXPECT_NE(t[k], t[k + 1]);
    EXPECT_NE(t[k + 1], t[k + 2]);
    EXPECT_NE(t[k], t[k + 2]);
  }
}

// A simple planar polygon is triangulated exactly when its triangles all turn its way and
// their areas sum to its area: any overlap or gap would break the sum.
void expect_exact_cover(const Poly& p, const std::vector<uint32_t>& t) {
  expect_complete(p, t);
  const double area = polygon_area2(p);
  double sum = 0.0;
  for (size_t k = 0; k < t.size(); k += 3) {
    const double a = triangle_area2(p, t[k], t[k + 1], t[k + 2]);
    EXPECT_GE(a * area, 0.0) << "triangle " << k / 3 << " is flipped";
    sum += a;
  }
  EXPECT_NEAR(sum, area, 1e-6 * std::abs(area));
}

Poly from_xy(std::initializer_list<std::pair<float, float>> xy, glm::vec2 offset = {}) {
  Poly p;
  for (auto [x, y] : xy) p.emplace_back(x + offset.x, y + offset.y, 0.0f);
  return p;
}

TEST(PolygonTriangulation, TrianglesAndConvexQuadsSplitAsBefore) {
  EXPECT_EQ(triangulate(from_xy({{0, 0}, {1, 0}, {0, 1}})), (std::vector<uint32_t>{0, 1, 2}));
  // The shorter diagonal, 0-2 here, then 1-3 (tinyobjloader's rule, kept for convex quads).
  EXPECT_EQ(triangulate(from_xy({{0, 0}, {4, 0}, {3, 1}, {0, 1}})), (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(triangulate(from_xy({{0, 0}, {3, 0}, {4, 1}, {0, 1}})), (std::vector<uint32_t>{0, 1, 3, 1, 2, 3}));
}

// A dart, reflex at corner 2: the shorter diagonal (1-3) runs outside it, so the split
// takes 0-2.
TEST(PolygonTriangulation, NonConvexQuadSplitsAlongItsInsideDiagonal) {
  const Poly dart = from_xy({{0, 0}, {4, -1}, {3, 0}, {4, 1}});
  const auto t = triangulate(dart);
  expect_exact_cover(dart, t);
  EXPECT_EQ(t, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

// Shapes tinyobjloader 2.0.0~rc10 left with holes at these offsets (its ear test depends
// on where the polygon lies): the U kept 3 of 6 triangles, the L 1 of 4.
TEST(PolygonTriangulation, ShapesTinyobjloaderCutHolesInAreCoveredExactly) {
  const Poly u = from_xy({{0, 0}, {4, 0}, {4, 4}, {3, 4}, {3, 1}, {1, 1}, {1, 4}, {0, 4}}, {-4, -4});
  const Poly l = from_xy({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}}, {-4, 1});
  expect_exact_cover(u, triangulate(u));
  expect_exact_cover(l, triangulate(l));
  // Either winding.
  const Poly l_cw(l.rbegin(), l.rend());
  expect_exact_cover(l_cw, triangulate(l_cw));
}

// Random simple polygons: star-shaped about a random centre, 5 to 40 corners, at random
// offsets and in random planes (rotated, so the projection axis varies).
TEST(PolygonTriangulation, RandomStarShapedPolygonsAreCoveredExactly) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int n = 0; n < 3000; ++n) {
    const int k = 5 + n % 36;
    const glm::vec2 c(3 * u(rng), 3 * u(rng));
    Poly flat;
    for (int i = 0; i < k; ++i) {
      const double a = 2 * std::numbers::pi * i / k;
      const float r = 0.2f + 1.5f * std::abs(u(rng));
      flat.emplace_back(c.x + r * static_cast<float>(std::cos(a)), c.y + r * static_cast<float>(std::sin(a)), 0.0f);
    }
    SCOPED_TRACE(n);
    expect_exact_cover(flat, triangulate(flat));
    // The same polygon turned into another plane: same triangles up to rounding, so check
    // completeness and that every triangle faces the polygon's way.
    const glm::vec3 axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0, 0, 0.01f));
    const float angle = 3.0f * u(rng);
    Poly turned;
    for (const glm::vec3& q : flat) {
      const glm::vec3 r = q * std::cos(angle) + glm::cross(axis, q) * std::sin(angle) +
                          axis * glm::dot(axis, q) * (1 - std::cos(angle));
      turned.push_back(r);
    }
    const auto t = triangulate(turned);
    expect_complete(turned, t);
    glm::dvec3 normal(0.0);
    for (size_t i = 0; i < turned.size(); ++i)
      normal += glm::cross(glm::dvec3(turned[i]), glm::dvec3(turned[(i + 1) % turned.size()]));
    double sum = 0.0;
    for (size_t j = 0; j < t.size(); j += 3) {
      const glm::dvec3 a(turned[t[j]]), b(turned[t[j + 1]]), d(turned[t[j + 2]]);
      const double facing = glm::dot(glm::cross(b - a, d - a), normal);
      EXPECT_GE(facing, -1e-6 * glm::dot(normal, normal)) << "triangle " << j / 3;
      sum += glm::length(glm::cross(b - a, d - a));
    }
    EXPECT_NEAR(sum, glm::length(normal), 1e-4 * glm::length(normal));
  }
}

// Whatever the input, the count is right and the corners are the polygon's: crossing
// polygons, non-planar ones, repeated corners, collinear and single-point ones, up to the
// 255 corners an OBJ face may have here.
TEST(PolygonTriangulation, HardPolygonsStillGetEveryTriangle) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Poly> hard = {
      from_xy({{0, 0}, {2, 2}, {2, 0}, {0, 2}, {1, 3}}),             // a bow tie and a cap
      from_xy({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}}),             // collinear
      from_xy({{1, 1}, {1, 1}, {1, 1}, {1, 1}, {1, 1}, {1, 1}}),     // one point
      from_xy({{0, 0}, {2, 0}, {2, 2}, {0, 0}, {-2, 0}, {-2, -2}}),  // touching itself
      from_xy({{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 1}}),             // a repeated corner
      from_xy({{0, 0}, {1e-30f, 0}, {1e-30f, 1e-30f}, {0, 1e-30f}, {0, 5e-31f}}),
      from_xy({{0, 0}, {3e38f, 0}, {3e38f, 3e38f}, {0, 3e38f}, {-3e38f, 1e38f}}),
  };
  for (int n = 0; n < 500; ++n) {  // random corners in space: crossing and non-planar
    Poly p(3 + n % 253);
    for (auto& q : p) q = glm::vec3(u(rng), u(rng), u(rng));
    hard.push_back(p);
  }
  for (size_t i = 0; i < hard.size(); ++i) {
    SCOPED_TRACE(i);
    expect_complete(hard[i], triangulate(hard[i]));
  }
}

}  // namespace
}  // namespace pelt::io
