#include "fur/fur_params.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace pelt::fur {
namespace {

std::string bad_field(const FurParams& p) {
  auto e = validate(p);
  if (!e) return "<accepted>";
  EXPECT_FALSE(e->reason.empty()) << e->field;
  return e->field;
}

TEST(FurParams, DefaultsAreValidAndAsDocumented) {
  FurParams p;
  EXPECT_FALSE(validate(p).has_value());
  EXPECT_EQ(p.shells, 16);
  EXPECT_EQ(p.texture_size, 256);
  EXPECT_EQ(p.fins, FinMode::silhouette);
  EXPECT_FALSE(p.texture_coordinates.has_value());  // the mesh's uvs where it has them
  EXPECT_EQ(p.texture_repeat, 1.0f);
  EXPECT_FALSE(p.gravity.has_value());
  EXPECT_FALSE(p.wind.has_value());
  EXPECT_FALSE(p.comb.has_value());
  p.gravity = GravityParams{};
  p.wind = WindParams{};
  p.comb = CombParams{};
  EXPECT_FALSE(validate(p).has_value());
}

// fur_params.h: shells and authored_shells lie in [2, 128], both ends included; the
// rejections below the range are tested next, the top of it here. Kills shells >= 128.
TEST(FurParams, TheEndsOfTheShellRangeAreValid) {
  for (int s : {2, 128}) {
    FurParams p;
    p.shells = s;
    EXPECT_FALSE(validate(p).has_value()) << "shells " << s;
    p.authored_shells = s;
    EXPECT_FALSE(validate(p).has_value()) << "authored_shells " << s;
  }
}

TEST(FurParams, EachBadFieldIsNamedByItsKeyPath) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  auto with = [](auto edit) {
    FurParams p;
    p.gravity = GravityParams{};
    p.wind = WindParams{};
    p.comb = CombParams{};
    edit(p);
    return p;
  };
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.shells = 1; })), "shells");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.shells = 129; })), "shells");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.length = 0.0f; })), "length");
  EXPECT_EQ(bad_field(with([&](FurParams& p) { p.length = nan; })), "length");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.density = 0.0f; })), "density");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.density = 100.5f; })), "density");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.density = 0.0001f; })), "density");  // < 1 strand
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.texture_size = 100; })), "texture_size");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.texture_size = 8; })), "texture_size");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.texture_size = 8192; })), "texture_size");
  for (const float r : {0.0f, -1.0f, 1000.5f, std::numeric_limits<float>::quiet_NaN(),
                        std::numeric_limits<float>::infinity()})
    EXPECT_EQ(bad_field(with([r](FurParams& p) { p.texture_repeat = r; })), "texture_repeat") << r;
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.texture_repeat = 1000.0f; })), "<accepted>");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.texture_repeat = 1e-3f; })), "<accepted>");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.texture_coordinates = StrandCoordinates(7); })),
            "texture_coordinates");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.fins = FinMode(7); })), "fins");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.root_color.z = 1.5f; })), "root_color[2]");
  EXPECT_EQ(bad_field(with([&](FurParams& p) { p.tip_color.x = nan; })), "tip_color[0]");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.gravity->direction = {0, 0, 0}; })),
            "gravity.direction");
  EXPECT_EQ(bad_field(with([&](FurParams& p) { p.gravity->direction.y = inf; })),
            "gravity.direction[1]");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.gravity->strength = -1.0f; })),
            "gravity.strength");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.gravity->stability = 0.0f; })),
            "gravity.stability");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.wind->direction = {0, 0, 0}; })),
            "wind.direction");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.wind->strength = -0.1f; })), "wind.strength");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.wind->gust_frequency = -2.0f; })),
            "wind.gust_frequency");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.wind->gust_scale = 1.5f; })), "wind.gust_scale");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.comb->direction = {0, 0, 0}; })),
            "comb.direction");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.comb->uv_direction = {0, 0}; })), "comb.uv_direction");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.comb->uv_direction = {NAN, 1}; })), "comb.uv_direction");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.authored_shells = 1; })), "authored_shells");
  EXPECT_EQ(bad_field(with([](FurParams& p) { p.comb->weight = -0.25f; })), "comb.weight");
}

TEST(FurParams, ReasonSaysWhatWasWrong) {
  FurParams p;
  p.gravity = GravityParams{};
  p.gravity->stability = -3.0f;
  auto e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "gravity.stability");
  EXPECT_NE(e->reason.find("-3"), std::string::npos) << e->reason;
}

// A direction is refused below length 1e-6 (normalised, it would be mostly rounding). A short
// direction that is not zero used to be told "must be a non-zero vector"; the reason now gives
// the bound and the length it got.
TEST(FurParams, AShortDirectionIsToldTheBoundNotThatItIsZero) {
  FurParams p;
  p.wind = WindParams{};
  p.wind->direction = {1e-7f, 0.0f, 0.0f};
  auto e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "wind.direction");
  EXPECT_NE(e->reason.find("1e-06"), std::string::npos) << e->reason;
  EXPECT_NE(e->reason.find("1e-07"), std::string::npos) << e->reason;
  p.wind->direction = {1.1e-6f, 0.0f, 0.0f};
  EXPECT_FALSE(validate(p).has_value());
  p.wind->direction = {0.0f, 0.0f, 0.0f};
  e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_NE(e->reason.find("non-zero"), std::string::npos) << e->reason;
}

// comb.uv_direction has the same bound, and a short one was told "must be a finite, non-zero
// [du, dv]": told the bound and its length now, as the 3-vectors are.
TEST(FurParams, AShortUvDirectionIsToldTheBoundNotThatItIsZero) {
  FurParams p;
  p.comb = CombParams{};
  p.comb->field = CombField::uv;
  p.comb->uv_direction = {5e-7f, 5e-7f};
  auto e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "comb.uv_direction");
  EXPECT_NE(e->reason.find("must have a length above 1e-06, got length 7.07107e-07"), std::string::npos) << e->reason;
  p.comb->uv_direction = {1.1e-6f, 0.0f};
  EXPECT_FALSE(validate(p).has_value());
  p.comb->uv_direction = {0.0f, 0.0f};
  e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->reason, "must be a non-zero vector");
  p.comb->uv_direction = {1.0f, INFINITY};
  e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->reason, "must be finite, got [1, inf]");
}

TEST(FurParams, FinModeStringsRoundTrip) {
  for (FinMode m : {FinMode::off, FinMode::all, FinMode::silhouette}) {
    auto back = fin_mode_from_string(to_string(m));
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(*back, m);
  }
  EXPECT_EQ(to_string(FinMode::silhouette), "silhouette");
  EXPECT_FALSE(fin_mode_from_string("Silhouette").has_value());
  EXPECT_FALSE(fin_mode_from_string("").has_value());
  EXPECT_FALSE(fin_mode_from_string("on").has_value());
  EXPECT_EQ(to_string(StrandCoordinates::mesh), "mesh");
  EXPECT_EQ(to_string(StrandCoordinates::projected), "projected");
  for (StrandCoordinates c : {StrandCoordinates::mesh, StrandCoordinates::projected, StrandCoordinates::box}) {
    auto back = strand_coordinates_from_string(to_string(c));
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(*back, c);
  }
  EXPECT_EQ(to_string(StrandCoordinates::box), "box");
  EXPECT_FALSE(strand_coordinates_from_string("Box").has_value());
  EXPECT_FALSE(strand_coordinates_from_string("cube").has_value());
}

}  // namespace
}  // namespace pelt::fur
