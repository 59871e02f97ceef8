// The sweep plan: --knobs parsing, the order and count of rows, each knob's setting reaching
// the quality, which rows provably repeat an earlier one, and the order of the way back.
#include "tools/tradeoff/sweep.h"

#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tools/io/input_error.h"

namespace pelt::tradeoff {
namespace {

TEST(TradeoffSweep, ParsesAKnobList) {
  EXPECT_EQ(parse_knob_list("sort"), std::vector<std::string>({"sort"}));
  EXPECT_EQ(parse_knob_list("spp,sort,multiple_scattering"),
            std::vector<std::string>({"spp", "sort", "multiple_scattering"}));
}

void expect_refused(const std::string& list, const std::string& words) {
  try {
    parse_knob_list(list);
    ADD_FAILURE() << "accepted `" << list << "`";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.field, "--knobs");
    EXPECT_NE(e.reason.find(words), std::string::npos) << e.reason;
  }
}

TEST(TradeoffSweep, RefusesBadKnobLists) {
  expect_refused("sort,bogus", "unknown knob `bogus`");
  expect_refused("sort,bogus", "shells, fins, fin_quads, sort");  // the valid names are listed
  expect_refused("", "empty knob name");
  expect_refused("sort,", "empty knob name");
  expect_refused("spp,,sort", "empty knob name");
  expect_refused("spp,sort,spp", "`spp` is listed twice");
}

TEST(TradeoffSweep, PlanOrderReferenceDefaultKnobsPresets) {
  const io::Quality base;
  const std::vector<Setting> plan = plan_sweep(base, {"sort", "spp"});
  std::vector<std::string> labels;
  for (const Setting& s : plan) labels.push_back(s.knob + "=" + s.setting);
  EXPECT_EQ(labels, std::vector<std::string>({"reference=reference", "default=scene", "sort=none", "sort=layer",
                                              "sort=tile", "sort=surface", "sort=exact", "spp=1", "spp=4", "spp=16", "preset=fast",
                                              "preset=balanced", "preset=high"}));
  EXPECT_EQ(plan[0].quality, *io::quality_preset("reference"));
  EXPECT_EQ(plan[1].quality, base);
  EXPECT_EQ(plan.back().quality, *io::quality_preset("high"));
}

TEST(TradeoffSweep, EveryKnobSettingReachesTheQualityAndNothingElseChanges) {
  io::Quality base;
  base.shells = 16;
  std::vector<std::string> all(std::begin(io::kKnobs), std::end(io::kKnobs));
  const std::vector<Setting> plan = plan_sweep(base, all);
  size_t swept = 0;
  for (const Setting& s : plan) {
    if (s.knob == kReferenceKnob || s.knob == kDefaultKnob || s.knob == kPresetKnob) continue;
    ++swept;
    EXPECT_EQ(io::knob_value(s.quality, s.knob), s.setting) << s.knob;
    for (std::string_view other : io::kKnobs) {
      if (other == s.knob) continue;
      EXPECT_EQ(io::knob_value(s.quality, other), io::knob_value(base, other)) << s.knob;
    }
  }
  size_t expected = 0;
  for (std::string_view k : io::kKnobs) expected += io::knob_sweep(k).size();
  EXPECT_EQ(swept, expected);
}

TEST(TradeoffSweep, RepeatsPointAtTheFirstIdenticalQuality) {
  io::Quality base;  // sort tile, spp 1, filter trilinear, precision simd: in the sweeps
  base.shells = 16;  // shells 16 too
  const std::vector<Setting> plan = plan_sweep(base, {"shells", "sort", "spp", "fins"});
  std::set<std::string> repeats;
  for (size_t i = 0; i < plan.size(); ++i) {
    const Setting& s = plan[i];
    if (!s.same_as) {
      for (size_t j = 0; j < i; ++j) EXPECT_FALSE(plan[j].quality == s.quality) << s.knob << "=" << s.setting;
      continue;
    }
    ASSERT_LT(*s.same_as, i);
    EXPECT_EQ(plan[*s.same_as].quality, s.quality);
    EXPECT_FALSE(plan[*s.same_as].same_as);  // the measured row, not another repeat
    repeats.insert(s.knob + "=" + s.setting);
  }
  // fins: the scene's fin mode is unset in `base`, so every fins setting is a new quality.
  EXPECT_EQ(repeats, std::set<std::string>({"shells=16", "sort=tile", "spp=1"}));
  for (const Setting& s : plan)
    if (s.same_as) {
      EXPECT_EQ(plan[*s.same_as].knob, kDefaultKnob);
    }
}

TEST(TradeoffSweep, TheWayBackTimesEveryRenderedRowButTheReferenceLastToFirst) {
  io::Quality base;
  base.shells = 16;
  const std::vector<Setting> plan = plan_sweep(base, {"shells", "sort"});
  const std::vector<size_t> back = second_pass_order(plan);
  std::vector<size_t> expected;
  for (size_t i = plan.size(); i-- > 1;)  // plan[0] is the reference
    if (!plan[i].same_as) expected.push_back(i);
  EXPECT_EQ(back, expected);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(plan[back.front()].knob, kPresetKnob);  // the last row of the sweep comes first
  EXPECT_EQ(plan[back.back()].knob, kDefaultKnob);  // and the first after the reference last
  for (size_t i : back) EXPECT_NE(plan[i].knob, kReferenceKnob);
  EXPECT_EQ(plan[0].knob, kReferenceKnob);
  EXPECT_TRUE(second_pass_order({}).empty());
}

}  // namespace
}  // namespace pelt::tradeoff
