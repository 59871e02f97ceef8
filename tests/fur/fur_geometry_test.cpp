#include "fur/fur_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <span>
#include <string>
#include <utility>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/fur/test_meshes.h"
#include "tools/io/builtin_meshes.h"

namespace pelt::fur {
namespace {

FurGeometry build(const Mesh& m, const FurParams& p) {
  FurGeometry g;
  auto e = build_fur_geometry(m, p, g);
  EXPECT_FALSE(e.has_value()) << e->field << ": " << e->reason;
  return g;
}

// The field build_fur_geometry refuses (m, p, scale) by, or "accepted".
std::string refused_field(const Mesh& m, const FurParams& p, std::span<const float> scale = {}) {
  FurGeometry g;
  const auto e = build_fur_geometry(m, p, g, scale);
  return e ? e->field : "accepted";
}

FurParams shells(int s) {
  FurParams p;
  p.shells = s;
  return p;
}

TEST(FurGeometry, TetrahedronCountsAndLayout) {
  const Mesh m = test::tetrahedron();
  const FurGeometry g = build(m, shells(4));
  EXPECT_EQ(g.counts.base_vertices, 4u);
  EXPECT_EQ(g.counts.shell_vertices, 16u);
  EXPECT_EQ(g.counts.fin_vertices, 16u);
  EXPECT_EQ(g.counts.total_vertices, 20u);
  EXPECT_EQ(g.counts.base_faces, 4u);
  EXPECT_EQ(g.counts.shell_faces, 16u);
  EXPECT_EQ(g.counts.edges, 6u);
  EXPECT_EQ(g.counts.fin_faces, 2u * 6u * 3u);
  EXPECT_EQ(g.counts.total_faces, 4u + 16u + 36u);
  EXPECT_EQ(g.positions.size(), 16u);
  EXPECT_EQ(g.shell_indices.size(), 3u * 16u);
  EXPECT_EQ(g.fin_indices.size(), 3u * 36u);
  // Shell triangle s*F + f is base triangle f shifted to layer s.
  for (uint32_t s = 0; s < 4; ++s)
    for (size_t k = 0; k < m.indices.size(); ++k)
      EXPECT_EQ(g.shell_indices[s * m.indices.size() + k], m.indices[k] + s * 4);
}

TEST(FurGeometry, PositionsFollowEquationOneExactly) {
  for (const Mesh& m : {test::tetrahedron(), test::unit_square()}) {
    FurParams p = shells(7);
    p.length = 0.25f;
    const FurGeometry g = build(m, p);
    const BoundingSphere b = bounding_sphere(m);
    const float sld = p.length * b.radius / float(p.shells - 1);
    EXPECT_EQ(g.layer_distance, sld);
    const size_t N = m.positions.size();
    for (int s = 0; s < p.shells; ++s) {
      for (size_t i = 0; i < N; ++i) {
        const glm::vec3 n = m.normals[i];
        const glm::vec3 want = m.positions[i] + n * (sld * float(s));
        EXPECT_EQ(g.positions[i + s * N], want) << "i=" << i << " s=" << s;
        // Layer s is s * SL_D from the base along the unit normal.
        EXPECT_NEAR(glm::length(g.positions[i + s * N] - m.positions[i]), sld * s, 1e-6);
        EXPECT_EQ(g.layer[i + s * N], s);
        EXPECT_EQ(g.shell_uvs[i + s * N], glm::vec2(glm::dvec2(m.uvs[i]) * g.strand_uv_scale));
        EXPECT_FLOAT_EQ(g.fin_uvs[i + s * N].y, float(s) / float(p.shells - 1));
        EXPECT_EQ(g.fin_uvs[i + s * N].x, g.fin_uvs[i].x);  // u depends on the base vertex only
      }
    }
  }
}

TEST(FurGeometry, EdgesAreSortedUniqueWithTheirFaces) {
  const FurGeometry tet = build(test::tetrahedron(), shells(3));
  ASSERT_EQ(tet.edges.size(), 6u);
  for (size_t k = 0; k < tet.edges.size(); ++k) {
    const FurEdge& e = tet.edges[k];
    EXPECT_LT(e.a, e.b);
    EXPECT_NE(e.face0, kNoFace);
    EXPECT_NE(e.face1, kNoFace);  // closed mesh: every edge has two faces
    EXPECT_NE(e.face0, e.face1);
    if (k > 0) {
      EXPECT_LT(std::make_pair(tet.edges[k - 1].a, tet.edges[k - 1].b), std::make_pair(e.a, e.b));
    }
  }
  const FurGeometry q = build(test::unit_square(), shells(3));
  ASSERT_EQ(q.edges.size(), 5u);
  int boundary = 0;
  for (const FurEdge& e : q.edges) boundary += e.face1 == kNoFace;
  EXPECT_EQ(boundary, 4);
  // Edge (0,2) is the diagonal shared by both triangles.
  EXPECT_EQ(q.edges[1].a, 0u);
  EXPECT_EQ(q.edges[1].b, 2u);
  EXPECT_EQ(q.edges[1].face0, 0u);
  EXPECT_EQ(q.edges[1].face1, 1u);
}

TEST(FurGeometry, FinQuadsUseTheSharedVerticesInLayerThenEdgeOrder) {
  const Mesh m = test::unit_square();
  const FurGeometry g = build(m, shells(5));
  const uint32_t N = 4, E = uint32_t(g.edges.size());
  for (uint32_t s = 0; s + 1 < 5; ++s) {
    for (uint32_t e = 0; e < E; ++e) {
      const size_t q = size_t(s) * E + e;
      const uint32_t a = g.edges[e].a, b = g.edges[e].b;
      const uint32_t* t = &g.fin_indices[q * 6];
      EXPECT_EQ(t[0], a + s * N);
      EXPECT_EQ(t[1], b + s * N);
      EXPECT_EQ(t[2], b + (s + 1) * N);
      EXPECT_EQ(t[3], a + s * N);
      EXPECT_EQ(t[4], b + (s + 1) * N);
      EXPECT_EQ(t[5], a + (s + 1) * N);
      EXPECT_EQ(&g.fin_edge(q), &g.edges[e]);
    }
  }
  for (uint32_t idx : g.fin_indices) EXPECT_LT(idx, g.positions.size());
}

// The lowest growth direction a unit square (normals +y) may have, heading along `heading`:
// kMinFurElevation above its plane.
glm::vec3 lying_flat(glm::vec3 heading) {
  return heading * float(std::cos(kMinFurElevation)) + glm::vec3(0, 1, 0) * float(std::sin(kMinFurElevation));
}

TEST(FurGeometry, CombingBlendsTheGrowthDirection) {
  const Mesh m = test::unit_square();  // normals +y
  FurParams p = shells(4);
  p.comb = CombParams{{2.0f, 0.0f, 0.0f}, 1.0f};
  FurGeometry g = build(m, p);
  for (const glm::vec3& d : g.growth) EXPECT_NEAR(glm::distance(d, lying_flat({1, 0, 0})), 0.0f, 1e-6f);
  p.comb->weight = 0.5f;
  g = build(m, p);
  for (const glm::vec3& d : g.growth) {
    EXPECT_NEAR(d.x, std::sqrt(0.5f), 1e-6);
    EXPECT_NEAR(d.y, std::sqrt(0.5f), 1e-6);
  }
  // Layers move along the combed direction.
  EXPECT_NEAR(glm::length(g.positions[4 * 3] - m.positions[0]), 3 * g.layer_distance, 1e-6);
  EXPECT_NEAR(g.positions[4 * 3].x - m.positions[0].x, 3 * g.layer_distance * std::sqrt(0.5f), 1e-6);
  // Opposite direction at weight 0.5 cancels: the normal is kept, never NaN.
  p.comb = CombParams{{0.0f, -1.0f, 0.0f}, 0.5f};
  g = build(m, p);
  for (const glm::vec3& d : g.growth) EXPECT_EQ(d, glm::vec3(0, 1, 0));
  p.comb->weight = 0.0f;
  g = build(m, p);
  for (const glm::vec3& d : g.growth) EXPECT_EQ(d, glm::vec3(0, 1, 0));
}

// A comb weight above 0.5 against the normal used to flip the growth direction into the mesh
// (the box's top face went bald at weight 0.51). The comb tilts fur down to kMinFurElevation
// above the surface, never into it; with no heading along the surface (d = -n) it keeps the
// normal, as the cancelling blend at 0.5 does; a blend that stays above is unchanged.
TEST(FurGeometry, CombNeverGrowsIntoTheSurface) {
  const Mesh m = test::unit_square();  // normals +y
  FurParams p = shells(4);
  for (float w : {0.51f, 0.75f, 1.0f}) {
    p.comb = CombParams{{0.0f, -1.0f, 0.0f}, w};
    for (const glm::vec3& d : build(m, p).growth) EXPECT_EQ(d, glm::vec3(0, 1, 0)) << "weight " << w;
    p.comb = CombParams{{1.0f, -1.0f, 0.0f}, w};  // 45 degrees into the surface: goes below from about w = 0.6
    for (const glm::vec3& d : build(m, p).growth) {
      if (w > 0.6f) {
        EXPECT_NEAR(glm::distance(d, lying_flat({1, 0, 0})), 0.0f, 1e-6f) << "weight " << w;
      } else {
        EXPECT_GT(d.y, std::sin(kMinFurElevation)) << "weight " << w;
      }
    }
    p.comb = CombParams{{0.0f, -1.0f, 1e-3f}, w};  // a hair off -n: still a heading
    for (const glm::vec3& d : build(m, p).growth) {
      EXPECT_NEAR(glm::distance(d, lying_flat({0, 0, 1})), 0.0f, 1e-6f) << "weight " << w;
      EXPECT_TRUE(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z));
    }
  }
  // Above the surface: exactly the blend.
  const glm::vec3 n(0, 1, 0);
  CombParams c{{1.0f, -1.0f, 0.0f}, 0.3f};
  const glm::vec3 d = c.direction / glm::length(c.direction);
  const glm::vec3 mix = (1.0f - c.weight) * n + c.weight * d;
  const glm::vec3 blend = mix / glm::length(mix);
  EXPECT_EQ(growth_direction(n, c), blend);
  EXPECT_GT(glm::dot(blend, n), std::sin(kMinFurElevation));
}

// Combing along the mesh's UV layout: the quad's u runs along +x and its v along +z, so
// the comb direction follows whichever way uv_direction points, per vertex.
TEST(FurGeometry, CombingFollowsTheUvLayout) {
  Mesh m = test::unit_square();  // normals +y
  FurParams p = shells(4);
  CombParams c;
  c.field = CombField::uv;
  c.weight = 1.0f;
  auto growth_with = [&](glm::vec2 uv_direction, float weight) {
    c.uv_direction = uv_direction;
    c.weight = weight;
    p.comb = c;
    return build(m, p).growth;
  };
  // Weight 1 combs along the surface, held kMinFurElevation above it.
  for (const glm::vec3& d : growth_with({1, 0}, 1.0f)) EXPECT_NEAR(glm::distance(d, lying_flat({1, 0, 0})), 0.0f, 1e-6f);
  for (const glm::vec3& d : growth_with({0, 1}, 1.0f)) EXPECT_NEAR(glm::distance(d, lying_flat({0, 0, 1})), 0.0f, 1e-6f);
  for (const glm::vec3& d : growth_with({0, -2}, 1.0f)) EXPECT_NEAR(glm::distance(d, lying_flat({0, 0, -1})), 0.0f, 1e-6f);
  for (const glm::vec3& d : growth_with({1, 0}, 0.5f))
    EXPECT_NEAR(glm::distance(d, glm::normalize(glm::vec3(1, 1, 0))), 0.0f, 1e-6f);
  // The same quad with its uvs turned a quarter: u now runs along +z, and the fur follows.
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const glm::vec3& d : growth_with({1, 0}, 1.0f)) EXPECT_NEAR(glm::distance(d, lying_flat({0, 0, 1})), 0.0f, 1e-6f);
  // Degenerate uvs give no direction: the normal is kept, never NaN. (They cannot lay the strand
  // texture either: the strands are projected.)
  m.uvs.assign(4, {0.5f, 0.5f});
  p.texture_coordinates = StrandCoordinates::projected;
  for (const glm::vec3& d : growth_with({1, 0}, 1.0f)) EXPECT_EQ(d, glm::vec3(0, 1, 0));
  // No uvs at all: an error naming the field.
  m.uvs.clear();
  p.comb = c;
  EXPECT_EQ(refused_field(m, p), "comb.field");
}

TEST(FurGeometry, UvCombOnACurvedMeshStaysInEachTangentPlane) {
  const Mesh sphere = io::make_builtin_mesh("sphere:24");
  ASSERT_EQ(sphere.uvs.size(), sphere.positions.size());
  const std::vector<glm::vec3> d = uv_comb_directions(sphere, sphere.normals, {1.0f, 0.0f});
  size_t directed = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    if (d[i] == glm::vec3(0.0f)) {
      EXPECT_EQ(std::abs(sphere.positions[i].y), 1.0f) << i << ": only the poles have no direction";
      continue;
    }
    ++directed;
    EXPECT_NEAR(glm::length(d[i]), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(d[i], sphere.normals[i]), 0.0f, 1e-5f);
    // u runs around the y axis: (almost) no component along y, the seam's columns included
    // (the sphere splits its seam: no triangle's u runs back from 23/24 to 0). Not next to the
    // poles; elsewhere the faceted vertex normals tilt the tangent plane by a few thousandths.
    if (std::abs(sphere.positions[i].y) < 0.95f) {
      EXPECT_NEAR(d[i].y, 0.0f, 5e-3f) << i;
    }
  }
  // Every vertex but the poles' copies (24 each, combing along 24 meridians: no one direction).
  EXPECT_EQ(directed, d.size() - 2 * 24);
}

// Copies of a vertex that differ only in texture coordinates grow the same strand: they name
// the lowest-indexed copy. A different normal or growth direction is another strand.
TEST(FurGeometry, SameStrandVerticesJoinCopiesOfOneStrand) {
  const glm::vec3 up(0, 1, 0), tilted = glm::normalize(glm::vec3(1, 1, 0));
  const std::vector<glm::vec3> positions = {{1, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {-0.0f, 0, 0}};
  const std::vector<glm::vec3> normals = {up, up, up, tilted, up, up};
  const std::vector<glm::vec3> growth = {up, up, up, tilted, tilted, up};
  EXPECT_EQ(same_strand_vertices(positions, normals, growth), (std::vector<uint32_t>{0, 1, 0, 3, 4, 1}));
}

// A cube split as a hard-edged exporter writes it: four vertices a face, each with the face's
// normal (as tools/data/BoxTextured.glb).
Mesh hard_edged_cube() {
  Mesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {-1.0f, 1.0f}) {
      glm::vec3 n(0.0f), u(0.0f), v(0.0f);
      n[axis] = sign;
      u[(axis + 1) % 3] = 1.0f;
      v[(axis + 2) % 3] = sign;  // u x v = n: counter-clockwise seen from outside
      const uint32_t base = uint32_t(m.positions.size());
      for (const auto& [a, b] : {std::pair{-1.0f, -1.0f}, {1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}}) {
        m.positions.push_back(n + a * u + b * v);
        m.normals.push_back(n);
        m.uvs.emplace_back((a + 1) / 2, (b + 1) / 2);
      }
      m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  return m;
}

// Fur has no hard edges: the copies of a cube corner grow along one direction (their face
// normals' normalised sum), so every shell layer closes over the edges instead of each face
// growing a slab of its own with a crack between, and each edge grows one fin.
TEST(FurGeometry, HardEdgesGrowOneStrandPerPosition) {
  const Mesh cube = hard_edged_cube();
  const FurGeometry g = build(cube, shells(4));
  const uint32_t N = g.base_vertex_count;
  ASSERT_EQ(N, 24u);
  for (uint32_t i = 0; i < N; ++i) {
    const glm::vec3 corner = glm::normalize(cube.positions[i]);
    EXPECT_NEAR(glm::length(g.base_normals[i] - corner), 0.0f, 1e-6f) << i;
    for (uint32_t j = 0; j < N; ++j) {
      if (cube.positions[j] != cube.positions[i]) continue;
      for (uint32_t s = 0; s < g.layers; ++s) EXPECT_EQ(g.positions[i + s * N], g.positions[j + s * N]) << i << " " << j;
    }
  }
  EXPECT_EQ(g.counts.edges, 18u);  // 12 cube edges and 6 face diagonals
  for (const FurEdge& e : g.edges) EXPECT_NE(e.face1, kNoFace) << e.a << "-" << e.b;
}

// Copies equal in everything the shells are drawn from are one vertex to them, so the rasterizer
// sees the triangles around them share edges, as on the welded mesh: the hard-edged cube without
// uvs, its fur normals joined and its texture coordinates projected along the diagonal from
// positions, names 8 vertices a layer. With its per-face uvs, copies whose uvs differ keep their
// own; so do the box mapping's, each face on its own axis plane (where two planes give a corner
// the same coordinate, the copies are one again).
TEST(FurGeometry, ShellsNameOneVertexForCopiesEqualInAllTheyAreDrawnFrom) {
  for (const StrandCoordinates mapping : {StrandCoordinates::mesh, StrandCoordinates::projected, StrandCoordinates::box}) {
    Mesh cube = hard_edged_cube();
    if (mapping != StrandCoordinates::mesh) cube.uvs.clear();
    FurParams p = shells(3);
    p.texture_coordinates = mapping;
    const FurGeometry g = build(cube, p);
    const uint32_t N = g.base_vertex_count, F = uint32_t(cube.triangle_count());
    ASSERT_EQ(N, cube.positions.size());  // each face on one axis: the box copies nothing
    std::set<std::array<float, 5>> distinct;
    for (uint32_t i = 0; i < N; ++i)
      distinct.insert({cube.positions[i].x, cube.positions[i].y, cube.positions[i].z, g.shell_uvs[i].x, g.shell_uvs[i].y});
    if (mapping == StrandCoordinates::mesh) {  // some faces meet with equal uvs at a corner, others not
      EXPECT_GT(distinct.size(), 8u);
      EXPECT_LT(distinct.size(), 24u);
    } else {
      if (mapping == StrandCoordinates::projected) EXPECT_EQ(distinct.size(), 8u);
      else EXPECT_GT(distinct.size(), 8u);
    }
    std::set<uint32_t> named;
    for (uint32_t s = 0; s < g.layers; ++s)
      for (uint32_t k = 0; k < 3 * F; ++k) {
        const uint32_t v = g.shell_indices[3 * size_t{s} * F + k], own = cube.indices[k] + s * N;
        EXPECT_EQ(v / N, s);
        EXPECT_EQ(g.positions[v], g.positions[own]);
        EXPECT_EQ(g.shell_uvs[v], g.shell_uvs[own]);
        EXPECT_LE(v, own);  // the first such copy
        if (s == 0) named.insert(v);
      }
    EXPECT_EQ(named.size(), distinct.size()) << "mapping " << to_string(mapping);
  }
}

// use_color_map reads the mesh's own uvs, kept per base vertex; copies that the strands would join
// (same position and strand uv, as the box mapping lays them) stay apart where those uvs differ, or
// a shell triangle would read the colour map across the seam.
TEST(FurGeometry, AColourMapKeepsTheMeshUvsAndTheirSeams) {
  Mesh cube = hard_edged_cube();
  FurParams p = shells(3);
  p.texture_coordinates = StrandCoordinates::box;
  const FurGeometry plain = build(cube, p);
  EXPECT_TRUE(plain.mesh_uvs.empty());
  p.use_color_map = true;
  const FurGeometry g = build(cube, p);
  const uint32_t N = g.base_vertex_count, F = uint32_t(cube.triangle_count());
  ASSERT_EQ(N, cube.positions.size());
  ASSERT_EQ(g.mesh_uvs, cube.uvs);
  std::set<uint32_t> named, named_plain;
  for (uint32_t k = 0; k < 3 * F; ++k) {
    const uint32_t v = g.shell_indices[k];
    EXPECT_EQ(g.mesh_uvs[v], cube.uvs[cube.indices[k]]) << "corner " << k;
    EXPECT_EQ(g.shell_uvs[v], g.shell_uvs[cube.indices[k]]) << "corner " << k;
    named.insert(v);
    named_plain.insert(plain.shell_indices[k]);
  }
  // Without the map the cube's copies that differ only in mesh uv are one vertex to the shells.
  EXPECT_GT(named.size(), named_plain.size());
  cube.uvs.clear();
  EXPECT_EQ(refused_field(cube, p), "use_color_map");
}

// The fins read the map at their ends' mesh uvs: with the map an edge names its face0's own copies
// of its ends (at positions equal to the first copies'), so a fin along a seam of the sphere's
// uvs reads one side of it, not the map across the atlas between its ends' first copies.
TEST(FurGeometry, AColourMapPutsEachFinOnItsFaceOwnCopies) {
  const Mesh sphere = io::make_builtin_mesh("sphere:16");
  FurParams p = shells(3);
  const FurGeometry plain = build(sphere, p);
  p.use_color_map = true;
  const FurGeometry g = build(sphere, p);
  ASSERT_EQ(plain.edges.size(), g.edges.size());
  auto corner_of_face0 = [&](const FurEdge& e, uint32_t v) {
    for (int k = 0; k < 3; ++k)
      if (sphere.indices[3 * size_t{e.face0} + k] == v) return true;
    return false;
  };
  size_t first_copy_elsewhere = 0;
  for (size_t i = 0; i < g.edges.size(); ++i) {
    const FurEdge &e = g.edges[i], &before = plain.edges[i];
    EXPECT_EQ(e.face0, before.face0);
    EXPECT_EQ(g.positions[e.a], plain.positions[before.a]) << "edge " << i;
    EXPECT_EQ(g.positions[e.b], plain.positions[before.b]) << "edge " << i;
    bool uv_a = false, uv_b = false;
    for (int k = 0; k < 3; ++k) {
      const glm::vec2 uv = sphere.uvs[sphere.indices[3 * size_t{e.face0} + k]];
      uv_a = uv_a || g.mesh_uvs[e.a] == uv;
      uv_b = uv_b || g.mesh_uvs[e.b] == uv;
    }
    EXPECT_TRUE(uv_a && uv_b) << "edge " << i;
    first_copy_elsewhere += !corner_of_face0(before, before.a) || !corner_of_face0(before, before.b);
  }
  // The seam's and the poles' edges, whose first copies belong to other faces.
  EXPECT_GT(first_copy_elsewhere, 0u);
  for (size_t k = 0; k < g.fin_indices.size(); k += 6) {
    const FurEdge& e = g.edges[(k / 6) % g.edges.size()];
    EXPECT_EQ(g.fin_indices[k] % g.base_vertex_count, e.a);
  }
}

// A length map scales eq. 1's offsets per base vertex; the copies of one strand take their mean
// scale (a map read on two sides of a uv seam gives them slightly apart, and apart they would crack
// the shells and double the fins); a face bare at all three corners has no shells (its shell
// triangles are points, in their places).
TEST(FurGeometry, ALengthMapScalesEachStrandAndBareFacesGrowNoShells) {
  const Mesh sphere = io::make_builtin_mesh("sphere:16");
  const FurParams p = shells(4);
  const FurGeometry full = build(sphere, p);
  const uint32_t N = full.base_vertex_count, F = uint32_t(sphere.triangle_count());
  // All ones: the fur without a map, bit for bit.
  FurGeometry ones;
  ASSERT_FALSE(build_fur_geometry(sphere, p, ones, std::vector<float>(sphere.vertex_count(), 1.0f)).has_value());
  EXPECT_EQ(ones.positions, full.positions);
  EXPECT_EQ(ones.shell_indices, full.shell_indices);
  EXPECT_EQ(ones.bald_faces, 0u);
  // Bare where x < 0, and a copy of a seam vertex told another length than its first copy.
  std::vector<float> scale(sphere.vertex_count());
  for (size_t i = 0; i < scale.size(); ++i) scale[i] = sphere.positions[i].x < 0.0f ? 0.0f : 0.5f;
  const std::vector<uint32_t> same = same_strand_vertices(sphere.positions, full.base_normals, full.growth);
  size_t copy = 0;
  while (copy < same.size() && (same[copy] == copy || sphere.positions[copy].x < 0.0f)) ++copy;
  ASSERT_LT(copy, same.size()) << "the sphere has a seam copy with x >= 0";
  scale[copy] = 0.25f;
  FurGeometry g;
  ASSERT_FALSE(build_fur_geometry(sphere, p, g, scale).has_value());
  ASSERT_EQ(g.length_scale.size(), N);
  uint32_t copies = 0;
  for (uint32_t i = 0; i < N; ++i) copies += same[i] == same[copy];
  const float mean = float((0.5 * (copies - 1) + 0.25) / copies);
  for (uint32_t i = 0; i < N; ++i) {
    const float want = same[i] == same[copy] ? mean : scale[i];
    ASSERT_EQ(g.length_scale[i], want) << "vertex " << i;
    for (uint32_t s = 0; s < g.layers; ++s)
      ASSERT_EQ(g.positions[i + s * N], sphere.positions[i] + g.growth[i] * (g.layer_distance * float(s) * want))
          << "vertex " << i << " layer " << s;
  }
  size_t bare = 0;
  for (uint32_t f = 0; f < F; ++f) {
    const uint32_t* t = &sphere.indices[3 * f];
    const bool all_bare = scale[t[0]] == 0.0f && scale[t[1]] == 0.0f && scale[t[2]] == 0.0f;
    bare += all_bare;
    for (uint32_t s = 0; s < g.layers; ++s) {
      const uint32_t* tri = &g.shell_indices[(size_t(s) * F + f) * 3];
      EXPECT_EQ(all_bare, tri[0] == tri[1] && tri[1] == tri[2]) << "face " << f << " layer " << s;
    }
  }
  EXPECT_EQ(g.bald_faces, bare);
  EXPECT_GT(bare, F / 4);
  // Bad scales are refused by field.
  for (const std::vector<float>& bad : {std::vector<float>(3, 0.5f), std::vector<float>(sphere.vertex_count(), 1.5f),
                                        std::vector<float>(sphere.vertex_count(), std::nanf(""))})
    EXPECT_EQ(refused_field(sphere, p, bad), "length_map");
}

// The strand texture lies at one scale whatever the UV layout: the mesh's uvs are scaled to cover
// as much texture as the projection along the body diagonal lays on the same mesh, so a mesh whose
// uvs span a tenth of the texture grows the same strands as one whose uvs span it all (before, its
// strands were ten times as wide). texture_repeat multiplies either mapping's scale.
TEST(FurGeometry, StrandsLieAtOneScaleWhateverTheUvLayout) {
  const Mesh square = test::unit_square();  // area 1, uv area 1, facing +y: 1/sqrt3 of it projected
  const double k = 2.449490 * std::sqrt(3.0) / double(bounding_sphere(square).radius);
  const FurGeometry g = build(square, shells(3));
  EXPECT_EQ(g.strand_coordinates, StrandCoordinates::mesh);
  EXPECT_NEAR(g.strand_uv_scale, k * std::pow(3.0, -0.25), 1e-6 * k);

  Mesh small_uvs = square;  // the same surface laid on a tenth of the texture, moved off the origin
  for (glm::vec2& uv : small_uvs.uvs) uv = uv * 0.1f + glm::vec2(0.5f, 0.25f);
  const FurGeometry h = build(small_uvs, shells(3));
  EXPECT_NEAR(h.strand_uv_scale, 10.0 * g.strand_uv_scale, 1e-5 * k);
  for (size_t i = 1; i < 4; ++i) {  // the same texture distances between the vertices
    const glm::vec2 a = g.shell_uvs[i] - g.shell_uvs[0], b = h.shell_uvs[i] - h.shell_uvs[0];
    EXPECT_NEAR(glm::length(a - b), 0.0f, 1e-4f) << i;
  }

  FurParams twice = shells(3);
  twice.texture_repeat = 2.0f;
  EXPECT_NEAR(build(square, twice).strand_uv_scale, 2.0 * g.strand_uv_scale, 1e-9 * k);
  twice.texture_coordinates = StrandCoordinates::projected;
  FurParams once = shells(3);
  once.texture_coordinates = StrandCoordinates::projected;
  const FurGeometry dp = build(square, twice), p = build(square, once);
  EXPECT_EQ(p.strand_uv_scale, k);
  EXPECT_EQ(dp.strand_uv_scale, 2.0 * k);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(glm::length(dp.shell_uvs[i] - 2.0f * p.shell_uvs[i]), 0.0f, 1e-5f) << i;
    EXPECT_NEAR(glm::length(dp.fin_uvs[i] - glm::vec2(2.0f * p.fin_uvs[i].x, p.fin_uvs[i].y)), 0.0f, 1e-5f) << i;
  }
}

// The built-in box's and teapot's uvs are the projection itself: they are kept bit for bit (the
// FPS tables and the llvmpipe harness's texture coordinates), not rescaled by a factor a rounding
// away from 1.
TEST(FurGeometry, UvsAlreadyAtTheStrandScaleAreKept) {
  for (const char* name : {"box:7", "teapot:3", "teapot:5"}) {
    const Mesh m = io::make_builtin_mesh(name);
    const FurGeometry g = build(m, shells(3));
    EXPECT_EQ(g.strand_uv_scale, 1.0) << name;
    for (size_t i = 0; i < m.positions.size(); ++i) ASSERT_EQ(g.shell_uvs[i], m.uvs[i]) << name << " " << i;
  }
}

// "projected" ignores the mesh's uvs: the same coordinates as the mesh without them, bit for bit.
TEST(FurGeometry, ProjectedCoordinatesIgnoreTheMeshUvs) {
  Mesh without = test::unit_square();
  without.uvs.clear();
  FurParams p = shells(3);
  p.texture_coordinates = StrandCoordinates::projected;
  const FurGeometry a = build(test::unit_square(), p), b = build(without, p);
  EXPECT_EQ(a.strand_coordinates, StrandCoordinates::projected);
  EXPECT_EQ(b.strand_coordinates, StrandCoordinates::projected);
  EXPECT_EQ(a.shell_uvs, b.shell_uvs);
  EXPECT_EQ(a.strand_uv_scale, b.strand_uv_scale);  // the projection's k
}

// A sheet seen nearly edge-on from the projection's diagonal: the projection lays almost no
// texture on it, and its uvs are scaled against a quarter of its area instead, not blown up.
TEST(FurGeometry, ASheetAlongTheDiagonalKeepsFiniteStrands) {
  Mesh sheet = test::unit_square();
  const glm::dvec3 d = glm::normalize(glm::dvec3(1, 1, 1)), a = glm::normalize(glm::dvec3(1, -1, 0));
  const glm::dvec3 b = glm::normalize(d + 1e-4 * glm::cross(d, a));  // in the sheet, 1e-4 off the diagonal
  for (size_t i = 0; i < 4; ++i) sheet.positions[i] = glm::vec3(a * double(sheet.uvs[i].x) + b * double(sheet.uvs[i].y));
  sheet.normals.assign(4, glm::vec3(glm::normalize(glm::cross(a, b))));
  const FurGeometry g = build(sheet, shells(3));
  const double k = 2.449490 * std::sqrt(3.0) / double(bounding_sphere(sheet).radius);
  EXPECT_NEAR(g.strand_uv_scale, k * 0.5, 1e-3 * k);  // sqrt(0.25) k: uv area 1, area 1
}

TEST(FurGeometry, MeshCoordinatesNeedUvsThatCoverArea) {
  Mesh without = test::unit_square();
  without.uvs.clear();
  FurParams p = shells(3);
  p.texture_coordinates = StrandCoordinates::mesh;
  FurGeometry g;
  auto e = build_fur_geometry(without, p, g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "texture_coordinates");
  EXPECT_NE(e->reason.find("has none"), std::string::npos) << e->reason;
  Mesh flat_uvs = test::unit_square();
  flat_uvs.uvs.assign(4, glm::vec2(0.3f, 0.3f));
  e = build_fur_geometry(flat_uvs, p, g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "texture_coordinates");
  EXPECT_NE(e->reason.find("cover no area"), std::string::npos) << e->reason;
  Mesh tiny_uvs = test::unit_square();  // scaled up 1e5 times they would outrun a float
  for (glm::vec2& uv : tiny_uvs.uvs) uv *= 1e-6f;
  EXPECT_TRUE(build_fur_geometry(tiny_uvs, p, g).has_value());
  // Not asked for: uvs collapsed to a point are taken for none (the box mapping), and the geometry
  // says so for the warning.
  const FurGeometry f = build(flat_uvs, shells(3));
  EXPECT_EQ(f.strand_coordinates, StrandCoordinates::box);
  EXPECT_TRUE(f.uvs_cover_no_area);
  Mesh without_uvs = flat_uvs;
  without_uvs.uvs.clear();
  EXPECT_EQ(f.shell_uvs, build(without_uvs, shells(3)).shell_uvs);
  EXPECT_FALSE(build(test::unit_square(), shells(3)).uvs_cover_no_area);
}

// A zero-area triangle's corners have no face: a glTF without normals gives them +y (flat
// normals of nothing). They take what the faced copies at their position give, and add nothing
// to it; counted in, the made-up +y would tilt the corner's fur, or stop the join and crack it.
TEST(FurGeometry, CopiesWithoutAFaceFollowTheFacedOnes) {
  Mesh cube = hard_edged_cube();
  const uint32_t extra = uint32_t(cube.positions.size());
  for (const glm::vec3& p : {glm::vec3(1, 1, 1), glm::vec3(1, 1, 1), glm::vec3(1, -1, 1)}) {
    cube.positions.push_back(p);
    cube.normals.emplace_back(0, 1, 0);
    cube.uvs.emplace_back(0, 0);
  }
  cube.indices.insert(cube.indices.end(), {extra, extra + 1, extra + 2});
  const FurGeometry g = build(cube, shells(4));
  for (uint32_t i = 0; i < g.base_vertex_count; ++i)
    EXPECT_NEAR(glm::length(g.base_normals[i] - glm::normalize(cube.positions[i])), 0.0f, 1e-6f) << i;
  // Where the faced copies agree (one triangle facing +z), the faceless ones take their normal.
  Mesh one;
  one.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {0, 0, 0}, {1, 0, 0}};
  one.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  one.indices = {0, 1, 2, 3, 4, 5};
  const FurGeometry h = build(one, shells(3));
  for (uint32_t i = 0; i < 6; ++i) EXPECT_EQ(h.base_normals[i], glm::vec3(0, 0, 1)) << i;
}

// A two-sided sheet: each position has a copy facing up and one facing (nearly) down. Their
// normals (nearly) cancel, and their sum would point along the sheet: each keeps its own.
TEST(FurGeometry, OppositeCopiesKeepTheirOwnNormals) {
  Mesh m;
  const glm::vec3 down = glm::normalize(glm::vec3(0.1f, -1.0f, 0.0f));
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  m.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, -1, 0}, down, down};
  m.indices = {0, 2, 1, 3, 4, 5};
  const FurGeometry g = build(m, shells(3));
  for (uint32_t i = 0; i < 6; ++i) EXPECT_EQ(g.base_normals[i], m.normals[i]) << i;
  // Each side's shells keep their own vertices: copies differing in normal are not one vertex.
  for (uint32_t s = 0; s < g.layers; ++s)
    for (uint32_t k = 0; k < 6; ++k) EXPECT_EQ(g.shell_indices[6 * s + k], m.indices[k] + 6 * s) << s << " " << k;
}

// Combed along u, the sphere's copies at each position grow one strand: the seam's join their
// directions, and the poles' (each combed along its own meridian, so no one direction) keep the
// normal. Copies combed apart would open cracks between the shells of the triangles around them.
TEST(FurGeometry, UvCombGrowsOneStrandPerPositionOnTheSphere) {
  const Mesh sphere = io::make_builtin_mesh("sphere:16");
  FurParams p = shells(4);
  CombParams c;
  c.field = CombField::uv;
  c.weight = 0.8f;
  p.comb = c;
  const FurGeometry g = build(sphere, p);
  size_t copies = 0;
  for (size_t i = 0; i < sphere.positions.size(); ++i)
    for (size_t j = i + 1; j < sphere.positions.size(); ++j) {
      if (sphere.positions[i] != sphere.positions[j]) continue;
      ++copies;
      EXPECT_EQ(g.growth[i], g.growth[j]) << i << " and " << j;
    }
  EXPECT_EQ(copies, 7u + 2u * (16u * 15u / 2u));  // the seam's 7 rings, each pole's 16 copies in pairs
  EXPECT_EQ(g.growth[0], g.base_normals[0]);      // the north pole: not combed
  EXPECT_EQ(g.counts.edges, sphere.triangle_count() * 3 / 2);
}

// A split seam is one edge with a face on each side, so it grows one fin: on the split sphere,
// as many edges as a closed mesh has (3 F / 2), the same as when the sphere was welded.
TEST(FurGeometry, ASplitSeamIsOneEdgeWithTwoFaces) {
  const Mesh sphere = io::make_builtin_mesh("sphere:16");
  const FurGeometry g = build(sphere, shells(4));
  EXPECT_EQ(g.counts.edges, sphere.triangle_count() * 3 / 2);
  EXPECT_EQ(g.counts.joined_vertices, 7u + 2u * 15u);  // the seam's 7 copies, each pole's 15 beyond its first
  for (const FurEdge& e : g.edges) EXPECT_NE(e.face1, kNoFace) << e.a << "-" << e.b;
  // Without the joining, each seam side and each pole fan triangle is a boundary edge.
  size_t boundary = 0;
  for (const FurEdge& e : mesh_edges(sphere)) boundary += e.face1 == kNoFace;
  EXPECT_EQ(boundary, 2u * (16 / 2 - 2) + 2u * 16u + 2u * 16u);
}

TEST(FurGeometry, MissingNormalsAndUvsAreComputed) {
  Mesh m = test::tetrahedron();
  const Mesh with = m;
  m.normals.clear();
  m.uvs.clear();
  const FurGeometry g = build(m, shells(3));
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(glm::length(g.base_normals[i] - with.normals[i]), 0.0f, 1e-6);
    EXPECT_TRUE(std::isfinite(g.shell_uvs[i].x) && std::isfinite(g.shell_uvs[i].y));
  }
  EXPECT_NE(g.shell_uvs[0], g.shell_uvs[1]);
}

TEST(FurGeometry, BadMeshesAreRejectedByField) {
  FurGeometry g;
  Mesh m = test::tetrahedron();
  m.indices[5] = 9;
  auto e = build_fur_geometry(m, shells(3), g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "mesh.indices");
  m = test::tetrahedron();
  m.indices.pop_back();
  e = build_fur_geometry(m, shells(3), g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "mesh.indices");
  m = test::tetrahedron();
  m.normals.pop_back();
  e = build_fur_geometry(m, shells(3), g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "mesh.normals");
  m = test::tetrahedron();
  m.normals[2] = {0, 0, 0};
  e = build_fur_geometry(m, shells(3), g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "mesh.normals");
  m = test::tetrahedron();
  m.uvs.resize(2);
  e = build_fur_geometry(m, shells(3), g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "mesh.uvs");
  m = test::tetrahedron();
  m.positions[1].x = std::numeric_limits<float>::quiet_NaN();
  e = build_fur_geometry(m, shells(3), g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "mesh.positions");
  e = build_fur_geometry(Mesh{}, shells(3), g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "mesh.positions");
  e = build_fur_geometry(test::tetrahedron(), shells(1), g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "shells");
}

// Seed Table 1, exactly.
TEST(FurGeometry, Box7MatchesSeedTable1) {
  const FurGeometry g = build(io::make_builtin_mesh("box:7"), shells(16));
  EXPECT_EQ(g.counts.base_vertices, 296u);
  EXPECT_EQ(g.counts.shell_vertices, 4736u);
  EXPECT_EQ(g.counts.fin_vertices, 4736u);
  EXPECT_EQ(g.counts.total_vertices, 5032u);
  EXPECT_EQ(g.counts.base_faces, 588u);
  EXPECT_EQ(g.counts.shell_faces, 9408u);
  EXPECT_EQ(g.counts.fin_faces, 26460u);
  EXPECT_EQ(g.counts.total_faces, 36456u);
  EXPECT_EQ(g.counts.edges, 882u);
  EXPECT_EQ(g.counts.joined_vertices, 0u);  // welded: no copies
  EXPECT_EQ(g.fin_indices.size(), 3u * 26460u);
  EXPECT_EQ(g.shell_indices.size(), 3u * 9408u);
  // The llvmpipe harness's fur: R = sqrt(3), outermost layer 0.1 R from the surface.
  EXPECT_NEAR(g.bounds.radius, std::sqrt(3.0f), 1e-6);
  EXPECT_NEAR(g.layer_distance, 0.1f * std::sqrt(3.0f) / 15.0f, 1e-7);
}

// The llvmpipe README's teapot counts (seed Tables 2 and 3 list 302 and 882 base
// vertices; the tessellation welds to 301 and 821, see the README).
TEST(FurGeometry, TeapotCountsMatchTheLlvmpipeHarness) {
  const FurGeometry t3 = build(io::make_builtin_mesh("teapot:3"), shells(16));
  EXPECT_EQ(t3.counts.base_vertices, 301u);
  EXPECT_EQ(t3.counts.shell_vertices, 4816u);
  EXPECT_EQ(t3.counts.total_vertices, 5117u);
  EXPECT_EQ(t3.counts.base_faces, 552u);
  EXPECT_EQ(t3.counts.shell_faces, 8832u);
  EXPECT_EQ(t3.counts.fin_faces, 25560u);
  EXPECT_EQ(t3.counts.total_faces, 34944u);
  EXPECT_EQ(t3.counts.edges, 852u);
  const FurGeometry t5 = build(io::make_builtin_mesh("teapot:5"), shells(16));
  EXPECT_EQ(t5.counts.base_vertices, 821u);
  EXPECT_EQ(t5.counts.shell_vertices, 13136u);
  EXPECT_EQ(t5.counts.total_vertices, 13957u);
  EXPECT_EQ(t5.counts.base_faces, 1560u);
  EXPECT_EQ(t5.counts.shell_faces, 24960u);
  EXPECT_EQ(t5.counts.fin_faces, 71400u);
  EXPECT_EQ(t5.counts.total_faces, 97920u);
  EXPECT_EQ(t5.counts.edges, 2380u);
  int boundary = 0;
  for (const FurEdge& e : t5.edges) boundary += e.face1 == kNoFace;
  EXPECT_EQ(boundary, 80);
}

// Kills a mutant that kept a degenerate triangle (one naming an edge twice) as the second
// face of that edge: the edge's real neighbour would be lost, and the fin's silhouette test
// (tools/render/fur_object.cpp) would read the degenerate face's fallback normal instead.
TEST(FurGeometry, ADegenerateTriangleIsNotASecondFace) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  m.indices = {0, 1, 0, 0, 1, 2};  // face 0 is degenerate and names edge (0, 1) twice
  const std::vector<FurEdge> edges = mesh_edges(m);
  ASSERT_EQ(edges.size(), 3u);
  EXPECT_EQ(edges[0].a, 0u);
  EXPECT_EQ(edges[0].b, 1u);
  EXPECT_EQ(edges[0].face0, 0u);
  EXPECT_EQ(edges[0].face1, 1u);  // the real triangle, not face 0 again
  // A degenerate triangle alone on an edge leaves it a boundary edge.
  m.indices = {0, 1, 2, 1, 2, 1};
  for (const FurEdge& e : mesh_edges(m)) {
    EXPECT_NE(e.face0, e.face1) << e.a << "-" << e.b;
    if (e.a == 1 && e.b == 2) {
      EXPECT_EQ(e.face0, 0u);
      EXPECT_EQ(e.face1, 1u);
    } else {
      EXPECT_EQ(e.face1, kNoFace) << e.a << "-" << e.b;
    }
  }
}

// fur_geometry.h: away from a true silhouette the fin follows the MORE edge-on of its two
// faces (c = min(|c_a|, |c_b|)); a fin next to a face seen edge-on must show even when the
// other face looks straight at the viewer. Kills min -> max.
TEST(FinWeight, TheMoreEdgeOnFaceDecides) {
  const glm::vec3 up(0, 1, 0), tilted = glm::normalize(glm::vec3(1, 0.2f, 0));
  const glm::vec3 view = up;  // c_a = 1, c_b = 0.196: same sign, no silhouette
  const float c = std::fabs(glm::dot(tilted, view));
  const float x = std::clamp(c / 0.5f, 0.0f, 1.0f);
  const float expect = 1.0f - x * x * (3.0f - 2.0f * x);
  ASSERT_GT(expect, 0.5f);  // the setting shows a mostly visible fin
  EXPECT_NEAR(fin_weight(up, tilted, view, FinMode::silhouette), expect, 1e-6f);
  EXPECT_NEAR(fin_weight(tilted, up, view, FinMode::silhouette), expect, 1e-6f);
  EXPECT_NEAR(fin_weight(up, tilted, -view, FinMode::silhouette), expect, 1e-6f);
}

TEST(FinWeight, ModesAndSilhouetteShape) {
  const glm::vec3 up(0, 1, 0), side(1, 0, 0);
  EXPECT_EQ(fin_weight(up, up, side, FinMode::off), 0.0f);
  EXPECT_EQ(fin_weight(up, up, up, FinMode::all), 1.0f);
  // Both faces facing the viewer: no fin.
  EXPECT_EQ(fin_weight(up, up, up, FinMode::silhouette), 0.0f);
  EXPECT_EQ(fin_weight(up, up, -up, FinMode::silhouette), 0.0f);
  // Edge-on: full fin.
  EXPECT_EQ(fin_weight(up, up, side, FinMode::silhouette), 1.0f);
  // True silhouette: one face toward, one away.
  const glm::vec3 a = glm::normalize(glm::vec3(1, 1, 0)), b = glm::normalize(glm::vec3(-1, 1, 0));
  EXPECT_EQ(fin_weight(a, b, side, FinMode::silhouette), 1.0f);
  // Boundary edge uses its one face.
  EXPECT_EQ(fin_weight(up, std::nullopt, side, FinMode::silhouette), 1.0f);
  EXPECT_EQ(fin_weight(up, std::nullopt, up, FinMode::silhouette), 0.0f);
  // Fades monotonically as the face turns toward the viewer; gone at |n.v| = 0.5.
  float prev = 1.0f;
  for (int k = 0; k <= 90; ++k) {
    const float ang = float(k) * 3.14159265f / 180.0f;  // angle between v and the face plane
    const glm::vec3 v(std::cos(ang), std::sin(ang), 0.0f);
    const float w = fin_weight(up, up, v, FinMode::silhouette);
    EXPECT_LE(w, prev + 1e-7f);
    prev = w;
    if (std::sin(ang) >= 0.5f + 1e-6f) {
      EXPECT_EQ(w, 0.0f);
    }
  }
  EXPECT_NEAR(fin_weight(up, up, glm::vec3(1, std::tan(3.14159265f / 12), 0), FinMode::silhouette),
              0.5f, 0.15f);
  // Degenerate view: the fin is shown, never NaN.
  EXPECT_EQ(fin_weight(up, up, glm::vec3(0), FinMode::silhouette), 1.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(fin_weight(up, up, glm::vec3(nan, 0, 0), FinMode::silhouette), 1.0f);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int k = 0; k < 1000; ++k) {
    glm::vec3 na(u(rng), u(rng), u(rng)), nb(u(rng), u(rng), u(rng)), v(u(rng), u(rng), u(rng));
    const float w = fin_weight(glm::normalize(na), glm::normalize(nb), v, FinMode::silhouette);
    EXPECT_GE(w, 0.0f);
    EXPECT_LE(w, 1.0f);
  }
}

// The texture area a layer of shells lays on the mesh, and the least ratio of a triangle's texture
// area to its area times scale^2 (1 / the most a strand is stretched along one direction).
struct UvCover {
  double area = 0.0, least_ratio = 1e30;
};
UvCover uv_cover(const FurGeometry& g) {
  UvCover c;
  const size_t F = g.counts.base_faces;
  for (size_t f = 0; f < F; ++f) {
    const uint32_t* t = &g.shell_indices[3 * f];
    const glm::dvec2 a(g.shell_uvs[t[0]]), du = glm::dvec2(g.shell_uvs[t[1]]) - a, dv = glm::dvec2(g.shell_uvs[t[2]]) - a;
    const double uv_area = 0.5 * std::abs(du.x * dv.y - du.y * dv.x);
    const glm::dvec3 p(g.positions[t[0]]);
    const double area = 0.5 * glm::length(glm::cross(glm::dvec3(g.positions[t[1]]) - p, glm::dvec3(g.positions[t[2]]) - p));
    c.area += uv_area;
    if (area > 1e-9) c.least_ratio = std::min(c.least_ratio, uv_area / (area * g.strand_uv_scale * g.strand_uv_scale));
  }
  return c;
}

// Without uvs the strands are laid by the box mapping: each triangle on the axis plane its
// corners' fur normals face most, so a strand is stretched at most sqrt(3) times along one
// direction. The harness's projection along the body diagonal stretches it without bound in the
// band where the sphere runs along the diagonal.
TEST(FurGeometry, BoxMappingLaysEachTriangleOnTheAxisItFaces) {
  Mesh sphere = io::make_builtin_mesh("sphere:24");
  sphere.uvs.clear();
  const FurGeometry g = build(sphere, shells(3));
  ASSERT_EQ(g.strand_coordinates, StrandCoordinates::box);
  const double k = g.strand_uv_scale;
  const size_t F = sphere.triangle_count();
  for (size_t f = 0; f < F; ++f) {
    const uint32_t* t = &g.shell_indices[3 * f];
    glm::dvec3 sum(0.0);
    for (int c = 0; c < 3; ++c) sum += glm::dvec3(g.base_normals[t[c]]);
    const glm::dvec3 a = glm::abs(sum);
    const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
    // The plane's two axes (x: z and y; y: x and z; z: x and y), by the lengths of the edges' steps.
    const int u_of[3] = {2, 0, 0}, v_of[3] = {1, 2, 1};
    for (int c = 1; c < 3; ++c) {
      const glm::dvec3 dp = glm::dvec3(g.positions[t[c]]) - glm::dvec3(g.positions[t[0]]);
      const glm::dvec2 duv = glm::dvec2(g.shell_uvs[t[c]]) - glm::dvec2(g.shell_uvs[t[0]]);
      EXPECT_NEAR(std::abs(duv.x), k * std::abs(dp[u_of[axis]]), 1e-4 * k) << "face " << f;
      EXPECT_NEAR(std::abs(duv.y), k * std::abs(dp[v_of[axis]]), 1e-4 * k) << "face " << f;
    }
  }
  EXPECT_GT(uv_cover(g).least_ratio, 0.55);  // a smooth sphere: 1 / sqrt(3) = 0.577, less the facets' tilt
  FurParams p = shells(3);
  p.texture_coordinates = StrandCoordinates::projected;
  EXPECT_LT(uv_cover(build(sphere, p)).least_ratio, 0.1);
}

// A vertex where two axis planes meet is copied, one copy a plane: the copies grow one strand (the
// same positions in every layer), so they are joined like a seam's and grow no fin between them.
// fur_base_vertex_count, which the memory estimate uses, counts what the build makes.
TEST(FurGeometry, BoxMappingCopiesAreOneStrand) {
  Mesh sphere = io::make_builtin_mesh("sphere:24");
  sphere.uvs.clear();
  const size_t n = sphere.positions.size();
  FurParams projected = shells(4);
  projected.texture_coordinates = StrandCoordinates::projected;
  const FurGeometry g = build(sphere, shells(4)), p = build(sphere, projected);
  const uint32_t N = g.base_vertex_count;
  ASSERT_GT(N, n);
  EXPECT_EQ(p.base_vertex_count, n);
  EXPECT_EQ(g.counts.edges, p.counts.edges);
  EXPECT_EQ(g.counts.joined_vertices - p.counts.joined_vertices, N - n);
  for (uint32_t i = uint32_t(n); i < N; ++i) {
    bool other_plane = false, found = false;  // a copy only where the plane changes
    for (uint32_t j = 0; j < n; ++j) {
      if (sphere.positions[j] != g.positions[i]) continue;
      found = true;
      other_plane |= g.shell_uvs[i] != g.shell_uvs[j];
      for (uint32_t s = 0; s < g.layers; ++s) EXPECT_EQ(g.positions[i + s * N], g.positions[j + s * N]) << i << " " << s;
    }
    EXPECT_TRUE(found && other_plane) << i;
  }
  EXPECT_EQ(fur_base_vertex_count(sphere, shells(4)), N);
  EXPECT_EQ(fur_base_vertex_count(sphere, projected), n);
  const Mesh with_uvs = io::make_builtin_mesh("sphere:24");
  EXPECT_EQ(fur_base_vertex_count(with_uvs, shells(4)), build(with_uvs, shells(4)).base_vertex_count);
  FurParams box = shells(4);
  box.texture_coordinates = StrandCoordinates::box;
  EXPECT_EQ(fur_base_vertex_count(with_uvs, box), build(with_uvs, box).base_vertex_count);
  Mesh collapsed = with_uvs;  // taken for none: the box's count
  collapsed.uvs.assign(collapsed.positions.size(), glm::vec2(0.5f));
  EXPECT_EQ(fur_base_vertex_count(collapsed, shells(4)), build(collapsed, shells(4)).base_vertex_count);
  EXPECT_GT(build(collapsed, shells(4)).base_vertex_count, collapsed.positions.size());
}

// The box lays as much strand texture on the mesh as the projection does, spread evenly instead
// of thinned where the projection stretches: the same number of strands at either mapping, and
// texture_repeat multiplies both alike.
TEST(FurGeometry, BoxMappingLaysAsMuchTextureAsTheProjection) {
  for (const char* name : {"sphere:24", "teapot:3", "box:3"}) {
    Mesh m = io::make_builtin_mesh(name);
    m.uvs.clear();
    FurParams p = shells(3);
    p.texture_coordinates = StrandCoordinates::projected;
    const double box = uv_cover(build(m, shells(3))).area, projected = uv_cover(build(m, p)).area;
    EXPECT_NEAR(box / projected, 1.0, 1e-3) << name;
    FurParams twice = shells(3);
    twice.texture_repeat = 2.0f;
    EXPECT_NEAR(uv_cover(build(m, twice)).area / box, 4.0, 4e-3) << name;
  }
}

// A faceted surface (a sphere whose points were jittered, without normals): where the smooth
// normals' axis leaves a facet tilted away from it facing it by less than a half, the facet takes
// its own normal's axis, so no triangle's texture area falls below half its area times k^2 (a
// strand stretched at most twice).
TEST(FurGeometry, BoxMappingBoundsTheStretchOnAFacetedSurface) {
  Mesh sphere = io::make_builtin_mesh("sphere:32");
  sphere.uvs.clear();
  sphere.normals.clear();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-0.06f, 0.06f);
  // The same jitter for every copy of a position (the sphere's seam), so the mesh stays closed.
  const std::vector<uint32_t> first = same_position_vertices(sphere.positions);
  for (size_t i = 0; i < sphere.positions.size(); ++i) {
    if (first[i] != i) continue;
    const float dx = jitter(rng), dy = jitter(rng), dz = jitter(rng);  // in this order on any compiler
    sphere.positions[i] += glm::vec3(dx, dy, dz);
  }
  for (size_t i = 0; i < sphere.positions.size(); ++i) sphere.positions[i] = sphere.positions[first[i]];
  const FurGeometry g = build(sphere, shells(3));
  ASSERT_EQ(g.strand_coordinates, StrandCoordinates::box);
  EXPECT_GT(uv_cover(g).least_ratio, 0.5 - 1e-4);
}

// The axis follows the fur's normals, unit length: a file's normal ten times too long does not
// outweigh the others. This triangle faces (1, 1, 0); two corners' normals say x, the third's,
// ten units long, y: the unit sum (2, 1, 0) picks x, the plane (-z, y), in which the first edge
// (-1, 1, 0) has no u. A vertex no triangle names is kept, on y's plane, finite.
TEST(FurGeometry, BoxMappingWeighsUnitNormals) {
  Mesh m;
  m.positions = {{1, 0, 0}, {0, 1, 0}, {1, 0, 1}, {5, 5, 5}};
  m.normals = {{1, 0, 0}, {1, 0, 0}, {0, 10, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2};
  const FurGeometry g = build(m, shells(3));
  ASSERT_EQ(g.base_vertex_count, 4u);
  const glm::vec2 edge = g.shell_uvs[1] - g.shell_uvs[0];
  EXPECT_EQ(edge.x, 0.0f);
  EXPECT_NEAR(std::abs(edge.y), g.strand_uv_scale, 1e-4 * g.strand_uv_scale);
  EXPECT_TRUE(std::isfinite(g.shell_uvs[3].x) && std::isfinite(g.shell_uvs[3].y));
}

// A vertex at 1e21 made the bounding radius overflow to infinity, and every fur vertex followed it
// there (found by fuzz_fur; tests/fuzz/regressions/fur/huge_coordinate.obj). Such a mesh is refused,
// naming the field; one within the reach grows finite fur.
TEST(FurGeometry, AMeshBeyondFloatReachIsRefused) {
  Mesh far = test::unit_square();
  far.positions[2].z = -1e21f;
  FurGeometry g;
  const auto e = build_fur_geometry(far, shells(3), g);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "mesh.positions");
  EXPECT_NE(e->reason.find("32-bit floats"), std::string::npos) << e->reason;
  Mesh large = test::unit_square();
  for (glm::vec3& p : large.positions) p *= 1e16f;
  const FurGeometry h = build(large, shells(3));
  for (const glm::vec3& p : h.positions) ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
}

}  // namespace
}  // namespace pelt::fur
