// `pelt bench fps` on a tiny image: the JSON names the knobs each run used, and a bad knob
// is an error naming its flag (exit 2, no JSON file). Its timings are not checked: speed is
// measured by running the benchmark, never in a test.
#include <gtest/gtest.h>

#include <tuple>

#include <nlohmann/json.hpp>

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

TEST(BenchFps, JsonRecordsTheKnobsOfTheRun) {
  const nlohmann::json own = run_json({"--filter", "bilinear_mip"});
  ASSERT_EQ(own.size(), 1u);
  EXPECT_EQ(own[0]["scene"], "box");
  EXPECT_EQ(own[0]["sort"], "tile");
  EXPECT_EQ(own[0]["filter"], "bilinear_mip");
  EXPECT_EQ(own[0]["frames"], 2);
  EXPECT_EQ(own[0]["vertices"]["sum"], 5032);
  EXPECT_EQ(own[0]["faces"]["sum"], 36456);
  EXPECT_GT(own[0]["fps_median"].get<double>(), 0.0);

  // The harness's scene keeps its own order and filter unless a flag says otherwise.
  const nlohmann::json match = run_json({"--match-llvmpipe"});
  ASSERT_EQ(match.size(), 1u);
  EXPECT_EQ(match[0]["sort"], "none");
  EXPECT_EQ(match[0]["filter"], "trilinear");
  const nlohmann::json sorted = run_json({"--match-llvmpipe", "--sort", "exact", "--filter", "nearest"});
  ASSERT_EQ(sorted.size(), 1u);
  EXPECT_EQ(sorted[0]["sort"], "exact");
  EXPECT_EQ(sorted[0]["filter"], "nearest");
}

TEST(BenchFps, AnUnknownKnobValueNamesItsFlag) {
  for (const auto& [flag, value, message] :
       {std::tuple{"--filter", "anisotropic", "--filter: unknown value `anisotropic` (nearest, bilinear, bilinear_mip, trilinear)"},
        std::tuple{"--sort", "depth", "--sort: unknown value `depth`"}}) {
    TempDir dir;
    const std::filesystem::path json = dir.path() / "fps.json";
    std::vector<std::string> args = tiny_run(json);
    args.insert(args.end(), {flag, value});
    const Result r = run_pelt(args, dir.path());
    EXPECT_EQ(r.code, 2) << flag;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(json)) << flag;
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
