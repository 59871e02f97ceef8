#include "fur/fin_spans.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include <glm/geometric.hpp>

namespace pelt::fur {

void fin_chain_breaks(std::span<const glm::vec3> pose, uint32_t base_vertex_count, uint32_t layers,
                      float tolerance, uint32_t max_span, uint32_t begin, uint32_t end,
                      std::span<uint64_t> breaks) {
  const uint32_t n = base_vertex_count, words = fin_break_words(layers);
  const float tol2 = tolerance * tolerance;
  max_span = std::max(1u, max_span);
  for (uint32_t i = begin; i < end; ++i) {
    uint64_t* mask = breaks.data() + size_t{i} * words;
    std::fill(mask, mask + words, uint64_t{0});
    if (layers == 0) continue;
    auto mark = [&](uint32_t s) { mask[s / 64] |= uint64_t{1} << (s % 64); };
    auto node = [&](uint32_t s) { return pose[i + size_t{s} * n]; };
    mark(0);
    uint32_t start = 0;
    // [start, to - 1] is one quad; can it reach `to`? If not, it ends at to - 1.
    for (uint32_t to = 2; to < layers; ++to) {
      bool fits = to - start <= max_span;
      const glm::vec3 p0 = node(start), p1 = node(to);
      const float inv = 1.0f / float(to - start);
      for (uint32_t k = start + 1; fits && k < to; ++k) {
        const glm::vec3 d = node(k) - (p0 + (p1 - p0) * (float(k - start) * inv));
        fits = glm::dot(d, d) <= tol2;  // false for NaN
      }
      if (!fits) {
        start = to - 1;
        mark(start);
      }
    }
    mark(layers - 1);
  }
}

uint32_t fin_quad_ends(std::span<const glm::vec3> pose, uint32_t base_vertex_count, uint32_t layers, uint32_t a,
                       uint32_t b, std::span<const uint64_t> breaks, float tolerance, uint32_t* ends) {
  const uint32_t n = base_vertex_count, words = fin_break_words(layers);
  const uint64_t* ba = breaks.data() + size_t{a} * words;
  const uint64_t* bb = breaks.data() + size_t{b} * words;
  const float max_twist = 4.0f * tolerance;
  uint32_t count = 0, s0 = 0;
  for (uint32_t w = 0; w < words; ++w)
    for (uint64_t bits = (ba[w] | bb[w]) & (w == 0 ? ~uint64_t{1} : ~uint64_t{0}); bits != 0; bits &= bits - 1) {
      const uint32_t s1 = w * 64 + static_cast<uint32_t>(std::countr_zero(bits));
      const uint32_t span = s1 - s0;
      // Layer steps a part may take: the twist grows with the steps (linearly for straight
      // chains), so whole parts of `steps` keep each within max_twist.
      uint32_t steps = span;
      if (span > 1) {
        const glm::vec3 twist = (pose[b + size_t{s1} * n] - pose[b + size_t{s0} * n]) -
                                (pose[a + size_t{s1} * n] - pose[a + size_t{s0} * n]);
        const float t = glm::length(twist);
        if (!(t <= max_twist))
          steps = std::isfinite(t) ? std::max(1u, static_cast<uint32_t>(float(span) * max_twist / t)) : 1u;
      }
      for (uint32_t k = steps; k < span + steps; k += steps) ends[count++] = s0 + std::min(k, span);
      s0 = s1;
    }
  return count;
}

}  // namespace pelt::fur
