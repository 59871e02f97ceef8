// The tile sort of SortMode::Tile: a tile's translucent triangles back to front.
#pragma once

#include <vector>

#include "raster/frame.h"

namespace pelt::raster {

// Orders refs by sort_key, largest (farthest) first, and equal keys by ascending id. -0 and
// +0 are one key, as the float comparison sees them; NaN keys (which set-up never produces)
// come first, in id order. `scratch` is reused storage (no allocation once it has grown).
void sort_back_to_front(std::vector<TranslucentRef>& refs, std::vector<TranslucentRef>& scratch);

// The order sort_back_to_front produces, as a comparison (the reference for its tests and the
// path for short lists).
inline bool back_to_front_before(const TranslucentRef& a, const TranslucentRef& b) {
  const float ka = a.sort_key, kb = b.sort_key;
  const bool nan_a = ka != ka, nan_b = kb != kb;
  if (nan_a || nan_b) return nan_a && (!nan_b || a.id < b.id);
  return ka > kb || (ka == kb && a.id < b.id);
}

}  // namespace pelt::raster
