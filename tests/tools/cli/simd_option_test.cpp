// --simd: a pinned target reaches every kernel's dispatch, targets of one arithmetic (fused
// multiply-add or not) draw the same bytes and the others within a few float steps, and the
// pin is reported and refused as the other options are.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <hwy/targets.h>

#include "raster/simd_targets.h"
#include "tests/tools/cli/run_pelt.h"
#include "tools/io/image_io.h"
#include "tools/io/scene.h"
#include "tools/render/scene_renderer.h"

namespace pelt::cli_test {
namespace {

namespace fs = std::filesystem;

// The shipped scenes that exercise every kernel family: fur (vertex transform, set-up, tile,
// sampler, fur lighting) and skin (the skin kernels and the normal blur).
const char* const kScenes[] = {"box_fur", "head_skin"};

struct Render {
  std::string bytes;
  io::ImageRGBA image;
};

// Every scene drawn small with --simd `target`, as EXR (float: the last bits show).
std::map<std::string, Render> render_all(const std::string& target) {
  const TempDir dir;
  std::map<std::string, Render> out;
  for (const char* scene : kScenes) {
    const fs::path path = dir.path() / (std::string(scene) + "_" + target + ".exr");
    const Result r = run_pelt({"render", (source_dir() / "tools/scenes" / (std::string(scene) + ".json")).string(),
                               "--frame", "0", "--width", "96", "--height", "72", "--threads", "2", "--simd", target,
                               "-q", "-o", path.string()},
                              dir.path());
    EXPECT_EQ(r.code, 0) << scene << " " << target << ": " << r.err;
    out[scene] = {read_text(path), io::read_image_rgba(path)};
  }
  return out;
}

// A shipped scene's frame 0 drawn in this process, its float colour: with dispatch as it stands
// (held = 0), or held to the targets of `held` while it draws.
std::vector<float> draw_here(const std::string& scene, int width, int height, int64_t held = 0) {
  const io::Scene parsed = io::load_scene(source_dir() / "tools/scenes" / (scene + ".json"));
  render::RenderSettings rs;
  rs.width = width;
  rs.height = height;
  rs.threads = 2;
  render::FrameImage img;
  render::FrameStats st;
  if (held) hwy::SetSupportedTargetsForTest(held);
  render::SceneRenderer(parsed, rs).render(0, img, st);
  if (held) hwy::SetSupportedTargetsForTest(0);
  return img.color;
}

// Dispatch held to `t` and the fallback (which Highway always keeps), as tests/hwy_targets.h does.
int64_t held_to(const raster::SimdTarget& t) { return t.hwy_bit | raster::runnable_simd_targets().back().hwy_bit; }

float max_difference(const io::ImageRGBA& a, const io::ImageRGBA& b) {
  float most = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) most = std::max(most, std::abs(a.rgba[i] - b.rgba[i]));
  return most;
}

// Every kernel takes the pin, not some: `pelt render --simd T` gives the floats of this
// process's render with dispatch held to T alone (the tests' own mechanism,
// tests/hwy_targets.h). Then targets of one arithmetic draw the same bytes, the others differ
// by a few float steps.
TEST(SimdOption, EveryKernelTakesThePinAndTargetsOfOneArithmeticDrawTheSameBytes) {
  const std::vector<raster::SimdTarget>& targets = raster::runnable_simd_targets();
  // The fallback is always compiled and runnable, so there is always a pair to compare.
  ASSERT_GE(targets.size(), 2u);
  std::vector<std::map<std::string, Render>> renders;
  for (const raster::SimdTarget& t : targets) {
    renders.push_back(render_all(t.name));
    for (const char* scene : kScenes) {
      const std::vector<float> here = draw_here(scene, 96, 72, held_to(t));
      const io::ImageRGBA& got = renders.back().at(scene).image;
      ASSERT_EQ(got.rgba.size(), here.size()) << scene << " " << t.name;
      size_t differ = 0;
      for (size_t i = 0; i < here.size(); ++i) differ += got.rgba[i] != here[i];
      EXPECT_EQ(differ, 0u) << scene << ": --simd " << t.name << " against every kernel on " << t.name;
    }
  }
  int close = 0;
  for (size_t i = 0; i < targets.size(); ++i)
    for (size_t j = i + 1; j < targets.size(); ++j)
      for (const char* scene : kScenes) {
        const Render& a = renders[i].at(scene);
        const Render& b = renders[j].at(scene);
        ASSERT_FALSE(a.image.empty());
        ASSERT_EQ(a.image.rgba.size(), b.image.rgba.size());
        const std::string pair = std::string(scene) + ": " + targets[i].name + " against " + targets[j].name;
        if (targets[i].fused_multiply_add == targets[j].fused_multiply_add) {
          EXPECT_TRUE(a.bytes == b.bytes) << pair << " differ by " << max_difference(a.image, b.image);
        } else {
          // Different bytes prove the pin reached dispatch (one MulAdd rounds once, the other
          // twice); the skin's largest difference on the shipped scenes is 2.7e-6.
          EXPECT_FALSE(a.bytes == b.bytes) << pair << ": the pin did not reach the kernels";
          EXPECT_LE(max_difference(a.image, b.image), 1e-5f) << pair;
          ++close;
        }
      }
  // The portable fallback never fuses: on a CPU with AVX2 there is a pair of each arithmetic.
  if (targets.front().fused_multiply_add) {
    EXPECT_GT(close, 0);
  }
}

// Coverage, depth and the fragment count are integer or exactly specified arithmetic (fixed-point
// edges, depth in float without fusing): every target draws the same bytes, FMA or not.
TEST(SimdOption, EveryTargetCoversAndDepthTestsTheSamePixels) {
  const TempDir dir;
  std::map<std::string, std::string> first;
  for (const raster::SimdTarget& t : raster::runnable_simd_targets())
    for (const char* aov : {"overdraw", "depth", "id"}) {
      const fs::path path = dir.path() / (std::string(aov) + "_" + t.name + ".exr");
      const Result r = run_pelt({"render", (source_dir() / "tools/scenes/teapot2_fur.json").string(), "--frame", "3",
                                 "--width", "96", "--height", "72", "--simd", t.name, "--aov", aov, "-q", "-o",
                                 path.string()},
                                dir.path());
      ASSERT_EQ(r.code, 0) << r.err;
      const std::string bytes = read_text(path);
      if (!first.count(aov)) first[aov] = bytes;
      EXPECT_TRUE(bytes == first[aov]) << aov << " on " << t.name;
    }
}

// The pin holds after the target is reported (asking Highway for its targets reset dispatch to
// the best one in Highway 1.0.3 when pinned through DisableTargets): each target pinned in turn,
// the probe kernel runs on it.
TEST(SimdOption, APinHoldsAfterItIsReported) {
  for (const raster::SimdTarget& t : raster::runnable_simd_targets()) {
    ASSERT_EQ(raster::pin_simd_target(t.name), "");
    EXPECT_STREQ(raster::active_simd_target().name, t.name);
    EXPECT_EQ(raster::dispatched_simd_target(), t.name) << "pinned to " << t.name;
  }
  ASSERT_EQ(raster::pin_simd_target("auto"), "");
  EXPECT_EQ(raster::dispatched_simd_target(), raster::runnable_simd_targets().front().name);
}

// `bench fps --versus simd=T` draws its second frames inside a SimdTargetScope: every kernel on
// T while it lives, then back to what was set before (no pin, a pin, an outer scope).
TEST(SimdOption, AScopeHoldsItsTargetThenRestoresWhatWasSet) {
  const std::vector<raster::SimdTarget>& targets = raster::runnable_simd_targets();
  const std::string best = targets.front().name, portable = targets.back().name;
  {
    raster::SimdTargetScope scope(portable);
    EXPECT_EQ(raster::dispatched_simd_target(), portable);
    {
      raster::SimdTargetScope inner(best);
      EXPECT_EQ(raster::dispatched_simd_target(), best);
    }
    EXPECT_EQ(raster::dispatched_simd_target(), portable) << "the outer scope's target must come back";
  }
  EXPECT_EQ(raster::dispatched_simd_target(), best) << "no pin: dispatch gets its choice back";
  ASSERT_EQ(raster::pin_simd_target(portable), "");
  {
    raster::SimdTargetScope scope(best);
    EXPECT_EQ(raster::dispatched_simd_target(), best);
  }
  EXPECT_EQ(raster::dispatched_simd_target(), portable) << "the pin must come back";
  ASSERT_EQ(raster::pin_simd_target("auto"), "");
  EXPECT_EQ(raster::dispatched_simd_target(), best);
}

// info and the set-up line name the target kernels run on after the pin (the probe, not
// Highway's report), --stats and bench fps's JSON record it.
TEST(SimdOption, ThePinIsReported) {
  TempDir dir;
  const std::string portable = raster::runnable_simd_targets().back().name;
  const std::string scene = (source_dir() / "tools/scenes/box_fur.json").string();
  const Result info = run_pelt({"info", scene, "--simd", portable}, dir.path());
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("simd       " + portable + " (this CPU runs "), std::string::npos) << info.out;
  const Result best = run_pelt({"info", scene}, dir.path());
  EXPECT_NE(best.out.find(std::string("simd       ") + raster::runnable_simd_targets().front().name + " "),
            std::string::npos)
      << best.out;

  const fs::path stats = dir.path() / "stats.json";
  const Result r = run_pelt({"render", scene, "--frame", "0", "--width", "32", "--height", "24", "--simd", portable,
                             "-o", (dir.path() / "f.png").string(), "--stats", stats.string()},
                            dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(read_text(stats)).at("simd"), portable);
  EXPECT_NE(r.err.find("before the frames); SIMD " + portable + "\n"), std::string::npos) << r.err;

  const fs::path json = dir.path() / "fps.json";
  const Result b = run_pelt({"bench", "fps", "--scenes", "box", "--threads", "1", "--frames", "1", "--warmup", "0",
                             "--width", "64", "--height", "48", "--simd", portable, "--json", json.string()},
                            dir.path());
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_NE(b.out.find("SIMD " + portable), std::string::npos) << b.out;
  EXPECT_EQ(nlohmann::json::parse(read_text(json)).at(0).at("simd"), portable);
}

TEST(SimdOption, AnUnknownTargetIsRefusedNamingTheChoices) {
  TempDir dir;
  const Result r = run_pelt({"render", (source_dir() / "tools/scenes/box_fur.json").string(), "--frame", "0", "--simd",
                             "neon", "-o", (dir.path() / "f.png").string()},
                            dir.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("pelt: error: --simd: `neon` is not a SIMD target of this build (auto|"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "f.png"));
}

TEST(SimdOption, ATargetTheCpuCannotRunIsRefusedNamingWhatItRuns) {
  // A CPU that runs only the portable fallback, as a list: the build's best target is refused
  // naming what the CPU runs.
  const std::vector<raster::SimdTarget>& compiled = raster::compiled_simd_targets();
  ASSERT_GE(compiled.size(), 2u);
  const std::vector<raster::SimdTarget> old_cpu = {compiled.back()};
  const std::string best = compiled.front().name, portable = compiled.back().name;
  EXPECT_EQ(raster::simd_pin_refusal(best, old_cpu), "this CPU cannot run `" + best + "` (it runs " + portable + ")");
  EXPECT_EQ(raster::simd_pin_refusal(portable, old_cpu), "");
  EXPECT_EQ(raster::simd_pin_refusal("auto", old_cpu), "");
  EXPECT_NE(raster::simd_pin_refusal("AVX2", old_cpu).find("is not a SIMD target of this build"), std::string::npos);
}

}  // namespace
}  // namespace pelt::cli_test
