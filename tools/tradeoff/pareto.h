// The Pareto front of measured settings: the ones no other setting beats on both time and
// error.
#pragma once

#include <span>
#include <vector>

namespace pelt::tradeoff {

struct CostPoint {
  double ms = 0;    // median frame time, minimised
  double rmse = 0;  // error against the reference, minimised
};

// front[i] is true when no other point is <= points[i] in both coordinates and < in at
// least one. Equal points do not dominate each other, so duplicates are on the front
// together or off it together. A NaN coordinate never dominates and is never dominated.
std::vector<bool> pareto_front(std::span<const CostPoint> points);

}  // namespace pelt::tradeoff
