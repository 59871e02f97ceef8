// Per-frame inputs of an animated scene: the keyframe tracks of the scene's `animation`
// block evaluated at one frame. The renderer compares two frames' inputs (member by
// member, with ==) to decide what to recompute: a static value is returned bit for bit
// unchanged in every frame.
#pragma once

#include <optional>
#include <vector>

#include "fur/fur_params.h"
#include "tools/io/scene.h"

namespace pelt::render {

struct FrameInputs {
  double time_seconds = 0.0;  // frame / fps (fps 24 without an animation block)
  io::Camera camera;
  std::vector<io::Light> lights;  // the scene's lights, in order
  struct Fur {
    // The object's fur wind / gravity with the animated direction and strength applied;
    // both empty for an object without fur, and each empty when its block is absent.
    std::optional<fur::WindParams> wind;
    std::optional<fur::GravityParams> gravity;
    friend bool operator==(const Fur& a, const Fur& b);
  };
  std::vector<Fur> fur;  // one per scene object
  bool operator==(const FrameInputs&) const = default;
};

// Evaluates every track at `frame` (0-based, in [0, frame count)); throws
// std::out_of_range for a frame outside that range (callers validate user input first).
// Pure and deterministic: the result depends only on the scene and the frame.
FrameInputs evaluate_frame_inputs(const io::Scene& scene, int frame);
// The same, into `out`, reusing its vectors: the renderer calls it every frame.
void evaluate_frame_inputs(const io::Scene& scene, int frame, FrameInputs& out);

// Field-by-field equality of the fur blocks (fur/ declares no operator== for them).
bool same_wind(const fur::WindParams& a, const fur::WindParams& b);
bool same_gravity(const fur::GravityParams& a, const fur::GravityParams& b);

}  // namespace pelt::render
