// Which of a furry object's poses a frame needs computed, from the frame's gravity and wind
// alone: the decisions FurObject::update acts on, kept apart from the arrays so that `pelt info`
// counts the same stages over a scene's frames without rendering them.
#pragma once

#include <optional>
#include <utility>

#include "fur/fur_params.h"

namespace pelt::render {

// One swing from the gravity pose to the wind pose and back (seed Fig. 12), in seconds of the
// scene's clock, as gusts are: the same motion at any fps (48 frames at 24 fps).
inline constexpr double kSwingSeconds = 2.0;

struct ForceStep {
  bool gravity = false;        // the gravity pose is made again: its inputs changed
  bool gravity_bends = false;  // ... by apply_gravity (else it is the rest pose)
  bool wind = false;           // the wind pose is pushed again from the gravity pose
  double wind_time = 0.0;      // the time its gusts are evaluated at (0 for a steady wind)
  float t = 0.0f;              // the wind pose's weight in the frame's pose (0: not used)
};

class ForceSchedule {
 public:
  // The step for a frame at `time_seconds` whose fur has `gravity` and `wind` (the animated
  // values); `still`: the scene has no animation, and shows the wind pose itself. What needs no
  // work is skipped:
  // - gravity that bends nothing (fur::gravity_bends) is no gravity;
  // - a wind of strength 0 pushes nothing at any time: no wind;
  // - a steady wind (no gusts) gives the same pose at every time;
  // - a frame at rest in the swing (t = 0) shows the gravity pose alone, and pushes no wind.
  ForceStep next(const std::optional<fur::GravityParams>& gravity, const std::optional<fur::WindParams>& wind,
                 double time_seconds, bool still);

 private:
  // The inputs the current poses were made from (outer nullopt: never made).
  std::optional<std::optional<fur::GravityParams>> gravity_in_;
  std::optional<std::pair<fur::WindParams, double>> wind_in_;
};

}  // namespace pelt::render
