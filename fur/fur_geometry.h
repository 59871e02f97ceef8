// Shells and fins on one shared vertex array (seed 3.1.1, eq. 1).
//
// For a base mesh with N vertices (the mesh's own, and under the box mapping the copies it makes
// where its planes meet: build_fur_geometry) and S layers, fur vertex I = i + s*N (s = 0..S-1)
// sits at base_v[i] + g[i] * (SL_D * s): layer 0 lies on the base surface, layer S-1 at
// the fur length. Shells are the base triangles copied per layer (layer 0 first, so the
// draw order is inner to outer). Fins are one quad per mesh edge and layer gap, drawn on
// the same vertices, so a deformation of the vertex array moves shells and fins together.
// Built once per object (allocates); nothing here runs per frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "fur/fur_params.h"
#include "raster/mesh.h"

namespace pelt::fur {

inline constexpr uint32_t kNoFace = 0xFFFFFFFFu;

// The farthest a fur vertex may lie from the origin, in scene units (the mesh's bounding radius
// times 1 + length, plus its centre's distance): squared, still a finite float. A larger mesh is
// refused ("mesh.positions") rather than grown into infinite positions.
inline constexpr double kMaxFurReach = 1e18;

// Fur never points into its base surface (a pelt rule where the seed is silent): every growth
// direction (combing) and every posed strand segment (gravity, wind) keeps at least this angle,
// in radians, above its base vertex's tangent plane; they may lay fur down toward the surface,
// never into it. Not zero: a strand lying in the plane would put its shells on the base
// surface, where they z-fight with it. 5 degrees holds a point h along a flat-lying strand
// 0.087 h off the surface, and still reads as fur lying flat.
inline constexpr double kMinFurElevation = 5.0 * std::numbers::pi / 180.0;

// An undirected mesh edge, a < b, with the (up to) two base triangles that share it. With a map
// read at the mesh uvs (FurGeometry::mesh_uvs: FurParams::use_color_map, a cut-out's map) a and b
// are instead face0's own copies of those vertices (the same strands), in either order.
// face1 = kNoFace on a boundary edge. On a non-manifold edge (3+ triangles) the first
// two triangles in index order are kept; the fin is still drawn once.
struct FurEdge {
  uint32_t a = 0, b = 0;
  uint32_t face0 = kNoFace, face1 = kNoFace;
};

// The seed's Tables 1-3 rows. Shell and fin vertices are the same array ("shared"), so
// total_vertices = base + shell, not base + shell + fin.
struct FurCounts {
  size_t base_vertices = 0, shell_vertices = 0, fin_vertices = 0, total_vertices = 0;
  size_t base_faces = 0, shell_faces = 0, fin_faces = 0, total_faces = 0;
  size_t edges = 0;
  // Base vertices that grow another vertex's strand (same_strand_vertices): the copies a file
  // split at texture seams or hard edges, and those the box mapping makes where its planes meet.
  // Not in the seed's tables; `pelt info` shows them.
  size_t joined_vertices = 0;
};

// Centre = bounding-box centre; radius = largest distance of a vertex from it (the
// llvmpipe harness's R). Zero radius for an empty or single-point mesh.
struct BoundingSphere {
  glm::vec3 centre{0.0f};
  float radius = 0.0f;
};

struct FurGeometry {
  uint32_t base_vertex_count = 0;  // N
  uint32_t layers = 0;             // S
  float fur_length = 0.0f;         // params.length * R, scene units (layer S-1's offset)
  float layer_distance = 0.0f;     // SL_D = fur_length / (S - 1)
  BoundingSphere bounds;

  // Per base vertex (size N).
  std::vector<glm::vec3> base_normals;  // unit vertex normals n[i] (the mesh's own, renormalised
                                        // only when more than 1e-6 off unit length; the copies
                                        // of a hard edge's vertex joined: fur has no hard edges)
  std::vector<glm::vec3> growth;        // unit growth directions g[i] (n, or combed)

  // Per fur vertex I = i + s*N (size S*N): the rest pose of eq. 1.
  std::vector<glm::vec3> positions;
  std::vector<glm::vec2> shell_uvs;  // the base vertex's strand uv, the same in every layer
  // Where the shell uvs come from (FurParams::texture_coordinates, resolved), and the factor
  // applied: to the mesh's uvs, or to the projection's or the box's planes (texture units per
  // scene unit).
  StrandCoordinates strand_coordinates = StrandCoordinates::projected;
  double strand_uv_scale = 0.0;
  // The mesh has uvs, texture_coordinates was not given, and they cover no area (all at a point):
  // the strands are laid by the box mapping instead, and the caller warns.
  bool uvs_cover_no_area = false;
  // Fins (empty when params.fins is off, as fin_indices is): u = k q.(1,2,3)/sqrt14 with q = p - centre and k = 2.449490 sqrt(3) / R times texture_repeat (the
  // llvmpipe harness's fin coordinate: runs along every edge that is not perpendicular
  // to (1,2,3)); v = s / (S-1), 0 at the root, 1 at the tip.
  std::vector<glm::vec2> fin_uvs;
  std::vector<uint16_t> layer;  // s
  // Per base vertex (size N), only with params.use_color_map or build_fur_geometry's map_uvs: the
  // mesh's own texture coordinate, where the colour map (or a cut-out's alpha) is read (the shell
  // uvs are the strand texture's, scaled or projected).
  std::vector<glm::vec2> mesh_uvs;
  // Per base vertex (size N), only with a length map: the scale of eq. 1's offsets (see
  // build_fur_geometry), and how many base faces grow no fur for it.
  std::vector<float> length_scale;
  size_t bald_faces = 0;

  // Shell triangles: layer s's copy of base triangle f is triangle s*F + f (S*F*3 indices).
  std::vector<uint32_t> shell_indices;
  // Fin triangles: quad q = s*E + e (s = 0..S-2, e = index into `edges`) is triangles
  // 2q, 2q+1 = (a_s, b_s, b_{s+1}), (a_s, b_{s+1}, a_{s+1}) ((S-1)*E*6 indices; none with fins off).
  std::vector<uint32_t> fin_indices;
  std::vector<FurEdge> edges;             // sorted by (a, b) (the first copies), deduplicated
  std::vector<glm::vec3> face_normals;    // unit normal per base triangle ((0,1,0) if degenerate)

  FurCounts counts;

  // The edge (and so the two base faces) behind fin quad q.
  const FurEdge& fin_edge(size_t quad) const { return edges[quad % edges.size()]; }
};

BoundingSphere bounding_sphere(const Mesh& mesh);

// The area the mesh's triangles cover in its texture coordinates (mesh.uvs, one per vertex;
// either winding counts alike, overlapping islands once each), in double. 0 for uvs collapsed to a
// point or a line, which lay no texture.
double mesh_uv_area(const Mesh& mesh);

// The six indices of the fin quad on `edge` between layers s0 < s1 of the shared array (N base
// vertices): (a_s0, b_s0, b_s1), (a_s0, b_s1, a_s1). FurGeometry::fin_indices holds these for
// s1 = s0 + 1; merged fins (fur/fin_spans.h) take them over several layers.
inline void fin_quad_indices(const FurEdge& edge, uint32_t base_vertex_count, uint32_t s0, uint32_t s1,
                             uint32_t out[6]) {
  const uint32_t a0 = edge.a + s0 * base_vertex_count, b0 = edge.b + s0 * base_vertex_count;
  const uint32_t a1 = edge.a + s1 * base_vertex_count, b1 = edge.b + s1 * base_vertex_count;
  out[0] = a0, out[1] = b0, out[2] = b1, out[3] = a0, out[4] = b1, out[5] = a1;
}

// Unique undirected edges of the triangles, sorted by (a, b), with their faces. With `same_as`
// (one entry per vertex, from same_strand_vertices), a vertex counts as the one it names: the two
// copies of a split seam then share one edge, with a face on each side, instead of being two
// boundary edges whose coincident fins would blend the seam twice.
std::vector<FurEdge> mesh_edges(const Mesh& mesh, const std::vector<uint32_t>& same_as = {});

// For each vertex, the lowest-indexed vertex with the same position, normal and growth direction:
// copies that exporters split at texture seams grow the same strand in every pose (gravity and wind
// read nothing else of a vertex), so their fins coincide.
std::vector<uint32_t> same_strand_vertices(const std::vector<glm::vec3>& positions,
                                           const std::vector<glm::vec3>& normals,
                                           const std::vector<glm::vec3>& growth);

// Table counts for a base mesh of the given size with S layers; `fins` off counts no fin faces
// (build_fur_geometry makes none).
FurCounts fur_counts(size_t base_vertices, size_t base_faces, size_t edges, int layers, FinMode fins);

// Unit growth direction from a unit normal and the optional combing (see CombParams). A blend
// that ends up lower than kMinFurElevation above the tangent plane is raised to it, keeping its
// direction along the surface; one with no direction along the surface (d = -n) keeps the
// normal, as a blend that cancels does.
glm::vec3 growth_direction(const glm::vec3& normal, const std::optional<CombParams>& comb);

// The per-vertex comb directions of CombField::uv (see CombParams::uv_direction): unit
// vectors in each vertex's tangent plane, or zero where the uvs (or the normal) give no
// direction. `normals`: one per vertex, any length; base.uvs must have one per vertex.
std::vector<glm::vec3> uv_comb_directions(const Mesh& base, const std::vector<glm::vec3>& normals,
                                          glm::vec2 uv_direction);

// Builds the fur of `base` with params.shells layers, params.length and params.comb.
// Uses base.normals when present (one per position), otherwise computes them as
// pelt::compute_vertex_normals does; lays the strands as FurParams::texture_coordinates says
// (the mesh's uvs when present, otherwise the box mapping). Under the box mapping the fur's base
// vertices are the mesh's followed by the copies made where two axis planes meet
// (base_vertex_count counts them, counts.joined_vertices too). Returns the first problem (a
// params field, or "mesh.indices", "mesh.normals", "mesh.uvs", "mesh.positions" with the reason)
// and leaves `out` unspecified on error.
// `length_scale` (optional, one per mesh vertex, each in [0, 1]; a length map read by the caller)
// scales eq. 1's offsets per base vertex: vertex I = i + s N sits at base_v[i] + g[i] SL_D s
// scale[i], the copies of one strand taking their mean scale. A face whose corners all have 0 grows
// no shells (its shell triangles are points); a fin between two bare vertices has no height.
// `map_uvs` (optional, one per mesh vertex): texture coordinates where the renderer reads a map
// under the fur (a cut-out's alpha), kept as mesh_uvs whatever lays the strands, so a caller may
// hand the fur a mesh without uvs (to lay its strands by the box mapping) and still read its maps.
// Empty: mesh_uvs are base.uvs, and only under use_color_map.
std::optional<ParamError> build_fur_geometry(const Mesh& base, const FurParams& params,
                                             FurGeometry& out, std::span<const float> length_scale = {},
                                             std::span<const glm::vec2> map_uvs = {});

// Makes every layer's copy of base face `face` one point, which set-up culls: the face grows no
// fur (bald under a length map, or cut away with its surface, tools/render/fur_object.h). The
// triangles keep their places, so layer s is still triangles s F .. s F + F - 1 of shell_indices.
void collapse_face_shells(FurGeometry& g, size_t face);

// The base vertex count build_fur_geometry would give (the mesh's own, or more under the box
// mapping), for estimating memory before building; the mesh's own count when it would fail.
size_t fur_base_vertex_count(const Mesh& base, const FurParams& params);

// How visible a fin is, in [0, 1] (Lengyel et al. 2001: fins matter only near
// silhouettes, where shells are seen edge-on and leave gaps).
//   off        -> 0
//   all        -> 1
//   silhouette -> with v = normalize(view_dir), c_a = n_a.v, c_b = n_b.v:
//                 1 if the edge is a true silhouette (c_a and c_b of opposite signs);
//                 otherwise with c = min(|c_a|, |c_b|) (the more edge-on face; |c_a|
//                 alone on a boundary edge) and x = clamp(c / 0.5, 0, 1):
//                 1 - x^2 (3 - 2x), i.e. full at edge-on, gone once both faces are
//                 within 60 degrees of facing the viewer.
// view_dir may point either way (only |n.v| and sign changes matter). Zero or
// non-finite inputs give 1 for silhouette mode (show the fin rather than a gap).
float fin_weight(const glm::vec3& face_normal_a, const std::optional<glm::vec3>& face_normal_b,
                 const glm::vec3& view_dir, FinMode mode);

}  // namespace pelt::fur
