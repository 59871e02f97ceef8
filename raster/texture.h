// Mipmapped 2-D RGBA textures and the sampler the shaders call: nearest, bilinear, bilinear on
// the nearest mip level and trilinear filtering, repeat or clamp-to-edge wrapping per axis,
// the level of detail taken from screen-space derivatives within each 4x4 block of a
// FragmentBatch.
//
// Storage: every mip level is packed RGBA8, one uint32_t per texel (R in the low byte,
// A in the high byte), row-major, row 0 = v = 0, rows of `width` texels plus one padding
// texel that repeats the row's first texel. One 32-bit gather fetches a whole texel; the
// padding makes x + 1 a valid neighbour of every x (repeat wraps onto it), so bilinear
// wraps only its left index. Gathers are the dominant cost of the sampler here (about half of
// a bilinear sample's time, measured with perf on this Zen 3): RGBA8 needs one gather per
// texel where float RGBA would need four, and a 256x256 level with its whole chain is 342 KiB,
// so a shell layer stays in a core's 512 KiB L2 while it is drawn (float RGBA: 1.4 MiB a
// layer). Colour channels are stored linear or sRGB-encoded (TexelEncoding); alpha is always
// linear. sRGB bytes are decoded through a 256-entry float table, so filtering happens in
// linear space as the colour-map brief asks.
//
// Alpha: texels are stored and filtered with STRAIGHT alpha (full colour precision at low
// alpha; four multiply-adds per texel, no division per sample). Fringes are prevented at
// build time instead: (1) the mip box filter averages colour weighted by alpha (the
// premultiplied average divided by the averaged alpha), so a level's colour is that of its
// visible texels; (2) a pull-push fill then gives every fully transparent texel (alpha 0) of
// every level the colour of the coarser-level texel covering it, i.e. the colour of the
// visible texels around it. Bilinear and trilinear filtering of straight colour between a
// strand (or cut-out edge) and its transparent neighbours therefore mixes in only similar
// colours: no dark (or any other) fringes whatever colour the input gave invisible texels.
// Only the colour bytes of alpha-0 texels differ from the input. A fully transparent texture
// keeps the plain average of its colours.
//
// Level sizes follow OpenGL: level k+1 is max(1, floor(w/2)) x max(1, floor(h/2)) of level
// k, down to 1x1. The box filter is area-exact: a destination texel averages the source
// interval it covers (2 texels when the side is even; 2 + a fraction, 3 taps, when odd), so
// no source texel is dropped and every source texel has the same total weight.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "raster/parallel.h"

namespace pelt::raster {

enum class TexelEncoding : uint8_t {
  Linear,  // bytes are value * 255 (data maps, the fur strand textures)
  Srgb,    // colour bytes are sRGB-encoded (colour maps); alpha stays linear
};

// What a source image's alpha means to the texture. `ignored`: nothing draws it (a material's
// colour or normal map), so every texel is stored opaque and the colours are filtered as stored:
// the alpha-weighted mips and the fill of transparent texels (above) exist for blended
// textures, and on an opaque map moved colours (a texel of alpha 0 took its neighbours').
enum class SourceAlpha : uint8_t { straight, ignored };

// How a level's texels are stored (rows of `width` texels plus the padding texel, a copy of
// the row's first, in both).
//   Rgba8: one 32-bit word a texel, R in the low byte .. A in the high byte.
//   La8:   a luminance-alpha texture (R = G = B = L): 2 bytes a texel, L in the low byte and
//          A in the high byte. A 32-bit read at texel x holds texel x in its low half and its
//          right neighbour x + 1 (the padding at the row's end) in its high half, so one
//          gather (byte offsets, 2 x index) fetches both texels of a bilinear row and four
//          bytes decode both, where RGBA8 needs two gathers and eight channels: the fur
//          shells, whose colour is the layer's tint times a strand brightness, sample in about
//          half the time. At 2 bytes a texel a frame's 16 shell layers also take half the
//          cache of 32-bit (texel, neighbour) words, the previous layout: fur frames ran 4-12 %
//          faster on one thread of the Zen 5 machine (README, measured figures), where 2x2
//          quads at 8 bytes a texel, half the gathered elements, ran about 10 % slower.
enum class TexelFormat : uint8_t { Rgba8, La8 };

enum class Filter : uint8_t {
  Nearest,    // level 0, the texel under the sample (GL_NEAREST)
  Bilinear,   // level 0, 2x2 texels (GL_LINEAR)
  Trilinear,  // bilinear on the two levels around the LOD, lerped (GL_LINEAR_MIPMAP_LINEAR)
  // Bilinear on the one level nearest the LOD (GL_LINEAR_MIPMAP_NEAREST, "bilinear" in most
  // engines): half of trilinear's taps, so about 1.25x faster fur frames here, at the price
  // of a seam where the level changes, which moves with the camera.
  BilinearMip,
};

enum class Wrap : uint8_t {
  Repeat,  // coordinate taken modulo 1 (GL_REPEAT)
  Clamp,   // texel index clamped to the edge (GL_CLAMP_TO_EDGE)
  // Every other repeat reflected (GL_MIRRORED_REPEAT, glTF's 33648): texel index i and
  // 2 size - 1 - i read the same texel. Sampled as a clamp on coordinates folded into [0, 1],
  // the level of detail taken from the coordinates before the fold. One difference from
  // OpenGL, in Nearest alone: a coordinate exactly on a texel boundary in a reflected period
  // takes the texel on the other side of it (the fold sends the tie the other way; the
  // filtered modes give the boundary texel weight 0 either way).
  Mirror,
};

struct TextureError {
  std::string field;
  std::string reason;
  std::string message() const { return field + ": " + reason; }
};

struct MipLevel {
  int width = 0;
  int height = 0;
  int stride = 0;     // texels per row: width + 1 (the padding texel repeats texel 0)
  size_t offset = 0;  // first texel of the level in the texture's storage (texels, not bytes)
};

// Largest accepted side: keeps texel coordinates exact in float's 24-bit mantissa and
// texel indices within int32.
inline constexpr int kMaxTextureSide = 16384;

class Texture {
 public:
  Texture() = default;

  // `rgba`: width * height * 4 bytes, R, G, B, A, straight alpha, row 0 = v = 0.
  // Builds the full mip chain and fills transparent texels (see above). Allocates: call when a texture is loaded or generated.
  // With `parallel` (raster/parallel.h), rows of level 0's packing and of each level's
  // reduction run as its items, each writing only its own texels: the same bytes either way.
  static std::optional<TextureError> from_rgba8(int width, int height, const uint8_t* rgba,
                                                TexelEncoding encoding, Texture& out,
                                                const ParallelFor& parallel = {});
  // `rgba`: width * height * 4 linear floats in [0, 1], straight alpha (e.g. io::ImageRGBA).
  // Stored with `encoding` (Srgb for colour maps keeps 8-bit precision in the darks; an
  // sRGB8 image read to linear floats and stored as Srgb gives back its bytes exactly).
  // Values outside [0, 1] or not finite are an error naming the texel and channel (alpha's only
  // when it is used: SourceAlpha::straight).
  static std::optional<TextureError> from_linear_float(int width, int height, const float* rgba,
                                                       TexelEncoding encoding, Texture& out,
                                                       const ParallelFor& parallel = {},
                                                       SourceAlpha alpha = SourceAlpha::straight);
  // `la`: width * height * 2 bytes, L, A (linear, straight alpha), row 0 = v = 0. The same
  // texture as from_rgba8 with R = G = B = L, in the La8 layout: its mip chain and fill are
  // built that way, so every level's bytes and every sample equal the RGBA8 texture's.
  static std::optional<TextureError> from_la8(int width, int height, const uint8_t* la, Texture& out,
                                              const ParallelFor& parallel = {});

  bool empty() const { return levels_.empty(); }
  int width() const { return empty() ? 0 : levels_[0].width; }
  int height() const { return empty() ? 0 : levels_[0].height; }
  int levels() const { return int(levels_.size()); }
  TexelEncoding encoding() const { return encoding_; }
  TexelFormat format() const { return format_; }
  const MipLevel& level(int k) const { return levels_[size_t(k)]; }
  // The storage, bytes() long, laid out as format() says (for comparing textures).
  const void* data() const { return format_ == TexelFormat::La8 ? static_cast<const void*>(la_.data()) : texels_.data(); }
  size_t bytes() const { return texels_.size() * sizeof(uint32_t) + la_.size() * sizeof(uint16_t); }
  // Level k's texels: level_texels for Rgba8, level_la for La8 (null for the other format).
  const uint32_t* level_texels(int k) const {
    return texels_.empty() ? nullptr : texels_.data() + levels_[size_t(k)].offset;
  }
  const uint16_t* level_la(int k) const { return la_.empty() ? nullptr : la_.data() + levels_[size_t(k)].offset; }
  // Texel (x, y) of level k as RGBA8 whatever the format: byte c (0 = R .. 3 = A) is
  // (t >> 8c) & 255.
  uint32_t texel(int k, int x, int y) const {
    const size_t i = size_t(y) * size_t(levels_[size_t(k)].stride) + size_t(x);
    if (format_ == TexelFormat::Rgba8) return level_texels(k)[i];
    const uint32_t t = level_la(k)[i], l = t & 255u, a = t >> 8;
    return l | (l << 8) | (l << 16) | (a << 24);
  }

 private:
  std::vector<uint32_t> texels_;  // Rgba8: all levels, level 0 first
  std::vector<uint16_t> la_;      // La8: the same, and one spare texel after the last level
  std::vector<MipLevel> levels_;
  TexelEncoding encoding_ = TexelEncoding::Linear;
  TexelFormat format_ = TexelFormat::Rgba8;
};

// Layers of equal size, e.g. the 16 fur shells.
struct TextureArray {
  std::vector<Texture> layers;

  int width() const { return layers.empty() ? 0 : layers[0].width(); }
  int height() const { return layers.empty() ? 0 : layers[0].height(); }

  // `rgba`: `count` layers one after another, each width * height * 4 bytes as in
  // Texture::from_rgba8 (the layout of fur::LayerTextures).
  // With `parallel`, the layers are built as its items.
  static std::optional<TextureError> from_rgba8_layers(int width, int height, int count,
                                                       const uint8_t* rgba, TexelEncoding encoding,
                                                       TextureArray& out, const ParallelFor& parallel = {});
  // `la`: `count` layers of width * height * 2 bytes, as in Texture::from_la8.
  static std::optional<TextureError> from_la8_layers(int width, int height, int count, const uint8_t* la,
                                                     TextureArray& out, const ParallelFor& parallel = {});
};

struct SamplerState {
  Filter filter = Filter::Trilinear;
  Wrap wrap_u = Wrap::Repeat;
  Wrap wrap_v = Wrap::Repeat;
  float lod_bias = 0.0f;  // added to the LOD before clamping (the mipmapped filters only)
};

// Samples `tex` at `lanes` points and writes linear straight-alpha r, g, b, a to
// out[0..3][0..lanes): the filter-weighted sum of the texels' straight colour and alpha. Texel centres are at ((i + 0.5) / width, (j + 0.5) / height).
//
// `lanes` is a multiple of 16, laid out as 4x4 blocks (lane l of a block is pixel
// (l % 4, l / 4), as in FragmentBatch). Trilinear takes ONE level of detail per block:
//   dU/dx = W * sum over rows r of (u[4r + 3] - u[4r]) / 12   (and dV/dx with H and v)
//   dU/dy = W * sum over columns c of (u[12 + c] - u[c]) / 12 (and dV/dy)
//   lambda = log2(max(|(dU/dx, dV/dx)|, |(dU/dy, dV/dy)|)) + lod_bias,
//            clamped to [0, levels - 1] (NaN or a zero derivative gives 0),
// evaluated in double. These are the mean differences over the whole block, i.e. the
// derivative at the block centre: one LOD per block means the two levels and their lerp
// weight are the same for all 16 lanes, so level addressing is scalar and the per-lane work
// is the bilinear taps alone; averaging four rows (columns) also keeps the estimate smooth
// where perspective bends u, v within the block. Blocks are 4 pixels wide, so the LOD is
// coarser than a GPU's 2x2 quads; the difference is the variation of the derivative over 2
// pixels, far below what is visible in the fur's shells.
//
// BilinearMip takes the same lambda and samples level nearest_mip_level(lambda) bilinearly.
//
// Repeat wraps u to u - floor(u) before scaling, so huge coordinates (1e6) keep their exact
// fraction; clamp clamps the texel index; mirror reflects it (see Wrap). Non-finite u, v give unspecified values but never
// read outside the texture. Throws std::invalid_argument (naming the argument) if the texture
// is empty, lanes is not a multiple of 16, a pointer is null, or the filter or a wrap is no
// value of its enum. Dispatches once per call to
// the best Highway target; allocation-free; safe to call concurrently.
//
// `block_mask` (optional, one per block, bit l = lane l, as FragmentBatch::mask): lanes
// outside it are written 0 and the kernel skips every vector of lanes outside it. A block's
// LOD still comes from all 16 of its u, v, so the sampled lanes are those of the call without
// a mask.
void sample(const Texture& tex, const SamplerState& state, const float* u, const float* v,
            size_t lanes, float* const out[4], const uint16_t* block_mask = nullptr);

// The scalar reference: the same contract evaluated in double from the same float inputs
// and texel bytes (the sRGB table in double), written as double. For tests.
void sample_reference(const Texture& tex, const SamplerState& state, const float* u,
                      const float* v, size_t lanes, double* const out[4],
                      const uint16_t* block_mask = nullptr);

// Wrap::Mirror's fold of `n` texture coordinates into [0, 1]: |c| modulo 2, reflected about 1,
// every step exact in float (so NaN and infinities give NaN). By a Highway kernel (sample() folds
// a mirrored axis with it), bit for bit fold_mirror_reference, which folds one. `in` and `out`
// must not overlap.
void fold_mirror(const float* in, float* out, size_t n);
float fold_mirror_reference(float c);

// The LOD of the 4x4 block at u[0..16), v[0..16) as defined above, before the bias and clamp
// (may be -inf for a zero derivative). For tests and for shaders that want to skip work.
double block_lod(const float* u, const float* v, int width, int height);
// The level of detail sample() takes for each of `blocks` 4x4 blocks (u, v: 16 floats a
// block): 0.5 * log2(block_lod_length2) + lod_bias clamped to [0, levels - 1], with NaN, 0 and
// -inf giving 0 and +inf giving levels - 1; by the sampler's SIMD kernel (block_lod_length2
// bit for bit, Highway's log, which differs from std::log2 by an ulp or two; exact integers
// where the length is a power of 4). Throws std::invalid_argument for a null pointer or a size
// below 1. For tests against block_lod, and for shaders that want to skip work.
void block_lods(const float* u, const float* v, size_t blocks, int width, int height, float lod_bias, int levels,
                double* out);
// block_lod_length2 of each of `blocks` blocks by the sampler's SIMD kernel, which must give it
// bit for bit (for tests). Throws std::invalid_argument for a null pointer or a size below 1.
void block_lod_length2s(const float* u, const float* v, size_t blocks, int width, int height, double* out);
// Its argument: block_lod = 0.5 * log2(block_lod_length2), the larger squared length of the
// two block derivatives in texels. Each row's three differences telescope to its last minus
// its first value (and each column's to its bottom minus its top), exact in double; the four
// of them are summed in pairs, (0 + 1) + (2 + 3), the order in which the SIMD kernel sums them
// (with extreme inputs, 1e38 next to 1, the sums cancel even in double, so the order is part
// of the definition). The sampler evaluates this bit for bit, four doubles at a time.
inline double block_lod_length2(const float* u, const float* v, int width, int height) {
  double d[4][4];  // du/dx, dv/dx per row; du/dy, dv/dy per column
  for (int k = 0; k < 4; ++k) {
    d[0][k] = double(u[4 * k + 3]) - double(u[4 * k]);
    d[1][k] = double(v[4 * k + 3]) - double(v[4 * k]);
    d[2][k] = double(u[12 + k]) - double(u[k]);
    d[3][k] = double(v[12 + k]) - double(v[k]);
  }
  const double sx = width / 12.0, sy = height / 12.0;
  const double ux = ((d[0][0] + d[0][1]) + (d[0][2] + d[0][3])) * sx;
  const double vx = ((d[1][0] + d[1][1]) + (d[1][2] + d[1][3])) * sy;
  const double uy = ((d[2][0] + d[2][1]) + (d[2][2] + d[2][3])) * sx;
  const double vy = ((d[3][0] + d[3][1]) + (d[3][2] + d[3][3])) * sy;
  const double lx = ux * ux + vx * vx, ly = uy * uy + vy * vy;
  return lx < ly ? ly : lx;  // std::max, NaN in lx included
}

// The level BilinearMip samples for a clamped lambda (>= 0): OpenGL's rule for
// *_MIPMAP_NEAREST, ceil(lambda + 0.5) - 1, i.e. the nearest level with halves rounding down
// (level 0 up to lambda = 0.5; in squared lengths, every length2 <= 2). Written with the
// exact fraction: lambda + 0.5 would round lambda = 0.5 + 1 ulp down onto 1.
inline int nearest_mip_level(double lambda) {
  const double whole = std::floor(lambda);
  return int(whole) + (lambda - whole > 0.5 ? 1 : 0);
}

// The 256 sRGB bytes decoded to linear (inverse transfer function in double, rounded once).
const float* srgb8_to_linear_table();

// The sRGB byte of linear x, as sRGB textures store their texels and mip levels and tools/io
// encodes images: round-half-up(255 s), s = 1.055 x^(1/2.4) - 0.055 (12.92 x below
// 0.0031308) in double, x clamped to [0, 1]. srgb_byte_reference evaluates that with std::pow;
// srgb_byte gives the same byte for every x by a search among the 255 boundaries, found once
// from the reference.
uint8_t srgb_byte(double x);
uint8_t srgb_byte_reference(double x);
// The smallest x whose srgb_byte is greater than b (b in 0..254): the boundaries srgb_byte
// searches.
double srgb_byte_threshold(int b);

// srgb_byte of n floats into n bytes, bit for bit, with SIMD (raster/srgb_kernels.cc; the
// tests compare it with srgb_byte on every target): colour maps' level 0 and the 8-bit
// resolve of image writes. A 1024x768 RGBA frame, three quarters background, in 3.3 ms
// instead of the scalar search's 7.1; random colours in 5.8 instead of 17.5.
void srgb_bytes(const float* src, uint8_t* dst, size_t n);
// The smallest float whose srgb_byte is greater than b (b in 0..254).
float srgb_float_threshold(int b);

// srgb_byte's tables, for loops over whole images that inline the search. bucket[k]: the byte
// of the first double of bucket k, the doubles in [2^-14, 1) sharing their exponent and top 7
// mantissa bits; within a bucket the byte rises by at most a step or two, found against the
// thresholds. Below 2^-14 every byte is 0 (the first boundary is 0.5 / (255 * 12.92), about
// 1.5e-4).
struct SrgbBoundaries {
  static constexpr int kBucketShift = 45;
  static constexpr double kFloor = 0x1p-14;
  static constexpr uint64_t kFirstBucket = std::bit_cast<uint64_t>(kFloor) >> kBucketShift;
  std::array<double, 255> threshold;  // threshold[b]: the smallest x with byte > b
  std::array<uint8_t, (std::bit_cast<uint64_t>(1.0) >> kBucketShift) - kFirstBucket> bucket;
};
const SrgbBoundaries& srgb_boundaries();

inline uint8_t srgb_byte(const SrgbBoundaries& t, double x) {
  if (!(x >= SrgbBoundaries::kFloor)) return 0;  // also NaN
  if (x >= 1.0) return 255;
  unsigned b = t.bucket[(std::bit_cast<uint64_t>(x) >> SrgbBoundaries::kBucketShift) - SrgbBoundaries::kFirstBucket];
  while (b < 255 && x >= t.threshold[b]) ++b;
  return uint8_t(b);
}

}  // namespace pelt::raster
