// Plain indexed triangle mesh: the hand-off between loaders/generators (tools/, fur/)
// and the rasterizer. Knows nothing of fur or skin.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <glm/ext/vector_double3.hpp>

namespace pelt {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty, or one per position
  std::vector<glm::vec2> uvs;      // empty, or one per position
  std::vector<uint32_t> indices;   // three per triangle, counter-clockwise seen from outside

  size_t vertex_count() const { return positions.size(); }
  size_t triangle_count() const { return indices.size() / 3; }
};

// For each vertex, the lowest-indexed vertex at the same position (raster/vertex_groups.h).
std::vector<uint32_t> same_position_vertices(const std::vector<glm::vec3>& positions);

// Which triangles a computed normal sums: those naming the vertex, or those naming any vertex at
// the same position. The second is for files whose vertices are split only where another
// attribute changes (an OBJ's texture seams): per vertex, the two sides of a seam would get
// different normals, a crease in the shading and a crack between the fur shells grown along them.
enum class NormalSharing { per_vertex, per_position };

// Per-vertex normals as the normalised sum of the unit normals of the adjacent
// triangles (unweighted), the convention of the fur paper's harness. A vertex with
// no usable triangle gets (0, 1, 0) so that later code never sees a zero vector.
// `smoothing` (empty, or one key per vertex) narrows per_position sharing to the copies whose
// keys are equal: an OBJ's smoothing groups, where the copies of a position in two groups are
// the two sides of a hard edge, and a face in no group has a key of its own (flat).
void compute_vertex_normals(Mesh& mesh, NormalSharing sharing = NormalSharing::per_vertex,
                            const std::vector<uint64_t>& smoothing = {});

// Per-vertex tangent frames for tangent-space normal maps: xyz = T, the surface direction
// of growing u (summed over the adjacent triangles, each weighted by its uv-space area,
// projected onto the vertex's tangent plane, normalised); w = +-1, the handedness, such
// that the bitangent B = w cross(N, T) points toward the TOP of the texture image (v
// decreasing: v = 0 is the top row in pelt, as in glTF), the OpenGL/glTF convention for the
// green channel. Needs normals and uvs (one per position). Where the uvs give no direction
// (degenerate uv triangles), T is any unit vector orthogonal to N and w = 1.
std::vector<glm::vec4> compute_vertex_tangents(const Mesh& mesh);
// The same with `uvs` (one per position) in place of mesh.uvs: a map read at other coordinates
// than the mesh's (placed by an affine transform) has its own frame.
std::vector<glm::vec4> compute_vertex_tangents(const Mesh& mesh, const std::vector<glm::vec2>& uvs);

// Per-vertex sums, over the adjacent triangles, of the surface derivatives dP/du and dP/dv,
// each triangle's scaled by its uv-space area (so a degenerate uv triangle adds nothing), in
// double. Both outputs get one entry per position; zero where no triangle has uv extent.
// Needs uvs (one per position). The building block of tangent frames and uv combing.
void uv_derivatives(const Mesh& mesh, std::vector<glm::dvec3>& dpdu, std::vector<glm::dvec3>& dpdv);
// The same with `uvs` in place of mesh.uvs.
void uv_derivatives(const Mesh& mesh, const std::vector<glm::vec2>& uvs, std::vector<glm::dvec3>& dpdu,
                    std::vector<glm::dvec3>& dpdv);

}  // namespace pelt
