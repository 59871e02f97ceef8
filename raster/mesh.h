// Plain indexed triangle mesh: the hand-off between loaders/generators (tools/, fur/)
// and the rasterizer. Knows nothing of fur or skin.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace pelt {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty, or one per position
  std::vector<glm::vec2> uvs;      // empty, or one per position
  std::vector<uint32_t> indices;   // three per triangle, counter-clockwise seen from outside

  size_t vertex_count() const { return positions.size(); }
  size_t triangle_count() const { return indices.size() / 3; }
};

// Per-vertex normals as the normalised sum of the unit normals of the adjacent
// triangles (unweighted), the convention of the fur paper's harness. A vertex with
// no usable triangle gets (0, 1, 0) so that later code never sees a zero vector.
void compute_vertex_normals(Mesh& mesh);

}  // namespace pelt
