// Texture construction (validation, mip chain) and the double-precision reference sampler.
#include "raster/texture.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <vector>

namespace pelt::raster {
namespace {

double srgb_decode(double s) {
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

double srgb_encode(double x) {
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

// round-half-up(255 x), clamped: the same rounding as tools/io's encoders.
uint8_t to_byte(double x) {
  const double b = std::floor(x * 255.0 + 0.5);
  return uint8_t(std::clamp(b, 0.0, 255.0));
}

const std::array<double, 256>& srgb_table_double() {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_decode(i / 255.0);
    return t;
  }();
  return table;
}

// Decoded texel: straight linear colour and alpha, in double.
struct Texel {
  double c[4];
};

Texel decode(uint32_t t, TexelEncoding enc) {
  Texel out{};
  for (int ch = 0; ch < 3; ++ch) {
    const uint32_t b = (t >> (8 * ch)) & 255u;
    out.c[ch] = enc == TexelEncoding::Srgb ? srgb_table_double()[b] : b / 255.0;
  }
  out.c[3] = (t >> 24) / 255.0;
  return out;
}

}  // namespace

uint8_t srgb_byte_reference(double x) { return to_byte(srgb_encode(std::clamp(x, 0.0, 1.0))); }

// Each boundary is a bisection on the bits: the byte is a non-decreasing function of x, and
// non-negative doubles are ordered like their bit patterns.
const SrgbBoundaries& srgb_boundaries() {
  static const SrgbBoundaries tables = [] {
    SrgbBoundaries t;
    const uint64_t one = std::bit_cast<uint64_t>(1.0);
    for (int b = 0; b < 255; ++b) {
      uint64_t lo = 0, hi = one;  // byte(lo) <= b < byte(hi)
      while (hi - lo > 1) {
        const uint64_t mid = lo + (hi - lo) / 2;
        (srgb_byte_reference(std::bit_cast<double>(mid)) > b ? hi : lo) = mid;
      }
      t.threshold[size_t(b)] = std::bit_cast<double>(hi);
    }
    for (size_t k = 0; k < t.bucket.size(); ++k)
      t.bucket[k] = srgb_byte_reference(
          std::bit_cast<double>((SrgbBoundaries::kFirstBucket + k) << SrgbBoundaries::kBucketShift));
    return t;
  }();
  return tables;
}

uint8_t srgb_byte(double x) { return srgb_byte(srgb_boundaries(), x); }

double srgb_byte_threshold(int b) { return srgb_boundaries().threshold[size_t(std::clamp(b, 0, 254))]; }

namespace {

uint32_t encode(const Texel& t, TexelEncoding enc) {
  const SrgbBoundaries& srgb = srgb_boundaries();
  uint32_t packed = 0;
  for (int ch = 0; ch < 3; ++ch)
    packed |= uint32_t{enc == TexelEncoding::Srgb ? srgb_byte(srgb, t.c[ch]) : to_byte(t.c[ch])} << (8 * ch);
  return packed | (uint32_t{to_byte(t.c[3])} << 24);
}

// Source texels and weights of one destination texel of an area-exact box reduction
// from `src` to `dst` texels along one axis: destination i covers [i s, (i + 1) s),
// s = src / dst, and each source texel weighs its overlap / s. At most 3 taps (s < 3).
struct AxisTaps {
  int first = 0;
  int count = 0;
  double w[3] = {};
};

std::vector<AxisTaps> box_taps(int src, int dst) {
  std::vector<AxisTaps> taps(static_cast<size_t>(dst));
  for (int i = 0; i < dst; ++i) {
    // Integer bounds in units of 1/dst source texels keep the overlaps exact.
    const int64_t lo = int64_t(i) * src, hi = int64_t(i + 1) * src;
    AxisTaps& t = taps[size_t(i)];
    t.first = int(lo / dst);
    for (int64_t j = t.first; j * dst < hi; ++j) {
      const int64_t a = std::max(lo, j * dst), b = std::min(hi, (j + 1) * dst);
      t.w[t.count++] = double(b - a) / double(src);
    }
  }
  return taps;
}

// fn(y0, y1) over rows [0, rows) in items of about kItemTexels texels (for_each_item).
void for_row_items(int rows, size_t row_texels, const ParallelFor& parallel, const std::function<void(int, int)>& fn) {
  constexpr size_t kItemTexels = 16384;
  const int per = int(std::max<size_t>(1, kItemTexels / std::max<size_t>(1, row_texels)));
  const size_t items = size_t((rows + per - 1) / per);
  for_each_item(parallel, items, [&](size_t k) {
    const int y0 = int(k) * per;
    fn(y0, std::min(rows, y0 + per));
  });
}

// One level of the chain from the previous one, as straight decoded texels; src(i) gives the
// previous level's texel i. Colour is averaged weighted by alpha; where the whole footprint
// is transparent, plainly.
template <class Source>
std::vector<Texel> reduce(const Source& src, int sw, int sh, int dw, int dh, const ParallelFor& parallel) {
  const std::vector<AxisTaps> tx = box_taps(sw, dw), ty = box_taps(sh, dh);
  std::vector<Texel> dst(size_t(dw) * size_t(dh));
  for_row_items(dh, size_t(dw), parallel, [&](int y_begin, int y_end) {
    for (int y = y_begin; y < y_end; ++y)
      for (int x = 0; x < dw; ++x) {
        double pm[3] = {}, plain[3] = {}, alpha = 0.0;
        const AxisTaps& ax = tx[size_t(x)];
        const AxisTaps& ay = ty[size_t(y)];
        for (int j = 0; j < ay.count; ++j)
          for (int i = 0; i < ax.count; ++i) {
            const Texel s = src(size_t(ay.first + j) * size_t(sw) + size_t(ax.first + i));
            const double w = ax.w[i] * ay.w[j];
            const double wa = w * s.c[3];
            for (int ch = 0; ch < 3; ++ch) {
              pm[ch] += wa * s.c[ch];
              plain[ch] += w * s.c[ch];
            }
            alpha += wa;
          }
        Texel& d = dst[size_t(y) * size_t(dw) + size_t(x)];
        for (int ch = 0; ch < 3; ++ch) d.c[ch] = alpha > 0.0 ? pm[ch] / alpha : plain[ch];
        d.c[3] = alpha;
      }
  });
  return dst;
}

std::optional<TextureError> check_size(int width, int height) {
  if (width < 1 || width > kMaxTextureSide)
    return TextureError{"width", std::to_string(width) + " is outside [1, " +
                                     std::to_string(kMaxTextureSide) + "]"};
  if (height < 1 || height > kMaxTextureSide)
    return TextureError{"height", std::to_string(height) + " is outside [1, " +
                                      std::to_string(kMaxTextureSide) + "]"};
  return std::nullopt;
}

}  // namespace

// Why a class builder and not a constructor: errors are returned as values naming the field.
struct TextureBuilder {
  static void build(int width, int height, std::vector<uint32_t> level0, TexelEncoding enc,
                    std::vector<uint32_t>& texels, std::vector<MipLevel>& levels, const ParallelFor& parallel) {
    levels.clear();
    size_t total = 0;
    for (int w = width, h = height;; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
      levels.push_back(MipLevel{w, h, w + 1, total});
      total += size_t(w + 1) * size_t(h);
      if (w == 1 && h == 1) break;
    }
    texels.assign(total, 0u);
    store(level0, levels[0], texels);
    // Each level is reduced from the previous one unquantised, so 8-bit rounding does not
    // compound down the chain. Level 0 is decoded as it is read, not kept in double (32
    // bytes a texel, 8 times the texture's own level 0): the largest decoded level held is
    // level 1 (budget_check.cpp counts it).
    std::vector<Texel> cur;
    for (size_t k = 1; k < levels.size(); ++k) {
      const MipLevel& s = levels[k - 1];
      const MipLevel& d = levels[k];
      if (k == 1)
        cur = reduce([&](size_t i) { return decode(level0[i], enc); }, s.width, s.height, d.width, d.height, parallel);
      else
        cur = reduce([&](size_t i) { return cur[i]; }, s.width, s.height, d.width, d.height, parallel);
      for_row_items(d.height, size_t(d.width), parallel, [&](int y_begin, int y_end) {
        for (int y = y_begin; y < y_end; ++y) {
          uint32_t* row = texels.data() + d.offset + size_t(y) * size_t(d.stride);
          const Texel* from = cur.data() + size_t(y) * size_t(d.width);
          for (int x = 0; x < d.width; ++x) row[x] = encode(from[x], enc);
        }
      });
    }
    fill_transparent(texels, levels);
    for (const MipLevel& L : levels)
      for (int y = 0; y < L.height; ++y) {
        uint32_t* row = texels.data() + L.offset + size_t(y) * size_t(L.stride);
        row[L.width] = row[0];
      }
  }

  // Rows of `width` packed texels into the level's padded rows.
  static void store(const std::vector<uint32_t>& packed, const MipLevel& L, std::vector<uint32_t>& texels) {
    for (int y = 0; y < L.height; ++y)
      std::copy_n(packed.begin() + long(y) * L.width, L.width, texels.begin() + long(L.offset) + long(y) * L.stride);
  }

  // Pull-push fill, coarse to fine: a texel with alpha 0 takes the colour bytes of the texel
  // of the next level that covers it (that is the alpha-weighted average of the visible
  // texels around it, or itself filled from further up). The sampler filters straight
  // colour; with this fill, a transparent texel next to a visible one carries the colour of
  // its visible surroundings, so filtering straight colour pulls in no foreign (dark) colour.
  // Only the colour of invisible texels changes.
  static void fill_transparent(std::vector<uint32_t>& texels, const std::vector<MipLevel>& levels) {
    for (size_t k = levels.size() - 1; k-- > 0;) {
      const MipLevel& L = levels[k];
      const MipLevel& P = levels[k + 1];
      for (int y = 0; y < L.height; ++y)
        for (int x = 0; x < L.width; ++x) {
          uint32_t& t = texels[L.offset + size_t(y) * size_t(L.stride) + size_t(x)];
          if ((t >> 24) != 0) continue;
          const size_t px = size_t(x) * size_t(P.width) / size_t(L.width);
          const size_t py = size_t(y) * size_t(P.height) / size_t(L.height);
          t = texels[P.offset + py * size_t(P.stride) + px] & 0x00FFFFFFu;
        }
    }
  }
};

std::optional<TextureError> Texture::from_rgba8(int width, int height, const uint8_t* rgba,
                                                TexelEncoding encoding, Texture& out, const ParallelFor& parallel) {
  if (auto e = check_size(width, height)) return e;
  if (rgba == nullptr) return TextureError{"rgba", "is null"};
  std::vector<uint32_t> level0(size_t(width) * size_t(height));
  for (size_t i = 0; i < level0.size(); ++i) {
    const uint8_t* p = rgba + i * 4;
    level0[i] = uint32_t{p[0]} | (uint32_t{p[1]} << 8) | (uint32_t{p[2]} << 16) | (uint32_t{p[3]} << 24);
  }
  out.encoding_ = encoding;
  out.format_ = TexelFormat::Rgba8;
  out.la_.clear();
  TextureBuilder::build(width, height, std::move(level0), encoding, out.texels_, out.levels_, parallel);
  return std::nullopt;
}

std::optional<TextureError> Texture::from_la8(int width, int height, const uint8_t* la, Texture& out,
                                              const ParallelFor& parallel) {
  if (auto e = check_size(width, height)) return e;
  if (la == nullptr) return TextureError{"la", "is null"};
  std::vector<uint32_t> level0(size_t(width) * size_t(height));
  for (size_t i = 0; i < level0.size(); ++i) {
    const uint32_t l = la[2 * i], a = la[2 * i + 1];
    level0[i] = l | (l << 8) | (l << 16) | (a << 24);
  }
  out.encoding_ = TexelEncoding::Linear;
  out.format_ = TexelFormat::La8;
  std::vector<uint32_t> rgba;
  TextureBuilder::build(width, height, std::move(level0), TexelEncoding::Linear, rgba, out.levels_, parallel);
  // Equal channels average to equal channels, so every level is still grey: keep L and A of
  // every texel, padding included. The spare texel after the last level keeps a 32-bit read at
  // any texel inside the storage (the sampler never reads it).
  out.texels_.clear();
  out.la_.resize(rgba.size() + 1);
  for (size_t i = 0; i < rgba.size(); ++i) out.la_[i] = uint16_t((rgba[i] & 255u) | ((rgba[i] >> 16) & 0xFF00u));
  out.la_.back() = 0;
  return std::nullopt;
}

std::optional<TextureError> Texture::from_linear_float(int width, int height, const float* rgba,
                                                       TexelEncoding encoding, Texture& out,
                                                       const ParallelFor& parallel, SourceAlpha alpha) {
  if (auto e = check_size(width, height)) return e;
  if (rgba == nullptr) return TextureError{"rgba", "is null"};
  const size_t n = size_t(width) * size_t(height);
  const bool opaque = alpha == SourceAlpha::ignored;
  const auto alpha_byte = [&](size_t texel) { return opaque ? uint8_t{255} : to_byte(rgba[4 * texel + 3]); };
  // Checked in order first, so the error names the first bad value whatever runs the packing.
  for (size_t i = 0; i < 4 * n; ++i) {
    const float x = rgba[i];
    if (opaque && i % 4 == 3) continue;
    if (!(x >= 0.0f && x <= 1.0f)) {
      static const char* const kChannel = "rgba";
      return TextureError{"rgba[" + std::to_string(i) + "]",
                          "texel (" + std::to_string(i / 4 % size_t(width)) + ", " +
                              std::to_string(i / 4 / size_t(width)) + ") channel " + kChannel[i % 4] + " = " +
                              std::to_string(x) + " is outside [0, 1] (textures store 8 bits per channel)"};
    }
  }
  std::vector<uint32_t> level0(n);
  for_row_items(height, size_t(width), parallel, [&](int y_begin, int y_end) {
    const size_t first = size_t(y_begin) * size_t(width), last = size_t(y_end) * size_t(width);
    if (encoding == TexelEncoding::Srgb) {
      // Colour through the SIMD search (srgb_bytes: srgb_byte bit for bit), alpha linearly,
      // as encode() packs a texel.
      std::vector<uint8_t> bytes(4 * (last - first));
      srgb_bytes(rgba + 4 * first, bytes.data(), bytes.size());
      for (size_t i = first; i < last; ++i) {
        const uint8_t* b = bytes.data() + 4 * (i - first);
        level0[i] = uint32_t{b[0]} | (uint32_t{b[1]} << 8) | (uint32_t{b[2]} << 16) | (uint32_t{alpha_byte(i)} << 24);
      }
      return;
    }
    for (size_t i = first; i < last; ++i) {
      Texel t{};
      for (int ch = 0; ch < 4; ++ch) t.c[ch] = rgba[i * 4 + size_t(ch)];
      if (opaque) t.c[3] = 1.0f;
      level0[i] = encode(t, encoding);
    }
  });
  out.encoding_ = encoding;
  out.format_ = TexelFormat::Rgba8;
  out.la_.clear();
  TextureBuilder::build(width, height, std::move(level0), encoding, out.texels_, out.levels_, parallel);
  return std::nullopt;
}

namespace {

// `count` layers of `layer_bytes` each from `bytes`, each built by make(layer bytes, texture),
// as items of `parallel` when given (each layer on one thread); the first failing layer in
// order names the error.
template <class Make>
std::optional<TextureError> build_layers(int width, int height, int count, const uint8_t* bytes, const char* field,
                                         size_t layer_bytes, Make&& make, TextureArray& out,
                                         const ParallelFor& parallel) {
  if (count < 1) return TextureError{"count", std::to_string(count) + " layers: need at least 1"};
  if (auto e = check_size(width, height)) return e;
  if (bytes == nullptr) return TextureError{field, "is null"};
  std::vector<Texture> layers(static_cast<size_t>(count));
  std::vector<std::optional<TextureError>> errors(static_cast<size_t>(count));
  for_each_item(parallel, size_t(count), [&](size_t s) { errors[s] = make(bytes + s * layer_bytes, layers[s]); });
  for (size_t s = 0; s < size_t(count); ++s)
    if (auto& e = errors[s]) {
      e->field = "layer " + std::to_string(s) + " " + e->field;
      return e;
    }
  out.layers = std::move(layers);
  return std::nullopt;
}

}  // namespace

std::optional<TextureError> TextureArray::from_rgba8_layers(int width, int height, int count,
                                                            const uint8_t* rgba,
                                                            TexelEncoding encoding,
                                                            TextureArray& out, const ParallelFor& parallel) {
  return build_layers(width, height, count, rgba, "rgba", size_t(width) * size_t(height) * 4,
                      [&](const uint8_t* layer, Texture& t) { return Texture::from_rgba8(width, height, layer, encoding, t); },
                      out, parallel);
}

std::optional<TextureError> TextureArray::from_la8_layers(int width, int height, int count, const uint8_t* la,
                                                          TextureArray& out, const ParallelFor& parallel) {
  return build_layers(width, height, count, la, "la", size_t(width) * size_t(height) * 2,
                      [&](const uint8_t* layer, Texture& t) { return Texture::from_la8(width, height, layer, t); }, out,
                      parallel);
}

const float* srgb8_to_linear_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = float(srgb_table_double()[size_t(i)]);
    return t;
  }();
  return table.data();
}

double block_lod(const float* u, const float* v, int width, int height) {
  return 0.5 * std::log2(block_lod_length2(u, v, width, height));
}

// ---- Reference sampler: written independently of the kernel, in double. ----
namespace {

// Texel index along one axis of `size`, for integer position i.
int64_t wrap_index(int64_t i, int64_t size, Wrap wrap) {
  if (wrap == Wrap::Repeat) return ((i % size) + size) % size;
  if (wrap == Wrap::Mirror) {  // period 2 size, the second half reversed
    const int64_t m = ((i % (2 * size)) + 2 * size) % (2 * size);
    return m < size ? m : 2 * size - 1 - m;
  }
  return std::clamp<int64_t>(i, 0, size - 1);
}

// Continuous texel-space coordinate along one axis (texel centres at integers + 0.5).
double texel_coord(float c, int size, Wrap wrap) {
  double x = double(c);
  if (wrap == Wrap::Repeat) x -= std::floor(x);
  if (wrap == Wrap::Mirror) x -= 2.0 * std::floor(0.5 * x);  // one period: wrap_index reflects
  x *= size;
  // Only keeps the integer conversion defined; changes no texel choice.
  return std::clamp(x, -2.0, double(wrap == Wrap::Mirror ? 2 * size : size) + 2.0);
}

// Straight colour and alpha, weighted (the fill makes premultiplication unnecessary).
struct RefAcc {
  double c[4] = {};
  void add(const Texel& t, double w) {
    for (int ch = 0; ch < 4; ++ch) c[ch] += w * t.c[ch];
  }
};

void ref_bilinear(const Texture& tex, int k, const SamplerState& s, float u, float v, double weight,
                  RefAcc& acc) {
  const MipLevel& L = tex.level(k);
  const double x = texel_coord(u, L.width, s.wrap_u) - 0.5;
  const double y = texel_coord(v, L.height, s.wrap_v) - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int64_t xi = wrap_index(int64_t(fx) + i, L.width, s.wrap_u);
      const int64_t yi = wrap_index(int64_t(fy) + j, L.height, s.wrap_v);
      const double w = (i ? ax : 1.0 - ax) * (j ? ay : 1.0 - ay) * weight;
      acc.add(decode(tex.texel(k, int(xi), int(yi)), tex.encoding()), w);
    }
}

double ref_lod(const Texture& tex, const float* u, const float* v, float bias) {
  // Mean of the 12 horizontal and 12 vertical neighbour differences of the block; each row's
  // (column's) three differences telescope to last - first. The sums run in the kernel's
  // order, in pairs: with extreme inputs (1e38 next to 1) they cancel catastrophically even in
  // double, and the order is then part of the definition.
  auto pairs = [](double a, double b, double c, double e) { return (a + b) + (c + e); };
  auto row = [](const float* p, int r) { return double(p[4 * r + 3]) - double(p[4 * r]); };
  auto column = [](const float* p, int c) { return double(p[12 + c]) - double(p[c]); };
  const double d[2][2] = {  // [x or y][u or v]
      {pairs(row(u, 0), row(u, 1), row(u, 2), row(u, 3)), pairs(row(v, 0), row(v, 1), row(v, 2), row(v, 3))},
      {pairs(column(u, 0), column(u, 1), column(u, 2), column(u, 3)),
       pairs(column(v, 0), column(v, 1), column(v, 2), column(v, 3))}};
  const double W = tex.width(), H = tex.height();
  const double lx = std::hypot(d[0][0] * W / 12, d[0][1] * H / 12);
  const double ly = std::hypot(d[1][0] * W / 12, d[1][1] * H / 12);
  const double lambda = std::log2(std::max(lx, ly)) + bias;
  const double top = tex.levels() - 1;
  return lambda > 0.0 ? std::min(lambda, top) : 0.0;  // NaN and -inf give 0
}

}  // namespace

void sample_reference(const Texture& tex, const SamplerState& s, const float* u, const float* v,
                      size_t lanes, double* const out[4], const uint16_t* block_mask) {
  if (tex.empty()) throw std::invalid_argument("sample_reference: texture is empty");
  if (lanes % 16 != 0) throw std::invalid_argument("sample_reference: lanes must be a multiple of 16");
  for (size_t b = 0; b < lanes; b += 16) {
    const bool mipmapped = s.filter == Filter::Trilinear || s.filter == Filter::BilinearMip;
    const double lambda = mipmapped ? ref_lod(tex, u + b, v + b, s.lod_bias) : 0.0;
    const int l0 = s.filter == Filter::BilinearMip ? nearest_mip_level(lambda) : int(std::floor(lambda));
    const int l1 = std::min(l0 + 1, tex.levels() - 1);
    const double t = lambda - l0;
    for (size_t i = b; i < b + 16; ++i) {
      if (block_mask && !(block_mask[b / 16] >> (i - b) & 1u)) {
        for (int ch = 0; ch < 4; ++ch) out[ch][i] = 0.0;
        continue;
      }
      if (s.filter == Filter::Nearest) {
        const MipLevel& L = tex.level(0);
        const int64_t xi = wrap_index(int64_t(std::floor(texel_coord(u[i], L.width, s.wrap_u))), L.width, s.wrap_u);
        const int64_t yi = wrap_index(int64_t(std::floor(texel_coord(v[i], L.height, s.wrap_v))), L.height, s.wrap_v);
        const Texel tx = decode(tex.texel(0, int(xi), int(yi)), tex.encoding());
        for (int ch = 0; ch < 4; ++ch) out[ch][i] = tx.c[ch];
        continue;
      }
      RefAcc acc;
      ref_bilinear(tex, l0, s, u[i], v[i], s.filter == Filter::Trilinear ? 1.0 - t : 1.0, acc);
      if (s.filter == Filter::Trilinear) ref_bilinear(tex, l1, s, u[i], v[i], t, acc);
      for (int ch = 0; ch < 4; ++ch) out[ch][i] = acc.c[ch];
    }
  }
}

}  // namespace pelt::raster
