// evaluate_frame_inputs and the track samplers: known values at and between keys,
// static inputs returned unchanged, orbit geometry, and determinism.
#include "tools/render/animation.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "tools/io/animation_tracks.h"
#include "tools/io/scene.h"

namespace pelt::render {
namespace {

io::Scene parse(const std::string& animation) {
  return io::parse_scene(R"({
  "pelt": 1,
  "camera": {"eye": [0, 0, 5], "target": [0, 0, 0]},
  "lights": [
    {"type": "directional", "direction": [0, 1, 0], "intensity": 2},
    {"type": "ambient", "intensity": 0.5}
  ],
  "objects": [
    {"name": "fuzzy", "mesh": "box:2", "material": {"type": "lambert"},
     "fur": {"gravity": {"strength": 0.5, "stability": 50}, "wind": {"direction": [1, 0, 0], "strength": 2, "gust_scale": 0.25}}},
    {"name": "floor", "mesh": "plane:2", "material": {"type": "lambert"}}
  ])" + (animation.empty() ? std::string() : ",\n  \"animation\": " + animation) + "\n}",
                         "shot.json");
}

TEST(TrackSample, LinearSmoothStepAndHold) {
  io::ScalarTrack t{io::Interpolation::linear, {{10, 1.0}, {20, 3.0}}};
  EXPECT_EQ(io::sample(t, 0), 1.0);   // before the first key: held
  EXPECT_EQ(io::sample(t, 10), 1.0);  // exact at keys
  EXPECT_EQ(io::sample(t, 15), 2.0);
  EXPECT_EQ(io::sample(t, 20), 3.0);
  EXPECT_EQ(io::sample(t, 99), 3.0);  // after the last key: held
  t.interpolation = io::Interpolation::smooth;
  EXPECT_DOUBLE_EQ(io::sample(t, 15), 2.0);                              // symmetric at the middle
  EXPECT_DOUBLE_EQ(io::sample(t, 12), 1.0 + 2.0 * (0.04 * (3 - 0.4)));  // s(0.2) = 0.104
  EXPECT_LT(io::sample(t, 11) - 1.0, io::sample(t, 16) - io::sample(t, 15));  // slow out of a key
  t.interpolation = io::Interpolation::step;
  EXPECT_EQ(io::sample(t, 19), 1.0);
  EXPECT_EQ(io::sample(t, 20), 3.0);
}

TEST(TrackSample, SmoothNeverOvershootsItsKeys) {
  const io::ScalarTrack t{io::Interpolation::smooth, {{0, 0.0}, {3, 5.0}, {7, 1.0}, {30, 4.0}}};
  for (int f = 0; f <= 30; ++f) {
    const double v = io::sample(t, f);
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 5.0);
  }
}

TEST(TrackSample, DirectionsTurnAlongTheArc) {
  const io::VectorTrack t{io::Interpolation::linear, {{0, {1, 0, 0}}, {10, {0, 1, 0}}}};
  const glm::dvec3 mid = io::sample_direction(t, 5);
  EXPECT_NEAR(mid.x, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(mid.y, std::sqrt(0.5), 1e-12);
  // Equal angle steps: 9 degrees a frame.
  for (int f = 0; f <= 10; ++f)
    EXPECT_NEAR(std::acos(glm::dot(io::sample_direction(t, f), glm::dvec3(1, 0, 0))), glm::radians(9.0 * f), 1e-12);
  EXPECT_EQ(io::sample_direction(t, 0), glm::dvec3(1, 0, 0));
  EXPECT_EQ(io::sample_direction(t, 10), glm::dvec3(0, 1, 0));
}

TEST(FrameInputs, StaticSceneIsTheSceneInEveryFrame) {
  const io::Scene s = parse(R"({"frames": 100, "fps": 25})");
  const FrameInputs first = evaluate_frame_inputs(s, 0);
  EXPECT_EQ(first.camera, s.camera);
  EXPECT_EQ(first.lights, s.lights);
  ASSERT_EQ(first.fur.size(), 2u);
  ASSERT_TRUE(first.fur[0].wind && first.fur[0].gravity);
  EXPECT_TRUE(same_wind(*first.fur[0].wind, *s.objects[0].fur->wind));
  EXPECT_TRUE(same_gravity(*first.fur[0].gravity, *s.objects[0].fur->gravity));
  EXPECT_FALSE(first.fur[1].wind || first.fur[1].gravity);  // no fur on the floor
  for (int f = 1; f < 100; ++f) {
    FrameInputs in = evaluate_frame_inputs(s, f);
    EXPECT_DOUBLE_EQ(in.time_seconds, f / 25.0);
    EXPECT_EQ(in.camera, first.camera);
    EXPECT_EQ(in.lights, first.lights);
    EXPECT_EQ(in.fur, first.fur);
    in.time_seconds = first.time_seconds;
    EXPECT_EQ(in, first);
  }
}

TEST(FrameInputs, WithoutAnimationBlockOneFrame) {
  const io::Scene s = parse("");
  const FrameInputs in = evaluate_frame_inputs(s, 0);
  EXPECT_EQ(in.time_seconds, 0.0);
  EXPECT_EQ(in.camera, s.camera);
  EXPECT_THROW(evaluate_frame_inputs(s, 1), std::out_of_range);
  EXPECT_THROW(evaluate_frame_inputs(s, -1), std::out_of_range);
}

TEST(FrameInputs, OrbitPlacesTheEye) {
  const io::Scene s = parse(R"({"frames": 11, "camera": {"orbit": {"target": [1, 2, 3], "distance": 4,
      "elevation_deg": 30, "azimuth_deg": {"keys": [{"frame": 0, "value": 0}, {"frame": 10, "value": 90}]}}}})");
  for (int f = 0; f <= 10; ++f) {
    const io::Camera c = evaluate_frame_inputs(s, f).camera;
    EXPECT_EQ(c.target, glm::vec3(1, 2, 3));
    const glm::dvec3 d = glm::dvec3(c.eye) - glm::dvec3(c.target);
    EXPECT_NEAR(glm::length(d), 4.0, 1e-5);
    EXPECT_NEAR(d.y, 4.0 * 0.5, 1e-5);  // sin 30
    EXPECT_NEAR(std::atan2(d.x, d.z), glm::radians(9.0 * f), 1e-5);
    EXPECT_EQ(c.fovy_deg, s.camera.fovy_deg);
  }
  // Azimuth 0 looks from +z, 90 from +x.
  EXPECT_NEAR(evaluate_frame_inputs(s, 0).camera.eye.x, 1.0, 1e-5);
  EXPECT_NEAR(evaluate_frame_inputs(s, 10).camera.eye.z, 3.0, 1e-5);
}

TEST(FrameInputs, OrbitOfTheSceneCameraStartsAtTheSceneCamera) {
  // Only the azimuth is animated and its first key is the scene camera's own azimuth (0).
  const io::Scene s = parse(R"({"frames": 5, "camera": {"orbit": {"azimuth_deg": {"keys": [{"frame": 0, "value": 0}, {"frame": 4, "value": 40}]}}}})");
  const io::Camera c = evaluate_frame_inputs(s, 0).camera;
  EXPECT_NEAR(glm::length(c.eye - s.camera.eye), 0.0f, 1e-6f);
  EXPECT_NE(evaluate_frame_inputs(s, 1).camera, evaluate_frame_inputs(s, 0).camera);
}

TEST(FrameInputs, PathMovesEyeAndTarget) {
  const io::Scene s = parse(R"({"frames": 5, "camera": {"path": {
      "eye": {"keys": [{"frame": 0, "value": [0, 0, 5]}, {"frame": 4, "value": [4, 0, 5]}]},
      "target": [0, 1, 0]}}})");
  EXPECT_EQ(evaluate_frame_inputs(s, 2).camera.eye, glm::vec3(2, 0, 5));
  EXPECT_EQ(evaluate_frame_inputs(s, 2).camera.target, glm::vec3(0, 1, 0));
  EXPECT_EQ(evaluate_frame_inputs(s, 2).camera.up, s.camera.up);
}

TEST(FrameInputs, LightsAndFurTracks) {
  const io::Scene s = parse(R"({"frames": 9,
    "lights": [{"light": 0, "intensity": {"keys": [{"frame": 0, "value": 1}, {"frame": 8, "value": 3}]},
                "direction": {"keys": [{"frame": 0, "value": [0, 1, 0]}, {"frame": 8, "value": [1, 0, 0]}]}}],
    "fur": [{"object": "fuzzy", "wind": {"strength": {"keys": [{"frame": 0, "value": 0}, {"frame": 8, "value": 8}]}},
             "gravity": {"direction": [0, 0, -1], "strength": 2}}]})");
  const FrameInputs in = evaluate_frame_inputs(s, 4);
  EXPECT_FLOAT_EQ(in.lights[0].intensity, 2.0f);
  EXPECT_NEAR(in.lights[0].direction.x, std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(in.lights[0].direction.y, std::sqrt(0.5f), 1e-6f);
  EXPECT_EQ(in.lights[1], s.lights[1]);  // not animated
  const fur::WindParams& w = *in.fur[0].wind;
  EXPECT_FLOAT_EQ(w.strength, 4.0f);
  EXPECT_EQ(w.direction, s.objects[0].fur->wind->direction);  // not animated
  EXPECT_EQ(w.gust_scale, 0.25f);                              // from the fur block
  const fur::GravityParams& g = *in.fur[0].gravity;
  EXPECT_EQ(g.direction, glm::vec3(0, 0, -1));
  EXPECT_EQ(g.strength, 2.0f);
  EXPECT_EQ(g.stability, 50.0f);
  // Gravity is constant over the shot, wind is not: the renderer can tell them apart.
  const FrameInputs other = evaluate_frame_inputs(s, 5);
  EXPECT_TRUE(same_gravity(*other.fur[0].gravity, g));
  EXPECT_FALSE(same_wind(*other.fur[0].wind, w));
  EXPECT_FALSE(other.fur[0] == in.fur[0]);
}

TEST(FrameInputs, Deterministic) {
  const io::Scene s = parse(R"({"frames": 30, "camera": {"orbit": {"azimuth_deg": {"interpolation": "smooth",
      "keys": [{"frame": 0, "value": 10}, {"frame": 29, "value": 300}]}}}})");
  for (int f : {29, 3, 17, 3, 0})
    EXPECT_EQ(evaluate_frame_inputs(s, f), evaluate_frame_inputs(parse(R"({"frames": 30, "camera": {"orbit": {"azimuth_deg": {"interpolation": "smooth",
      "keys": [{"frame": 0, "value": 10}, {"frame": 29, "value": 300}]}}}})"), f));
}

}  // namespace
}  // namespace pelt::render
