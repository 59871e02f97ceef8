#include "tools/io/weld.h"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace pelt::io {

PointWelder::PointWelder(double tolerance)
    : tolerance_(tolerance), cell_size_(tolerance > 0.0 ? tolerance : 1e-300) {}

size_t PointWelder::CellHash::operator()(const glm::i64vec3& c) const {
  uint64_t h = static_cast<uint64_t>(c.x) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<uint64_t>(c.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
  h ^= static_cast<uint64_t>(c.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
  return static_cast<size_t>(h);
}

glm::i64vec3 PointWelder::cell_of(const glm::dvec3& p) const {
  return glm::i64vec3(static_cast<int64_t>(std::floor(p.x / cell_size_)),
                      static_cast<int64_t>(std::floor(p.y / cell_size_)),
                      static_cast<int64_t>(std::floor(p.z / cell_size_)));
}

uint32_t PointWelder::add(const glm::dvec3& p) {
  // Cells are one tolerance wide, so any point within tolerance lies in one of the 27
  // cells around p's cell.
  const glm::i64vec3 c = cell_of(p);
  uint32_t found = std::numeric_limits<uint32_t>::max();
  for (int64_t dz = -1; dz <= 1; ++dz)
    for (int64_t dy = -1; dy <= 1; ++dy)
      for (int64_t dx = -1; dx <= 1; ++dx) {
        auto it = cells_.find(c + glm::i64vec3(dx, dy, dz));
        if (it == cells_.end()) continue;
        for (uint32_t idx : it->second)
          if (idx < found && glm::distance(points_[idx], p) <= tolerance_) found = idx;
      }
  if (found != std::numeric_limits<uint32_t>::max()) return found;
  const auto idx = static_cast<uint32_t>(points_.size());
  points_.push_back(p);
  cells_[c].push_back(idx);
  return idx;
}

}  // namespace pelt::io
