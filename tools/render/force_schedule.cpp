#include "tools/render/force_schedule.h"

#include "fur/dynamics.h"
#include "tools/render/animation.h"

namespace pelt::render {

ForceStep ForceSchedule::next(const std::optional<fur::GravityParams>& gravity,
                              const std::optional<fur::WindParams>& wind, double time_seconds, bool still) {
  ForceStep step;
  std::optional<fur::GravityParams> bending;
  if (gravity && fur::gravity_bends(*gravity)) bending = gravity;
  const bool same_gravity_in =
      gravity_in_ && gravity_in_->has_value() == bending.has_value() && (!bending || same_gravity(**gravity_in_, *bending));
  if (!same_gravity_in) {
    step.gravity = true;
    step.gravity_bends = bending.has_value();
    gravity_in_ = bending;
    wind_in_.reset();  // the wind pose is pushed from the gravity pose
  }
  // Gusts scale the strength, so a wind of strength 0 this frame (static, or an animated
  // strength at 0) pushes nothing at any time: no per-frame re-simulation of a scene without it.
  if (!wind || wind->strength == 0.0f) return step;
  // A still has no clock to swing on: it shows the wind it names, the wind pose.
  step.t = still ? 1.0f : fur::animation_t(time_seconds, kSwingSeconds);
  if (step.t == 0.0f) return step;
  const bool gusty = wind->gust_scale > 0.0f && wind->gust_frequency > 0.0f;
  step.wind_time = gusty ? time_seconds : 0.0;
  if (!wind_in_ || !same_wind(wind_in_->first, *wind) || wind_in_->second != step.wind_time) {
    step.wind = true;
    wind_in_ = std::make_pair(*wind, step.wind_time);
  }
  return step;
}

}  // namespace pelt::render
