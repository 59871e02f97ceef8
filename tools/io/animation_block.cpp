#include "tools/io/animation_block.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "tools/io/suggest.h"

namespace pelt::io {
namespace {

using nlohmann::json;

constexpr int kMaxFrames = 10000000;

// Direction keys closer than this to opposite have no well-defined shorter arc.
constexpr double kOppositeCos = -0.9999;

struct ScalarRange {
  double lo, hi;
  bool lo_open = false, hi_open = false;
};

struct TrackReader {
  const JsonFields& js;
  int frames;

  Interpolation interpolation(const json& j, const std::string& field) const {
    const std::string text = js.string(j, field);
    if (text == "linear") return Interpolation::linear;
    if (text == "smooth") return Interpolation::smooth;
    if (text == "step") return Interpolation::step;
    static constexpr std::string_view kNames[] = {"linear", "smooth", "step"};
    const std::string hint = did_you_mean(text, kNames);
    js.fail(field, "unknown interpolation `" + text + "`" +
                       (hint.empty() ? "; expected linear, smooth or step" : hint));
  }

  // The keys array of a track object; `read_value` parses one key's value.
  template <class T, class ReadValue>
  Track<T> keys(const json& j, const std::string& path, ReadValue read_value) const {
    js.expect_object(j, path, {"interpolation", "keys"});
    Track<T> t;
    if (const json* v = JsonFields::find(j, "interpolation"))
      t.interpolation = interpolation(*v, json_child(path, "interpolation"));
    const std::string keys_field = json_child(path, "keys");
    const json& keys = js.require(j, path, "keys");
    if (!keys.is_array()) js.fail(keys_field, "expected an array of keys, got " + json_type_name(keys));
    if (keys.empty()) js.fail(keys_field, "needs at least one key");
    for (size_t i = 0; i < keys.size(); ++i) {
      const std::string key_path = json_index(keys_field, i);
      js.expect_object(keys[i], key_path, {"frame", "value"});
      const std::string frame_field = json_child(key_path, "frame");
      const int frame =
          static_cast<int>(js.integer(js.require(keys[i], key_path, "frame"), frame_field, 0, frames - 1));
      if (!t.keys.empty() && frame <= t.keys.back().frame)
        js.fail(frame_field, "must be greater than the previous key's frame (" +
                                 std::to_string(t.keys.back().frame) + ")");
      const std::string value_field = json_child(key_path, "value");
      t.keys.push_back({frame, read_value(js.require(keys[i], key_path, "value"), value_field)});
    }
    return t;
  }

  ScalarTrack scalar(const json& j, const std::string& path, ScalarRange r) const {
    const auto read = [&](const json& v, const std::string& field) {
      return js.number_in(v, field, r.lo, r.hi, r.lo_open, r.hi_open);
    };
    if (j.is_number()) return constant_track(read(j, path));
    if (!j.is_object())
      js.fail(path, "expected a number or a keyframe track {\"keys\": [...]}, got " + json_type_name(j));
    return keys<double>(j, path, read);
  }

  VectorTrack point(const json& j, const std::string& path) const {
    const auto read = [&](const json& v, const std::string& field) {
      const auto n = js.numbers(v, field, 3, 3);
      return glm::dvec3(n[0], n[1], n[2]);
    };
    if (j.is_array()) return constant_track(read(j, path));
    if (!j.is_object())
      js.fail(path, "expected [x, y, z] or a keyframe track {\"keys\": [...]}, got " + json_type_name(j));
    return keys<glm::dvec3>(j, path, read);
  }

  VectorTrack direction(const json& j, const std::string& path) const {
    const auto read = [&](const json& v, const std::string& field) { return js.unit_direction(v, field); };
    if (j.is_array()) return constant_track(read(j, path));
    if (!j.is_object())
      js.fail(path, "expected [x, y, z] or a keyframe track {\"keys\": [...]}, got " + json_type_name(j));
    VectorTrack t = keys<glm::dvec3>(j, path, read);
    if (t.interpolation != Interpolation::step) {
      for (size_t i = 1; i < t.keys.size(); ++i)
        if (glm::dot(t.keys[i - 1].value, t.keys[i].value) < kOppositeCos)
          js.fail(json_child(json_index(json_child(path, "keys"), i), "value"),
                  "points opposite to the previous key's direction, so the way round is ambiguous; "
                  "add a key in between");
    }
    return t;
  }
};

int last_key_frame(const ScalarTrack& t) { return t.keys.back().frame; }
int last_key_frame(const VectorTrack& t) { return t.keys.back().frame; }

CameraOrbit parse_orbit(const TrackReader& r, const json& j, const std::string& path, const Camera& cam) {
  const JsonFields& js = r.js;
  js.expect_object(j, path, {"target", "azimuth_deg", "elevation_deg", "distance"});
  if (j.empty()) js.fail(path, "needs at least one of `target`, `azimuth_deg`, `elevation_deg`, `distance`");
  if (glm::length(glm::dvec3(cam.up) - glm::dvec3(0.0, 1.0, 0.0)) > 1e-6)
    js.fail(path, "an orbit turns about +y: the scene's camera.up must be [0, 1, 0]");
  // The static camera expressed as an orbit supplies every field left out.
  const glm::dvec3 offset = glm::dvec3(cam.eye) - glm::dvec3(cam.target);
  const double dist = glm::length(offset);
  CameraOrbit o;
  o.target = constant_track(glm::dvec3(cam.target));
  o.distance = constant_track(dist);
  o.elevation_deg = constant_track(glm::degrees(std::asin(std::clamp(offset.y / dist, -1.0, 1.0))));
  o.azimuth_deg = constant_track(glm::degrees(std::atan2(offset.x, offset.z)));
  if (const json* v = JsonFields::find(j, "target")) o.target = r.point(*v, json_child(path, "target"));
  if (const json* v = JsonFields::find(j, "azimuth_deg"))
    o.azimuth_deg = r.scalar(*v, json_child(path, "azimuth_deg"), {-1e9, 1e9});
  if (const json* v = JsonFields::find(j, "elevation_deg"))
    o.elevation_deg = r.scalar(*v, json_child(path, "elevation_deg"), {-90.0, 90.0, true, true});
  if (const json* v = JsonFields::find(j, "distance"))
    o.distance = r.scalar(*v, json_child(path, "distance"), {0.0, 1e30, true});
  return o;
}

CameraPath parse_path(const TrackReader& r, const json& j, const std::string& path, const Camera& cam) {
  r.js.expect_object(j, path, {"eye", "target"});
  if (j.empty()) r.js.fail(path, "needs `eye`, `target` or both");
  CameraPath p;
  p.eye = constant_track(glm::dvec3(cam.eye));
  p.target = constant_track(glm::dvec3(cam.target));
  if (const json* v = JsonFields::find(j, "eye")) p.eye = r.point(*v, json_child(path, "eye"));
  if (const json* v = JsonFields::find(j, "target")) p.target = r.point(*v, json_child(path, "target"));
  return p;
}

const char* light_type_name(LightType t) {
  switch (t) {
    case LightType::directional: return "directional";
    case LightType::point: return "point";
    case LightType::ambient: return "ambient";
  }
  return "?";
}

LightTracks parse_light_tracks(const TrackReader& r, const json& j, const std::string& path,
                               const Scene& scene) {
  const JsonFields& js = r.js;
  js.expect_object(j, path, {"light", "intensity", "direction"});
  LightTracks t;
  const std::string light_field = json_child(path, "light");
  if (scene.lights.empty()) js.fail(light_field, "the scene has no lights to animate");
  t.light = static_cast<size_t>(js.integer(js.require(j, path, "light"), light_field, 0,
                                           static_cast<long long>(scene.lights.size()) - 1));
  const Light& light = scene.lights[t.light];
  if (const json* v = JsonFields::find(j, "intensity"))
    t.intensity = r.scalar(*v, json_child(path, "intensity"), {0.0, 1e6});
  if (const json* v = JsonFields::find(j, "direction")) {
    const std::string field = json_child(path, "direction");
    if (light.type != LightType::directional)
      js.fail(field, "only directional lights have a direction; lights[" + std::to_string(t.light) + "] is " +
                         light_type_name(light.type));
    t.direction = r.direction(*v, field);
  }
  if (!t.intensity && !t.direction) js.fail(path, "needs `intensity` or `direction` (or both)");
  return t;
}

size_t object_index(const JsonFields& js, const json& j, const std::string& field, const Scene& scene) {
  if (j.is_string()) {
    const std::string name = j.get<std::string>();
    std::vector<std::string_view> names;
    size_t found = scene.objects.size(), count = 0;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      names.push_back(scene.objects[i].name);
      if (scene.objects[i].name == name) found = i, ++count;
    }
    if (count > 1) js.fail(field, "more than one object is named `" + name + "`; use its index");
    if (count == 0) {
      const std::string hint = did_you_mean(name, names);
      js.fail(field, "no object is named `" + name + "`" + (hint.empty() ? "" : hint));
    }
    return found;
  }
  if (!j.is_number()) js.fail(field, "expected an object index or name, got " + json_type_name(j));
  return static_cast<size_t>(js.integer(j, field, 0, static_cast<long long>(scene.objects.size()) - 1));
}

FurTracks parse_fur_tracks(const TrackReader& r, const json& j, const std::string& path, const Scene& scene) {
  const JsonFields& js = r.js;
  js.expect_object(j, path, {"object", "wind", "gravity"});
  FurTracks t;
  t.object = object_index(js, js.require(j, path, "object"), json_child(path, "object"), scene);
  const SceneObject& obj = scene.objects[t.object];
  const std::string obj_path = json_index("objects", t.object);
  if (!obj.fur) js.fail(json_child(path, "object"), obj_path + " has no fur block to animate");
  if (const json* v = JsonFields::find(j, "wind")) {
    const std::string w = json_child(path, "wind");
    if (!obj.fur->wind)
      js.fail(w, obj_path + ".fur has no `wind` block to animate; add one (it also sets gust_frequency "
                            "and gust_scale)");
    js.expect_object(*v, w, {"direction", "strength"});
    if (v->empty()) js.fail(w, "needs `direction`, `strength` or both");
    if (const json* d = JsonFields::find(*v, "direction"))
      t.wind_direction = r.direction(*d, json_child(w, "direction"));
    if (const json* s = JsonFields::find(*v, "strength"))
      t.wind_strength = r.scalar(*s, json_child(w, "strength"), {0.0, 1e3});
  }
  if (const json* v = JsonFields::find(j, "gravity")) {
    const std::string g = json_child(path, "gravity");
    if (!obj.fur->gravity) js.fail(g, obj_path + ".fur has no `gravity` block to animate; add one");
    js.expect_object(*v, g, {"direction", "strength"});
    if (v->empty()) js.fail(g, "needs `direction`, `strength` or both");
    if (const json* d = JsonFields::find(*v, "direction"))
      t.gravity_direction = r.direction(*d, json_child(g, "direction"));
    if (const json* s = JsonFields::find(*v, "strength"))
      t.gravity_strength = r.scalar(*s, json_child(g, "strength"), {0.0, 1e3});
  }
  if (!t.wind_direction && !t.wind_strength && !t.gravity_direction && !t.gravity_strength)
    js.fail(path, "needs `wind`, `gravity` or both");
  return t;
}

Camera animated_camera(const Camera& base, const Animation& a, int frame) {
  Camera c = base;
  if (a.orbit) {
    const glm::dvec3 target = sample_point(a.orbit->target, frame);
    const double az = glm::radians(sample(a.orbit->azimuth_deg, frame));
    const double el = glm::radians(sample(a.orbit->elevation_deg, frame));
    const double d = sample(a.orbit->distance, frame);
    const glm::dvec3 dir(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
    c.target = glm::vec3(target);
    c.eye = glm::vec3(target + d * dir);
  } else if (a.path) {
    c.eye = glm::vec3(sample_point(a.path->eye, frame));
    c.target = glm::vec3(sample_point(a.path->target, frame));
  }
  return c;
}

// Every frame up to the last key must give a usable view: interpolation never leaves the
// keys' range for a single field, but a path's eye and target can still cross.
void check_camera_frames(const JsonFields& js, const std::string& path, const Camera& base,
                         const Animation& a) {
  int last = 0;
  if (a.orbit)
    last = std::max({last_key_frame(a.orbit->target), last_key_frame(a.orbit->azimuth_deg),
                     last_key_frame(a.orbit->elevation_deg), last_key_frame(a.orbit->distance)});
  if (a.path) last = std::max(last_key_frame(a.path->eye), last_key_frame(a.path->target));
  const int end = std::min(a.frames, last + 1);
  for (int f = 0; f < end; ++f) {
    const Camera c = animated_camera(base, a, f);
    const glm::dvec3 forward = glm::dvec3(c.target) - glm::dvec3(c.eye);
    if (!(glm::length(forward) > 1e-9))
      js.fail(path, "at frame " + std::to_string(f) + " the eye reaches the target");
    if (!(glm::length(glm::cross(glm::normalize(forward), glm::dvec3(c.up))) > 1e-6))
      js.fail(path, "at frame " + std::to_string(f) + " the view direction is parallel to camera.up");
  }
}

}  // namespace

Camera camera_at(const Scene& scene, int frame) {
  return scene.animation ? animated_camera(scene.camera, *scene.animation, frame) : scene.camera;
}

namespace detail {

Animation parse_animation_block(const JsonFields& js, const json& j, const std::string& path,
                                const Scene& scene) {
  js.expect_object(j, path, {"frames", "fps", "camera", "lights", "fur"});
  Animation a;
  if (const json* v = JsonFields::find(j, "frames"))
    a.frames = static_cast<int>(js.integer(*v, json_child(path, "frames"), 1, kMaxFrames));
  if (const json* v = JsonFields::find(j, "fps")) a.fps = js.number_in(*v, json_child(path, "fps"), 0.0, 1e6, true);
  const TrackReader r{js, a.frames};

  const std::string cam_path = json_child(path, "camera");
  if (const json* v = JsonFields::find(j, "camera")) {
    js.expect_object(*v, cam_path, {"orbit", "path"});
    const json* orbit = JsonFields::find(*v, "orbit");
    const json* cpath = JsonFields::find(*v, "path");
    if (orbit && cpath) js.fail(cam_path, "holds both `orbit` and `path`; use one");
    if (!orbit && !cpath) js.fail(cam_path, "needs `orbit` or `path`");
    if (orbit) a.orbit = parse_orbit(r, *orbit, json_child(cam_path, "orbit"), scene.camera);
    if (cpath) a.path = parse_path(r, *cpath, json_child(cam_path, "path"), scene.camera);
  }

  if (const json* v = JsonFields::find(j, "lights")) {
    const std::string field = json_child(path, "lights");
    if (!v->is_array()) js.fail(field, "expected an array, got " + json_type_name(*v));
    for (size_t i = 0; i < v->size(); ++i) {
      const std::string p = json_index(field, i);
      LightTracks t = parse_light_tracks(r, (*v)[i], p, scene);
      for (const LightTracks& prev : a.lights)
        if (prev.light == t.light)
          js.fail(json_child(p, "light"), "lights[" + std::to_string(t.light) + "] is already animated above");
      a.lights.push_back(std::move(t));
    }
  }

  if (const json* v = JsonFields::find(j, "fur")) {
    const std::string field = json_child(path, "fur");
    if (!v->is_array()) js.fail(field, "expected an array, got " + json_type_name(*v));
    for (size_t i = 0; i < v->size(); ++i) {
      const std::string p = json_index(field, i);
      FurTracks t = parse_fur_tracks(r, (*v)[i], p, scene);
      for (const FurTracks& prev : a.fur)
        if (prev.object == t.object)
          js.fail(json_child(p, "object"), "objects[" + std::to_string(t.object) + "] is already animated above");
      a.fur.push_back(std::move(t));
    }
  }

  if (a.orbit || a.path)
    check_camera_frames(js, json_child(cam_path, a.orbit ? "orbit" : "path"), scene.camera, a);
  return a;
}

}  // namespace detail
}  // namespace pelt::io
