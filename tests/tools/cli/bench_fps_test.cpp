// `pelt bench fps` on a tiny image: the JSON names the knobs each run used, --fins and
// --shells change the counts beside the paper's, --versus reports a second setting beside the
// run, and a bad knob is an error naming its flag (exit 2, no JSON file). Its timings are not checked: speed is
// measured by running the benchmark, never in a test.
#include <gtest/gtest.h>

#include <tuple>
#include <utility>

#include <nlohmann/json.hpp>

#include "raster/simd_targets.h"
#include "tests/tools/cli/run_pelt.h"

namespace pelt::cli_test {
namespace {

std::vector<std::string> tiny_run(const std::filesystem::path& json) {
  return {"bench", "fps", "--scenes", "box", "--width", "64", "--height", "48", "--threads", "1",
          "--frames", "2", "--warmup", "0", "--json", json.string()};
}

nlohmann::json run_json(const std::vector<std::string>& extra) {
  TempDir dir;
  const std::filesystem::path json = dir.path() / "results" / "fps.json";  // a folder made for it
  std::vector<std::string> args = tiny_run(json);
  args.insert(args.end(), extra.begin(), extra.end());
  const Result r = run_pelt(args, dir.path());
  EXPECT_EQ(r.code, 0) << r.err;
  if (r.code != 0) return nlohmann::json::array();
  return nlohmann::json::parse(read_text(json));
}

// A run with `extra` flags is refused: exit 2, `message` on stderr, no JSON file, no table.
void expect_refused(const std::vector<std::string>& extra, const std::string& message) {
  TempDir dir;
  const std::filesystem::path json = dir.path() / "fps.json";
  std::vector<std::string> args = tiny_run(json);
  args.insert(args.end(), extra.begin(), extra.end());
  const Result r = run_pelt(args, dir.path());
  EXPECT_EQ(r.code, 2) << message;
  EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(json)) << message;
  EXPECT_EQ(r.out.find("FPS"), std::string::npos) << r.out;
}

TEST(BenchFps, JsonRecordsTheKnobsOfTheRun) {
  const nlohmann::json own = run_json({"--filter", "bilinear_mip"});
  ASSERT_EQ(own.size(), 1u);
  EXPECT_EQ(own[0]["scene"], "box");
  EXPECT_EQ(own[0]["sort"], "tile");
  EXPECT_EQ(own[0]["filter"], "bilinear_mip");
  EXPECT_EQ(own[0]["fins"], "silhouette");
  EXPECT_EQ(own[0]["shells"], 16);
  EXPECT_EQ(own[0]["fin_quads"], "merged");
  EXPECT_EQ(own[0]["frames"], 2);
  EXPECT_EQ(own[0]["vertices"]["sum"], 5032);
  EXPECT_EQ(own[0]["faces"]["sum"], 36456);
  EXPECT_GT(own[0]["fps_median"].get<double>(), 0.0);
  // The work a frame's time buys: fur fragments blended in shaded lanes, over the opaque box.
  EXPECT_GT(own[0]["fragments_blended_mean"].get<double>(), 0.0);
  EXPECT_GE(own[0]["lanes_shaded_mean"].get<double>(),
            own[0]["fragments_blended_mean"].get<double>() + own[0]["pixels_shaded_mean"].get<double>());
  EXPECT_GT(own[0]["pixels_shaded_mean"].get<double>(), 0.0);
  EXPECT_GT(own[0]["ns_per_fragment"].get<double>(), 0.0);
  EXPECT_EQ(own[0]["framebuffer"], "rgba8");  // the GPU's and the harness's, unless asked
  const nlohmann::json floats = run_json({"--framebuffer", "float"});
  ASSERT_EQ(floats.size(), 1u);
  EXPECT_EQ(floats[0]["framebuffer"], "float");

  // The harness's scene keeps its own order and filter unless a flag says otherwise.
  const nlohmann::json match = run_json({"--match-llvmpipe"});
  ASSERT_EQ(match.size(), 1u);
  EXPECT_EQ(match[0]["sort"], "none");
  EXPECT_EQ(match[0]["filter"], "trilinear");
  EXPECT_EQ(match[0]["fins"], "all");
  EXPECT_EQ(match[0]["fin_quads"], "layer");
  const nlohmann::json sorted = run_json({"--match-llvmpipe", "--sort", "exact", "--filter", "nearest"});
  ASSERT_EQ(sorted.size(), 1u);
  EXPECT_EQ(sorted[0]["sort"], "exact");
  EXPECT_EQ(sorted[0]["filter"], "nearest");
}

// --shells changes the geometry, and the counts beside the paper's say so: 8 shells of the
// box's 588 faces and 296 vertices, fins between 7 pairs of layers on its 882 edges. --fins off
// builds no fin faces, so the counts have none; the other modes build every edge's fin (the
// paper's count) and draw what they choose of them.
TEST(BenchFps, FinsAndShellsFlagsChangeTheDrawnFur) {
  const nlohmann::json eight = run_json({"--shells", "8"});
  ASSERT_EQ(eight.size(), 1u);
  EXPECT_EQ(eight[0]["shells"], 8);
  EXPECT_EQ(eight[0]["vertices"]["base"], 296);
  EXPECT_EQ(eight[0]["vertices"]["shell"], 8 * 296);
  EXPECT_EQ(eight[0]["faces"]["shell"], 8 * 588);
  EXPECT_EQ(eight[0]["faces"]["fin"], 882 * 7 * 2);
  EXPECT_EQ(eight[0]["faces"]["sum"], 588 + 8 * 588 + 882 * 7 * 2);
  const nlohmann::json run = run_json({"--fins", "off", "--shells", "8"});
  ASSERT_EQ(run.size(), 1u);
  EXPECT_EQ(run[0]["fins"], "off");
  EXPECT_EQ(run[0]["vertices"]["shell"], 8 * 296);
  EXPECT_EQ(run[0]["vertices"]["fin"], 0);
  EXPECT_EQ(run[0]["faces"]["shell"], 8 * 588);
  EXPECT_EQ(run[0]["faces"]["fin"], 0);
  EXPECT_EQ(run[0]["faces"]["sum"], 588 + 8 * 588);
  const nlohmann::json all = run_json({"--fins", "all"});
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0]["fins"], "all");
  EXPECT_EQ(all[0]["faces"]["fin"], 26460);
}

TEST(BenchFps, MergedFinsAreRefusedInTheHarnessMode) {
  expect_refused({"--match-llvmpipe", "--fin-quads", "merged"},
                 "--fin-quads: merged fins are not drawn with --match-llvmpipe");
}

TEST(BenchFps, AnUnknownKnobValueNamesItsFlag) {
  for (const auto& [flag, value, message] :
       {std::tuple{"--filter", "anisotropic", "--filter: unknown value `anisotropic` (nearest, bilinear, bilinear_mip, trilinear)"},
        std::tuple{"--sort", "depth", "--sort: unknown value `depth`"},
        std::tuple{"--fins", "sideways", "--fins: unknown value `sideways`"},
        std::tuple{"--shells", "1", "--shells:"},
        std::tuple{"--fin-quads", "fused", "--fin-quads: unknown value `fused` (layer, merged)"},
        std::tuple{"--framebuffer", "rgb", "--framebuffer: rgb not in {rgba8,float}"}})
    expect_refused({flag, value}, message);
}

// --versus draws every frame a second time with the knobs it names and reports the per-frame ratio
// of the two times; the run's own figures are those of a run without it (the other renderer's
// work is not counted in), and JSON without --versus says null.
TEST(BenchFps, VersusDrawsEachFrameBothWays) {
  const nlohmann::json plain = run_json({});
  ASSERT_EQ(plain.size(), 1u);
  EXPECT_TRUE(plain[0]["versus"].is_null());
  const nlohmann::json both = run_json({"--versus", "filter=bilinear_mip,fins=off"});
  ASSERT_EQ(both.size(), 1u);
  EXPECT_EQ(both[0]["filter"], "trilinear");  // the run keeps its own setting
  EXPECT_EQ(both[0]["fins"], "silhouette");
  EXPECT_EQ(both[0]["fragments_blended_mean"], plain[0]["fragments_blended_mean"]);
  EXPECT_EQ(both[0]["lanes_shaded_mean"], plain[0]["lanes_shaded_mean"]);
  const nlohmann::json& v = both[0]["versus"];
  ASSERT_TRUE(v.is_object()) << both.dump();
  EXPECT_EQ(v["knobs"], (nlohmann::json{{"filter", "bilinear_mip"}, {"fins", "off"}}));
  EXPECT_GT(v["fps_median"].get<double>(), 0.0);
  EXPECT_GT(v["time_ratio_median"].get<double>(), 0.0);
  EXPECT_LE(v["time_ratio_q25"].get<double>(), v["time_ratio_median"].get<double>());
  EXPECT_LE(v["time_ratio_median"].get<double>(), v["time_ratio_q75"].get<double>());

  TempDir dir;
  std::vector<std::string> args = tiny_run(dir.path() / "fps.json");
  args.insert(args.end(), {"--versus", "shells=8"});
  const Result r = run_pelt(args, dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Versus   1 thread : shells=8 takes "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("over 2 frames drawn both ways"), std::string::npos) << r.out;
}

// `simd=T` draws the second frame with every kernel on target T (raster::SimdTargetScope, whose
// switch tests/tools/cli/simd_option_test.cpp checks): the price of the vector width, paired.
TEST(BenchFps, VersusAnotherSimdTarget) {
  const std::string best = raster::runnable_simd_targets().front().name;
  const std::string portable = raster::runnable_simd_targets().back().name;
  const nlohmann::json both = run_json({"--versus", "simd=" + portable + ",fins=off"});
  ASSERT_EQ(both.size(), 1u);
  EXPECT_EQ(both[0]["simd"], best);  // the run keeps the best target
  const nlohmann::json& v = both[0]["versus"];
  ASSERT_TRUE(v.is_object()) << both.dump();
  EXPECT_EQ(v["knobs"], (nlohmann::json{{"fins", "off"}, {"simd", portable}}));
  EXPECT_GT(v["time_ratio_median"].get<double>(), 0.0);
  const nlohmann::json pinned = run_json({"--simd", portable, "--versus", "simd=" + best});
  ASSERT_EQ(pinned.size(), 1u);
  EXPECT_EQ(pinned[0]["simd"], portable);
  EXPECT_EQ(pinned[0]["versus"]["knobs"], (nlohmann::json{{"simd", best}}));

  expect_refused({"--simd", portable, "--versus", "simd=" + portable},
                 "--versus: `simd=" + portable + "` is the run's own setting");
  expect_refused({"--versus", "simd=auto"}, "--versus: simd=auto: name a target (");
  expect_refused({"--versus", "simd=neon"}, "--versus: simd=neon: `neon` is not a SIMD target of this build");
  expect_refused({"--versus", "simd=" + portable + ",simd=" + best}, "--versus: knob `simd` given twice");
}

TEST(BenchFps, AMalformedVersusNamesItsFlag) {
  for (const auto& [spec, message] :
       {std::pair{"filter", "--versus: `filter` is not knob=value"},
        std::pair{"=nearest", "--versus: `=nearest` is not knob=value"},
        std::pair{"filter=", "--versus: `filter=` is not knob=value"},
        std::pair{"filter=anisotropic", "--versus: unknown value `anisotropic`"},
        std::pair{"colour=red", "--versus: unknown quality knob `colour`"},
        std::pair{"fins=off,fins=all", "--versus: knob `fins` given twice"},
        std::pair{"filter=trilinear", "--versus: `filter=trilinear` is the run's own setting"},
        std::pair{"", "--versus: needs a value, got an empty one"}})
    expect_refused({"--versus", spec}, message);
  expect_refused({"--match-llvmpipe", "--versus", "fin_quads=merged"},
                 "--versus: merged fins are not drawn with --match-llvmpipe");
}

// A scene or thread count listed twice would be measured twice, its table printed twice and its
// rows doubled in --json: refused, as --versus refuses a knob given twice. tiny_run already
// passes `--scenes box --threads 1`, and a list option given again adds to it: box, teapot, box.
TEST(BenchFps, AListedTwiceSceneOrThreadCountIsRefused) {
  expect_refused({"--scenes", "teapot,box"}, "--scenes: scene `box` is listed twice");
  expect_refused({"--threads", "2,1"}, "--threads: thread count 1 is listed twice");
}

// An empty item in a list (a script's variable that came out empty) is refused, as an empty
// value is; CLI11 would drop it and measure the rest with no word said.
TEST(BenchFps, AnEmptyListItemIsRefused) {
  expect_refused({"--scenes", "teapot,,teapot2"}, "--scenes: `teapot,,teapot2` has an empty item");
  expect_refused({"--threads=2,"}, "--threads: `2,` has an empty item");
  expect_refused({"--versus", "filter=bilinear_mip,"}, "--versus: `filter=bilinear_mip,` has an empty item");
}

// The fur scenes have no skin: a skin knob draws the same frame, and its "ratio" measured nothing.
TEST(BenchFps, VersusASkinKnobAloneIsRefused) {
  expect_refused({"--versus", "multiple_scattering=reference"},
                 "--versus: `multiple_scattering=reference` changes only skin knobs");
  expect_refused({"--versus", "single_scattering=off,multiple_scattering=paper"}, "changes only skin knobs");
}

// The benchmarks run at the default budgets and take no budget flags: a size past the pixel budget
// is refused naming --width, not a field of the built-in scene and a --max-pixels the command
// lacks; and before the header is printed.
TEST(BenchFps, AnImageOverThePixelBudgetNamesTheSizeFlag) {
  TempDir dir;
  for (const std::string bench : {"fps", "skin"}) {
    const Result r = run_pelt({"bench", bench, "--width", "16384", "--height", "4097", "--json",
                               (dir.path() / "b.json").string()},
                              dir.path());
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("--width: the image is 16384 x 4097 = 67125248 pixels, more than the default budget of "
                         "67108864 pixels"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("image.width"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << bench;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "b.json"));
  }
}

// A --json path that cannot be written is refused before the first frame, not after the
// whole benchmark: no table row is printed.
TEST(BenchFps, AnUnwritableJsonPathFailsBeforeTheRun) {
  TempDir dir;
  const std::filesystem::path taken = dir.write("taken", "a file, not a folder");
  const std::filesystem::path json = taken / "fps.json";
  const Result r = run_pelt(tiny_run(json), dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(json.string() + ": --json: cannot create folder " + taken.string()), std::string::npos)
      << r.err;
  EXPECT_EQ(r.out.find("FPS"), std::string::npos) << r.out;
  EXPECT_EQ(read_text(taken), "a file, not a folder");
}

}  // namespace
}  // namespace pelt::cli_test
