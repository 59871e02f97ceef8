// Geometric properties shared by the loader and built-in mesh tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

#include <glm/geometric.hpp>

#include "raster/mesh.h"

namespace pelt::io::testing {

// Number of triangles using each undirected edge.
inline std::map<std::pair<uint32_t, uint32_t>, int> edge_use(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3)
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = m.indices[t + e], b = m.indices[t + (e + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  return uses;
}

// Number of directed edges used by more than one triangle: zero exactly when every pair
// of neighbouring triangles agrees on the winding.
inline int winding_conflicts(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3)
    for (int e = 0; e < 3; ++e) ++directed[{m.indices[t + e], m.indices[t + (e + 1) % 3]}];
  int conflicts = 0;
  for (const auto& [edge, count] : directed) conflicts += count > 1;
  return conflicts;
}

inline double signed_volume(const Mesh& m) {
  double v = 0.0;
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]),
        c(m.positions[m.indices[t + 2]]);
    v += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return v;
}

inline double min_triangle_area(const Mesh& m) {
  double lo = INFINITY;
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]),
        c(m.positions[m.indices[t + 2]]);
    lo = std::min(lo, 0.5 * glm::length(glm::cross(b - a, c - a)));
  }
  return lo;
}

inline double max_normal_length_error(const Mesh& m) {
  double err = 0.0;
  for (const auto& n : m.normals) err = std::max(err, std::abs(glm::length(glm::dvec3(n)) - 1.0));
  return err;
}

}  // namespace pelt::io::testing
