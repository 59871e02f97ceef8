// `pelt bench skin`'s outputs, checked before any work. Its timings are not checked: speed is
// measured by running the benchmark, never in a test.
#include <gtest/gtest.h>

#include <filesystem>

#include "tests/tools/cli/run_pelt.h"

namespace pelt::cli_test {
namespace {

// --json naming the head scan (here as ./head.glb against head.glb) would replace the input
// the benchmark measures with its results: refused, and the scan is left as it was.
TEST(BenchSkin, AJsonPathThatIsTheHeadScanIsRefused) {
  TempDir dir;
  const std::filesystem::path head = dir.path() / "head.glb";
  std::filesystem::copy_file(source_dir() / "tools" / "data" / "LeePerrySmith" / "LeePerrySmith.glb", head);
  const std::string before = read_text(head);
  const Result r = run_pelt({"bench", "skin", "--head", head.string(), "--json", (dir.path() / "." / "head.glb").string(),
                             "--width", "16", "--height", "16", "--frames", "1", "--warmup", "0"},
                            dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--json: is an input of this benchmark (" + head.string() + ")"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(head), before);
}

}  // namespace
}  // namespace pelt::cli_test
