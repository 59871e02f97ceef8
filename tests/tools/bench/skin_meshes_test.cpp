// The meshes of `pelt bench skin`: each step checked on small meshes with known answers,
// then the three bench meshes built from the real head scan.
#include "tools/bench/skin_meshes.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tools/io/builtin_meshes.h"
#include "tools/io/input_error.h"

namespace pelt::bench {
namespace {

Mesh octahedron() {
  Mesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // Counter-clockwise from outside: for each octant (sx, sy, sz) the x, y, z vertices.
  for (int sx : {0, 1})
    for (int sy : {2, 3})
      for (int sz : {4, 5}) {
        const bool flip = (sx == 1) ^ (sy == 3) ^ (sz == 5);
        if (flip)
          m.indices.insert(m.indices.end(), {uint32_t(sx), uint32_t(sz), uint32_t(sy)});
        else
          m.indices.insert(m.indices.end(), {uint32_t(sx), uint32_t(sy), uint32_t(sz)});
      }
  return m;
}

Mesh position_only(Mesh m) {
  m.normals.clear();
  m.uvs.clear();
  return m;
}

double signed_volume(const Mesh& m) {
  double v = 0.0;
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    const glm::dvec3 a(m.positions[m.indices[3 * t]]), b(m.positions[m.indices[3 * t + 1]]),
        c(m.positions[m.indices[3 * t + 2]]);
    v += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return v;
}

void expect_valid(const Mesh& m, const std::string& what) {
  const MeshTopology t = mesh_topology(m);
  EXPECT_EQ(t.nonfinite_values, 0u) << what;
  EXPECT_EQ(t.bad_indices, 0u) << what;
  EXPECT_EQ(t.degenerate_triangles, 0u) << what;
  EXPECT_EQ(t.winding_conflicts, 0u) << what;
  EXPECT_EQ(t.nonmanifold_edges, 0u) << what;
  if (!m.normals.empty()) {
    ASSERT_EQ(m.normals.size(), m.positions.size()) << what;
    for (const glm::vec3& n : m.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f) << what;
  }
}

TEST(SkinBenchRows, ArePaperTable1) {
  const auto& rows = skin_bench_rows();
  EXPECT_EQ(rows[0].name, "Face");
  EXPECT_EQ(rows[0].paper_triangles, 17244u);
  EXPECT_EQ(rows[0].target_triangles, 0u);
  EXPECT_EQ(rows[1].name, "Male body");
  EXPECT_EQ(rows[1].paper_triangles, 103381u);
  EXPECT_EQ(rows[1].target_triangles, 103381u);
  EXPECT_EQ(rows[2].name, "Female body");
  EXPECT_EQ(rows[2].paper_triangles, 120518u);
  EXPECT_EQ(rows[2].target_triangles, 120518u);
  EXPECT_EQ(rows[0].paper_skin_s, 2.0);
  EXPECT_EQ(rows[0].paper_blinn_lambert_s, 1.0);
  EXPECT_EQ(rows[0].paper_stam_s, 3.0);
  for (int i : {1, 2}) {
    EXPECT_EQ(rows[i].paper_skin_s, 7.0);
    EXPECT_EQ(rows[i].paper_blinn_lambert_s, 6.0);
    EXPECT_EQ(rows[i].paper_stam_s, 7.0);
  }
}

TEST(WeldPositions, MergesSeamCopiesIntoTheFirst) {
  // A quad whose diagonal is a "seam": vertices 3 and 4 copy 0 and 2.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0.5f, 0}, {0.5f, 1}, {0, 1}};
  m.indices = {0, 1, 2, 3, 4, 5};
  EXPECT_EQ(mesh_topology(m).boundary_edges, 4u);  // topology is measured after welding
  const Mesh w = weld_positions(m);
  ASSERT_EQ(w.positions.size(), 4u);
  EXPECT_EQ(w.positions[3], glm::vec3(0, 1, 0));
  EXPECT_EQ(w.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_TRUE(w.uvs.empty());
  EXPECT_TRUE(w.normals.empty());
}

TEST(WeldPositions, DropsTrianglesThatCollapse) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2, 0, 1, 3};
  const Mesh w = weld_positions(m);
  EXPECT_EQ(w.indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(w.positions.size(), 3u);
}

TEST(WeldPositions, RejectsIndexOutOfRange) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.indices = {0, 1, 3};
  EXPECT_THROW(weld_positions(m), io::InputError);
}

TEST(LoopSubdivide, OctahedronKnownAnswer) {
  // Valence 4, beta = 3/32: a vertex moves to (1 - 12/32) v + 3/32 (sum of its four
  // neighbours, which is 0), and an edge point is 3/8 (a + b) + 1/8 (c + d) with c = -d.
  const Mesh s = loop_subdivide(octahedron());
  ASSERT_EQ(s.triangle_count(), 32u);
  ASSERT_EQ(s.positions.size(), 6u + 12u);
  EXPECT_FLOAT_EQ(s.positions[0].x, 0.625f);
  EXPECT_FLOAT_EQ(s.positions[0].y, 0.0f);
  EXPECT_FLOAT_EQ(s.positions[0].z, 0.0f);
  for (size_t i = 6; i < s.positions.size(); ++i) {
    const glm::vec3 p = glm::abs(s.positions[i]);
    const float sum = p.x + p.y + p.z;
    EXPECT_FLOAT_EQ(sum, 0.75f) << i;  // two coordinates are 0.375, one is 0
    EXPECT_EQ(int(p.x == 0.0f) + int(p.y == 0.0f) + int(p.z == 0.0f), 1) << i;
  }
  const MeshTopology t = mesh_topology(s);
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.winding_conflicts, 0u);
  EXPECT_GT(signed_volume(s), 0.0);  // still outward
}

TEST(LoopSubdivide, ClosedMeshStaysClosedAndShrinksInsideHull) {
  const Mesh box = position_only(io::make_builtin_mesh("box:2"));
  Mesh s = box;
  for (int i = 0; i < 2; ++i) s = loop_subdivide(s);
  EXPECT_EQ(s.triangle_count(), box.triangle_count() * 16);
  const MeshTopology t = mesh_topology(s);
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.nonmanifold_edges, 0u);
  EXPECT_EQ(t.winding_conflicts, 0u);
  EXPECT_EQ(t.degenerate_triangles, 0u);
  // Loop points are convex combinations of old points: they stay in the cube.
  for (const glm::vec3& p : s.positions)
    for (int k = 0; k < 3; ++k) EXPECT_LE(std::abs(p[k]), 1.0f);
  // Euler characteristic 2: V - E + F with E = 3F/2.
  EXPECT_EQ(int64_t(s.positions.size()) - int64_t(s.triangle_count() * 3 / 2) + int64_t(s.triangle_count()), 2);
}

TEST(LoopSubdivide, OpenSheetKeepsItsOutline) {
  // plane:2 is the square [-1,1]^2 in y = 0: every point stays in the plane and inside
  // the square, the outline is split (twice as many border edges), and a border vertex
  // follows the crease rule of its two border neighbours only.
  const Mesh plane = position_only(io::make_builtin_mesh("plane:2"));
  const Mesh s = loop_subdivide(plane);
  EXPECT_EQ(mesh_topology(s).boundary_edges, mesh_topology(plane).boundary_edges * 2);
  for (const glm::vec3& p : s.positions) {
    EXPECT_EQ(p.y, 0.0f);
    EXPECT_LE(std::abs(p.x), 1.0f);
    EXPECT_LE(std::abs(p.z), 1.0f);
  }
  // The border vertex (1, 0, 0): crease neighbours (1, 0, +-1) -> 3/4 (1,0,0) + 1/8 (2,0,0).
  bool found = false;
  for (size_t i = 0; i < plane.positions.size(); ++i)
    if (plane.positions[i] == glm::vec3(1, 0, 0)) {
      EXPECT_EQ(s.positions[i], glm::vec3(1, 0, 0));
      found = true;
    }
  EXPECT_TRUE(found);
  // Interior vertex (0,0,0) of a flat grid stays at the origin (affine invariance).
  for (size_t i = 0; i < plane.positions.size(); ++i)
    if (plane.positions[i] == glm::vec3(0, 0, 0)) {
      EXPECT_NEAR(s.positions[i].x, 0.0f, 1e-7f);
      EXPECT_NEAR(s.positions[i].z, 0.0f, 1e-7f);
    }
}

TEST(DecimateTo, ReachesTheCountWithinOnePercent) {
  const Mesh sphere = position_only(io::make_builtin_mesh("sphere:128"));
  for (uint64_t target : {1000u, 4321u, 7777u}) {
    const Mesh d = decimate_to(sphere, target, "sphere");
    EXPECT_LE(std::abs(double(d.triangle_count()) - double(target)), 0.01 * double(target)) << target;
    const MeshTopology t = mesh_topology(d);
    EXPECT_EQ(t.boundary_edges, 0u) << target;
    EXPECT_EQ(t.bad_indices, 0u) << target;
    EXPECT_EQ(t.winding_conflicts, 0u) << target;
    // Compacted: every vertex is used.
    std::set<uint32_t> used(d.indices.begin(), d.indices.end());
    EXPECT_EQ(used.size(), d.positions.size()) << target;
  }
}

TEST(DecimateTo, RejectsImpossibleTargets) {
  const Mesh box = position_only(io::make_builtin_mesh("box:1"));
  try {
    decimate_to(box, 13, "Male body");
    FAIL() << "no throw";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.field, "Male body");
    EXPECT_NE(e.reason.find("1..12"), std::string::npos) << e.reason;
  }
  EXPECT_THROW(decimate_to(box, 0, "x"), io::InputError);
}

TEST(MeshTopology, CountsProblems) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {NAN, 0, 0}};
  m.indices = {0, 1, 2, 0, 1, 3, 0, 3, 7};
  const MeshTopology t = mesh_topology(m);
  EXPECT_EQ(t.nonfinite_values, 1u);
  EXPECT_EQ(t.bad_indices, 1u);
  EXPECT_EQ(t.degenerate_triangles, 1u);  // the collinear 0,1,2
  EXPECT_EQ(t.winding_conflicts, 1u);     // 0->1 used by both valid triangles
}

// The three meshes, built once for the suite (about a second). The head is found the way
// the CLI finds it; ctest sets PELT_SOURCE_DIR, so this is the checkout's copy.
class HeadMeshes : public ::testing::Test {
 protected:
  static const std::filesystem::path& head() {
    static const std::filesystem::path p = find_head_scan("test");
    return p;
  }
  static const std::vector<SkinBenchMesh>& meshes() {
    static const std::vector<SkinBenchMesh> m = make_skin_bench_meshes(head());
    return m;
  }
};

TEST_F(HeadMeshes, CountsMatchThePaperWithinOnePercent) {
  ASSERT_EQ(meshes().size(), 3u);
  EXPECT_EQ(meshes()[0].mesh.triangle_count(), 17684u);  // the scan as is
  for (size_t i = 0; i < 3; ++i) {
    const SkinBenchMesh& m = meshes()[i];
    EXPECT_EQ(m.row, &skin_bench_rows()[i]);
    if (m.row->target_triangles == 0) continue;
    const double target = double(m.row->target_triangles);
    EXPECT_LE(std::abs(double(m.mesh.triangle_count()) - target), kTriangleCountTolerance * target)
        << m.row->name << ": " << m.mesh.triangle_count();
  }
}

TEST_F(HeadMeshes, AreValidAndClosed) {
  for (const SkinBenchMesh& m : meshes()) {
    expect_valid(m.mesh, std::string(m.row->name));
    ASSERT_EQ(m.mesh.normals.size(), m.mesh.positions.size()) << m.row->name;
    const MeshTopology t = mesh_topology(m.mesh);
    // Once its UV-seam copies are welded the scan is closed; refining and decimating must
    // keep it so (no cracks along the seams, no holes).
    EXPECT_EQ(t.boundary_edges, 0u) << m.row->name;
    // Outward winding kept: the head's signed volume is positive in every mesh.
    EXPECT_GT(signed_volume(m.mesh), 0.0) << m.row->name;
  }
}

TEST_F(HeadMeshes, Deterministic) {
  const std::vector<SkinBenchMesh> again = make_skin_bench_meshes(head());
  ASSERT_EQ(again.size(), meshes().size());
  for (size_t i = 0; i < again.size(); ++i) {
    const Mesh &a = again[i].mesh, &b = meshes()[i].mesh;
    EXPECT_EQ(a.indices, b.indices) << again[i].row->name;
    EXPECT_EQ(a.positions, b.positions) << again[i].row->name;
    EXPECT_EQ(a.normals, b.normals) << again[i].row->name;
    EXPECT_EQ(a.uvs, b.uvs) << again[i].row->name;
  }
}

TEST_F(HeadMeshes, FindHeadScanUsesPeltSourceDir) {
  const char* root = std::getenv("PELT_SOURCE_DIR");
  ASSERT_NE(root, nullptr) << "ctest sets PELT_SOURCE_DIR";
  EXPECT_EQ(find_head_scan("--head"), std::filesystem::path(root) / "tools/data/LeePerrySmith/LeePerrySmith.glb");
}

TEST(MakeSkinBenchMeshes, MissingFileIsInputError) {
  EXPECT_THROW(make_skin_bench_meshes("/nonexistent/LeePerrySmith.glb"), io::InputError);
}

}  // namespace
}  // namespace pelt::bench
