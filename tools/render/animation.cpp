#include "tools/render/animation.h"

#include <stdexcept>
#include <string>

namespace pelt::render {
namespace {

template <class T, class Same>
bool same_optional(const std::optional<T>& a, const std::optional<T>& b, Same same) {
  if (a.has_value() != b.has_value()) return false;
  return !a || same(*a, *b);
}

}  // namespace

bool same_wind(const fur::WindParams& a, const fur::WindParams& b) {
  return a.direction == b.direction && a.strength == b.strength && a.gust_frequency == b.gust_frequency &&
         a.gust_scale == b.gust_scale;
}

bool same_gravity(const fur::GravityParams& a, const fur::GravityParams& b) {
  return a.direction == b.direction && a.strength == b.strength && a.stability == b.stability;
}

bool operator==(const FrameInputs::Fur& a, const FrameInputs::Fur& b) {
  return same_optional(a.wind, b.wind, same_wind) && same_optional(a.gravity, b.gravity, same_gravity);
}

FrameInputs evaluate_frame_inputs(const io::Scene& scene, int frame) {
  FrameInputs in;
  evaluate_frame_inputs(scene, frame, in);
  return in;
}

void evaluate_frame_inputs(const io::Scene& scene, int frame, FrameInputs& in) {
  const int frames = scene.animation ? scene.animation->frames : 1;
  if (frame < 0 || frame >= frames)
    throw std::out_of_range("evaluate_frame_inputs: frame " + std::to_string(frame) + " outside [0, " +
                            std::to_string(frames) + ")");
  const double fps = scene.animation ? scene.animation->fps : io::Animation{}.fps;

  in.time_seconds = double(frame) / fps;
  in.camera = io::camera_at(scene, frame);
  in.lights.assign(scene.lights.begin(), scene.lights.end());
  in.fur.resize(scene.objects.size());
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    in.fur[i] = FrameInputs::Fur{};
    if (!scene.objects[i].fur) continue;
    in.fur[i].wind = scene.objects[i].fur->wind;
    in.fur[i].gravity = scene.objects[i].fur->gravity;
  }
  if (!scene.animation) return;

  for (const io::LightTracks& t : scene.animation->lights) {
    io::Light& l = in.lights[t.light];
    if (t.intensity) l.intensity = static_cast<float>(io::sample(*t.intensity, frame));
    if (t.direction) l.direction = glm::vec3(io::sample_direction(*t.direction, frame));
  }
  for (const io::FurTracks& t : scene.animation->fur) {
    FrameInputs::Fur& f = in.fur[t.object];
    if (t.wind_direction) f.wind->direction = glm::vec3(io::sample_direction(*t.wind_direction, frame));
    if (t.wind_strength) f.wind->strength = static_cast<float>(io::sample(*t.wind_strength, frame));
    if (t.gravity_direction) f.gravity->direction = glm::vec3(io::sample_direction(*t.gravity_direction, frame));
    if (t.gravity_strength) f.gravity->strength = static_cast<float>(io::sample(*t.gravity_strength, frame));
  }
}

}  // namespace pelt::render
