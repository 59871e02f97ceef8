// Which frames a `pelt render` run renders and where each goes: the --frames range,
// the --shard split for render farms, and the -o pattern with its `#` run.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace pelt::render {

// Inclusive range of 0-based frame numbers.
struct FrameRange {
  int first = 0, last = 0;
  int count() const { return last - first + 1; }
};

// "A:B" (inclusive) or "K" (= "K:K"), both ends in [0, frame_count - 1] and A <= B.
// Throws io::InputError naming `option` ("--frames").
FrameRange parse_frame_range(const std::string& text, int frame_count, const std::string& option);

// "K" alone, in [0, frame_count - 1], as the range K:K; "A:B" is refused, so that `--frame`
// keeps its promise of one frame. Throws io::InputError naming `option` ("--frame").
FrameRange parse_frame(const std::string& text, int frame_count, const std::string& option);

// `--shard i/N`: the i-th (0-based) of N interleaved parts of a range: frames
// first + i, first + i + N, first + i + 2N, ... up to last. The N shards of a range are
// disjoint and together are the whole range, whatever its length, so job i of a farm
// array of N jobs runs `--shard i/N` without knowing the frame count.
struct Shard {
  int index = 0, count = 1;
};
// "i/N" with N in [1, 1000000] and i in [0, N - 1]; throws io::InputError("--shard").
Shard parse_shard(const std::string& text);
std::vector<int> shard_frames(FrameRange range, Shard shard);

// An output path in which one run of `#` stands for the frame number, zero-padded to the
// run's length (`frame_####.png` -> `frame_0007.png`; numbers wider than the run are
// written in full: `f_##.png` -> `f_123.png`). A path without `#` names one file.
class OutputPattern {
 public:
  // Throws io::InputError("-o") for two or more separate `#` runs.
  explicit OutputPattern(std::string pattern);
  bool has_frame_field() const { return run_length_ > 0; }
  const std::string& pattern() const { return pattern_; }
  std::filesystem::path path_for(int frame) const;

 private:
  std::string pattern_;
  size_t run_start_ = 0, run_length_ = 0;
};

// Output kinds by extension (case-insensitive): one image per frame, or one animated GIF.
enum class OutputKind { png, exr, tiff, gif };
// Throws io::InputError("-o") for any other extension.
OutputKind output_kind(const std::filesystem::path& path);

// Frames whose output file is missing (for --resume), in the given order. Writes are
// atomic (a temporary renamed into place), so an existing file is a finished frame; an empty
// one (left by another tool, a copy cut short) counts as missing. Throws io::InputError("-o")
// for a folder at a frame's name.
std::vector<int> frames_without_output(const std::vector<int>& frames, const OutputPattern& out);

}  // namespace pelt::render
