// Grouping of vertices by an exact key (a position; a position with its normal and growth),
// for the copies a mesh file makes of one vertex at texture seams and hard edges.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pelt {

// For each of n vertices, the lowest index whose `bits(i)` (K words) equal its own. Found by
// sorting, so the result depends on no hash order.
template <size_t K, class BitsFn>
std::vector<uint32_t> first_with_equal_bits(size_t n, BitsFn bits) {
  std::vector<uint32_t> first(n), order(n);
  for (size_t i = 0; i < n; ++i) first[i] = order[i] = uint32_t(i);
  std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) {
    const std::array<uint32_t, K> bx = bits(x), by = bits(y);
    return bx != by ? bx < by : x < y;
  });
  for (size_t r = 1; r < n; ++r)
    if (bits(order[r]) == bits(order[r - 1])) first[order[r]] = first[order[r - 1]];
  return first;
}

// A float as a key word: equal as values where that is an order (-0 equals 0) and by its bits
// otherwise, so a NaN makes no sort undefined (it equals only its own bits).
inline uint32_t key_bits(float f) { return std::bit_cast<uint32_t>(f + 0.0f); }  // -0 + 0 = +0

// The same for a key of K floats (`key(i)`), compared by key_bits.
template <size_t K, class KeyFn>
std::vector<uint32_t> first_with_equal_key(size_t n, KeyFn key) {
  return first_with_equal_bits<K>(n, [&](uint32_t i) {
    const std::array<float, K> k = key(i);
    std::array<uint32_t, K> b;
    for (size_t c = 0; c < K; ++c) b[c] = key_bits(k[c]);
    return b;
  });
}

}  // namespace pelt
