#include "raster/mesh.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace pelt {

void compute_vertex_normals(Mesh& mesh) {
  std::vector<glm::dvec3> sum(mesh.positions.size(), glm::dvec3(0.0));
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const glm::dvec3 pa(mesh.positions[a]), pb(mesh.positions[b]), pc(mesh.positions[c]);
    const glm::dvec3 n = glm::cross(pb - pa, pc - pa);
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) continue;  // degenerate: contributes nothing
    const glm::dvec3 u = n / len;
    sum[a] += u;
    sum[b] += u;
    sum[c] += u;
  }
  mesh.normals.resize(mesh.positions.size());
  for (size_t i = 0; i < sum.size(); ++i) {
    const double len = glm::length(sum[i]);
    mesh.normals[i] = (len > 1e-12) ? glm::vec3(sum[i] / len) : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

}  // namespace pelt
