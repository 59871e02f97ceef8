// The animated scene and fixture of the `pelt render` tests (render_command_test.cpp, and
// render_readback_test.cpp, which reads outputs back with OpenImageIO in a binary of its own).
#pragma once

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>

#include <gtest/gtest.h>

#include "tests/tools/cli/run_pelt.h"

namespace pelt::cli_test {

namespace fs = std::filesystem;

// A small animated scene: the camera orbits, the key light dims.
inline std::string animated_scene(int frames) {
  return R"({
  "pelt": 1,
  "image": {"width": 48, "height": 36, "background": [0.1, 0.1, 0.1]},
  "camera": {"eye": [0, 2, 6], "target": [0, 0, 0], "fovy_deg": 45, "near": 0.5, "far": 30},
  "lights": [
    {"type": "directional", "direction": [0.3, 0.8, 0.5], "intensity": 1},
    {"type": "ambient", "intensity": 0.2}
  ],
  "objects": [
    {"mesh": "box:3", "transform": {"rotate_deg": [10, 20, 0]}, "material": {"type": "lambert", "color": [0.8, 0.5, 0.3]}},
    {"mesh": "plane:2", "transform": {"translate": [0, -1.5, 0], "scale": 4}, "material": {"type": "lambert"}}
  ],
  "animation": {"frames": )" + std::to_string(frames) + R"(, "fps": 12,
    "camera": {"orbit": {"azimuth_deg": {"keys": [{"frame": 0, "value": 0}, {"frame": )" + std::to_string(frames - 1) + R"(, "value": 120}]}}},
    "lights": [{"light": 0, "intensity": {"interpolation": "smooth", "keys": [{"frame": 0, "value": 1.5}, {"frame": )" +
         std::to_string(frames - 1) + R"(, "value": 0.3}]}}]}
})";
}

struct RenderCommand : ::testing::Test {
  TempDir dir;
  fs::path scene;
  void SetUp() override { scene = dir.write("shot.json", animated_scene(8)); }
  Result pelt(std::vector<std::string> args) {
    args.insert(args.begin(), {"render", scene.string()});
    return run_pelt(args, dir.path());
  }
  std::string frame_file(const std::string& folder, int k) {
    char name[32];
    std::snprintf(name, sizeof name, "f_%03d.png", k);
    return read_text(dir.path() / folder / name);
  }
  // Starts a render of 20000 tiny frames (still running when a signal comes) to `out` and waits
  // until `ready()`: by then its signal handler is installed. False when pelt ended first.
  bool start_long_render(const fs::path& out, const std::function<bool()>& ready, Child& c) {
    const fs::path long_scene = dir.write("long.json", animated_scene(20000));
    c = start_pelt({"render", long_scene.string(), "-o", out.string(), "--width", "8", "--height", "8", "--threads", "1"},
                   dir.path());
    int status = 0;
    pid_t ended = 0;
    while (!ready() && (ended = ::waitpid(c.pid, &status, WNOHANG)) == 0)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return ended == 0;
  }
  // The regular files in `folder`, sorted.
  std::vector<std::string> files(const std::string& folder) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir.path() / folder)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
};

}  // namespace pelt::cli_test
