#include "tools/io/animation_tracks.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace pelt::io {
namespace {

// Which two keys bracket `frame`, and the shaped fraction between them. from == to
// outside the keys' span, so the caller returns that key's value untouched.
struct Bracket {
  size_t from = 0, to = 0;
  double s = 0.0;
};

template <class T>
Bracket bracket(const Track<T>& track, int frame) {
  const auto& keys = track.keys;
  if (keys.size() <= 1 || frame <= keys.front().frame) return {0, 0, 0.0};
  if (frame >= keys.back().frame) return {keys.size() - 1, keys.size() - 1, 0.0};
  // The first key after `frame`; keys are strictly increasing.
  const auto next = std::upper_bound(keys.begin(), keys.end(), frame,
                                     [](int f, const Key<T>& k) { return f < k.frame; });
  const size_t to = static_cast<size_t>(next - keys.begin());
  const size_t from = to - 1;
  if (frame == keys[from].frame) return {from, from, 0.0};
  const double u = double(frame - keys[from].frame) / double(keys[to].frame - keys[from].frame);
  switch (track.interpolation) {
    case Interpolation::linear: return {from, to, u};
    case Interpolation::smooth: return {from, to, u * u * (3.0 - 2.0 * u)};
    case Interpolation::step: return {from, from, 0.0};
  }
  return {from, to, u};
}

}  // namespace

double sample(const ScalarTrack& track, int frame) {
  const Bracket b = bracket(track, frame);
  const double a = track.keys[b.from].value;
  if (b.from == b.to) return a;
  const double c = track.keys[b.to].value;
  return a + (c - a) * b.s;
}

glm::dvec3 sample_point(const VectorTrack& track, int frame) {
  const Bracket b = bracket(track, frame);
  const glm::dvec3 a = track.keys[b.from].value;
  if (b.from == b.to) return a;
  const glm::dvec3 c = track.keys[b.to].value;
  return a + (c - a) * b.s;
}

glm::dvec3 sample_direction(const VectorTrack& track, int frame) {
  const Bracket b = bracket(track, frame);
  const glm::dvec3 a = track.keys[b.from].value;
  if (b.from == b.to) return a;
  const glm::dvec3 c = track.keys[b.to].value;
  if (a == c) return a;
  const double cos_angle = std::clamp(glm::dot(a, c), -1.0, 1.0);
  const double angle = std::acos(cos_angle);
  const double sin_angle = std::sin(angle);
  // Nearly equal keys: the chord is as good as the arc and avoids 0/0.
  if (sin_angle < 1e-9) return glm::normalize(a + (c - a) * b.s);
  const glm::dvec3 d = (std::sin((1.0 - b.s) * angle) * a + std::sin(b.s * angle) * c) / sin_angle;
  return glm::normalize(d);
}

}  // namespace pelt::io
