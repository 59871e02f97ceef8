#include "raster/translucent_sort.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <utility>

namespace pelt::raster {
namespace {

// The key as an unsigned integer whose ascending order is back to front: the float's bits
// made monotonic (negative floats reversed, positive ones above them), then inverted. Every
// NaN maps to 0, ahead of +inf.
uint32_t radix_key(float f) {
  if (f != f) return 0;
  const uint32_t u = std::bit_cast<uint32_t>(f + 0.0f);  // -0 + 0 = +0
  const uint32_t ascending = (u & 0x80000000u) ? ~u : (u | 0x80000000u);
  return ~ascending;
}

// Below this many refs the comparison sort wins over four histogram passes (the lists of a
// tile with few translucent triangles).
constexpr size_t kRadixMin = 96;

}  // namespace

// LSD radix sort, 8 bits a pass, stable, so equal keys keep the list's order. The tile builds
// its list in setup-id order (ForEachItem walks chunks, then each chunk's items, in order),
// so that is ascending id; the comparison sort serves lists that are not (and short ones).
// Passes whose byte is the same for every key (the top bytes of nearby depths) are skipped.
// Against std::sort with back_to_front_before, this took the tile sort from 3.1 % of a
// one-thread furry-box frame to 0.55 % (README, measured figures).
void sort_back_to_front(std::vector<TranslucentRef>& refs, std::vector<TranslucentRef>& scratch) {
  const size_t n = refs.size();
  bool ids_ascending = true;
  for (size_t i = 1; i < n && ids_ascending; ++i) ids_ascending = refs[i - 1].id < refs[i].id;
  if (n < kRadixMin || !ids_ascending) {
    std::sort(refs.begin(), refs.end(), back_to_front_before);
    return;
  }
  uint32_t count[4][256];
  std::memset(count, 0, sizeof(count));
  for (const TranslucentRef& r : refs) {
    const uint32_t k = radix_key(r.sort_key);
    for (int p = 0; p < 4; ++p) ++count[p][(k >> (8 * p)) & 0xFF];
  }
  scratch.resize(n);
  TranslucentRef* from = refs.data();
  TranslucentRef* to = scratch.data();
  for (int p = 0; p < 4; ++p) {
    const int shift = 8 * p;
    if (count[p][(radix_key(from[0].sort_key) >> shift) & 0xFF] == n) continue;
    uint32_t start[256];
    uint32_t sum = 0;
    for (int b = 0; b < 256; ++b) {
      start[b] = sum;
      sum += count[p][b];
    }
    for (size_t i = 0; i < n; ++i) to[start[(radix_key(from[i].sort_key) >> shift) & 0xFF]++] = from[i];
    std::swap(from, to);
  }
  if (from != refs.data()) std::copy(from, from + n, refs.data());
}

}  // namespace pelt::raster
