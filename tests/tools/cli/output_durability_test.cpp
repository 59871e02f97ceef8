// An output is flushed to the disk before it is renamed into place, and its folder's entry
// after (io::AtomicOutput::commit): a machine that loses power right after a frame is reported
// done finds it whole. Seen from outside: `pelt` run with a preloaded library that logs its
// fsync and rename calls (sync_log_preload.cpp).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "tests/tools/cli/run_pelt.h"

namespace pelt::cli_test {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(OutputDurability, EachOutputIsSyncedBeforeItsRenameAndItsFolderAfter) {
  TempDir dir;
  const fs::path folder = fs::canonical(dir.path());
  const fs::path scene = dir.write("s.json", R"({"pelt": 1, "image": {"width": 32, "height": 24},
      "objects": [{"mesh": "box:2", "material": {"type": "lambert"}}]})");
  const fs::path log = folder / "sync.log";
  // ASan (the test build) wants its runtime first among the libraries; the preload comes first.
  const char* asan = std::getenv("ASAN_OPTIONS");
  const std::string asan_options =
      "ASAN_OPTIONS=" + std::string(asan ? std::string(asan) + ":" : "") + "verify_asan_link_order=0";
  const Result r = run_program("/usr/bin/env",
                               {"LD_PRELOAD=" PELT_SYNC_LOG_LIBRARY, "PELT_SYNC_LOG=" + log.string(), asan_options,
                                pelt_binary().string(), "render", scene.string(), "-o", (folder / "out.png").string(),
                                "--stats", (folder / "stats.json").string()},
                               dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<std::string> log_lines = lines_of(read_text(log));
  for (const char* name : {"out.png", "stats.json"}) {
    const std::string target = (folder / name).string();
    size_t renamed = log_lines.size();
    std::string from;
    for (size_t i = 0; i < log_lines.size(); ++i) {
      const std::string& l = log_lines[i];
      if (l.rfind("rename ", 0) == 0 && l.size() > target.size() && l.compare(l.size() - target.size(), target.size(), target) == 0) {
        renamed = i;
        from = l.substr(7, l.size() - 7 - target.size() - 1);
      }
    }
    ASSERT_LT(renamed, log_lines.size()) << name << " was not renamed into place:\n" << read_text(log);
    bool synced_before = false, folder_after = false;
    for (size_t i = 0; i < renamed; ++i) synced_before |= log_lines[i] == "fsync " + from;
    for (size_t i = renamed + 1; i < log_lines.size(); ++i) folder_after |= log_lines[i] == "fsync " + folder.string();
    EXPECT_TRUE(synced_before) << name << ": " << from << " not flushed before its rename:\n" << read_text(log);
    EXPECT_TRUE(folder_after) << name << ": the folder not flushed after:\n" << read_text(log);
  }
}

}  // namespace
}  // namespace pelt::cli_test
