#include "shading/skin_params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace pelt::shading {
namespace {

TEST(SkinParams, DefaultsArePaperValuesAndValid) {
  SkinParams p;
  EXPECT_FLOAT_EQ(p.g, 0.8f);
  EXPECT_FLOAT_EQ(p.Eta, 1.4f);
  EXPECT_FALSE(validate(p).has_value());
  EXPECT_GE(p.normal_blur_radius[0], p.normal_blur_radius[1]);
  EXPECT_GE(p.normal_blur_radius[1], p.normal_blur_radius[2]);
}

TEST(SkinParams, ValidateNamesTheBadField) {
  SkinParams p;
  p.Eta = 0.0f;
  auto e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "Eta");
  EXPECT_NE(e->reason.find("[0.25, 4]"), std::string::npos) << e->reason;

  p = SkinParams{};
  p.DiffusionColor[1] = std::numeric_limits<float>::quiet_NaN();
  e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "DiffusionColor[1]");
  EXPECT_NE(e->reason.find("finite"), std::string::npos);

  p = SkinParams{};
  p.g = 1.5f;
  e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "g");

  p = SkinParams{};
  p.phase = static_cast<Phase>(7);
  e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "phase");
}

TEST(SkinParams, RangeEndsAreValid) {
  SkinParams p;
  p.g = -1.0f;
  p.Thickness = 1e6f;
  p.ClampCoeff = 0.0f;
  p.Eta = 0.25f;
  p.Power = 256.0f;
  EXPECT_FALSE(validate(p).has_value());
}

// normal_blur_mix is a mix weight, documented as [0, 1]: above 1 the flat N.L term would be
// subtracted ((1 - w) < 0). Both ends are valid, just past the top is not.
TEST(SkinParams, NormalBlurMixIsAWeightInZeroOne) {
  SkinParams p;
  for (float& w : p.normal_blur_mix) w = 1.0f;
  EXPECT_FALSE(validate(p).has_value());
  for (float& w : p.normal_blur_mix) w = 0.0f;
  EXPECT_FALSE(validate(p).has_value());
  p.normal_blur_mix[2] = 1.001f;
  const auto e = validate(p);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "normal_blur_mix[2]");
  EXPECT_NE(e->reason.find("[0, 1]"), std::string::npos) << e->reason;
}

TEST(SkinParams, SwitchNamesRoundTrip) {
  for (auto v : {SingleScattering::off, SingleScattering::paper, SingleScattering::correct}) {
    SingleScattering out = SingleScattering::off;
    EXPECT_FALSE(parse("single_scattering", to_string(v), out).has_value());
    EXPECT_EQ(out, v);
  }
  for (auto v : {MultipleScattering::off, MultipleScattering::paper, MultipleScattering::normal_blur,
                 MultipleScattering::reference}) {
    MultipleScattering out = MultipleScattering::off;
    EXPECT_FALSE(parse("multiple_scattering", to_string(v), out).has_value());
    EXPECT_EQ(out, v);
  }
  Fresnel f = Fresnel::exact;
  EXPECT_FALSE(parse("fresnel", "efresnel", f).has_value());
  EXPECT_EQ(f, Fresnel::efresnel);
  Phase ph = Phase::correct;
  EXPECT_FALSE(parse("phase", "paper", ph).has_value());
  EXPECT_EQ(ph, Phase::paper);
  Specular s = Specular::phong;
  EXPECT_FALSE(parse("specular", "blinn", s).has_value());
  EXPECT_EQ(s, Specular::blinn);
}

TEST(SkinParams, UnknownSwitchListsValidNames) {
  MultipleScattering out = MultipleScattering::paper;
  auto e = parse("multiple_scattering", "blurry", out);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "multiple_scattering");
  EXPECT_NE(e->reason.find("blurry"), std::string::npos);
  EXPECT_NE(e->reason.find("off, paper, normal_blur, reference"), std::string::npos) << e->reason;
  EXPECT_EQ(out, MultipleScattering::paper);
}

}  // namespace
}  // namespace pelt::shading
