// The scene's `animation` block: every kind of bad field is rejected with the file, the
// field path and the reason; good blocks parse into the tracks they describe.
#include <string>

#include <gtest/gtest.h>

#include "tools/io/input_error.h"
#include "tools/io/scene.h"

namespace pelt::io {
namespace {

// A scene with two lights and a furry and a bare object; `animation` is spliced in.
std::string scene_with(const std::string& animation, const std::string& up = "[0, 1, 0]") {
  return R"({
  "pelt": 1,
  "camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": )" + up + R"(},
  "lights": [
    {"type": "directional", "direction": [0, 1, 0], "intensity": 2},
    {"type": "point", "position": [1, 5, 1]}
  ],
  "objects": [
    {"name": "fuzzy", "mesh": "box:2", "material": {"type": "lambert"},
     "fur": {"gravity": {"strength": 0.5}, "wind": {"direction": [1, 0, 0], "strength": 2}}},
    {"name": "floor", "mesh": "plane:2", "material": {"type": "lambert"}},
    {"name": "bald", "mesh": "box:1", "material": {"type": "lambert"}, "fur": {}}
  ],
  "animation": )" + animation + "\n}";
}

struct BadCase {
  const char* name;
  std::string animation;
  const char* field;   // expected InputError::field
  const char* reason;  // expected substring of InputError::reason
  std::string up = "[0, 1, 0]";
};

// Test names in ctest show the case's name, not its bytes.
void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class BadAnimation : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadAnimation, NamesFileFieldAndReason) {
  const BadCase& c = GetParam();
  try {
    parse_scene(scene_with(c.animation, c.up), "shot.json");
    FAIL() << "accepted: " << c.animation;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, "shot.json");
    EXPECT_EQ(e.field, c.field) << e.what();
    EXPECT_NE(e.reason.find(c.reason), std::string::npos) << "reason: " << e.reason;
  }
}

const std::string kKeys = R"("keys": [{"frame": 0, "value": 1}, {"frame": 9, "value": 2}])";

INSTANTIATE_TEST_SUITE_P(
    Fields, BadAnimation,
    ::testing::Values(
        BadCase{"UnknownKey", R"({"frames": 10, "camra": {}})", "animation.camra", "did you mean `camera`"},
        BadCase{"FramesZero", R"({"frames": 0})", "animation.frames", "must be in [1,"},
        BadCase{"FpsNegative", R"({"fps": -24})", "animation.fps", "must be in (0,"},
        BadCase{"CameraEmpty", R"({"camera": {}})", "animation.camera", "needs `orbit` or `path`"},
        BadCase{"CameraBoth", R"({"camera": {"orbit": {"distance": 3}, "path": {"eye": [0, 0, 4]}}})",
                "animation.camera", "use one"},
        BadCase{"OrbitEmpty", R"({"camera": {"orbit": {}}})", "animation.camera.orbit", "at least one"},
        BadCase{"OrbitUnknownKey", R"({"camera": {"orbit": {"azimuth_dg": 3}}})", "animation.camera.orbit.azimuth_dg",
                "did you mean `azimuth_deg`"},
        BadCase{"OrbitNeedsYUp", R"({"camera": {"orbit": {"distance": 3}}})", "animation.camera.orbit",
                "camera.up must be [0, 1, 0]", "[1, 0, 0]"},
        BadCase{"ElevationAtPole", R"({"camera": {"orbit": {"elevation_deg": 90}}})",
                "animation.camera.orbit.elevation_deg", "must be in (-90, 90)"},
        BadCase{"DistanceZero", R"({"frames": 10, "camera": {"orbit": {"distance": {"keys": [{"frame": 0, "value": 1}, {"frame": 5, "value": 0}]}}}})",
                "animation.camera.orbit.distance.keys[1].value", "must be in (0,"},
        BadCase{"TrackWrongType", R"({"camera": {"orbit": {"distance": "far"}}})", "animation.camera.orbit.distance",
                "expected a number or a keyframe track"},
        BadCase{"TrackUnknownKey", R"({"camera": {"orbit": {"distance": {"key": []}}}})",
                "animation.camera.orbit.distance.key", "did you mean `keys`"},
        BadCase{"KeysMissing", R"({"camera": {"orbit": {"distance": {"interpolation": "linear"}}}})",
                "animation.camera.orbit.distance.keys", "required field is missing"},
        BadCase{"KeysEmpty", R"({"camera": {"orbit": {"distance": {"keys": []}}}})",
                "animation.camera.orbit.distance.keys", "at least one key"},
        BadCase{"KeyNotObject", R"({"camera": {"orbit": {"distance": {"keys": [3]}}}})",
                "animation.camera.orbit.distance.keys[0]", "expected an object"},
        BadCase{"KeyValueMissing", R"({"camera": {"orbit": {"distance": {"keys": [{"frame": 0}]}}}})",
                "animation.camera.orbit.distance.keys[0].value", "required field is missing"},
        BadCase{"Interpolation", R"({"frames": 10, "camera": {"orbit": {"distance": {"interpolation": "smoth", )" + kKeys + "}}}}",
                "animation.camera.orbit.distance.interpolation", "did you mean `smooth`"},
        BadCase{"KeyFrameFraction", R"({"frames": 10, "camera": {"orbit": {"distance": {"keys": [{"frame": 0.5, "value": 1}]}}}})",
                "animation.camera.orbit.distance.keys[0].frame", "whole number"},
        BadCase{"KeyFramePastEnd", R"({"frames": 10, "camera": {"orbit": {"distance": {"keys": [{"frame": 10, "value": 1}]}}}})",
                "animation.camera.orbit.distance.keys[0].frame", "must be in [0, 9]"},
        BadCase{"KeyFramesNotIncreasing", R"({"frames": 10, "camera": {"orbit": {"distance": {"keys": [{"frame": 4, "value": 1}, {"frame": 4, "value": 2}]}}}})",
                "animation.camera.orbit.distance.keys[1].frame", "greater than the previous key's frame (4)"},
        BadCase{"PointWrongLength", R"({"camera": {"path": {"eye": [0, 1]}}})", "animation.camera.path.eye",
                "expected 3 numbers"},
        BadCase{"PathEmpty", R"({"camera": {"path": {}}})", "animation.camera.path", "needs `eye`, `target`"},
        BadCase{"PathEyeMeetsTarget", R"({"frames": 10, "camera": {"path": {"eye": {"keys": [{"frame": 0, "value": [0, 0, 5]}, {"frame": 8, "value": [0, 0, -3]}]}}}})",
                "animation.camera.path", "at frame 5 the eye reaches the target"},
        BadCase{"PathLooksAlongUp", R"({"frames": 10, "camera": {"path": {"eye": {"keys": [{"frame": 0, "value": [0, 0, 5]}, {"frame": 2, "value": [0, 5, 0]}]}}}})",
                "animation.camera.path", "at frame 2 the view direction is parallel to camera.up"},
        BadCase{"LightsNotArray", R"({"lights": {}})", "animation.lights", "expected an array"},
        BadCase{"LightIndexRange", R"({"lights": [{"light": 2, "intensity": 1}]})", "animation.lights[0].light",
                "must be in [0, 1]"},
        BadCase{"LightIndexMissing", R"({"lights": [{"intensity": 1}]})", "animation.lights[0].light",
                "required field is missing"},
        BadCase{"LightNothingAnimated", R"({"lights": [{"light": 0}]})", "animation.lights[0]",
                "needs `intensity` or `direction`"},
        BadCase{"LightTwice", R"({"lights": [{"light": 1, "intensity": 1}, {"light": 1, "intensity": 2}]})",
                "animation.lights[1].light", "already animated"},
        BadCase{"LightIntensityNegative", R"({"lights": [{"light": 0, "intensity": -1}]})",
                "animation.lights[0].intensity", "must be in [0,"},
        BadCase{"PointLightDirection", R"({"lights": [{"light": 1, "direction": [0, 1, 0]}]})",
                "animation.lights[0].direction", "only directional lights have a direction; lights[1] is point"},
        BadCase{"DirectionZero", R"({"lights": [{"light": 0, "direction": [0, 0, 0]}]})",
                "animation.lights[0].direction", "direction must be non-zero"},
        BadCase{"DirectionShort", R"({"lights": [{"light": 0, "direction": [1e-7, 0, 0]}]})",
                "animation.lights[0].direction", "direction must have a length above 1e-06 (it is normalised, "
                "and a shorter one would be mostly rounding), got length 1e-07"},
        BadCase{"DirectionKeysOpposite", R"({"frames": 10, "lights": [{"light": 0, "direction": {"keys": [{"frame": 0, "value": [0, 1, 0]}, {"frame": 9, "value": [0, -2, 0]}]}}]})",
                "animation.lights[0].direction.keys[1].value", "opposite"},
        BadCase{"FurObjectRange", R"({"fur": [{"object": 3, "wind": {"strength": 1}}]})", "animation.fur[0].object",
                "must be in [0, 2]"},
        BadCase{"FurObjectName", R"({"fur": [{"object": "fuzy", "wind": {"strength": 1}}]})",
                "animation.fur[0].object", "did you mean `fuzzy`"},
        BadCase{"FurObjectWithoutFur", R"({"fur": [{"object": "floor", "wind": {"strength": 1}}]})",
                "animation.fur[0].object", "objects[1] has no fur block"},
        BadCase{"FurWithoutWindBlock", R"({"fur": [{"object": 2, "wind": {"strength": 1}}]})",
                "animation.fur[0].wind", "objects[2].fur has no `wind` block"},
        BadCase{"FurWithoutGravityBlock", R"({"fur": [{"object": 2, "gravity": {"strength": 1}}]})",
                "animation.fur[0].gravity", "objects[2].fur has no `gravity` block"},
        BadCase{"FurNothingAnimated", R"({"fur": [{"object": 0}]})", "animation.fur[0]", "needs `wind`, `gravity`"},
        BadCase{"FurWindUnknownKey", R"({"fur": [{"object": 0, "wind": {"strenght": 1}}]})",
                "animation.fur[0].wind.strenght", "did you mean `strength`"},
        BadCase{"WindStrengthRange", R"({"fur": [{"object": 0, "wind": {"strength": 1001}}]})",
                "animation.fur[0].wind.strength", "must be in [0, 1000]"},
        BadCase{"GravityStrengthNegative", R"({"fur": [{"object": 0, "gravity": {"strength": -0.5}}]})",
                "animation.fur[0].gravity.strength", "must be in [0, 1000]"},
        BadCase{"FurTwice", R"({"fur": [{"object": 0, "wind": {"strength": 1}}, {"object": "fuzzy", "gravity": {"strength": 1}}]})",
                "animation.fur[1].object", "already animated"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.name); });

TEST(AnimationParse, TracksAndDefaults) {
  const Scene s = parse_scene(scene_with(R"({
    "frames": 20, "fps": 10,
    "camera": {"orbit": {"azimuth_deg": {"interpolation": "smooth", "keys": [{"frame": 0, "value": 0}, {"frame": 19, "value": 90}]}}},
    "lights": [{"light": 0, "intensity": {"interpolation": "step", "keys": [{"frame": 2, "value": 1}, {"frame": 4, "value": 3}]}}],
    "fur": [{"object": "fuzzy", "wind": {"direction": [0, 0, 2], "strength": 3}}]
  })"), "shot.json");
  ASSERT_TRUE(s.animation);
  const Animation& a = *s.animation;
  EXPECT_EQ(a.frames, 20);
  EXPECT_EQ(a.fps, 10.0);
  ASSERT_TRUE(a.orbit);
  EXPECT_FALSE(a.path);
  EXPECT_EQ(a.orbit->azimuth_deg.interpolation, Interpolation::smooth);
  ASSERT_EQ(a.orbit->azimuth_deg.keys.size(), 2u);
  EXPECT_EQ(a.orbit->azimuth_deg.keys[1].frame, 19);
  EXPECT_EQ(a.orbit->azimuth_deg.keys[1].value, 90.0);
  // Fields left out come from the scene camera (eye on +z at distance 5).
  EXPECT_FALSE(a.orbit->distance.animated());
  EXPECT_DOUBLE_EQ(a.orbit->distance.keys[0].value, 5.0);
  EXPECT_DOUBLE_EQ(a.orbit->elevation_deg.keys[0].value, 0.0);
  ASSERT_EQ(a.lights.size(), 1u);
  EXPECT_EQ(a.lights[0].light, 0u);
  EXPECT_EQ(a.lights[0].intensity->interpolation, Interpolation::step);
  EXPECT_FALSE(a.lights[0].direction);
  ASSERT_EQ(a.fur.size(), 1u);
  EXPECT_EQ(a.fur[0].object, 0u);
  ASSERT_TRUE(a.fur[0].wind_direction);
  EXPECT_EQ(a.fur[0].wind_direction->keys[0].value, glm::dvec3(0, 0, 1));  // normalised
  EXPECT_FALSE(a.fur[0].gravity_strength);
}

TEST(AnimationParse, StepDirectionsMayBeOpposite) {
  // A step track jumps, so opposite keys are fine there.
  EXPECT_NO_THROW(parse_scene(scene_with(R"({"frames": 10, "lights": [{"light": 0, "direction": {"interpolation": "step",
      "keys": [{"frame": 0, "value": [0, 1, 0]}, {"frame": 5, "value": [0, -1, 0]}]}}]})"), "shot.json"));
}

}  // namespace
}  // namespace pelt::io
