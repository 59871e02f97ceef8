// The meshes of `pelt bench skin`: the paper's Table 1 (Face 17,244 / Male body 103,381 /
// Female body 120,518 triangles) rebuilt from the one real scan we ship, the LeePerrySmith
// head (17,684 triangles).
//
// How each mesh is made (deterministic: same input file, same bytes out):
//   Face         the head exactly as loaded (positions, normals, UVs, triangles of the GLB).
//   Male body,   1. weld: vertices at bitwise-equal positions (the copies the scan has along
//   Female body     its UV seams) merged into the lowest-index one, so subdivision sees one
//                   connected surface and cannot open cracks along the seams;
//                2. Loop subdivision twice (x16 triangles, 282,944): new edge points
//                   3/8 (a + b) + 1/8 (c + d), old points (1 - n beta) v + beta sum, Warren's
//                   beta = 3 / (8 n) for n > 3 and 3/16 for n = 3 (the welded head is
//                   closed and manifold, so only these rules apply to it; for other meshes,
//                   edges on a boundary or shared by more than two triangles use the
//                   crease rules 1/2, 1/2 and 3/4 v + 1/8 of the two crease neighbours,
//                   and vertices with one or more than two crease edges stay put);
//                3. meshopt_simplify (meshoptimizer 0.18, error bound 1 = the whole
//                   mesh, so the count alone stops it) to the paper's triangle count;
//                   0.18 does not keep the surface manifold, and leaves a few closed
//                   pockets (two triangles folded back to back, a tetrahedron) hanging on
//                   an edge: triangles are joined across edges used by exactly two and
//                   only the largest piece is kept; when the count is then outside 1% of
//                   the target, the request is moved by the miss and simplify re-run from
//                   the subdivided mesh (at most 8 times); unused vertices are dropped,
//                   the rest kept in first-use order;
//                4. normals recomputed with pelt::compute_vertex_normals. No UVs (the
//                   weld merges seam copies whose UVs differ; the bench needs none).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include "raster/mesh.h"

namespace pelt::bench {

// One row of the paper's Table 1 and how we rebuild its mesh.
struct SkinBenchRow {
  std::string_view name;        // "Face", "Male body", "Female body"
  uint64_t paper_triangles;     // the paper's "No. of triangle"
  double paper_skin_s;          // the paper's render times, seconds: proposed skin shader,
  double paper_blinn_lambert_s; //   Blinn and Lambert (one column in the paper),
  double paper_stam_s;          //   Stam's Maya skin shader
  uint64_t target_triangles;    // what we build: 0 = the head as scanned
};

// Face, Male body, Female body, in the paper's order.
const std::array<SkinBenchRow, 3>& skin_bench_rows();

// Relative tolerance of a rebuilt mesh's triangle count against its target.
inline constexpr double kTriangleCountTolerance = 0.01;

struct SkinBenchMesh {
  const SkinBenchRow* row;
  Mesh mesh;
};

// The three meshes from the head scan at `head_glb` (LeePerrySmith.glb), in row order.
// Throws io::InputError when the file cannot be loaded, and when a count cannot be met
// (naming the row and the count reached).
std::vector<SkinBenchMesh> make_skin_bench_meshes(const std::filesystem::path& head_glb);

// How `pelt bench skin` frames a mesh (and raster_bench's dense_head, the same frame without
// lighting): the mesh translated by -centre (its bounding box's centre), seen from (0, 0,
// distance) looking at the origin with fovy 30 degrees, the box spanning 80% of the image
// height (or width, when that is the wider one for the aspect), near and far planes around it.
struct SkinBenchView {
  glm::vec3 centre;
  float fovy_deg, distance, near, far;
};
SkinBenchView skin_bench_view(const Mesh& mesh, int width, int height);

// Finds tools/data/LeePerrySmith/LeePerrySmith.glb: under $PELT_SOURCE_DIR, else under the
// working directory or one of its parents, else under the folder of the running program
// or one of its parents (a build folder inside the checkout). Throws io::InputError
// naming `option` when none exists.
std::filesystem::path find_head_scan(std::string_view option);

// ---- The steps, exposed for tests and for other meshes -------------------------------

// Merges vertices whose positions are bitwise equal into the first of them (in index
// order); returns a mesh of positions and triangles only (no normals, no UVs), the
// vertices in order of first appearance in the original vertex array.
Mesh weld_positions(const Mesh& mesh);

// One step of Loop subdivision of a position-only mesh (each triangle into four).
// Boundary and non-manifold edges follow the crease rules described above. Vertex order:
// the old vertices first (same indices), then one per edge in order of first use.
Mesh loop_subdivide(const Mesh& mesh);

// meshopt_simplify of a position-only mesh to `target_triangles` within
// kTriangleCountTolerance, pockets removed and vertices compacted as in step 3 above. Throws io::InputError
// naming `what` when the count cannot be reached.
Mesh decimate_to(const Mesh& mesh, uint64_t target_triangles, std::string_view what);

// Facts about a mesh's connectivity after welding bitwise-equal positions.
struct MeshTopology {
  uint64_t boundary_edges = 0;     // edges used by one triangle
  uint64_t nonmanifold_edges = 0;  // edges used by three or more
  uint64_t winding_conflicts = 0;  // directed edges used twice: neighbours disagree on winding
  uint64_t degenerate_triangles = 0;  // repeated welded vertex or zero area
  uint64_t nonfinite_values = 0;   // NaN/Inf in positions or normals
  uint64_t bad_indices = 0;        // indices >= vertex count
};
MeshTopology mesh_topology(const Mesh& mesh);

}  // namespace pelt::bench
