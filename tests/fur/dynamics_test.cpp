#include "fur/dynamics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/fur/test_meshes.h"
#include "tools/io/builtin_meshes.h"

namespace pelt::fur {
namespace {

constexpr uint32_t kS = 16;
constexpr float kSeg = 0.1f;
const float kNaN = std::numeric_limits<float>::quiet_NaN();

// One chain (N = 1) from `root` along unit `dir`, `nodes` nodes `seg` apart.
std::vector<glm::vec3> chain(glm::vec3 dir, glm::vec3 root = glm::vec3(0.3f, -0.2f, 0.5f), uint32_t nodes = kS,
                             float seg = kSeg) {
  std::vector<glm::vec3> p(nodes);
  for (uint32_t k = 0; k < nodes; ++k) p[k] = root + dir * (seg * float(k));
  return p;
}

// A zero surface normal: no surface to keep the strand above, the bending law alone.
const glm::vec3 kNoSurface(0.0f);

// Fur of `length` (FurParams' default otherwise) on the built-in box:3, the tests' small whole
// mesh. Call through ASSERT_NO_FATAL_FAILURE.
void build_furry_box3(FurGeometry& geo, float length = FurParams{}.length) {
  FurParams p;
  p.length = length;
  ASSERT_FALSE(build_fur_geometry(io::make_builtin_mesh("box:3"), p, geo).has_value());
}

// One chain bent by gravity; its node count is rest's. `authored`: the node count the
// parameters were chosen for (0: the chain's own, the formula as printed). `surface`: the
// base vertex's normal.
std::vector<glm::vec3> gravity(const std::vector<glm::vec3>& rest, GravityParams g,
                               GravityLaw law = GravityLaw::lever, uint32_t authored = 0,
                               glm::vec3 surface = kNoSurface) {
  std::vector<glm::vec3> out(rest.size());
  const glm::vec3 normals[1] = {surface};
  apply_gravity(rest, normals, 1, uint32_t(rest.size()), authored, g, law, out, 0, 1);
  return out;
}

bool all_finite(const std::vector<glm::vec3>& p) {
  for (const glm::vec3& v : p)
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return false;
  return true;
}

void expect_segments_kept(const std::vector<glm::vec3>& rest, const std::vector<glm::vec3>& out,
                          uint32_t N = 1) {
  for (size_t i = 0; i < N; ++i)
    for (uint32_t k = 0; k + 1 < rest.size() / N; ++k)
      EXPECT_NEAR(glm::length(out[i + (k + 1) * N] - out[i + k * N]),
                  glm::length(rest[i + (k + 1) * N] - rest[i + k * N]), 1e-5)
          << "vertex " << i << " segment " << k;
}

glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> n;
  glm::vec3 v;
  do v = {n(rng), n(rng), n(rng)};
  while (glm::length(v) < 1e-3f);
  return glm::normalize(v);
}

TEST(Gravity, KeepsSegmentLengths) {
  std::mt19937 rng(11);
  for (GravityLaw law : {GravityLaw::lever, GravityLaw::seed_dot}) {
    for (int k = 0; k < 200; ++k) {
      const std::vector<glm::vec3> rest = chain(random_unit(rng));
      GravityParams g;
      g.direction = random_unit(rng) * 3.0f;
      g.strength = std::uniform_real_distribution<float>(0.0f, 5.0f)(rng);
      g.stability = std::uniform_real_distribution<float>(0.5f, 500.0f)(rng);
      const auto out = gravity(rest, g, law);
      ASSERT_TRUE(all_finite(out));
      EXPECT_EQ(out[0], rest[0]);  // the root stays on the surface
      expect_segments_kept(rest, out);
    }
  }
}

TEST(Gravity, NoBendAlongGravityOrWithHugeStability) {
  for (GravityLaw law : {GravityLaw::lever, GravityLaw::seed_dot}) {
    GravityParams g;
    g.stability = 1.0f;
    g.strength = 10.0f;
    for (glm::vec3 dir : {glm::vec3(0, -1, 0), glm::vec3(0, 1, 0)}) {
      const auto rest = chain(dir);
      EXPECT_EQ(gravity(rest, g, law), rest);
    }
    g.stability = 1e30f;
    const auto rest = chain(glm::normalize(glm::vec3(1, 0.3f, 0.2f)));
    const auto out = gravity(rest, g, law);
    for (uint32_t k = 0; k < kS; ++k) EXPECT_NEAR(glm::length(out[k] - rest[k]), 0.0f, 1e-6);
    g.stability = std::numeric_limits<float>::infinity();
    EXPECT_EQ(gravity(rest, g, law), rest);
  }
}

TEST(Gravity, BendsMoreFurtherAlongTheChain) {
  GravityParams g;
  g.stability = 100.0f;
  const auto rest = chain({1, 0, 0});  // horizontal strand
  const auto out = gravity(rest, g);
  float prev_disp = 0.0f, prev_angle = 0.0f;
  for (uint32_t k = 1; k < kS; ++k) {
    const float disp = glm::length(out[k] - rest[k]);
    EXPECT_GT(disp, prev_disp) << k;
    prev_disp = disp;
    const glm::vec3 seg = glm::normalize(out[k] - out[k - 1]);
    const float angle = std::acos(std::clamp(glm::dot(seg, glm::vec3(1, 0, 0)), -1.0f, 1.0f));
    EXPECT_GE(angle, prev_angle - 1e-6f) << k;
    prev_angle = angle;
    EXPECT_LT(out[k].y, rest[k].y);  // toward gravity
  }
  // Node 0's rotation uses RN = 15 nodes: theta = 1 * 1 * 15 / 100 (lever, sin = 1).
  const glm::vec3 seg0 = glm::normalize(out[1] - out[0]);
  EXPECT_NEAR(std::atan2(-seg0.y, seg0.x), 0.15f, 1e-5);
  // Stiffer fur bends less.
  g.stability = 400.0f;
  const auto stiff = gravity(rest, g);
  EXPECT_LT(glm::length(stiff[kS - 1] - rest[kS - 1]), glm::length(out[kS - 1] - rest[kS - 1]));
}

TEST(Gravity, SeedDotLawFollowsTheFormulaAsPrinted) {
  GravityParams g;
  g.stability = 100.0f;
  // Horizontal: dot(V, G) = 0, no bend.
  EXPECT_EQ(gravity(chain({1, 0, 0}), g, GravityLaw::seed_dot), chain({1, 0, 0}));
  // Pointing up at 45 degrees: dot < 0 clamps to no bend.
  const auto up = chain(glm::normalize(glm::vec3(1, 1, 0)));
  EXPECT_EQ(gravity(up, g, GravityLaw::seed_dot), up);
  // Pointing down at 45 degrees: theta = cos(45) * 15 / 100 at the root.
  const auto down = chain(glm::normalize(glm::vec3(1, -1, 0)));
  const auto out = gravity(down, g, GravityLaw::seed_dot);
  const glm::vec3 seg0 = glm::normalize(out[1] - out[0]);
  const float angle = std::atan2(-seg0.y, seg0.x);
  EXPECT_NEAR(angle - 0.785398163f, std::sqrt(0.5f) * 15.0f / 100.0f, 1e-5);
}

// dynamics.h: theta is clamped to [0, angle(V, G)], so a huge strength hangs every segment
// straight along G and never swings it past G. Kills a clamp that only keeps theta >= 0.
TEST(Gravity, AHugeStrengthHangsTheStrandAlongGravityNeverPast) {
  GravityParams g;
  g.direction = {0, -1, 0};
  g.strength = 1e4f;
  g.stability = 1.0f;
  // lever: a horizontal strand; seed_dot: one 45 degrees below the horizon (cos > 0).
  const std::pair<GravityLaw, glm::vec3> cases[] = {{GravityLaw::lever, glm::vec3(1, 0, 0)},
                                                    {GravityLaw::seed_dot, glm::normalize(glm::vec3(1, -1, 0))}};
  for (const auto& [law, dir] : cases) {
    const auto rest = chain(dir);
    const auto out = gravity(rest, g, law);
    ASSERT_TRUE(all_finite(out));
    for (uint32_t k = 0; k < kS; ++k) {
      const glm::vec3 hang = rest[0] + glm::vec3(0, -1, 0) * (kSeg * float(k));
      EXPECT_NEAR(glm::length(out[k] - hang), 0.0f, 1e-5f) << "law " << int(law) << " node " << k;
    }
  }
}

TEST(Gravity, NoNaNForDegenerateInputs) {
  // Also with a re-slicing scale far from 1 either way (authored 2 or 128 nodes for 16).
  for (uint32_t authored : {0u, 2u, 128u}) {
    for (GravityLaw law : {GravityLaw::lever, GravityLaw::seed_dot}) {
      for (glm::vec3 dir : {glm::vec3(0, -1, 0), glm::vec3(0, 1, 0), glm::vec3(1, 0, 0),
                            glm::normalize(glm::vec3(1, -1e-8f, 0))}) {
        const auto rest = chain(dir);
        GravityParams g;
        g.stability = 0.0f;  // no restoring force: hangs straight down
        auto out = gravity(rest, g, law, authored);
        ASSERT_TRUE(all_finite(out));
        expect_segments_kept(rest, out);
        g.direction = glm::vec3(0.0f);  // G = 0: no force
        g.stability = 10.0f;
        out = gravity(rest, g, law, authored);
        EXPECT_EQ(out, rest);
        g.direction = {0, -1, 0};
        g.strength = 1e30f;
        out = gravity(rest, g, law, authored);
        ASSERT_TRUE(all_finite(out));
        expect_segments_kept(rest, out);
        g.stability = kNaN;
        ASSERT_TRUE(all_finite(gravity(rest, g, law, authored)));
        g.stability = 1.0f;
        g.strength = kNaN;
        EXPECT_EQ(gravity(rest, g, law, authored), rest);
      }
      // Zero-length chain (fur length 0).
      const std::vector<glm::vec3> point(kS, glm::vec3(1, 2, 3));
      GravityParams g;
      g.stability = 0.0f;
      EXPECT_EQ(gravity(point, g, law, authored), point);
    }
  }
  // With stability 0 a sideways strand hangs along G.
  GravityParams g;
  g.stability = 0.0f;
  const auto out = gravity(chain({1, 0, 0}), g);
  for (uint32_t k = 0; k + 1 < kS; ++k)
    EXPECT_GT(glm::dot(glm::normalize(out[k + 1] - out[k]), glm::vec3(0, -1, 0)), 0.9999f);
}

// The lowest segment of every chain of a pose, as the sine of its elevation above its base
// vertex's tangent plane (N base vertices, S layers).
double lowest_elevation_sin(const std::vector<glm::vec3>& pose, const std::vector<glm::vec3>& normals,
                            uint32_t N, uint32_t S) {
  double lowest = 1.0;
  for (uint32_t i = 0; i < N; ++i)
    for (uint32_t k = 0; k + 1 < S; ++k)
      lowest = std::min(lowest, double(glm::dot(glm::normalize(pose[i + (k + 1) * N] - pose[i + k * N]),
                                                normals[i])));
  return lowest;
}

// Rounding to float leaves a raised segment this far (in sine) below the exact minimum.
constexpr double kElevationSlack = 1e-5;

// Furry sphere, each vertex's chain hanging under gravity.
struct HangingSphere {
  FurGeometry geo;
  std::vector<glm::vec3> with_surface, law_alone;
  explicit HangingSphere(GravityParams g) {
    FurParams p;
    p.length = 0.3f;
    EXPECT_FALSE(build_fur_geometry(io::make_builtin_mesh("sphere:16"), p, geo).has_value());
    const uint32_t N = geo.base_vertex_count, S = geo.layers;
    with_surface.resize(geo.positions.size());
    law_alone.resize(geo.positions.size());
    const std::vector<glm::vec3> none(N, glm::vec3(0.0f));
    apply_gravity(geo.positions, geo.base_normals, N, S, 0, g, GravityLaw::lever, with_surface, 0, N);
    apply_gravity(geo.positions, none, N, S, 0, g, GravityLaw::lever, law_alone, 0, N);
  }
};

// Strong gravity on a sphere (the review's sphere_g.json): the upper hemisphere's fur used to
// hang straight down through the sphere. It lies down on it instead, no segment lower than
// kMinFurElevation above its base vertex's tangent plane, lengths kept.
TEST(Gravity, NeverBendsIntoTheSurface) {
  for (float stability : {0.0f, 1.0f, 30.0f}) {
    GravityParams g;
    g.strength = 1000.0f;
    g.stability = stability;
    const HangingSphere h(g);
    const uint32_t N = h.geo.base_vertex_count, S = h.geo.layers;
    ASSERT_TRUE(all_finite(h.with_surface));
    expect_segments_kept(h.geo.positions, h.with_surface, N);
    EXPECT_GE(lowest_elevation_sin(h.with_surface, h.geo.base_normals, N, S),
              std::sin(kMinFurElevation) - kElevationSlack)
        << "stability " << stability;
    EXPECT_LT(lowest_elevation_sin(h.law_alone, h.geo.base_normals, N, S), -0.5);  // the law alone goes in
    for (uint32_t i = 0; i < N; ++i) EXPECT_EQ(h.with_surface[i], h.geo.positions[i]);  // roots fixed
  }
}

// The rule changes only chains that reached the surface: every chain that the law alone keeps
// above it comes out bit for bit the same.
TEST(Gravity, ChainsThatStayAboveTheSurfaceAreUnchanged) {
  GravityParams g;
  g.stability = 40.0f;
  const HangingSphere h(g);
  const uint32_t N = h.geo.base_vertex_count, S = h.geo.layers;
  size_t above = 0, raised = 0;
  for (uint32_t i = 0; i < N; ++i) {
    bool clear = true;
    for (uint32_t k = 0; k + 1 < S; ++k)
      clear &= glm::dot(glm::dvec3(h.law_alone[i + (k + 1) * N]) - glm::dvec3(h.law_alone[i + k * N]),
                        glm::dvec3(h.geo.base_normals[i])) >=
               std::sin(kMinFurElevation) * glm::length(glm::dvec3(h.law_alone[i + (k + 1) * N]) -
                                                        glm::dvec3(h.law_alone[i + k * N]));
    bool same = true;
    for (uint32_t k = 0; k < S; ++k) same &= h.with_surface[i + k * N] == h.law_alone[i + k * N];
    if (clear) {
      EXPECT_TRUE(same) << "vertex " << i;
      ++above;
    } else {
      ++raised;
    }
  }
  EXPECT_GT(above, 0u);
  EXPECT_GT(raised, 0u);  // the case is real for these parameters
}

TEST(Gravity, RaisingTheStrandNeverGivesNaN) {
  const glm::vec3 up(0, 1, 0);
  GravityParams g;
  g.stability = 0.0f;
  // Gravity straight into the surface, the strand along it (no bend: V antiparallel to G), and a
  // hair off it (hangs straight in, then is raised).
  for (glm::vec3 dir : {up, glm::normalize(glm::vec3(1e-4f, 1, 0)), glm::normalize(glm::vec3(1e-9f, 1, 0))}) {
    const auto rest = chain(dir);
    const auto out = gravity(rest, g, GravityLaw::lever, 0, up);
    ASSERT_TRUE(all_finite(out));
    expect_segments_kept(rest, out);
    EXPECT_GE(lowest_elevation_sin(out, {up}, 1, kS), std::sin(kMinFurElevation) - kElevationSlack);
  }
  // A rest chain pointing straight into the surface has no heading: raised all the same.
  const auto in = chain(-up);
  g.direction = {1, 0, 0};
  const auto out = gravity(in, g, GravityLaw::lever, 0, up);
  ASSERT_TRUE(all_finite(out));
  expect_segments_kept(in, out);
  EXPECT_GE(lowest_elevation_sin(out, {up}, 1, kS), std::sin(kMinFurElevation) - kElevationSlack);
  // Zero-length chain: nothing to raise.
  const std::vector<glm::vec3> point(kS, glm::vec3(1, 2, 3));
  EXPECT_EQ(gravity(point, g, GravityLaw::lever, 0, up), point);
}

// The tip of a horizontal chain of `layers` nodes spanning `length`, bent by gravity with the
// parameters authored for `authored` nodes (0: the formula as printed).
glm::vec3 bent_tip(uint32_t layers, uint32_t authored, float length, const GravityParams& g) {
  const auto rest = chain({1.0f, 0.0f, 0.0f}, glm::vec3(0.0f), layers, length / float(layers - 1));
  return gravity(rest, g, GravityLaw::lever, authored).back();
}

// The same fur re-sliced (a quality setting's shell count) keeps its shape: eq. 2 as printed
// bends a chain of 64 nodes 16 times as far in all as one of 16, so the fur would hang
// straight down at 64 shells where it curls at 16; with the authored count the tips of 24,
// 32, 64 and 128 nodes lie within 2 % of the fur's length of the 16-node tip, and the finer
// chains agree ever more closely (they resolve one curve).
TEST(Gravity, ReslicedChainKeepsTheAuthoredBend) {
  GravityParams g;
  g.direction = {0.0f, -1.0f, 0.0f};
  g.strength = 1.0f;
  g.stability = 400.0f;  // a 16-node chain curls: its tip drops by 10-50 % of its length (asserted)
  const float length = 1.0f;
  const glm::vec3 authored = bent_tip(16, 0, length, g);
  const float drop = -authored.y;
  ASSERT_GT(drop, 0.1f * length);  // a real bend, and not hanging straight down
  ASSERT_LT(drop, 0.5f * length);
  EXPECT_EQ(bent_tip(16, 16, length, g), authored);  // the authored count itself: the same bits
  for (uint32_t layers : {24u, 32u, 64u, 128u}) {
    EXPECT_LT(glm::length(bent_tip(layers, 16, length, g) - authored), 0.02f * length) << layers << " layers";
    // As printed, the finer chain bends far more: the reason for the scale.
    EXPECT_GT(glm::length(bent_tip(layers, 0, length, g) - authored), 0.1f * length) << layers << " layers";
  }
  const float coarse_step = glm::length(bent_tip(32, 16, length, g) - bent_tip(24, 16, length, g));
  const float fine_step = glm::length(bent_tip(128, 16, length, g) - bent_tip(64, 16, length, g));
  EXPECT_LT(fine_step, coarse_step);
}

TEST(Gravity, RangesAndInPlaceGiveTheSameResult) {
  FurGeometry geo;
  ASSERT_NO_FATAL_FAILURE(build_furry_box3(geo, 0.3f));
  const uint32_t N = geo.base_vertex_count, S = geo.layers;
  GravityParams g;
  g.stability = 50.0f;
  std::vector<glm::vec3> whole(geo.positions.size()), split(geo.positions.size());
  const std::vector<glm::vec3>& n = geo.base_normals;
  apply_gravity(geo.positions, n, N, S, 0, g, GravityLaw::lever, whole, 0, N);
  apply_gravity(geo.positions, n, N, S, 0, g, GravityLaw::lever, split, 0, N / 3);
  apply_gravity(geo.positions, n, N, S, 0, g, GravityLaw::lever, split, N / 3, N);
  EXPECT_EQ(whole, split);
  std::vector<glm::vec3> in_place = geo.positions;
  apply_gravity(in_place, n, N, S, 0, g, GravityLaw::lever, in_place, 0, N);
  EXPECT_EQ(whole, in_place);
  expect_segments_kept(geo.positions, whole, N);
  for (uint32_t i = 0; i < N; ++i) EXPECT_EQ(whole[i], geo.positions[i]);  // roots fixed
}

// ---- wind ----

// `n`: the growth direction the chain leans from; `surface`: the base vertex's normal.
std::vector<glm::vec3> wind(const std::vector<glm::vec3>& pose, glm::vec3 n, glm::vec3 force,
                            glm::vec3 surface = kNoSurface) {
  std::vector<glm::vec3> out(pose.size());
  const glm::vec3 normals[1] = {n};
  const glm::vec3 surfaces[1] = {surface};
  const glm::vec3 forces[1] = {force};
  apply_wind(pose, normals, surfaces, forces, 1, uint32_t(pose.size()), out, 0, 1);
  return out;
}

float angle(glm::vec3 a, glm::vec3 b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0f, 1.0f));
}

TEST(Wind, RotatesTheWholeChainOnceTowardTheForce) {
  const glm::vec3 n(0, 1, 0);
  const auto rest = chain(n);
  const glm::vec3 F(2.0f, 0.0f, 0.0f);
  const auto out = wind(rest, n, F);
  ASSERT_TRUE(all_finite(out));
  EXPECT_EQ(out[0], rest[0]);
  expect_segments_kept(rest, out);
  // One rigid rotation: every segment has the same direction, theta = phi (1 - e^-|F|).
  const float theta = 1.5707963f * (1.0f - std::exp(-2.0f));
  for (uint32_t k = 0; k + 1 < kS; ++k) {
    const glm::vec3 seg = glm::normalize(out[k + 1] - out[k]);
    EXPECT_NEAR(angle(seg, n), theta, 1e-5);
    EXPECT_NEAR(angle(seg, n) + angle(seg, F), angle(n, F), 1e-5);  // between n and F
  }
  // A stronger force bends further, never past the force.
  float prev = 0.0f;
  for (float m : {0.1f, 0.5f, 1.0f, 3.0f, 8.0f, 1e20f}) {
    const auto o = wind(rest, n, glm::vec3(m, 0, 0));
    const float a = angle(o[kS - 1] - o[0], n);
    if (m < 1e3f) {
      EXPECT_GT(a, prev) << m;
    }
    EXPECT_LE(a, angle(n, F) + 1e-6f);
    prev = a;
  }
}

TEST(Wind, NoRotationOrNaNForDegenerateForces) {
  const glm::vec3 n(0, 1, 0);
  const auto rest = chain(n);
  for (glm::vec3 F : {glm::vec3(0.0f), glm::vec3(0, 5, 0), glm::vec3(0, -5, 0),
                      glm::vec3(kNaN, 0, 0), glm::vec3(std::numeric_limits<float>::infinity(), 0, 0)}) {
    EXPECT_EQ(wind(rest, n, F), rest);
  }
  // A zero normal (never produced by the geometry) does not poison the output either.
  EXPECT_EQ(wind(rest, glm::vec3(0.0f), glm::vec3(1, 0, 0)), rest);
  // Random forces on random chains: finite, lengths kept.
  std::mt19937 rng(3);
  for (int k = 0; k < 200; ++k) {
    const glm::vec3 nn = random_unit(rng);
    const auto r = chain(nn);
    const auto o = wind(r, nn, random_unit(rng) * std::uniform_real_distribution<float>(0, 10)(rng), nn);
    ASSERT_TRUE(all_finite(o));
    expect_segments_kept(r, o);
  }
}

// A windward face (phi > 90 degrees) used to turn the strand past the tangent plane, into the
// mesh. It is flattened onto the surface instead, for straight and bent chains, lengths kept.
TEST(Wind, NeverPushesFurIntoTheSurface) {
  const glm::vec3 n(0, 1, 0);
  GravityParams g;
  g.stability = 60.0f;
  const auto bent = gravity(chain(glm::normalize(glm::vec3(1, 1, 0))), g, GravityLaw::lever, 0, n);
  ASSERT_GE(lowest_elevation_sin(bent, {n}, 1, kS), std::sin(kMinFurElevation) - kElevationSlack);
  for (const std::vector<glm::vec3>& pose : {chain(n), bent}) {
    for (glm::vec3 dir : {glm::vec3(1, -1, 0), glm::vec3(-1, -1, 0), glm::vec3(0, -1, 1e-6f), glm::vec3(1, 0, 0)}) {
      for (float m : {0.5f, 1.0f, 3.0f, 8.0f, 1e20f}) {
        const auto out = wind(pose, n, glm::normalize(dir) * m, n);
        ASSERT_TRUE(all_finite(out));
        expect_segments_kept(pose, out);
        EXPECT_GE(lowest_elevation_sin(out, {n}, 1, kS), std::sin(kMinFurElevation) - kElevationSlack)
            << "direction " << dir.x << " " << dir.y << " " << dir.z << " strength " << m;
      }
    }
  }
  // A leeward wind that stays clear of the surface turns the strand exactly as without the rule.
  const glm::vec3 F(0.8f, 0.3f, 0.1f);
  EXPECT_EQ(wind(chain(n), n, F, n), wind(chain(n), n, F));
  // The shipped scenes' case: a whole furry box in a strong wind, after gravity.
  FurGeometry geo;
  ASSERT_NO_FATAL_FAILURE(build_furry_box3(geo, 0.3f));
  const uint32_t N = geo.base_vertex_count, S = geo.layers;
  std::vector<glm::vec3> pose(geo.positions.size()), forces(N);
  apply_gravity(geo.positions, geo.base_normals, N, S, 0, g, GravityLaw::lever, pose, 0, N);
  WindParams w;
  w.direction = {1.0f, -0.3f, 0.2f};
  w.strength = 4.0f;
  make_wind_field(geo, w).forces(0.0, forces, 0, N);
  apply_wind(pose, geo.growth, geo.base_normals, forces, N, S, pose, 0, N);
  ASSERT_TRUE(all_finite(pose));
  EXPECT_GE(lowest_elevation_sin(pose, geo.base_normals, N, S), std::sin(kMinFurElevation) - kElevationSlack);
}

// A field updated in place holds the phases a fresh field of the new wind would. Directions whose
// unit vectors round to the same float but differ in double make different phases (found below
// among nearby directions): keyed on that float, a field kept one wind's phases for the other,
// and a frame drawn in a sequence differed from the frame drawn alone. It is keyed on the
// direction as given.
TEST(Wind, AFieldUpdatedInPlaceHoldsTheNewWindsPhases) {
  FurGeometry geo;
  ASSERT_NO_FATAL_FAILURE(build_furry_box3(geo, 0.3f));
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int same_unit_other_phases = 0;
  for (int trial = 0; trial < 4000 && same_unit_other_phases < 3; ++trial) {
    WindParams a;
    a.direction = {u(rng), u(rng), u(rng)};
    WindParams b = a;
    b.direction.x = std::nextafter(a.direction.x, 2.0f);
    const WindField fa = make_wind_field(geo, a), fb = make_wind_field(geo, b);
    if (fa.direction != fb.direction || fa.phase == fb.phase) continue;
    ++same_unit_other_phases;
    WindField f = fa;
    update_wind_field(geo, b, f);
    EXPECT_EQ(f.phase, fb.phase) << "trial " << trial;
  }
  EXPECT_GT(same_unit_other_phases, 0);  // the case exists, so the check above ran
  // The same direction keeps its phases, the array's storage with them.
  WindParams a;
  a.direction = {1.0f, 0.3f, 0.0f};
  WindField f = make_wind_field(geo, a);
  const float* storage = f.phase.data();
  WindParams stronger = a;
  stronger.strength = 3.0f;
  update_wind_field(geo, stronger, f);
  EXPECT_EQ(f.phase.data(), storage);
  EXPECT_EQ(f.strength, 3.0f);
}

TEST(Wind, FieldIsUniformWithoutGustsAndTravelsWithThem) {
  FurGeometry geo;
  ASSERT_NO_FATAL_FAILURE(build_furry_box3(geo));
  const uint32_t N = geo.base_vertex_count;
  WindParams w;
  w.direction = {0, 0, 2};
  w.strength = 1.5f;
  w.gust_scale = 0.0f;
  std::vector<glm::vec3> f(N);
  make_wind_field(geo, w).forces(3.7, f, 0, N);
  for (const glm::vec3& v : f) EXPECT_EQ(v, glm::vec3(0, 0, 1.5f));
  w.gust_scale = 0.5f;
  w.gust_frequency = 2.0f;
  const WindField field = make_wind_field(geo, w);
  std::vector<glm::vec3> f0(N), f1(N), fq(N);
  field.forces(1.0, f0, 0, N);
  field.forces(1.5, f1, 0, N);   // one full period later
  field.forces(1.125, fq, 0, N);  // a quarter period later
  bool moved = false;
  for (uint32_t i = 0; i < N; ++i) {
    const float m = glm::length(f0[i]);
    EXPECT_GE(m, 1.5f * 0.5f - 1e-5f);
    EXPECT_LE(m, 1.5f * 1.5f + 1e-5f);
    EXPECT_NEAR(glm::length(f0[i] - f1[i]), 0.0f, 1e-4);
    EXPECT_NEAR(glm::dot(glm::normalize(f0[i]), glm::vec3(0, 0, 1)), 1.0f, 1e-6);
    moved |= std::fabs(glm::length(fq[i]) - m) > 0.1f;
  }
  EXPECT_TRUE(moved);
  // Varies over the surface at one instant.
  float lo = 1e9f, hi = 0.0f;
  for (const glm::vec3& v : f0) lo = std::min(lo, glm::length(v)), hi = std::max(hi, glm::length(v));
  EXPECT_GT(hi - lo, 0.3f);
}

// dynamics.h: F_i(t) = d * strength * (1 + gust_scale * sin(2 pi (gust_frequency t -
// (q_i.d) / L))), L = 2 R: a gust crest one object across, moving downwind. Kills the
// phase's sign (a gust running upwind) and a wavelength of R instead of 2 R.
TEST(Wind, GustsFollowTheDocumentedTravellingWave) {
  FurGeometry geo;
  ASSERT_NO_FATAL_FAILURE(build_furry_box3(geo));
  const uint32_t N = geo.base_vertex_count;
  WindParams w;
  w.direction = {0.0f, 0.6f, 0.8f};
  w.strength = 1.5f;
  w.gust_scale = 0.5f;
  w.gust_frequency = 2.0f;
  const WindField field = make_wind_field(geo, w);
  const glm::dvec3 d = glm::normalize(glm::dvec3(w.direction));
  const double L = 2.0 * double(geo.bounds.radius);
  std::vector<glm::vec3> f(N);
  double spread = 0.0;  // the largest phase difference the check sees, in wavelengths
  for (double t : {0.3, 1.1, 2.45}) {
    field.forces(t, f, 0, N);
    for (uint32_t i = 0; i < N; ++i) {
      const double phase = glm::dot(glm::dvec3(geo.positions[i]) - glm::dvec3(geo.bounds.centre), d) / L;
      spread = std::max(spread, std::fabs(phase));
      const double m = 1.5 * (1.0 + 0.5 * std::sin(2.0 * 3.14159265358979 * (2.0 * t - phase)));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[i][c], d[c] * m, 2e-5) << "vertex " << i << " t " << t;
    }
  }
  EXPECT_GT(spread, 0.2);  // the box spans enough of a wavelength for the phase to matter
  // Downwind means later: the vertex farthest along d sees the upwind vertex's force
  // (q_j.d - q_i.d) / (L gust_frequency) seconds after it.
  uint32_t up = 0, down = 0;
  auto along = [&](uint32_t i) { return glm::dot(glm::dvec3(geo.positions[i]), d); };
  for (uint32_t i = 1; i < N; ++i) {
    if (along(i) < along(up)) up = i;
    if (along(i) > along(down)) down = i;
  }
  const double delay = (along(down) - along(up)) / (L * 2.0);
  std::vector<glm::vec3> a(N), b(N);
  for (double t : {0.1, 0.4, 0.77}) {
    field.forces(t, a, 0, N);
    field.forces(t + delay, b, 0, N);
    EXPECT_NEAR(glm::length(b[down]), glm::length(a[up]), 1e-4) << "t " << t;
  }
}

// ---- animation ----

TEST(Animation, LerpEndpointsAreThePoses) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-10, 10);
  std::vector<glm::vec3> a(1000), b(1000), out(1000);
  for (size_t k = 0; k < a.size(); ++k) a[k] = {u(rng), u(rng), u(rng)}, b[k] = {u(rng), u(rng), u(rng)};
  lerp_poses(a, b, 0.0f, out);
  EXPECT_EQ(out, a);
  lerp_poses(a, b, 1.0f, out);
  EXPECT_EQ(out, b);
  lerp_poses(a, b, 0.25f, out);
  for (size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(glm::length(out[k] - (0.75f * a[k] + 0.25f * b[k])), 0.0f, 1e-5);
}

// A coordinate equal in both poses (every root, which neither gravity nor wind moves) comes out
// unchanged for every t: a * (1 - t) + a * t is an ulp off a for many (a, t), which put shell 0
// an ulp off the base and broke its less-equal depth test in stripes.
TEST(Animation, LerpKeepsWhatBothPosesShare) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-10, 10);
  std::vector<glm::vec3> a(4000), b(4000), out(4000);
  for (size_t k = 0; k < a.size(); ++k) {
    a[k] = {u(rng), u(rng), u(rng)};
    b[k] = k % 2 ? a[k] : glm::vec3(a[k].x, u(rng), a[k].z);  // odd: equal; even: only y moves
  }
  size_t off_by_the_old_formula = 0;
  for (int step = 1; step < 48; ++step) {
    const float t = animation_t(step, 48);
    lerp_poses(a, b, t, out);
    for (size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(out[k].x, a[k].x) << k << " t " << t;
      ASSERT_EQ(out[k].z, a[k].z) << k << " t " << t;
      if (k % 2) {
        ASSERT_EQ(out[k].y, a[k].y) << k << " t " << t;
      }
      off_by_the_old_formula += a[k].x * (1.0f - t) + a[k].x * t != a[k].x;
    }
  }
  EXPECT_GT(off_by_the_old_formula, 0u);  // the case is real for these inputs
}

TEST(Animation, TimeCurveSwingsBetweenThePoses) {
  EXPECT_EQ(animation_t(0, 120), 0.0f);
  EXPECT_NEAR(animation_t(60, 120), 1.0f, 1e-6);
  EXPECT_NEAR(animation_t(30, 120), 0.5f, 1e-6);
  EXPECT_NEAR(animation_t(120 * 1000 + 60, 120), 1.0f, 1e-6);
  for (int f = 0; f < 500; ++f) {
    const float t = animation_t(f, 77.0);
    EXPECT_GE(t, 0.0f);
    EXPECT_LE(t, 1.0f);
  }
  EXPECT_EQ(animation_t(10, 0), 0.0f);
  EXPECT_EQ(animation_t(10, kNaN), 0.0f);
  EXPECT_EQ(llvmpipe_animation_t(0), 0.5f);
  EXPECT_NEAR(llvmpipe_animation_t(5), 0.5f + 0.5f * std::sin(0.5f), 1e-7);
}

TEST(Animation, TangentsFollowTheDeformedChain) {
  const glm::vec3 dir = glm::normalize(glm::vec3(1, 2, 3));
  const auto straight = chain(dir);
  const glm::vec3 growth[1] = {glm::vec3(0, 1, 0)};
  std::vector<glm::vec3> t(kS);
  strand_tangents(straight, growth, 1, kS, t, 0, 1);
  for (const glm::vec3& v : t) EXPECT_NEAR(glm::length(v - dir), 0.0f, 1e-6);
  GravityParams g;
  g.stability = 30.0f;
  const auto bent = gravity(chain({1, 0, 0}), g);
  strand_tangents(bent, growth, 1, kS, t, 0, 1);
  for (uint32_t k = 0; k < kS; ++k) EXPECT_NEAR(glm::length(t[k]), 1.0f, 1e-6);
  for (uint32_t k = 1; k + 1 < kS; ++k) EXPECT_GT(glm::dot(t[k], glm::normalize(bent[k + 1] - bent[k - 1])), 0.99999f);
  EXPECT_LT(t[kS - 1].y, t[0].y);  // tip points further down than the root
  const std::vector<glm::vec3> point(kS, glm::vec3(1.0f));
  strand_tangents(point, growth, 1, kS, t, 0, 1);
  for (const glm::vec3& v : t) EXPECT_EQ(v, growth[0]);
}

TEST(Animation, LlvmpipePosesFollowTheHarness) {
  FurParams p;  // 16 shells, length 0.1 R
  FurGeometry geo;
  ASSERT_FALSE(build_fur_geometry(io::make_builtin_mesh("box:7"), p, geo).has_value());
  const size_t V = geo.positions.size();
  std::vector<glm::vec3> p0(V), p1(V);
  llvmpipe_poses(geo, p0, p1);
  const uint32_t N = geo.base_vertex_count;
  const float R = std::sqrt(3.0f);
  for (uint32_t i = 0; i < N; ++i) {
    EXPECT_EQ(p0[i], geo.positions[i]);  // bend 0 at the root
    EXPECT_EQ(p1[i], geo.positions[i]);
    const glm::vec3 n = geo.base_normals[i];
    const glm::vec3 q = geo.positions[i] - geo.bounds.centre;
    const float bend = 0.1f * R;  // s = 15
    const size_t I = i + 15 * size_t(N);
    const glm::vec3 g(0, -1, 0), w = glm::normalize(glm::vec3(1, 0.2f, 0.6f));
    const glm::vec3 want0 = geo.positions[I] + (g - n * glm::dot(g, n)) * 0.4f * bend;
    const float gust = 0.75f + 0.25f * std::sin(3.0f * (q.x + q.z) / R);
    const glm::vec3 want1 = geo.positions[I] + (w - n * glm::dot(w, n)) * 0.8f * bend * gust;
    EXPECT_NEAR(glm::length(p0[I] - want0), 0.0f, 1e-5);
    EXPECT_NEAR(glm::length(p1[I] - want1), 0.0f, 1e-5);
  }
}

}  // namespace
}  // namespace pelt::fur
