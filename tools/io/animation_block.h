// Parser of a scene's `animation` block (frames, fps and keyframe tracks). Internal to
// pelt_io: called by parse_scene after the camera, lights and objects, which the tracks
// refer to and are checked against.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "tools/io/json_fields.h"
#include "tools/io/scene.h"

namespace pelt::io::detail {

// `scene` holds everything parsed so far (camera, lights, objects). Every field is
// checked: types, ranges, key frames within [0, frames - 1] and strictly increasing,
// directions non-zero and no two consecutive direction keys opposite, references to
// lights and objects that exist (and have the light type / fur block animated), and the
// animated camera valid in every frame.
Animation parse_animation_block(const JsonFields& js, const nlohmann::json& j, const std::string& path,
                                const Scene& scene);

}  // namespace pelt::io::detail
