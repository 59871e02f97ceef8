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

int64_t held_to(const raster::SimdTarget& t) { return t.hwy_bit | HWY_SCALAR; }

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
  int same = 0, close = 0;
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
          ++same;
        } else {
          // Different bytes prove the pin reached dispatch (one MulAdd rounds once, the other
          // twice); the skin's largest difference on the shipped scenes is 2.7e-6.
          EXPECT_FALSE(a.bytes == b.bytes) << pair << ": the pin did not reach the kernels";
          EXPECT_LE(max_difference(a.image, b.image), 1e-5f) << pair;
          ++close;
        }
      }
  // sse4 and scalar are compiled for every x86-64 CPU: on one with AVX2, both kinds of pair.
  if (targets.front().fused_multiply_add) {
    EXPECT_GT(same, 0);
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

// The pin holds after the target is reported (active_simd_target asks Highway for its
// targets, which in Highway 1.0.3 could reset dispatch to the best one): pinned in this
// process, a frame matches the one drawn with dispatch held to that target.
TEST(SimdOption, APinHoldsAfterItIsReported) {
  const auto draw = [] { return draw_here("box_fur", 64, 48); };
  int pinned = 0;
  for (const raster::SimdTarget& t : raster::runnable_simd_targets()) {
    if (t.fused_multiply_add) continue;  // the best target's family: a lost pin would not show
    const std::vector<float> want = draw_here("box_fur", 64, 48, held_to(t));
    ASSERT_EQ(raster::pin_simd_target(t.name), "");
    EXPECT_STREQ(raster::active_simd_target().name, t.name);
    EXPECT_TRUE(draw() == want) << "pinned to " << t.name << ", the frame is another target's";
    ASSERT_EQ(raster::pin_simd_target("auto"), "");
    hwy::DisableTargets(0);  // a DisableTargets pin (which the test must catch) undone too
    ++pinned;
  }
  EXPECT_EQ(pinned, 2);  // sse4 and scalar, compiled for every x86-64 CPU
}

// `bench fps --versus simd=T` draws its second frames inside a SimdTargetScope: every kernel on
// T while it lives, then back to the pin.
TEST(SimdOption, AScopeHoldsItsTargetThenRestoresThePin) {
  const auto draw = [] { return draw_here("box_fur", 64, 48); };
  std::vector<float> sse4;
  for (const raster::SimdTarget& t : raster::runnable_simd_targets())
    if (std::string(t.name) == "sse4") sse4 = draw_here("box_fur", 64, 48, held_to(t));
  ASSERT_FALSE(sse4.empty());
  const std::vector<float> best = draw();
  // Every x86-64 CPU of the last decade has AVX2, whose fused MulAdd makes the frames differ.
  ASSERT_FALSE(sse4 == best) << "the frames of the two arithmetics must differ for this test to see a switch";
  {
    raster::SimdTargetScope scope("sse4");
    EXPECT_TRUE(draw() == sse4);
  }
  EXPECT_TRUE(draw() == best) << "no pin: the scope must give dispatch back its choice";
  ASSERT_EQ(raster::pin_simd_target("sse4"), "");
  {
    raster::SimdTargetScope scope(raster::runnable_simd_targets().front().name);
    EXPECT_TRUE(draw() == best);
  }
  EXPECT_TRUE(draw() == sse4) << "pinned to sse4: the scope must restore the pin";
  ASSERT_EQ(raster::pin_simd_target("auto"), "");
  EXPECT_TRUE(draw() == best) << "`auto` must undo the pin";
}

TEST(SimdOption, ThePinIsReported) {
  TempDir dir;
  const std::string scene = (source_dir() / "tools/scenes/box_fur.json").string();
  const Result info = run_pelt({"info", scene, "--simd", "scalar"}, dir.path());
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("simd       scalar (this CPU runs "), std::string::npos) << info.out;
  const Result best = run_pelt({"info", scene}, dir.path());
  EXPECT_NE(best.out.find(std::string("simd       ") + raster::runnable_simd_targets().front().name + " "),
            std::string::npos)
      << best.out;

  const fs::path stats = dir.path() / "stats.json";
  const Result r = run_pelt({"render", scene, "--frame", "0", "--width", "32", "--height", "24", "--simd", "sse4", "-q",
                             "-o", (dir.path() / "f.png").string(), "--stats", stats.string()},
                            dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(read_text(stats)).at("simd"), "sse4");

  const fs::path json = dir.path() / "fps.json";
  const Result b = run_pelt({"bench", "fps", "--scenes", "box", "--threads", "1", "--frames", "1", "--warmup", "0",
                             "--width", "64", "--height", "48", "--simd", "scalar", "--json", json.string()},
                            dir.path());
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_NE(b.out.find("SIMD scalar"), std::string::npos) << b.out;
  EXPECT_EQ(nlohmann::json::parse(read_text(json)).at(0).at("simd"), "scalar");
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
  // A CPU of SSE4 only, as a list: the build compiled avx2, so the refusal names the CPU.
  std::vector<raster::SimdTarget> sse4_cpu;
  for (const raster::SimdTarget& t : raster::compiled_simd_targets())
    if (std::string(t.name) == "sse4" || std::string(t.name) == "scalar") sse4_cpu.push_back(t);
  ASSERT_EQ(sse4_cpu.size(), 2u);
  EXPECT_EQ(raster::simd_pin_refusal("avx2", sse4_cpu), "this CPU cannot run `avx2` (it runs sse4, scalar)");
  EXPECT_EQ(raster::simd_pin_refusal("sse4", sse4_cpu), "");
  EXPECT_EQ(raster::simd_pin_refusal("auto", sse4_cpu), "");
  EXPECT_NE(raster::simd_pin_refusal("AVX2", sse4_cpu).find("is not a SIMD target of this build"), std::string::npos);
}

}  // namespace
}  // namespace pelt::cli_test
