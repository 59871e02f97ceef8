// render::time_side_by_side: the two draws of a pair take turns at going first, and each time
// is reported for its own draw. No speed is checked: a sleep only bounds a time from below.
#include "tools/render/frame_timing.h"

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include <gtest/gtest.h>

namespace pelt::render {
namespace {

TEST(FrameTiming, SideBySideTakesTurnsAtGoingFirst) {
  for (int turn = 0; turn < 4; ++turn) {
    std::string order;
    time_side_by_side(turn, [&] { order += 'a'; }, [&] { order += 'b'; });
    EXPECT_EQ(order, turn % 2 == 0 ? "ab" : "ba") << turn;
  }
}

TEST(FrameTiming, EachTimeBelongsToItsOwnDraw) {
  const auto nap = [] { std::this_thread::sleep_for(std::chrono::milliseconds(5)); };
  for (int turn = 0; turn < 2; ++turn) {
    EXPECT_GE(time_side_by_side(turn, nap, [] {}).first, 5.0) << turn;
    EXPECT_GE(time_side_by_side(turn, [] {}, nap).second, 5.0) << turn;
  }
  EXPECT_GE(time_ms(nap), 5.0);
}

// One rule for every benchmark's median and quartiles: linear between the nearest ranks.
TEST(FrameTiming, QuantileInterpolatesBetweenTheNearestRanks) {
  EXPECT_EQ(quantile({7.0}, 0.5), 7.0);
  EXPECT_EQ(quantile({3.0, 1.0, 2.0}, 0.5), 2.0);
  EXPECT_EQ(quantile({4.0, 1.0, 3.0, 2.0}, 0.5), 2.5);  // the mean of the middle two
  EXPECT_EQ(quantile({4.0, 1.0, 3.0, 2.0, 5.0}, 0.25), 2.0);
  EXPECT_EQ(quantile({4.0, 1.0, 3.0, 2.0}, 0.25), 1.75);
  EXPECT_EQ(quantile({4.0, 1.0, 3.0, 2.0}, 0.0), 1.0);
  EXPECT_EQ(quantile({4.0, 1.0, 3.0, 2.0}, 1.0), 4.0);
  EXPECT_THROW(quantile({}, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace pelt::render
