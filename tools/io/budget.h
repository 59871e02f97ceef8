// Resource budgets: the largest request pelt accepts before it allocates anything for it.
// A request beyond a budget is refused with an io::InputError naming the file, the field
// and both numbers; every budget is configurable from the command line (tools/cli,
// --max-pixels, --max-texture-side, --max-shells, --max-faces, --max-memory, --max-blur-pairs).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace pelt::io {

// Why each default is what it is:
// - max_pixels 2^26 (64 Mpx, 8192 x 8192): the float colour image alone is 1 GiB there, and
//   supersampling adds 48 bytes a pixel (one sample image and a double accumulator), so
//   64 Mpx at spp > 1 is 4 GiB, half the memory budget; a print-size frame still fits.
// - max_texture_side 16384: raster::kMaxTextureSide, the largest texture the rasterizer
//   samples; a 16384^2 colour map costs 5.3 GiB while it is read (float RGBA plus mips).
// - max_shells 128: the fur block's own upper bound (fur/fur_params.h); a lower budget lets
//   a shared machine refuse heavy fur early.
// - max_faces 2^25 (33.5 million triangles per mesh): a dense photogrammetry scan, over
//   250x the largest mesh the benchmarks draw (120,518 triangles); one such closed mesh
//   (~16.8M vertices) is about 1.5 GiB with its varyings, before any fur.
// - max_memory_bytes 8 GiB: a third of this 23 GiB machine, so two renders and a build fit
//   side by side; raise it with --max-memory on a bigger machine.
// - max_blur_pairs 2^32: the (source, neighbour) vertex pairs the blurred normals of one
//   `normal_blur` skin mesh may settle (shading::NormalBlurBudget), the measure of their time:
//   at 60-100 ns a pair on one core of this machine, 4-7 core-minutes. The head scan at the
//   default radius is about 3.6 x 10^6 pairs (0.3-0.4 s); sphere:256 at radius 1e6, where
//   every vertex reaches every other, 1.06 x 10^9 (about 100 s on one core) fits; sphere:1024
//   at the default radius (2.6 x 10^10) and sphere:2048 (2.5 x 10^11, hours) do not.

// Limits no budget can raise: the largest texture side the rasterizer samples
// (raster::kMaxTextureSide; tools/render/budget_check.cpp asserts they agree) and the fur
// block's own shell range. The flags refuse budgets above them, and a texture beyond the side
// limit is refused without advice to raise a flag that cannot let it through.
inline constexpr int kTextureSideLimit = 16384;
inline constexpr int kShellsLimit = 128;

struct Budget {
  uint64_t max_pixels = uint64_t{1} << 26;        // image width x height
  int max_texture_side = kTextureSideLimit;       // colour maps and fur strand textures, per side
  int max_shells = kShellsLimit;                  // fur shells per object
  uint64_t max_faces = uint64_t{1} << 25;         // triangles per mesh
  uint64_t max_memory_bytes = uint64_t{8} << 30;  // estimated bytes for one render
  uint64_t max_blur_pairs = uint64_t{1} << 32;    // normal blur vertex pairs per mesh
};

// The command-line flags that raise each budget, for error messages.
inline constexpr const char* kMaxPixelsFlag = "--max-pixels";
inline constexpr const char* kMaxTextureSideFlag = "--max-texture-side";
inline constexpr const char* kMaxShellsFlag = "--max-shells";
inline constexpr const char* kMaxFacesFlag = "--max-faces";
inline constexpr const char* kMaxMemoryFlag = "--max-memory";
inline constexpr const char* kMaxBlurPairsFlag = "--max-blur-pairs";

// What a process of `pelt render` holds before any scene: its code and shared libraries
// (OpenImageIO's plug-ins, about 88 MiB resident) and the heap, thread stacks and allocator
// arenas it starts with (about 44 MiB): measured as the peak resident set of a 16 x 16 render
// of one small sphere (`/usr/bin/time -v`, 134 MiB; 2026-11-27).
inline constexpr uint64_t kProcessBaselineBytes = uint64_t{136} << 20;

// "1234567890 bytes (1.1 GiB)": exact for the record, rounded for the reader.
inline std::string describe_bytes(uint64_t bytes) {
  char rounded[32];
  const double b = double(bytes);
  if (b >= double(uint64_t{1} << 30)) std::snprintf(rounded, sizeof rounded, "%.1f GiB", b / double(uint64_t{1} << 30));
  else if (b >= double(uint64_t{1} << 20)) std::snprintf(rounded, sizeof rounded, "%.1f MiB", b / double(uint64_t{1} << 20));
  else std::snprintf(rounded, sizeof rounded, "%.1f KiB", b / 1024.0);
  return std::to_string(bytes) + " bytes (" + rounded + ")";
}

// The tail every budget refusal ends with: "more than the budget of LIMIT (raise it with FLAG)".
inline std::string over_budget(const std::string& limit, const char* flag) {
  return "more than the budget of " + limit + " (raise it with " + flag + ")";
}

// Why a texture of width x height is refused, when a side is over `budget_side`.
inline std::string texture_side_refusal(int width, int height, int budget_side) {
  const std::string size = std::to_string(width) + " x " + std::to_string(height) + " texels, a side ";
  if (width > kTextureSideLimit || height > kTextureSideLimit)
    return size + "more than " + std::to_string(kTextureSideLimit) + ", the largest the rasterizer samples";
  return size + over_budget(std::to_string(budget_side), kMaxTextureSideFlag);
}

// Saturating arithmetic for request sizes computed from untrusted counts: a product that
// would wrap reads as UINT64_MAX, which every budget refuses.
inline uint64_t sat_mul(uint64_t a, uint64_t b) {
  if (a != 0 && b > UINT64_MAX / a) return UINT64_MAX;
  return a * b;
}
inline uint64_t sat_add(uint64_t a, uint64_t b) { return b > UINT64_MAX - a ? UINT64_MAX : a + b; }

}  // namespace pelt::io
