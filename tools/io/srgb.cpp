#include "tools/io/srgb.h"

#include <cmath>
#include <vector>

#include "raster/texture.h"

namespace pelt::io {
namespace {

double srgb_encode(double x) {
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

}  // namespace

uint8_t linear_to_srgb8(float x) {
  if (!(x > 0.0f)) return 0;  // also NaN
  if (x >= 1.0f) return 255;
  return static_cast<uint8_t>(std::floor(255.0 * srgb_encode(x) + 0.5));
}

uint8_t linear_to_unorm8(float x) {
  if (!(x > 0.0f)) return 0;
  if (x >= 1.0f) return 255;
  return static_cast<uint8_t>(std::floor(255.0 * static_cast<double>(x) + 0.5));
}

// The texture builder's decoding and encoding (raster/texture.h): the same transfer function
// in double, so images and textures share one table and one boundary search.
float srgb8_to_linear(uint8_t b) { return raster::srgb8_to_linear_table()[b]; }

float srgb8_threshold(int b) { return raster::srgb_float_threshold(b); }

uint8_t linear_to_srgb8_fast(float x) { return raster::srgb_byte(x); }

void encode_srgb8_span(const float* src, uint8_t* dst, size_t n) { raster::srgb_bytes(src, dst, n); }

void encode_srgb8_rows(const float* src, size_t src_row_stride, uint8_t* dst, size_t dst_row_stride, int width,
                       int height, int channels, Alpha alpha) {
  const bool has_alpha = channels == 2 || channels == 4;
  const size_t nc = static_cast<size_t>(channels);
  const size_t row = static_cast<size_t>(width) * nc;
  const bool divide = has_alpha && alpha == Alpha::premultiplied;
  std::vector<float> straight(divide ? row : 0);
  for (int y = 0; y < height; ++y) {
    const float* s = src + static_cast<size_t>(y) * src_row_stride;
    uint8_t* d = dst + static_cast<size_t>(y) * dst_row_stride;
    if (divide) {
      // Alpha 1 (every opaque pixel) keeps its colour bit for bit, so an image without
      // transparency writes the same bytes as before the division existed.
      for (size_t p = 0; p < row; p += nc) {
        const float a = s[p + nc - 1];
        for (size_t c = 0; c + 1 < nc; ++c)
          straight[p + c] = !(a > 0.0f) ? 0.0f : a >= 1.0f ? s[p + c] : s[p + c] / a;
        straight[p + nc - 1] = a;
      }
      s = straight.data();
    }
    // The whole row through the sRGB curve, then the alpha channel again, linearly.
    encode_srgb8_span(s, d, row);
    if (has_alpha)
      for (size_t a = nc - 1; a < row; a += nc) d[a] = linear_to_unorm8(s[a]);
  }
}

}  // namespace pelt::io
