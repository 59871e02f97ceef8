// Merging of coincident points for the procedural meshes (internal to pelt_io).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

namespace pelt::io {

// Adds points one at a time; a point within `tolerance` (Euclidean) of an earlier one
// gets that point's index, the lowest such index, so the result does not depend on
// hash order. Points are kept in first-seen order.
class PointWelder {
 public:
  explicit PointWelder(double tolerance);
  uint32_t add(const glm::dvec3& p);
  const std::vector<glm::dvec3>& points() const { return points_; }

 private:
  struct CellHash {
    size_t operator()(const glm::i64vec3& c) const;
  };
  glm::i64vec3 cell_of(const glm::dvec3& p) const;

  double tolerance_;
  double cell_size_;
  std::vector<glm::dvec3> points_;
  std::unordered_map<glm::i64vec3, std::vector<uint32_t>, CellHash> cells_;
};

}  // namespace pelt::io
