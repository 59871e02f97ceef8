// The tile's back-to-front sort (radix for long lists in id order, comparison otherwise) must
// give exactly the order of its comparison: farthest key first, equal keys by ascending id.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "raster/translucent_sort.h"

namespace pelt::raster::test {
namespace {

std::vector<TranslucentRef> refs_from(const std::vector<float>& keys) {
  std::vector<TranslucentRef> refs;
  for (size_t i = 0; i < keys.size(); ++i) refs.push_back({nullptr, uint32_t(3 * i + 7), keys[i]});
  return refs;
}

void expect_same_order(std::vector<TranslucentRef> refs) {
  std::vector<TranslucentRef> expected = refs, scratch;
  std::sort(expected.begin(), expected.end(), back_to_front_before);
  sort_back_to_front(refs, scratch);
  ASSERT_EQ(refs.size(), expected.size());
  for (size_t i = 0; i < refs.size(); ++i) ASSERT_EQ(refs[i].id, expected[i].id) << "position " << i;
}

TEST(TranslucentSort, MatchesTheComparisonOnRandomKeysOfEveryLength) {
  std::mt19937 rng(11);
  for (size_t n : {0u, 1u, 2u, 50u, 95u, 96u, 97u, 500u, 4000u}) {
    // Depths in a narrow range (the top bytes agree, so passes are skipped) and in a wide one.
    for (float spread : {0.01f, 1000.0f}) {
      std::uniform_real_distribution<float> depth(5.0f, 5.0f + spread);
      std::vector<float> keys(n);
      for (float& k : keys) k = depth(rng);
      expect_same_order(refs_from(keys));
    }
  }
}

TEST(TranslucentSort, EqualKeysKeepIdOrder) {
  // Few distinct keys, so long runs of ties (the triangles of a quad share one key).
  std::mt19937 rng(12);
  std::vector<float> keys(3000);
  for (float& k : keys) k = float(rng() % 7) * 0.25f;
  expect_same_order(refs_from(keys));
}

TEST(TranslucentSort, HardKeys) {
  const float inf = std::numeric_limits<float>::infinity();
  const float hard[] = {0.0f, -0.0f, inf, -inf, std::numeric_limits<float>::denorm_min(), -1e-38f,
                        std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), 1.0f, -1.0f};
  std::vector<float> keys;
  for (int rep = 0; rep < 40; ++rep)
    for (float k : hard) keys.push_back(k);
  expect_same_order(refs_from(keys));

  // -0 and +0 are one key: ties, in id order.
  std::vector<TranslucentRef> zeros = refs_from(std::vector<float>(200, 0.0f)), scratch;
  for (size_t i = 0; i < zeros.size(); i += 2) zeros[i].sort_key = -0.0f;
  sort_back_to_front(zeros, scratch);
  for (size_t i = 1; i < zeros.size(); ++i) EXPECT_LT(zeros[i - 1].id, zeros[i].id);
}

TEST(TranslucentSort, NanKeysComeFirstInIdOrder) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> keys(300);
  for (size_t i = 0; i < keys.size(); ++i) keys[i] = i % 5 == 0 ? (i % 2 ? -nan : nan) : float(i % 17);
  std::vector<TranslucentRef> refs = refs_from(keys), scratch;
  sort_back_to_front(refs, scratch);
  const size_t nans = 60;
  for (size_t i = 0; i < refs.size(); ++i) {
    EXPECT_EQ(std::isnan(refs[i].sort_key), i < nans) << i;
    if (i > 0 && i < nans) {
      EXPECT_LT(refs[i - 1].id, refs[i].id);
    }
    if (i > nans) {
      EXPECT_GE(refs[i - 1].sort_key, refs[i].sort_key);
    }
  }
  expect_same_order(refs_from(keys));
}

TEST(TranslucentSort, ListsNotInIdOrderAreSortedByTheComparison) {
  std::mt19937 rng(13);
  std::vector<float> keys(1000);
  for (float& k : keys) k = float(rng() % 50);
  std::vector<TranslucentRef> refs = refs_from(keys);
  std::shuffle(refs.begin(), refs.end(), rng);
  expect_same_order(refs);
}

}  // namespace
}  // namespace pelt::raster::test
