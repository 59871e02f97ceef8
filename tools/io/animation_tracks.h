// Keyframe tracks of a scene's `animation` block and their evaluation. A track holds one
// quantity (a number, a point or a direction) as keys at whole frames; between two keys
// the value follows the track's interpolation, before the first key it holds the first
// value and after the last key the last value. A constant in the JSON is a track with
// one key, so evaluation needs no special case and a constant is returned unchanged
// (bit for bit) in every frame.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

namespace pelt::io {

// How a track moves from one key to the next (u = fraction of the way between them):
//   linear: value = a + (b - a) u
//   smooth: value = a + (b - a) s(u), s = 3u^2 - 2u^3: eases out of and into each key
//           (zero rate of change at every key), never overshoots the two keys' values
//   step:   value = a until the next key's frame
// Directions turn along the shorter great-circle arc, by the same fraction s(u) of the
// angle between the two keys (spherical interpolation).
enum class Interpolation { linear, smooth, step };

template <class T>
struct Key {
  int frame = 0;  // whole frame number, >= 0
  T value{};
  bool operator==(const Key&) const = default;
};

template <class T>
struct Track {
  Interpolation interpolation = Interpolation::linear;
  std::vector<Key<T>> keys;  // at least one; frames strictly increasing
  bool operator==(const Track&) const = default;
  bool animated() const { return keys.size() > 1; }
};

using ScalarTrack = Track<double>;
using VectorTrack = Track<glm::dvec3>;  // a point (component-wise) or a unit direction (slerp)

// A one-key track holding `value`.
template <class T>
Track<T> constant_track(const T& value) {
  return Track<T>{Interpolation::linear, {Key<T>{0, value}}};
}

// The value of a track at `frame`. Exact at keys and for constant tracks.
double sample(const ScalarTrack& track, int frame);
glm::dvec3 sample_point(const VectorTrack& track, int frame);
// Unit direction; keys must be unit vectors that are not opposite (the parser checks).
glm::dvec3 sample_direction(const VectorTrack& track, int frame);

}  // namespace pelt::io
