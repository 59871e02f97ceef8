#include "tools/io/builtin_meshes.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "tests/tools/io/mesh_checks.h"
#include "tools/io/input_error.h"

namespace pelt::io {
namespace {

using testing::edge_use;
using testing::max_normal_length_error;
using testing::min_triangle_area;
using testing::signed_volume;
using testing::winding_conflicts;

void expect_well_formed(const Mesh& m) {
  ASSERT_EQ(m.normals.size(), m.positions.size());
  ASSERT_EQ(m.uvs.size(), m.positions.size());
  ASSERT_EQ(m.indices.size() % 3, 0u);
  for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
  EXPECT_GT(min_triangle_area(m), 0.0);
  EXPECT_LT(max_normal_length_error(m), 1e-6);
  EXPECT_EQ(winding_conflicts(m), 0);
  EXPECT_GT(signed_volume(m), 0.0);
  // Every vertex is used by some triangle.
  std::vector<bool> used(m.positions.size(), false);
  for (uint32_t i : m.indices) used[i] = true;
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
}

void expect_closed(const Mesh& m) {
  for (const auto& [edge, uses] : edge_use(m))
    ASSERT_EQ(uses, 2) << "edge " << edge.first << "-" << edge.second;
}

TEST(BuiltinMeshes, Box7HasTheAnchorCounts) {
  const Mesh m = make_builtin_mesh("box:7");
  EXPECT_EQ(m.vertex_count(), 296u);
  EXPECT_EQ(m.triangle_count(), 588u);
  EXPECT_EQ(edge_use(m).size(), 882u);
  expect_well_formed(m);
  expect_closed(m);
  EXPECT_NEAR(signed_volume(m), 8.0, 1e-5);
}

TEST(BuiltinMeshes, BoxCountsFollowTheFormula) {
  for (int n : {1, 2, 3, 10}) {
    const Mesh m = make_box(n);
    EXPECT_EQ(m.vertex_count(), static_cast<size_t>(6 * n * n + 2)) << n;
    EXPECT_EQ(m.triangle_count(), static_cast<size_t>(12 * n * n)) << n;
    expect_well_formed(m);
    expect_closed(m);
    for (const auto& p : m.positions)
      EXPECT_FLOAT_EQ(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 1.0f);
  }
}

TEST(BuiltinMeshes, BoxUvsAreTheBodyDiagonalProjection) {
  const Mesh m = make_box(2);
  const double k = 2.449490;  // 2.449490 * sqrt(3) / R with R = sqrt(3)
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const glm::dvec3 q(m.positions[i]);
    EXPECT_NEAR(m.uvs[i].x, k * (q.x - q.y) / std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(m.uvs[i].y, k * (q.x + q.y - 2.0 * q.z) / std::sqrt(6.0), 1e-6);
  }
}

TEST(BuiltinMeshes, TeapotHasTheAnchorCounts) {
  const Mesh t3 = make_builtin_mesh("teapot:3");
  EXPECT_EQ(t3.vertex_count(), 301u);
  EXPECT_EQ(t3.triangle_count(), 552u);
  EXPECT_EQ(edge_use(t3).size(), 852u);
  expect_well_formed(t3);
  const Mesh t5 = make_builtin_mesh("teapot:5");
  EXPECT_EQ(t5.vertex_count(), 821u);
  EXPECT_EQ(t5.triangle_count(), 1560u);
  EXPECT_EQ(edge_use(t5).size(), 2380u);
  expect_well_formed(t5);
}

TEST(BuiltinMeshes, TeapotBoundaryAndFrame) {
  for (auto [n, boundary, radius] : {std::tuple{3, 48, 3.336181}, std::tuple{5, 80, 3.339957}}) {
    const Mesh m = make_teapot(n);
    int open = 0;
    for (const auto& [edge, uses] : edge_use(m)) {
      EXPECT_LE(uses, 2);
      open += uses == 1;
    }
    EXPECT_EQ(open, boundary) << n;
    // Centred on the bounding box, y up, with the anchor's bounding radius.
    glm::vec3 lo(1e9f), hi(-1e9f);
    double r = 0.0;
    for (const auto& p : m.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
      r = std::max(r, glm::length(glm::dvec3(p)));
    }
    EXPECT_NEAR(lo.x + hi.x, 0.0, 1e-5);
    EXPECT_NEAR(lo.y + hi.y, 0.0, 1e-5);
    EXPECT_NEAR(lo.z + hi.z, 0.0, 1e-5);
    EXPECT_NEAR(hi.y - lo.y, 3.15, 1e-5);  // bpt z runs 0 .. 3.15: now the height
    EXPECT_NEAR(r, radius, 1e-5) << n;
  }
}

TEST(BuiltinMeshes, BezierPatchInterpolatesCorners) {
  BezierPatch p;
  for (int k = 0; k < 16; ++k) p[k] = glm::dvec3(k, 2 * k, -k);
  EXPECT_EQ(eval_bezier_patch(p, 0, 0), p[0]);
  EXPECT_EQ(eval_bezier_patch(p, 0, 1), p[3]);   // v runs along c
  EXPECT_EQ(eval_bezier_patch(p, 1, 0), p[12]);  // u runs along r
  EXPECT_EQ(eval_bezier_patch(p, 1, 1), p[15]);
}

TEST(BuiltinMeshes, EmbeddedTeapotHas32Patches) {
  EXPECT_EQ(teapot_patches().size(), 32u);
}

TEST(BuiltinMeshes, BptParserRejectsBadText) {
  EXPECT_THROW(parse_bpt("", "t.bpt"), InputError);
  EXPECT_THROW(parse_bpt("1\n3 3\n0 0 0\n", "t.bpt"), InputError);
  EXPECT_THROW(parse_bpt("1\n2 3\n", "t.bpt"), InputError);
  try {
    parse_bpt("1\n3 3\n0 0 0\n0 0 nan\n", "t.bpt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "t.bpt");
    EXPECT_EQ(e.field, "patch 0 point 1");
  }
}

// The sphere is split at its texture seam and poles as an exporter splits them: closed once the
// copies at a position count as one vertex, every copy with the same normal, and no triangle whose
// u runs back across the texture (the band a mipmapped map showed down the welded meridian).
TEST(BuiltinMeshes, SphereIsClosedAndOnTheUnitSphere) {
  for (int n : {4, 5, 16, 33}) {
    const Mesh m = make_builtin_mesh("sphere:" + std::to_string(n));
    const int rings = n / 2;
    EXPECT_EQ(m.vertex_count(), static_cast<size_t>(2 * n + (n + 1) * (rings - 1))) << n;
    EXPECT_EQ(m.triangle_count(), static_cast<size_t>(2 * n * (rings - 1))) << n;
    expect_well_formed(m);
    Mesh welded = m;
    for (uint32_t& v : welded.indices) {
      const auto first = static_cast<uint32_t>(std::find(m.positions.begin(), m.positions.end(), m.positions[v]) -
                                                m.positions.begin());
      EXPECT_EQ(m.normals[v], m.normals[first]) << "vertex " << v << " and its copy " << first;
      v = first;
    }
    expect_closed(welded);
    for (size_t i = 0; i < m.positions.size(); ++i) {
      EXPECT_NEAR(glm::length(m.positions[i]), 1.0f, 1e-6f);
      EXPECT_GT(glm::dot(m.normals[i], m.positions[i]), 0.99f) << i;
      EXPECT_GE(m.uvs[i].x, 0.0f);
      EXPECT_LE(m.uvs[i].x, 1.0f);
      EXPECT_NEAR(m.uvs[i].y, 1.0 - std::acos(std::clamp(m.positions[i].y, -1.0f, 1.0f)) / M_PI, 1e-3);
    }
    for (size_t t = 0; t < m.indices.size(); t += 3) {
      float lo = 1.0f, hi = 0.0f;
      for (int k = 0; k < 3; ++k) {
        lo = std::min(lo, m.uvs[m.indices[t + k]].x);
        hi = std::max(hi, m.uvs[m.indices[t + k]].x);
      }
      EXPECT_LE(hi - lo, 1.0f / float(n) + 1e-6f) << "triangle " << t / 3 << " of sphere:" << n;
    }
  }
  // A fine sphere's volume approaches 4/3 pi.
  EXPECT_NEAR(signed_volume(make_sphere(256)), 4.0 / 3.0 * M_PI, 2e-3);
}

TEST(BuiltinMeshes, PlaneFacesUp) {
  const Mesh m = make_builtin_mesh("plane:3");
  EXPECT_EQ(m.vertex_count(), 16u);
  EXPECT_EQ(m.triangle_count(), 18u);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_EQ(m.positions[i].y, 0.0f);
    EXPECT_EQ(m.normals[i], glm::vec3(0, 1, 0));
    EXPECT_FLOAT_EQ(m.uvs[i].x, (m.positions[i].x + 1) / 2);
    EXPECT_FLOAT_EQ(m.uvs[i].y, (m.positions[i].z + 1) / 2);
  }
  double area = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]),
        c(m.positions[m.indices[t + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    EXPECT_GT(n.y, 0.0);  // counter-clockwise seen from +y
    area += 0.5 * n.y;
  }
  EXPECT_NEAR(area, 4.0, 1e-9);
  int open = 0;
  for (const auto& [edge, uses] : edge_use(m)) open += uses == 1;
  EXPECT_EQ(open, 12);
}

TEST(BuiltinMeshes, SpecDetection) {
  EXPECT_TRUE(looks_like_builtin_spec("box:7"));
  EXPECT_TRUE(looks_like_builtin_spec("cube:3"));
  EXPECT_TRUE(looks_like_builtin_spec("box:"));
  EXPECT_FALSE(looks_like_builtin_spec("meshes/bunny.obj"));
  EXPECT_FALSE(looks_like_builtin_spec("bunny.obj"));
  EXPECT_FALSE(looks_like_builtin_spec("box"));
  EXPECT_FALSE(looks_like_builtin_spec("box:1.5"));
  EXPECT_FALSE(looks_like_builtin_spec("C:/x/box.obj"));
}

void expect_spec_error(const std::string& spec, const std::string& reason_part) {
  try {
    parse_builtin_spec(spec, "scene.json", "objects[0].mesh");
    FAIL() << spec << " was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "scene.json");
    EXPECT_EQ(e.field, "objects[0].mesh");
    EXPECT_NE(e.reason.find(reason_part), std::string::npos) << e.reason;
  }
}

TEST(BuiltinMeshes, SpecErrors) {
  expect_spec_error("bax:3", "did you mean `box`?");
  expect_spec_error("cube:3", "unknown built-in mesh `cube`");
  expect_spec_error("box", "has no size");
  expect_spec_error("box:", "has no size");
  expect_spec_error("box:0", "must be positive");
  expect_spec_error("box:-2", "must be positive");
  expect_spec_error("box:2x", "whole number");
  expect_spec_error("box:99999999999999", "too large");
  expect_spec_error("box:1025", "[1, 1024]");
  expect_spec_error("teapot:257", "[1, 256]");
  expect_spec_error("sphere:3", "[4, 2048]");
  expect_spec_error("plane:2000", "[1, 1024]");
  const BuiltinSpec s = parse_builtin_spec("teapot:12");
  EXPECT_EQ(s.shape, BuiltinShape::teapot);
  EXPECT_EQ(s.n, 12);
}

TEST(BuiltinMeshes, InputErrorMessageFormat) {
  const InputError e("a.json", "objects[1].transform.scale", "must be non-zero");
  EXPECT_STREQ(e.what(), "a.json: objects[1].transform.scale: must be non-zero");
  const InputError f("b.obj", "", "no triangles");
  EXPECT_STREQ(f.what(), "b.obj: no triangles");
}

}  // namespace
}  // namespace pelt::io
