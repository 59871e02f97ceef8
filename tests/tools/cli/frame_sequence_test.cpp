// Frame ranges, farm shards, output patterns, resume selection and progress text.
#include "tools/render/frame_sequence.h"

#include <algorithm>
#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "tests/tools/cli/run_pelt.h"
#include "tools/io/input_error.h"
#include "tools/render/progress.h"

namespace pelt::render {
namespace {

void expect_option_error(const std::function<void()>& f, const std::string& option, const std::string& reason) {
  try {
    f();
    FAIL() << "accepted";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.field, option);
    EXPECT_NE(e.reason.find(reason), std::string::npos) << e.reason;
  }
}

TEST(FrameRange, Parses) {
  const FrameRange r = parse_frame_range("3:7", 10, "--frames");
  EXPECT_EQ(r.first, 3);
  EXPECT_EQ(r.last, 7);
  EXPECT_EQ(r.count(), 5);
  const FrameRange one = parse_frame("9", 10, "--frame");
  EXPECT_EQ(one.first, 9);
  EXPECT_EQ(one.last, 9);
}

TEST(FrameRange, RejectsBadText) {
  expect_option_error([] { parse_frame_range("7:3", 10, "--frames"); }, "--frames", "first frame 7 is after last frame 3");
  expect_option_error([] { parse_frame_range("0:10", 10, "--frames"); }, "--frames", "frame 10 is out of range");
  for (const char* bad : {"", ":", "1:", ":4", "-1:3", "a:b", "1.5:3", "1:2:3", " 1:2", "0x3"})
    expect_option_error([&] { parse_frame_range(bad, 10, "--frames"); }, "--frames", "expected FIRST:LAST");
}

// --frame takes one number: its message offers no range it would refuse.
TEST(FrameRange, OneFrameRejectsRangesAndBadText) {
  expect_option_error([] { parse_frame("12", 10, "--frame"); }, "--frame", "0..9");
  expect_option_error([] { parse_frame("2:3", 10, "--frame"); }, "--frame", "takes one frame number, got `2:3`");
  for (const char* bad : {"", "-1", "a", "1.5", " 1", "0x3"})
    expect_option_error([&] { parse_frame(bad, 10, "--frame"); }, "--frame",
                        std::string("expected a frame number (a whole number >= 0), got `") + bad + "`");
}

// A frame number past long long's range is a whole number >= 0: it is told it is out of range,
// as a smaller one past the scene is, not that it is malformed.
TEST(FrameRange, AHugeFrameNumberIsOutOfRangeNotMalformed) {
  const std::string huge = "99999999999999999999";
  expect_option_error([&] { parse_frame(huge, 10, "--frame"); }, "--frame",
                      "frame " + huge + " is out of range: the scene has 10 frame(s), 0..9");
  for (const std::string& text : {huge, "0:" + huge, huge + ":3"})
    expect_option_error([&] { parse_frame_range(text, 10, "--frames"); }, "--frames",
                        "frame " + huge + " is out of range: the scene has 10 frame(s), 0..9");
  // Malformed elsewhere, still malformed.
  expect_option_error([&] { parse_frame_range(huge + ":x", 10, "--frames"); }, "--frames", "expected FIRST:LAST");
}

TEST(Shard, Parses) {
  const Shard s = parse_shard("2/5");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 5);
  expect_option_error([] { parse_shard("5/5"); }, "--shard", "0-based");
  expect_option_error([] { parse_shard("0/0"); }, "--shard", "count must be in [1,");
  for (const char* bad : {"", "1", "1/", "/2", "-1/2", "a/b", "1/2/3"})
    expect_option_error([&] { parse_shard(bad); }, "--shard", "expected INDEX/COUNT");
}

TEST(Shard, ShardsPartitionTheRange) {
  for (int first : {0, 3})
    for (int length : {1, 2, 7, 48})
      for (int n : {1, 2, 3, 5, 60}) {
        const FrameRange r{first, first + length - 1};
        std::multiset<int> all;
        for (int i = 0; i < n; ++i) {
          const std::vector<int> f = shard_frames(r, {i, n});
          EXPECT_TRUE(std::is_sorted(f.begin(), f.end()));
          for (size_t k = 0; k < f.size(); ++k) EXPECT_EQ(f[k], first + i + int(k) * n);
          all.insert(f.begin(), f.end());
        }
        std::multiset<int> want;
        for (int k = r.first; k <= r.last; ++k) want.insert(k);
        EXPECT_EQ(all, want) << first << " " << length << " " << n;
      }
}

TEST(OutputPattern, FillsTheHashRun) {
  EXPECT_EQ(OutputPattern("out/frame_####.png").path_for(7), "out/frame_0007.png");
  EXPECT_EQ(OutputPattern("f_#.exr").path_for(12), "f_12.exr");
  EXPECT_EQ(OutputPattern("f_##.png").path_for(123), "f_123.png");
  EXPECT_EQ(OutputPattern("shot_#####_v2.tif").path_for(42), "shot_00042_v2.tif");
  const OutputPattern plain("still.png");
  EXPECT_FALSE(plain.has_frame_field());
  EXPECT_EQ(plain.path_for(5), "still.png");
  expect_option_error([] { OutputPattern("a_##/f_##.png"); }, "-o", "more than one run");
}

TEST(OutputPattern, Kinds) {
  EXPECT_EQ(output_kind("a.PNG"), OutputKind::png);
  EXPECT_EQ(output_kind("a.exr"), OutputKind::exr);
  EXPECT_EQ(output_kind("a.tiff"), OutputKind::tiff);
  EXPECT_EQ(output_kind("a.gif"), OutputKind::gif);
  expect_option_error([] { output_kind("a.jpg"); }, "-o", "unsupported output extension `.jpg`");
  expect_option_error([] { output_kind("noext"); }, "-o", "unsupported output extension");
}

TEST(Resume, SelectsFramesWithoutOutput) {
  cli_test::TempDir dir;
  const OutputPattern p((dir.path() / "f_###.png").string());
  dir.write("f_001.png", "x");
  dir.write("f_004.png", "x");
  dir.write(".f_002.png.tmp-123", "partial");  // a temporary is not a finished frame
  EXPECT_EQ(frames_without_output({0, 1, 2, 3, 4, 5}, p), (std::vector<int>{0, 2, 3, 5}));
}

TEST(Progress, Text) {
  EXPECT_EQ(format_duration(1.25), "1.2 s");
  EXPECT_EQ(format_duration(125.0), "2:05");
  EXPECT_EQ(format_duration(3723.0), "1:02:03");
  EXPECT_EQ(progress_bar(3, 12, 6.0, 12), "[###.........]  3/12 frames  0.50 frames/s  18.0 s left");
  EXPECT_EQ(progress_bar(12, 12, 6.0, 4), "[####]  12/12 frames  2.00 frames/s  6.0 s total");
  EXPECT_EQ(progress_line(7, 2, 4, 0.5, 1.0), "frame 7 done (2/4): 0.50 s, 2.00 frames/s, 1.0 s left");
  EXPECT_EQ(progress_mode(true, 2), ProgressMode::quiet);
  // A regular file is not a terminal.
  cli_test::TempDir dir;
  const auto f = dir.write("log.txt", "");
  std::FILE* fp = std::fopen(f.c_str(), "w");
  EXPECT_EQ(progress_mode(false, fileno(fp)), ProgressMode::lines);
  std::fclose(fp);
}

}  // namespace
}  // namespace pelt::render
