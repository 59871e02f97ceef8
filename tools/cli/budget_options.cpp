#include "tools/cli/budget_options.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <type_traits>

#include "tools/io/input_error.h"

namespace pelt::cli {
namespace {

// One flag whose value lands in a uint64_t or int member of the budget.
// `limit`: the largest value the flag takes (a budget no further code could honour is refused).
template <typename T>
void add_flag(CLI::App& sub, const char* flag, T& target, bool bytes, const std::string& help,
              uint64_t limit = UINT64_MAX) {
  sub.add_option_function<std::string>(
         flag,
         [flag, &target, bytes, limit](const std::string& text) {
           const uint64_t max = std::min(limit, std::is_same_v<T, int> ? uint64_t(INT_MAX) : UINT64_MAX);
           try {
             target = static_cast<T>(parse_budget_value(text, flag, max, bytes));
           } catch (const io::InputError& e) {
             throw CLI::ValidationError(flag, e.reason);
           }
         },
         help + " (default " + std::to_string(target) + ")")
      ->type_name(bytes ? "BYTES" : "N");
}

}  // namespace

uint64_t parse_budget_value(std::string_view text, const std::string& flag, uint64_t max, bool bytes) {
  const std::string quoted = "`" + std::string(text) + "`";
  const std::string form = bytes ? "a byte count such as 1500000, 512M or 8G" : "a whole number such as 4096 or 64M";
  size_t i = 0;
  uint64_t value = 0;
  while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) {
    const uint64_t digit = uint64_t(text[i] - '0');
    if (value > (UINT64_MAX - digit) / 10) throw io::InputError("", flag, quoted + " is too large");
    value = value * 10 + digit;
    ++i;
  }
  if (i == 0) throw io::InputError("", flag, "expected " + form + ", got " + quoted);
  int shift = 0;
  if (i < text.size()) {
    switch (std::toupper(static_cast<unsigned char>(text[i]))) {
      case 'K': shift = 10; break;
      case 'M': shift = 20; break;
      case 'G': shift = 30; break;
      case 'T': shift = 40; break;
      default: break;
    }
    if (shift) ++i;
  }
  std::string_view rest = text.substr(i);
  if (bytes && shift && (rest == "iB" || rest == "ib")) rest = {};
  if (bytes && (rest == "B" || rest == "b")) rest = {};
  if (!rest.empty())
    throw io::InputError("", flag, "expected " + form + " (suffixes K, M, G, T are powers of 1024), got " + quoted);
  if (value > (UINT64_MAX >> shift)) throw io::InputError("", flag, quoted + " is too large");
  value <<= shift;
  if (value == 0) throw io::InputError("", flag, "must be at least 1, got " + quoted);
  if (value > max)
    throw io::InputError("", flag, quoted + " is " + std::to_string(value) + ", more than the largest accepted value " +
                                       std::to_string(max));
  return value;
}

void add_budget_options(CLI::App& sub, io::Budget& b) {
  add_flag(sub, io::kMaxPixelsFlag, b.max_pixels, false, "Largest image, width x height pixels");
  add_flag(sub, io::kMaxTextureSideFlag, b.max_texture_side, false,
           "Largest colour map or fur strand texture side, texels, at most " + std::to_string(io::kTextureSideLimit),
           io::kTextureSideLimit);
  add_flag(sub, io::kMaxShellsFlag, b.max_shells, false,
           "Most fur shells per object, at most " + std::to_string(io::kShellsLimit), io::kShellsLimit);
  add_flag(sub, io::kMaxFacesFlag, b.max_faces, false, "Most triangles per mesh");
  add_flag(sub, io::kMaxMemoryFlag, b.max_memory_bytes, true,
           "Largest estimated memory for one render, bytes (K, M, G, T: powers of 1024)");
  add_flag(sub, io::kMaxBlurPairsFlag, b.max_blur_pairs, false,
           "Most vertex pairs the blurred normals of one normal_blur skin mesh may settle (their time)");
}

void check_default_pixel_budget(int width, int height) {
  const uint64_t pixels = uint64_t(std::max(width, 0)) * uint64_t(std::max(height, 0));
  const uint64_t budget = io::Budget{}.max_pixels;
  if (pixels > budget)
    throw io::InputError("", "--width",
                         "the image is " + std::to_string(width) + " x " + std::to_string(height) + " = " +
                             std::to_string(pixels) + " pixels, more than the default budget of " +
                             std::to_string(budget) + " pixels that the benchmarks run at (they take no --max-pixels)");
}

}  // namespace pelt::cli
