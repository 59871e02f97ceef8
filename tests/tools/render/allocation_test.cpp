// A frame allocates nothing once the renderer has warmed up: the frame loop reuses every
// buffer (tile scratch, bin chunks, sort orders, lights, frame inputs), so rendering a
// sequence again at the same size performs no C++ heap allocation. This binary replaces the
// global operator new to count them; it holds no other tests.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "tests/tools/render/render_test_scenes.h"

namespace {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};
}  // namespace

void* operator new(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// Not inlined: GCC 12 would otherwise see free() on a pointer from operator new at the call
// sites and warn (-Wmismatched-new-delete), although both are these replacements.
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace pelt::render::test {
namespace {

// Renders frames [0, frames) twice and returns the allocations of the second pass.
long allocations_of_second_pass(const std::string& json, int frames, int threads) {
  SceneDir dir;
  RenderSettings rs;
  rs.threads = threads;
  SceneRenderer r(dir.scene(json), rs);
  FrameImage img;
  FrameStats st;
  for (int f = 0; f < frames; ++f) r.render(f, img, st);
  g_allocations = 0;
  g_counting = true;
  for (int f = 0; f < frames; ++f) r.render(f, img, st);
  g_counting = false;
  return g_allocations.load();
}

TEST(FrameAllocations, AnimatedFurFramesAllocateNothingOnceWarm) {
  // Gravity, a gusting wind re-simulated every frame, fins and the per-tile sort.
  const std::string scene = furry_box_scene(
      R"("fins": "silhouette", "gravity": {}, "wind": {"strength": 1, "gust_frequency": 0.5, "gust_scale": 0.3})", 4);
  for (int threads : {1, 2}) EXPECT_EQ(allocations_of_second_pass(scene, 4, threads), 0) << threads << " threads";
  // The surface sort's keys are made every frame from the pose, into buffers kept from the first.
  std::string surface = scene;
  surface.insert(surface.find('{') + 1, R"("quality": {"sort": "surface"}, )");
  for (int threads : {1, 2}) EXPECT_EQ(allocations_of_second_pass(surface, 4, threads), 0) << threads << " threads, surface";
}

// A wind whose strength and direction are keyed changes its field every frame: the field's
// phases are made again in place, into the array the first frames sized.
TEST(FrameAllocations, KeyedWindAllocatesNothingOnceWarm) {
  const std::string scene = R"({"pelt": 1, "image": {"width": 96, "height": 72},
    "camera": {"eye": [3.5, 2.5, 5.0], "target": [0, 0, 0]},
    "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}],
    "animation": {"frames": 4, "fps": 24,
      "fur": [{"object": 0, "wind": {
        "strength": {"keys": [{"frame": 0, "value": 0.5}, {"frame": 3, "value": 2}]},
        "direction": {"keys": [{"frame": 0, "value": [1, 0, 0]}, {"frame": 3, "value": [0, 0, 1]}]}}}]},
    "objects": [{"mesh": "box:3", "material": {"type": "lambert"},
                 "fur": {"shells": 8, "texture_size": 32, "wind": {"gust_scale": 0}}}]})";
  for (int threads : {1, 2}) EXPECT_EQ(allocations_of_second_pass(scene, 4, threads), 0) << threads << " threads";
}

TEST(FrameAllocations, SkinFramesAllocateNothingOnceWarm) {
  const std::string scene = R"({"pelt": 1, "image": {"width": 96, "height": 72},
    "camera": {"eye": [0, 0.5, 3], "target": [0, 0, 0]},
    "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5]}, {"type": "ambient", "intensity": 0.1}],
    "animation": {"frames": 3, "fps": 24,
                  "camera": {"orbit": {"azimuth_deg": {"keys": [{"frame": 0, "value": 0}, {"frame": 2, "value": 40}]}}}},
    "objects": [{"mesh": "sphere:24", "material": {"type": "skin", "skin": {"multiple_scattering": "normal_blur"}}}]})";
  for (int threads : {1, 2}) EXPECT_EQ(allocations_of_second_pass(scene, 3, threads), 0) << threads << " threads";
}

}  // namespace
}  // namespace pelt::render::test
