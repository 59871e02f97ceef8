#include "tools/tradeoff/pareto.h"

namespace pelt::tradeoff {

std::vector<bool> pareto_front(std::span<const CostPoint> points) {
  // Quadratic: a sweep has a few dozen settings.
  std::vector<bool> front(points.size(), true);
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t j = 0; j < points.size() && front[i]; ++j) {
      const CostPoint& p = points[i];
      const CostPoint& q = points[j];
      if (q.ms <= p.ms && q.rmse <= p.rmse && (q.ms < p.ms || q.rmse < p.rmse)) front[i] = false;
    }
  return front;
}

}  // namespace pelt::tradeoff
