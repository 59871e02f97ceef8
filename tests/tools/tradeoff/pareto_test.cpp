// The Pareto front on hand-made points: dominance, ties on one axis, duplicates, one point.
#include "tools/tradeoff/pareto.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace pelt::tradeoff {
namespace {

std::vector<bool> front_of(const std::vector<CostPoint>& p) { return pareto_front(p); }

TEST(TradeoffPareto, EmptyAndSinglePoint) {
  EXPECT_TRUE(front_of({}).empty());
  EXPECT_EQ(front_of({{5, 0.1}}), std::vector<bool>({true}));
}

TEST(TradeoffPareto, DominatedPointsAreOff) {
  // (2, 0.2) beats (3, 0.3); (1, 0.5), (2, 0.2) and (10, 0) trade time for error.
  EXPECT_EQ(front_of({{1, 0.5}, {3, 0.3}, {2, 0.2}, {10, 0}}), std::vector<bool>({true, false, true, true}));
}

TEST(TradeoffPareto, TieOnOneAxisIsDecidedByTheOther) {
  // Same time: the lower error wins. Same error: the faster wins.
  EXPECT_EQ(front_of({{1, 0.5}, {1, 0.3}}), std::vector<bool>({false, true}));
  EXPECT_EQ(front_of({{4, 0.2}, {2, 0.2}}), std::vector<bool>({false, true}));
}

TEST(TradeoffPareto, DuplicatesShareTheirFate) {
  // Equal points do not dominate each other...
  EXPECT_EQ(front_of({{2, 0.1}, {2, 0.1}, {5, 0}}), std::vector<bool>({true, true, true}));
  // ...and are dominated together.
  EXPECT_EQ(front_of({{2, 0.1}, {2, 0.1}, {1, 0.1}}), std::vector<bool>({false, false, true}));
}

TEST(TradeoffPareto, AllEqualPointsAreAllOnTheFront) {
  EXPECT_EQ(front_of({{3, 0.4}, {3, 0.4}, {3, 0.4}}), std::vector<bool>({true, true, true}));
}

TEST(TradeoffPareto, NanNeitherDominatesNorIsDominated) {
  EXPECT_EQ(front_of({{NAN, 0.1}, {1, 0.05}, {2, 0.2}}), std::vector<bool>({true, true, false}));
}

}  // namespace
}  // namespace pelt::tradeoff
