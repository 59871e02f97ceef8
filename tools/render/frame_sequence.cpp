#include "tools/render/frame_sequence.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <optional>
#include <string_view>
#include <system_error>

#include "tools/io/input_error.h"

namespace pelt::render {
namespace {

bool is_digits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// A whole decimal number filling all of `text` (no sign, no spaces), or false.
bool parse_int(std::string_view text, long long& out) {
  if (!is_digits(text)) return false;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), out);
  return r.ec == std::errc() && r.ptr == text.data() + text.size();
}

// A frame number as written: digits only (no sign, no spaces), else nullopt. Digits past long
// long's range read as kPastEveryScene, a frame no scene has, so that the range checks refuse
// them as out of range rather than as no number.
constexpr long long kPastEveryScene = LLONG_MAX;
std::optional<long long> frame_number(std::string_view text) {
  long long v = 0;
  if (parse_int(text, v)) return v;
  if (is_digits(text)) return kPastEveryScene;
  return std::nullopt;
}

// `written` is the frame as the option gave it, shown when it was past long long's range.
[[noreturn]] void refuse_out_of_range(long long frame, std::string_view written, int frame_count,
                                      const std::string& option) {
  const std::string shown = frame == kPastEveryScene ? std::string(written) : std::to_string(frame);
  throw io::InputError("", option, "frame " + shown + " is out of range: the scene has " +
                                       std::to_string(frame_count) + " frame(s), 0.." +
                                       std::to_string(frame_count - 1));
}

}  // namespace

FrameRange parse_frame_range(const std::string& text, int frame_count, const std::string& option) {
  const std::string_view t(text);
  const size_t colon = t.find(':');
  const std::string_view first = t.substr(0, colon), last = colon == std::string_view::npos ? t : t.substr(colon + 1);
  const std::optional<long long> a = frame_number(first), b = frame_number(last);
  if (!a || !b)
    throw io::InputError("", option, "expected FIRST:LAST or FRAME (whole numbers >= 0), got `" + text + "`");
  if (*a == kPastEveryScene) refuse_out_of_range(*a, first, frame_count, option);
  if (*a > *b)
    throw io::InputError("", option, "first frame " + std::to_string(*a) + " is after last frame " +
                                         std::to_string(*b));
  if (*b >= frame_count) refuse_out_of_range(*b, last, frame_count, option);
  return {static_cast<int>(*a), static_cast<int>(*b)};
}

FrameRange parse_frame(const std::string& text, int frame_count, const std::string& option) {
  if (text.find(':') != std::string::npos)
    throw io::InputError("", option, "takes one frame number, got `" + text + "`; use --frames A:B for a range");
  const std::optional<long long> k = frame_number(text);
  if (!k) throw io::InputError("", option, "expected a frame number (a whole number >= 0), got `" + text + "`");
  if (*k >= frame_count) refuse_out_of_range(*k, text, frame_count, option);
  return {static_cast<int>(*k), static_cast<int>(*k)};
}

Shard parse_shard(const std::string& text) {
  const size_t slash = text.find('/');
  long long i = 0, n = 0;
  if (slash == std::string::npos || !parse_int(std::string_view(text).substr(0, slash), i) ||
      !parse_int(std::string_view(text).substr(slash + 1), n))
    throw io::InputError("", "--shard", "expected INDEX/COUNT such as 0/4, got `" + text + "`");
  if (n < 1 || n > 1000000)
    throw io::InputError("", "--shard", "shard count must be in [1, 1000000], got " + std::to_string(n));
  if (i >= n)
    throw io::InputError("", "--shard", "shard index " + std::to_string(i) + " must be below the count " +
                                            std::to_string(n) + " (indices are 0-based)");
  return {static_cast<int>(i), static_cast<int>(n)};
}

std::vector<int> shard_frames(FrameRange range, Shard shard) {
  std::vector<int> out;
  for (long long f = static_cast<long long>(range.first) + shard.index; f <= range.last; f += shard.count)
    out.push_back(static_cast<int>(f));
  return out;
}

OutputPattern::OutputPattern(std::string pattern) : pattern_(std::move(pattern)) {
  const size_t first = pattern_.find('#');
  if (first == std::string::npos) return;
  size_t end = first;
  while (end < pattern_.size() && pattern_[end] == '#') ++end;
  if (pattern_.find('#', end) != std::string::npos)
    throw io::InputError(pattern_, "-o", "holds more than one run of `#`; use one run for the frame number");
  run_start_ = first;
  run_length_ = end - first;
}

std::filesystem::path OutputPattern::path_for(int frame) const {
  if (run_length_ == 0) return pattern_;
  std::string digits = std::to_string(frame);
  if (digits.size() < run_length_) digits.insert(0, run_length_ - digits.size(), '0');
  std::string p = pattern_;
  p.replace(run_start_, run_length_, digits);
  return p;
}

OutputKind output_kind(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".png") return OutputKind::png;
  if (ext == ".exr") return OutputKind::exr;
  if (ext == ".tif" || ext == ".tiff") return OutputKind::tiff;
  if (ext == ".gif") return OutputKind::gif;
  throw io::InputError(path.string(), "-o",
                       "unsupported output extension `" + path.extension().string() +
                           "` (expected .png, .exr, .tif, .tiff or .gif)");
}

std::vector<int> frames_without_output(const std::vector<int>& frames, const OutputPattern& out) {
  std::vector<int> missing;
  for (int f : frames) {
    const std::filesystem::path path = out.path_for(f);
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(st)) {
      missing.push_back(f);
    } else if (std::filesystem::is_directory(st)) {
      // Not a finished frame, and no frame can be written there: refused as without --resume.
      throw io::InputError(path.string(), "-o", "is a folder, not a file");
    } else if (std::filesystem::is_regular_file(st) && std::filesystem::file_size(path, ec) == 0 && !ec) {
      // pelt never leaves an empty frame (writes are atomic): another tool's, cut short.
      missing.push_back(f);
    }
  }
  return missing;
}

}  // namespace pelt::render
