// Replays every fuzz regression input (tests/fuzz/regressions/<target>/) and the seed corpus
// through the fuzzers' own entry points in the normal build: a fixed crash stays fixed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_entries.h"

namespace pelt::fuzz {
namespace {

namespace fs = std::filesystem;
using Entry = Outcome (*)(const uint8_t*, size_t);

fs::path repo() {
  const char* dir = std::getenv("PELT_SOURCE_DIR");
  return dir ? fs::path(dir) : fs::path(PELT_REPO_DIR);
}

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> out;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file() && e.path().filename() != ".gitkeep") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<uint8_t> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs `entry` on each file; nothing but a clean accept or reject may come out.
void replay(Entry entry, const std::vector<fs::path>& files, bool must_accept) {
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    const std::vector<uint8_t> bytes = read_bytes(f);
    Outcome outcome = Outcome::rejected;
    try {
      outcome = entry(bytes.data(), bytes.size());
    } catch (const std::exception& e) {
      ADD_FAILURE() << "escaped the entry point: " << e.what();
      continue;
    }
    if (must_accept) {
      EXPECT_EQ(outcome, Outcome::accepted) << "a shipped seed was rejected";
    }
  }
}

struct Target {
  const char* name;
  Entry entry;
};
const Target kTargets[] = {{"obj", run_obj},       {"fur", run_fur},         {"gltf", run_gltf},
                           {"scene", run_scene},   {"raster", run_raster}, {"sampler", run_sampler}};

TEST(FuzzReplay, RegressionInputsEndCleanly) {
  size_t total = 0;
  for (const Target& t : kTargets) {
    const auto files = files_in(repo() / "tests/fuzz/regressions" / t.name);
    replay(t.entry, files, false);
    std::printf("fuzz regressions replayed for %s: %zu\n", t.name, files.size());
    total += files.size();
  }
  std::printf("fuzz regressions replayed in all: %zu\n", total);
}

// The seeds must be accepted: a harness that rejected everything would fuzz nothing.
TEST(FuzzReplay, SeedCorpusIsAccepted) {
  std::vector<fs::path> scenes;
  for (const auto& f : files_in(repo() / "tools/scenes"))
    if (f.extension() == ".json") scenes.push_back(f);
  ASSERT_FALSE(scenes.empty());
  replay(run_scene, scenes, true);

  auto obj = files_in(repo() / "tests/fuzz/seeds/obj");
  obj.push_back(repo() / "tools/data/bunny.obj");
  replay(run_obj, obj, true);
  replay(run_fur, obj, true);  // every seed mesh grows fur under each mapping it allows

  auto gltf = files_in(repo() / "tests/fuzz/seeds/gltf");
  gltf.push_back(repo() / "tools/data/BoxTextured.glb");
  replay(run_gltf, gltf, true);

  const auto raster = files_in(repo() / "tests/fuzz/seeds/raster");
  ASSERT_FALSE(raster.empty());
  replay(run_raster, raster, true);

  const auto sampler = files_in(repo() / "tests/fuzz/seeds/sampler");
  ASSERT_FALSE(sampler.empty());
  replay(run_sampler, sampler, true);
  std::printf("seeds accepted: %zu scenes, %zu obj, %zu gltf, %zu raster, %zu sampler\n", scenes.size(), obj.size(),
              gltf.size(), raster.size(), sampler.size());
}

// The rejection path itself: garbage is refused with InputError, not accepted or crashed on.
TEST(FuzzReplay, GarbageIsRejected) {
  const std::string junk = "\x01\x02 not a mesh {";
  const auto* p = reinterpret_cast<const uint8_t*>(junk.data());
  EXPECT_EQ(run_obj(p, junk.size()), Outcome::rejected);
  EXPECT_EQ(run_fur(p, junk.size()), Outcome::rejected);
  EXPECT_EQ(run_gltf(p, junk.size()), Outcome::rejected);
  EXPECT_EQ(run_scene(p, junk.size()), Outcome::rejected);
}

}  // namespace
}  // namespace pelt::fuzz
