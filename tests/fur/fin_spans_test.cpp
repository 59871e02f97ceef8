// Where a fin's quads may span several layers: at the ends always, never across a bend or
// uneven spacing beyond the tolerance, never longer than the span limit, never across a
// non-finite node; every interior node of a span within the tolerance of its chord, on
// chains bent by the real gravity pass; and a fin whose chains fan out cut until each quad's
// twist is within bounds.
#include "fur/fin_spans.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "fur/dynamics.h"

namespace pelt::fur {
namespace {

// The layers whose bits are set in vertex i's mask.
std::vector<uint32_t> breaks_of(const std::vector<uint64_t>& masks, uint32_t layers, uint32_t i = 0) {
  std::vector<uint32_t> out;
  const uint32_t words = fin_break_words(layers);
  for (uint32_t s = 0; s < layers; ++s)
    if (masks[size_t{i} * words + s / 64] >> (s % 64) & 1) out.push_back(s);
  return out;
}

std::vector<uint64_t> breaks(const std::vector<glm::vec3>& pose, uint32_t n, uint32_t layers, float tol,
                             uint32_t max_span) {
  std::vector<uint64_t> masks(size_t{n} * fin_break_words(layers), ~uint64_t{0});  // overwritten
  fin_chain_breaks(pose, n, layers, tol, max_span, 0, n, masks);
  return masks;
}

// One chain (N = 1) of `layers` nodes 0.1 apart along `dir`.
std::vector<glm::vec3> straight(uint32_t layers, glm::vec3 dir = glm::normalize(glm::vec3(0.2f, 1.0f, -0.3f))) {
  std::vector<glm::vec3> p(layers);
  for (uint32_t k = 0; k < layers; ++k) p[k] = glm::vec3(0.3f, -0.2f, 0.5f) + dir * (0.1f * float(k));
  return p;
}

TEST(FinSpans, AStraightChainIsCutOnlyByTheSpanLimit) {
  EXPECT_EQ(breaks_of(breaks(straight(16), 1, 16, 0.025f, 8), 16), (std::vector<uint32_t>{0, 8, 15}));
  EXPECT_EQ(breaks_of(breaks(straight(16), 1, 16, 0.025f, 15), 16), (std::vector<uint32_t>{0, 15}));
  EXPECT_EQ(breaks_of(breaks(straight(16), 1, 16, 0.025f, 1), 16).size(), 16u);  // every layer
  EXPECT_EQ(breaks_of(breaks(straight(2), 1, 2, 0.025f, 8), 2), (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(breaks_of(breaks(straight(1), 1, 1, 0.025f, 8), 1), (std::vector<uint32_t>{0}));
  // More than 64 layers: the mask's second word.
  EXPECT_EQ(breaks_of(breaks(straight(100), 1, 100, 0.025f, 64), 100), (std::vector<uint32_t>{0, 64, 99}));
}

TEST(FinSpans, AKinkOrUnevenSpacingEndsAQuad) {
  std::vector<glm::vec3> kinked = straight(16);
  for (uint32_t k = 6; k < 16; ++k) kinked[k] += glm::vec3(0.05f, 0.0f, 0.0f) * float(k - 5);  // bends after 5
  EXPECT_EQ(breaks_of(breaks(kinked, 1, 16, 0.025f, 15), 16), (std::vector<uint32_t>{0, 5, 15}));
  // Straight, but layer 3 sits a third of a step off its place along the line: the texture's
  // v (linear in the layer) would move with it, so no quad runs past it.
  std::vector<glm::vec3> uneven = straight(16);
  uneven[3] += (uneven[4] - uneven[3]) * 0.34f;
  const std::vector<uint32_t> b = breaks_of(breaks(uneven, 1, 16, 0.025f, 15), 16);
  EXPECT_GT(b.size(), 2u);
  EXPECT_EQ(b.front(), 0u);
  EXPECT_EQ(b.back(), 15u);
}

TEST(FinSpans, ANonFiniteNodeIsNeverInsideAQuad) {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    std::vector<glm::vec3> p = straight(16);
    p[7].y = bad;
    const std::vector<uint32_t> b = breaks_of(breaks(p, 1, 16, 0.025f, 15), 16);
    for (size_t j = 0; j + 1 < b.size(); ++j) EXPECT_FALSE(b[j] < 7 && 7 < b[j + 1]) << b[j] << "-" << b[j + 1];
  }
}

// Many chains bent by the gravity pass, laid out N = 64 vertices a layer: the breaks of each
// chain bound every span's interior nodes by the tolerance and its length by the limit, and
// one call over all vertices equals calls over split ranges.
TEST(FinSpans, EverySpanOfABentChainStaysWithinTheTolerance) {
  constexpr uint32_t kN = 64, kS = 16;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> rest(kN * kS), normals(kN);
  for (uint32_t i = 0; i < kN; ++i) {
    const glm::vec3 root(u(rng), u(rng), u(rng));
    const glm::vec3 dir = glm::normalize(glm::vec3(u(rng), 1.5f, u(rng)));
    normals[i] = dir;
    for (uint32_t s = 0; s < kS; ++s) rest[i + s * kN] = root + dir * (0.02f * float(s));
  }
  GravityParams g;
  g.strength = 1.0f;
  g.stability = 8.0f;
  std::vector<glm::vec3> pose(rest.size());
  apply_gravity(rest, normals, kN, kS, 0, g, GravityLaw::lever, pose, 0, kN);

  const float tol = 0.25f * 0.02f;
  const std::vector<uint64_t> all = breaks(pose, kN, kS, tol, 8);
  std::vector<uint64_t> split(all.size(), 0);
  fin_chain_breaks(pose, kN, kS, tol, 8, 0, 20, split);
  fin_chain_breaks(pose, kN, kS, tol, 8, 20, kN, split);
  EXPECT_EQ(split, all);

  size_t quads = 0;
  for (uint32_t i = 0; i < kN; ++i) {
    const std::vector<uint32_t> b = breaks_of(all, kS, i);
    ASSERT_GE(b.size(), 2u);
    EXPECT_EQ(b.front(), 0u);
    EXPECT_EQ(b.back(), kS - 1);
    for (size_t j = 0; j + 1 < b.size(); ++j) {
      const uint32_t s0 = b[j], s1 = b[j + 1];
      EXPECT_LE(s1 - s0, 8u);
      const glm::vec3 p0 = pose[i + s0 * kN], p1 = pose[i + s1 * kN];
      for (uint32_t k = s0 + 1; k < s1; ++k) {
        const glm::vec3 on = p0 + (p1 - p0) * (float(k - s0) / float(s1 - s0));
        EXPECT_LE(glm::length(pose[i + k * kN] - on), tol * 1.0001f) << "vertex " << i << " layer " << k;
      }
      ++quads;
    }
  }
  // The chains bend, so more than the span limit's 2 quads a chain; yet most of 15 merge.
  EXPECT_LT(quads, size_t{kN} * 15 / 2);
  EXPECT_GT(quads, size_t{kN} * 2);
}

// Two straight chains (N = 2) of 16 layers 0.1 apart: parallel, they share their breaks and
// the fin is two quads; fanning out, the fin is cut until each quad's twist is within 4
// tolerances.
TEST(FinSpans, AFinIsCutWhereItsChainsFanOut) {
  constexpr uint32_t kS = 16;
  auto two_chains = [](glm::vec3 dir_a, glm::vec3 dir_b) {
    std::vector<glm::vec3> pose(2 * kS);
    for (uint32_t s = 0; s < kS; ++s) {
      pose[0 + 2 * s] = glm::vec3(0.0f) + dir_a * (0.1f * float(s));
      pose[1 + 2 * s] = glm::vec3(0.3f, 0.0f, 0.0f) + dir_b * (0.1f * float(s));
    }
    return pose;
  };
  const float tol = 0.025f;
  uint32_t ends[kS];
  const std::vector<glm::vec3> parallel = two_chains(glm::vec3(0, 1, 0), glm::vec3(0, 1, 0));
  const std::vector<uint64_t> pb = breaks(parallel, 2, kS, tol, 8);
  ASSERT_EQ(fin_quad_ends(parallel, 2, kS, 0, 1, pb, tol, ends), 2u);
  EXPECT_EQ(ends[0], 8u);
  EXPECT_EQ(ends[1], 15u);

  // 30 degrees apart: each layer step adds |T| = 2 sin(15 deg) 0.1 = 0.052 of twist, so a
  // quad may span one layer (0.052 <= 0.1) but not two.
  const float h = glm::radians(15.0f);
  const std::vector<glm::vec3> fan =
      two_chains(glm::vec3(-std::sin(h), std::cos(h), 0), glm::vec3(std::sin(h), std::cos(h), 0));
  const std::vector<uint64_t> fb = breaks(fan, 2, kS, tol, 8);
  EXPECT_EQ(breaks_of(fb, kS, 0), breaks_of(pb, kS, 0));  // each chain alone is straight
  const uint32_t count = fin_quad_ends(fan, 2, kS, 0, 1, fb, tol, ends);
  ASSERT_GE(count, 2u);
  EXPECT_EQ(ends[count - 1], kS - 1);
  for (uint32_t k = 0, s0 = 0; k < count; s0 = ends[k++]) {
    ASSERT_GT(ends[k], s0);
    const glm::vec3 twist = (fan[1 + 2 * ends[k]] - fan[1 + 2 * s0]) - (fan[0 + 2 * ends[k]] - fan[0 + 2 * s0]);
    EXPECT_LE(glm::length(twist), 4.0f * tol * 1.0001f) << s0 << "-" << ends[k];
  }
  // A non-finite node cuts its spans into single layers.
  std::vector<glm::vec3> bad = parallel;
  bad[1 + 2 * 4].x = std::numeric_limits<float>::quiet_NaN();
  const std::vector<uint64_t> bb = breaks(bad, 2, kS, tol, 8);
  const uint32_t n = fin_quad_ends(bad, 2, kS, 0, 1, bb, tol, ends);
  for (uint32_t k = 0, s0 = 0; k < n; s0 = ends[k++]) EXPECT_FALSE(s0 < 4 && 4 < ends[k]) << s0 << "-" << ends[k];
}

}  // namespace
}  // namespace pelt::fur
