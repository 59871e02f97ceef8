// The `surface` order's keys: every shell layer after its own layer below and after the layer
// below of each neighbour it leans over on screen; the plain mean depth where nothing leans
// across or where the triangles below are culled; one key per quad; no NaN from a vertex behind
// the eye.
#include "fur/surface_order.h"

#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <gtest/gtest.h>

#include "fur/fur_geometry.h"
#include "raster/mesh.h"

namespace pelt::fur {
namespace {

// A flat n x n grid of unit-size quads in the xz-plane, normals up, each quad two triangles in
// a row sharing its diagonal (as the built-in meshes lay quads out).
Mesh grid(int n) {
  Mesh m;
  for (int z = 0; z <= n; ++z)
    for (int x = 0; x <= n; ++x) m.positions.push_back({float(x), 0.0f, float(z)});
  auto at = [&](int x, int z) { return uint32_t(z * (n + 1) + x); };
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x) {
      const uint32_t a = at(x, z), b = at(x, z + 1), c = at(x + 1, z + 1), d = at(x + 1, z);
      m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
    }
  m.normals.assign(m.positions.size(), {0.0f, 1.0f, 0.0f});
  return m;
}

FurGeometry grid_fur(int n, int shells) {
  FurParams params;
  params.shells = shells;
  params.length = 0.2f;
  FurGeometry geo;
  EXPECT_FALSE(build_fur_geometry(grid(n), params, geo).has_value());
  return geo;
}

// Every fur vertex in clip space; layer s of base vertex i at root + s * step.
std::vector<glm::vec4> clip_of(const FurGeometry& geo, const glm::mat4& clip_from_world, glm::vec3 step) {
  std::vector<glm::vec4> clip(geo.positions.size());
  const uint32_t n = geo.base_vertex_count;
  for (size_t i = 0; i < clip.size(); ++i) {
    const glm::vec3 p = geo.positions[i % n] + float(i / n) * step;
    clip[i] = clip_from_world * glm::vec4(p, 1.0f);
  }
  return clip;
}

glm::mat4 camera(glm::vec3 eye, glm::vec3 target, glm::vec3 up = {0, 1, 0}) {
  return glm::perspective(glm::radians(45.0f), 4.0f / 3.0f, 0.1f, 100.0f) * glm::lookAt(eye, target, up);
}

// The mean view depth of a triangle of the shell draw (what the tile sort keys it by).
float mean_w(const FurGeometry& geo, const std::vector<glm::vec4>& clip, size_t tri) {
  const uint32_t* t = &geo.shell_indices[3 * tri];
  return (clip[t[0]].w + clip[t[1]].w + clip[t[2]].w) / 3.0f;
}

glm::vec2 screen(const glm::vec4& c) { return {c.x / c.w, c.y / c.w}; }

// Every key is its quad's mean depth (the `tile` order's key): no rule held anything back.
void expect_quad_mean_depths(const FurGeometry& geo, const std::vector<glm::vec4>& clip, const std::vector<float>& keys) {
  const uint32_t F = uint32_t(geo.counts.base_faces);
  ASSERT_EQ(keys.size(), size_t{geo.layers} * F);
  for (uint32_t s = 0; s < geo.layers; ++s)
    for (uint32_t f = 0; f < F; f += 2) {
      const size_t t = size_t{s} * F + f;
      const float quad = (3.0f * mean_w(geo, clip, t) + 3.0f * mean_w(geo, clip, t + 1)) / 6.0f;
      EXPECT_NEAR(keys[t], quad, 1e-5f * quad) << "layer " << s << " face " << f;
      EXPECT_EQ(keys[t], keys[t + 1]);  // a quad's halves share one key
    }
}

TEST(SurfaceOrder, EveryLayerIsDrawnAfterTheLayersBelowThatItLeansOver) {
  const int shells = 8;
  const FurGeometry geo = grid_fur(6, shells);
  // Seen at a slant, strands leaning far along the grid (toward +x, a little +z): each quad's
  // upper layers cover its neighbour's lower ones.
  const glm::mat4 m = camera({3.0f, 2.5f, 9.0f}, {3.0f, 0.0f, 3.0f});
  const glm::vec3 step = 0.2f / float(shells - 1) * glm::normalize(glm::vec3(3.0f, 0.3f, 1.0f));
  const std::vector<glm::vec4> clip = clip_of(geo, m, step);
  SurfaceOrder order(geo);
  std::vector<float> keys;
  order.compute(clip, keys);
  const uint32_t F = uint32_t(geo.counts.base_faces), n = geo.base_vertex_count;
  ASSERT_EQ(keys.size(), size_t{shells} * F);
  for (uint32_t s = 1; s < uint32_t(shells); ++s)
    for (uint32_t f = 0; f < F; ++f) ASSERT_LT(keys[s * F + f], keys[(s - 1) * F + f]) << "face " << f << " layer " << s;
  int rules = 0, depth_alone_breaks = 0;
  for (const FurEdge& e : geo.edges) {
    if (e.face1 == kNoFace) continue;
    // Which face the strands lean onto, from face1's side of the edge (the code looks from
    // face0's): its vertex off the edge lies on the side the edge's screen normal points to.
    const uint32_t* t1 = &geo.shell_indices[3 * size_t{e.face1}];
    uint32_t off = t1[0];
    for (int k = 0; k < 3; ++k)
      if (t1[k] != e.a && t1[k] != e.b) off = t1[k];
    const glm::vec2 a = screen(clip[e.a]), b = screen(clip[e.b]);
    glm::vec2 normal(a.y - b.y, b.x - a.x);
    if (glm::dot(normal, screen(clip[off]) - a) < 0.0f) normal = -normal;  // toward face1
    const size_t top = size_t{shells - 1} * n;
    const float lean = glm::dot(screen(clip[e.a + top]) - a + screen(clip[e.b + top]) - b, normal);
    ASSERT_NE(lean, 0.0f);
    const uint32_t upper = lean > 0.0f ? e.face0 : e.face1, lower = lean > 0.0f ? e.face1 : e.face0;
    for (uint32_t s = 1; s < uint32_t(shells); ++s) {
      ++rules;
      EXPECT_LT(keys[s * F + upper], keys[(s - 1) * F + lower]) << "edge " << e.a << "-" << e.b << " layer " << s;
      if (mean_w(geo, clip, s * F + upper) >= mean_w(geo, clip, (s - 1) * F + lower)) ++depth_alone_breaks;
    }
  }
  EXPECT_GT(rules, 0);
  // The view and lean are chosen so that keying by depth alone (the `tile` order) breaks rules.
  EXPECT_GT(depth_alone_breaks, rules / 10);
}

TEST(SurfaceOrder, WhereNothingLeansAcrossAnEdgeTheKeysAreTheQuadsMeanDepths) {
  const int shells = 6;
  const FurGeometry geo = grid_fur(4, shells);
  // Straight down the strands: no layer moves on screen, so no rule holds anything back, and
  // the outer layers are nearer anyway.
  const glm::mat4 m = camera({2.0f, 6.0f, 2.0f}, {2.0f, 0.0f, 2.0f}, {0, 0, -1});
  const std::vector<glm::vec4> clip = clip_of(geo, m, {0.0f, 0.04f, 0.0f});
  SurfaceOrder order(geo);
  std::vector<float> keys;
  order.compute(clip, keys);
  expect_quad_mean_depths(geo, clip, keys);
}

// Only a drawn triangle holds another back. Seen from below, every shell faces away and is culled:
// no rule applies, though the strands lean across every edge and each layer lies behind the one
// below it. (Culled keys passed the chain on from the hidden side of a fold to the visible one.)
TEST(SurfaceOrder, TrianglesFacingAwayHoldNothingBack) {
  const int shells = 8;
  const FurGeometry geo = grid_fur(6, shells);
  const glm::mat4 m = camera({3.0f, -2.5f, 9.0f}, {3.0f, 0.0f, 3.0f});
  const glm::vec3 step = 0.2f / float(shells - 1) * glm::normalize(glm::vec3(3.0f, 0.3f, 1.0f));
  const std::vector<glm::vec4> clip = clip_of(geo, m, step);
  SurfaceOrder order(geo);
  std::vector<float> keys;
  order.compute(clip, keys);
  for (size_t t = 0; t < keys.size(); ++t) {
    const glm::vec2 a = screen(clip[geo.shell_indices[3 * t]]), b = screen(clip[geo.shell_indices[3 * t + 1]]),
                    c = screen(clip[geo.shell_indices[3 * t + 2]]);
    ASSERT_LT((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y), 0.0f) << "faces the viewer: triangle " << t;
  }
  expect_quad_mean_depths(geo, clip, keys);
}

TEST(SurfaceOrder, VerticesBehindTheEyeOrNotFiniteLeaveTheOtherKeysFinite) {
  const int shells = 4;
  const FurGeometry geo = grid_fur(4, shells);
  const glm::mat4 m = camera({2.0f, 1.0f, 6.0f}, {2.0f, 0.0f, 2.0f});
  std::vector<glm::vec4> clip = clip_of(geo, m, {0.03f, 0.02f, 0.0f});
  const uint32_t n = geo.base_vertex_count, F = uint32_t(geo.counts.base_faces);
  // Vertex 0's chain behind the eye, vertex 1's tip not finite.
  for (uint32_t s = 0; s < uint32_t(shells); ++s) clip[s * n].w = -1.0f;
  clip[1 + size_t{shells - 1} * n] = glm::vec4(std::numeric_limits<float>::quiet_NaN());
  SurfaceOrder order(geo);
  std::vector<float> keys;
  order.compute(clip, keys);
  for (uint32_t s = 0; s < uint32_t(shells); ++s)
    for (uint32_t f = 0; f < F; ++f) {
      const uint32_t* t = &geo.shell_indices[3 * (size_t{s} * F + f)];
      const uint32_t* u = &geo.shell_indices[3 * (size_t{s} * F + (f ^ 1u))];
      bool nan_vertex = false;
      for (int k = 0; k < 3; ++k) nan_vertex |= std::isnan(clip[t[k]].w) || std::isnan(clip[u[k]].w);
      EXPECT_EQ(std::isfinite(keys[size_t{s} * F + f]), !nan_vertex) << "layer " << s << " face " << f;
    }
}

// A triangle with a corner behind the eye has no winding on screen, and the clipper may still draw
// part of it: it is not taken for culled, and still holds its own next layer back. Strands leaning
// away from the eye, so each layer lies behind the one below it and the rule moves every key.
TEST(SurfaceOrder, ATriangleReachingBehindTheEyeStillHoldsItsNextLayerBack) {
  const int shells = 4;
  const FurGeometry geo = grid_fur(4, shells);
  const glm::mat4 m = camera({2.0f, 1.0f, 6.0f}, {2.0f, 0.0f, 2.0f});
  std::vector<glm::vec4> clip = clip_of(geo, m, {0.0f, 0.01f, -0.08f});
  const uint32_t n = geo.base_vertex_count, F = uint32_t(geo.counts.base_faces);
  for (uint32_t s = 0; s < uint32_t(shells); ++s) clip[s * n].w = -1.0f;  // vertex 0's chain
  SurfaceOrder order(geo);
  std::vector<float> keys;
  order.compute(clip, keys);
  int checked = 0;
  for (uint32_t s = 1; s < uint32_t(shells); ++s)
    for (uint32_t f = 0; f < F; ++f) {
      const uint32_t* t = &geo.shell_indices[3 * size_t{f}];
      if (t[0] != 0 && t[1] != 0 && t[2] != 0) continue;
      EXPECT_LT(keys[size_t{s} * F + f], keys[size_t{s - 1} * F + f]) << "layer " << s << " face " << f;
      ++checked;
    }
  EXPECT_GT(checked, 0);
}

// A mesh split along a texture seam (or the box mapping's border) orders its shells as the same
// mesh welded: a seam edge names the first copy of each end, and its face may name the other
// copy, which must not pass for the face's corner off the edge (that left the edge no side, and
// its rule was skipped).
TEST(SurfaceOrder, ASplitSeamKeepsTheWeldedMeshesRules) {
  const int n = 6, shells = 8;
  Mesh welded = grid(n);
  welded.uvs.clear();
  for (const glm::vec3& p : welded.positions) welded.uvs.push_back({p.x, p.z});
  // The quads right of x = 3 take their own copies of the column x = 3, uvs shifted by 10.
  Mesh split = welded;
  std::vector<uint32_t> copy(welded.positions.size(), UINT32_MAX);
  for (size_t t = 0; t < split.indices.size(); t += 6) {
    bool right = true;
    for (int k = 0; k < 6; ++k) right &= welded.positions[welded.indices[t + k]].x >= 3.0f;
    for (int k = 0; k < 6 && right; ++k) {
      const uint32_t v = welded.indices[t + k];
      if (welded.positions[v].x != 3.0f) continue;
      if (copy[v] == UINT32_MAX) {
        copy[v] = uint32_t(split.positions.size());
        split.positions.push_back(welded.positions[v]);
        split.normals.push_back(welded.normals[v]);
        split.uvs.push_back(welded.uvs[v] + glm::vec2(10.0f, 0.0f));
      }
      split.indices[t + k] = copy[v];
    }
  }
  FurParams params;
  params.shells = shells;
  params.length = 0.2f;
  FurGeometry a, b;
  ASSERT_FALSE(build_fur_geometry(welded, params, a).has_value());
  ASSERT_FALSE(build_fur_geometry(split, params, b).has_value());
  ASSERT_GT(b.counts.joined_vertices, 0u);
  ASSERT_EQ(a.counts.edges, b.counts.edges);
  // The strands lean across the seam (toward +x), seen at a slant.
  const glm::mat4 m = camera({3.0f, 2.5f, 9.0f}, {3.0f, 0.0f, 3.0f});
  const glm::vec3 step = 0.2f / float(shells - 1) * glm::normalize(glm::vec3(3.0f, 0.3f, 1.0f));
  std::vector<float> ka, kb;
  SurfaceOrder(a).compute(clip_of(a, m, step), ka);
  SurfaceOrder(b).compute(clip_of(b, m, step), kb);
  EXPECT_EQ(ka, kb);
}

}  // namespace
}  // namespace pelt::fur
