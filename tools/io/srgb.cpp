#include "tools/io/srgb.h"

#include <array>
#include <bit>
#include <cmath>

namespace pelt::io {
namespace {

double srgb_encode(double x) {
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

constexpr uint32_t kOneBits = 0x3F800000u;  // bit pattern of 1.0f
constexpr int kBucketShift = 16;            // fast table: one entry per 2^16 floats

struct Tables {
  std::array<float, 255> threshold;                       // threshold[b]: first x with byte > b
  std::array<uint8_t, (kOneBits >> kBucketShift) + 1> bucket;  // byte of a bucket's first float
  std::array<float, 256> decode;
};

const Tables& tables() {
  static const Tables t = [] {
    Tables t{};
    // Non-negative floats are ordered like their bit patterns, and the byte is a
    // non-decreasing function of x, so each boundary is found by bisection on the bits.
    for (int b = 0; b < 255; ++b) {
      uint32_t lo = 0, hi = kOneBits;  // byte(lo) <= b < byte(hi) is kept invariant
      while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        (linear_to_srgb8(std::bit_cast<float>(mid)) > b ? hi : lo) = mid;
      }
      t.threshold[b] = std::bit_cast<float>(hi);
    }
    for (size_t k = 0; k < t.bucket.size(); ++k)
      t.bucket[k] = linear_to_srgb8(std::bit_cast<float>(static_cast<uint32_t>(k << kBucketShift)));
    for (int b = 0; b < 256; ++b) {
      const double s = b / 255.0;
      t.decode[b] = static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return t;
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

float srgb8_to_linear(uint8_t b) { return tables().decode[b]; }

float srgb8_threshold(int b) { return tables().threshold[b]; }

uint8_t linear_to_srgb8_fast(float x) {
  if (!(x > 0.0f)) return 0;
  if (x >= 1.0f) return 255;
  const Tables& t = tables();
  // The bucket gives the byte of the bucket's first float; within one bucket the byte
  // rises by at most a step or two, found against the exact thresholds.
  unsigned b = t.bucket[std::bit_cast<uint32_t>(x) >> kBucketShift];
  while (b < 255 && x >= t.threshold[b]) ++b;
  return static_cast<uint8_t>(b);
}

void encode_srgb8_rows(const float* src, size_t src_row_stride, uint8_t* dst,
                       size_t dst_row_stride, int width, int height, int channels) {
  const bool has_alpha = channels == 2 || channels == 4;
  const int colour = has_alpha ? channels - 1 : channels;
  for (int y = 0; y < height; ++y) {
    const float* s = src + static_cast<size_t>(y) * src_row_stride;
    uint8_t* d = dst + static_cast<size_t>(y) * dst_row_stride;
    for (int x = 0; x < width; ++x, s += channels, d += channels) {
      for (int c = 0; c < colour; ++c) d[c] = linear_to_srgb8_fast(s[c]);
      if (has_alpha) d[colour] = linear_to_unorm8(s[colour]);
    }
  }
}

}  // namespace pelt::io
