// Small scenes for the frame-pipeline tests, as JSON text.
#pragma once

#include <string>

namespace pelt::render::test {

// A furry box seen from a three-quarter view. `fur_extra` is spliced into the fur block.
inline std::string furry_box_scene(const std::string& fur_extra, int frames = 1) {
  return R"({"pelt": 1,
  "image": {"width": 160, "height": 120, "background": [0.05, 0.05, 0.08]},
  "camera": {"eye": [3.5, 2.5, 5.0], "target": [0, 0, 0], "fovy_deg": 45, "near": 0.5, "far": 30},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]},
             {"type": "ambient", "color": [0.3, 0.3, 0.35]}],
  "animation": {"frames": )" +
         std::to_string(frames) + R"(, "fps": 24},
  "objects": [{"mesh": "box:7", "material": {"type": "lambert", "color": [0.3, 0.2, 0.1]},
               "fur": {"shells": 16, "texture_size": 64)" +
         (fur_extra.empty() ? "" : ", " + fur_extra) + R"(}}]})";
}

inline std::string bare_box_scene(int frames) {
  return R"({"pelt": 1, "image": {"width": 64, "height": 48},
  "camera": {"eye": [3, 2, 4], "target": [0, 0, 0]},
  "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}],
  "animation": {"frames": )" +
         std::to_string(frames) + R"(, "fps": 24},
  "objects": [{"mesh": "box:3", "material": {"type": "lambert"}}]})";
}

}  // namespace pelt::render::test
