// tools/bench/against_llvmpipe.sh, with a stand-in for the llvmpipe harness (a script that
// records how it was called and prints a RESULT line as the harness does): each round runs
// both, the ratio is pelt's median FPS over the harness's, the harness gets the image size,
// the scene, pelt's teapot patches and llvmpipe's environment, and what the script cannot run is
// an error (exit 2).
// No timing is checked: the figures come from running the script.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "raster/simd_targets.h"
#include "tests/tools/cli/run_pelt.h"

namespace pelt::cli_test {
namespace {

std::filesystem::path script() { return source_dir() / "tools" / "bench" / "against_llvmpipe.sh"; }

// A harness folder whose build/fur_bench runs `body` (a shell script) after logging its arguments
// and llvmpipe's variables to calls.txt beside it.
std::filesystem::path fake_harness(const TempDir& dir, const std::string& body) {
  const std::filesystem::path bench =
      dir.write("harness/build/fur_bench",
                "#!/bin/sh\n"
                "echo \"$* LP_NUM_THREADS=$LP_NUM_THREADS GALLIUM_DRIVER=$GALLIUM_DRIVER "
                "LIBGL_ALWAYS_SOFTWARE=$LIBGL_ALWAYS_SOFTWARE\" >> \"$(dirname \"$0\")/calls.txt\"\n" +
                    body);
  std::filesystem::permissions(bench, std::filesystem::perms::owner_all);
  return dir.path() / "harness";
}

constexpr const char* kTenFps =
    "echo 'RESULT scene=box width=64 height=48 threads=1 readback=0 discard=0 cull=1 frames=3,3,3 "
    "fps=9.00,10.00,11.00 median_fps=10.00'\n";

Result run_script(const std::vector<std::string>& args, const TempDir& dir) {
  std::vector<std::string> all{script().string()};
  all.insert(all.end(), args.begin(), args.end());
  return run_program("/bin/bash", all, dir.path());
}

std::vector<std::string> small_run(const std::filesystem::path& harness) {
  return {harness.string(), "--scenes", "box", "--rounds", "2",    "--frames", "2",
          "--width",        "64",       "--height", "48",  "--threads", "1", "--pelt", pelt_binary().string()};
}

TEST(AgainstLlvmpipe, PrintsEachRoundAndTheMedianRatio) {
  TempDir dir;
  const std::filesystem::path harness = fake_harness(dir, kTenFps);
  const Result r = run_script(small_run(harness), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::regex round(R"(box round (\d): pelt ([0-9.]+) FPS \((\w+)\), llvmpipe 10\.00 FPS: ([0-9.]+)x)");
  int rounds = 0;
  for (auto it = std::sregex_iterator(r.out.begin(), r.out.end(), round); it != std::sregex_iterator(); ++it) {
    ++rounds;
    EXPECT_EQ(std::stoi((*it)[1]), rounds);
    const double pelt_fps = std::stod((*it)[2]), ratio = std::stod((*it)[4]);
    EXPECT_EQ((*it)[3], raster::runnable_simd_targets().front().name);  // pelt's best, without --simd
    EXPECT_GT(pelt_fps, 0.0);
    // The ratio is of the unrounded FPS, printed to 0.01; pelt's FPS is printed to 0.1.
    EXPECT_NEAR(ratio, pelt_fps / 10.0, 0.011) << r.out;
  }
  EXPECT_EQ(rounds, 2) << r.out;
  EXPECT_NE(r.out.find("box: median "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("over 2 rounds"), std::string::npos) << r.out;

  // The harness drew the same scene at the same size, on llvmpipe, with pelt's thread count.
  const std::string calls = read_text(harness / "build" / "calls.txt");
  size_t lines = 0;
  for (char c : calls) lines += c == '\n';
  EXPECT_EQ(lines, 2u) << calls;
  const std::string bpt = "--bpt " + (source_dir() / "tools" / "data" / "teapot.bpt").string();
  for (const std::string& part : {std::string("bench --scene box --width 64 --height 48"), std::string("--frames 2"),
                                  bpt, std::string("LP_NUM_THREADS=1"), std::string("GALLIUM_DRIVER=llvmpipe"),
                                  std::string("LIBGL_ALWAYS_SOFTWARE=1")})
    EXPECT_NE(calls.find(part), std::string::npos) << part << " in " << calls;
}

// --simd reaches pelt: each round names the target pelt ran on (llvmpipe draws 256-bit vectors on
// any CPU, so `--simd avx2` compares the two at one width).
TEST(AgainstLlvmpipe, PeltRunsOnTheTargetAskedFor) {
  TempDir dir;
  std::vector<std::string> args = small_run(fake_harness(dir, kTenFps));
  const std::string portable = raster::runnable_simd_targets().back().name;
  args.insert(args.end(), {"--simd", portable});
  const Result r = run_script(args, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("box round 1: pelt "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" FPS (" + portable + "), llvmpipe 10.00 FPS"), std::string::npos) << r.out;
  TempDir bad_dir;
  std::vector<std::string> bad = small_run(fake_harness(bad_dir, kTenFps));
  bad.insert(bad.end(), {"--simd", "neon"});
  const Result refused = run_script(bad, bad_dir);
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.err.find("`neon` is not a SIMD target of this build"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("pelt bench fps failed on box"), std::string::npos) << refused.err;
}

TEST(AgainstLlvmpipe, RefusesWhatItCannotRun) {
  TempDir dir;
  const std::filesystem::path good = fake_harness(dir, kTenFps);
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  std::vector<Case> cases = {
      {{(dir.path() / "nowhere").string()}, "no such folder (the llvmpipe harness)"},
      {{good.string(), "--rounds", "0"}, "--rounds: `0` is not a positive integer"},
      {{good.string(), "--threads", "two"}, "--threads: `two` is not a positive integer"},
      {{good.string(), "--scenes", "box,sphere"}, "--scenes: unknown scene `sphere`"},
      {{good.string(), "--scenes", ""}, "--scenes: no scene given"},
      {{good.string(), "--colour", "red"}, "unknown option `--colour`"},
      {{good.string(), "--frames"}, "--frames: needs a value"},
      {{good.string(), "--pelt", (dir.path() / "no-pelt").string()}, "no pelt binary"},
      {{good.string(), "--simd", ""}, "--simd: needs a target"},
  };
  for (const Case& c : cases) {
    const Result r = run_script(c.args, dir);
    EXPECT_EQ(r.code, 2) << c.message;
    EXPECT_NE(r.err.find("against_llvmpipe: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
  }
  // A harness that fails, prints no result or no speed stops the run with its output shown.
  TempDir failing_dir, silent_dir;
  const Result failing =
      run_script(small_run(fake_harness(failing_dir, "echo 'EGL: no llvmpipe here' >&2; exit 1\n")), failing_dir);
  EXPECT_EQ(failing.code, 2);
  EXPECT_NE(failing.err.find("EGL: no llvmpipe here"), std::string::npos) << failing.err;
  EXPECT_NE(failing.err.find("failed on box"), std::string::npos) << failing.err;
  const Result silent = run_script(small_run(fake_harness(silent_dir, "echo 'GL_RENDERER: llvmpipe'\n")), silent_dir);
  EXPECT_EQ(silent.code, 2);
  EXPECT_NE(silent.err.find("printed no RESULT line with median_fps"), std::string::npos) << silent.err;
  TempDir stalled_dir;  // no division by zero: a harness at 0 FPS is a failed run
  const Result stalled =
      run_script(small_run(fake_harness(stalled_dir, "echo 'RESULT scene=box fps=0,0,0 median_fps=0.00'\n")), stalled_dir);
  EXPECT_EQ(stalled.code, 2);
  EXPECT_NE(stalled.err.find("reported 0.00 FPS on box"), std::string::npos) << stalled.err;
}

}  // namespace
}  // namespace pelt::cli_test
