// srgb_byte over whole spans of floats with Highway, compiled for every target and dispatched once
// per call. Per vector: the float's bucket (its exponent and top 7 mantissa bits, as
// SrgbBoundaries buckets doubles) gives the byte at the bucket's start through one
// gather; a bucket spans less than one byte step (checked when the tables are built), so one
// gathered threshold and one compare finish the byte. Vectors of only 0s and 1s (or what
// clamps to them) skip both gathers: without that the kernel was slower than the scalar
// search on rendered frames, whose background and alpha exit early there. Bit for bit the
// scalar table search, which the tests compare it with on every target.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/srgb_kernels.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <array>
#include <bit>
#include <cstddef>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "raster/texture.h"

#ifndef PELT_RASTER_SRGB_TABLES_ONCE
#define PELT_RASTER_SRGB_TABLES_ONCE
namespace pelt::raster::detail {

// The float view of SrgbBoundaries: the bucket bytes widened for a 32-bit gather, and
// threshold[b] = srgb_float_threshold(b) with threshold[255] = +inf.
struct SrgbSpanTables {
  static constexpr uint32_t kFirstBucket = std::bit_cast<uint32_t>(float(SrgbBoundaries::kFloor)) >> 16;
  static constexpr int32_t kBuckets = int32_t((std::bit_cast<uint32_t>(1.0f) >> 16) - kFirstBucket);
  std::array<int32_t, size_t(kBuckets)> bucket;
  std::array<float, 256> threshold;
};
const SrgbSpanTables& srgb_span_tables();

}  // namespace pelt::raster::detail
#endif

HWY_BEFORE_NAMESPACE();
namespace pelt::raster {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void SrgbBytes(const float* HWY_RESTRICT src, uint8_t* HWY_RESTRICT dst, size_t n) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const hn::RebindToUnsigned<decltype(df)> du;
  const hn::Rebind<uint8_t, decltype(df)> d8;
  const size_t N = hn::Lanes(df);
  const detail::SrgbSpanTables& t = detail::srgb_span_tables();
  const auto floor = hn::Set(df, float(SrgbBoundaries::kFloor));
  const auto one = hn::Set(df, 1.0f);
  const auto first = hn::Set(di, int32_t(detail::SrgbSpanTables::kFirstBucket));
  const auto last = hn::Set(di, detail::SrgbSpanTables::kBuckets - 1);
  size_t i = 0;
  for (; i + N <= n; i += N) {
    const auto x = hn::LoadU(df, src + i);
    // Vectors of only 0s and 1s and what clamps to them (a frame's background, its alpha,
    // saturated colour) skip the gathers: most of a rendered frame's vectors.
    const auto high = hn::Ge(x, one);
    if (hn::AllTrue(df, hn::Or(hn::Lt(x, floor), high))) {
      hn::StoreU(hn::DemoteTo(d8, hn::IfThenElseZero(hn::RebindMask(di, high), hn::Set(di, 255))), d8, dst + i);
      continue;
    }
    // Lanes outside [kFloor, 1) (negative, NaN, tiny, >= 1) read bucket 0 or the last and
    // are replaced below.
    const auto k = hn::Min(hn::Max(hn::Sub(hn::BitCast(di, hn::ShiftRight<16>(hn::BitCast(du, x))), first),
                                   hn::Zero(di)),
                           last);
    const auto b0 = hn::GatherIndex(di, t.bucket.data(), k);
    const auto above = hn::Ge(x, hn::GatherIndex(df, t.threshold.data(), b0));
    auto b = hn::Sub(b0, hn::VecFromMask(di, hn::RebindMask(di, above)));  // + 1 where above
    b = hn::IfThenElse(hn::RebindMask(di, high), hn::Set(di, 255), b);
    b = hn::IfThenElseZero(hn::RebindMask(di, hn::Ge(x, floor)), b);  // also NaN
    hn::StoreU(hn::DemoteTo(d8, b), d8, dst + i);
  }
  for (; i < n; ++i) dst[i] = srgb_byte(src[i]);
}

}  // namespace HWY_NAMESPACE
}  // namespace pelt::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::raster {
namespace detail {

const SrgbSpanTables& srgb_span_tables() {
  static const SrgbSpanTables tables = [] {
    SrgbSpanTables t{};
    for (int b = 0; b < 255; ++b) t.threshold[size_t(b)] = srgb_float_threshold(b);
    t.threshold[255] = std::numeric_limits<float>::infinity();
    for (int32_t k = 0; k < SrgbSpanTables::kBuckets; ++k) {
      const uint32_t first_bits = (SrgbSpanTables::kFirstBucket + uint32_t(k)) << 16;
      const float lo = std::bit_cast<float>(first_bits), hi = std::bit_cast<float>(first_bits | 0xFFFFu);
      const uint8_t b = srgb_byte(lo);
      // The kernel's single compare needs every bucket to hold at most one byte boundary.
      if (srgb_byte(hi) > b + 1)
        throw std::logic_error("srgb_span_tables: bucket " + std::to_string(k) + " spans two sRGB byte steps");
      t.bucket[size_t(k)] = b;
    }
    return t;
  }();
  return tables;
}

}  // namespace detail

HWY_EXPORT(SrgbBytes);

void srgb_bytes(const float* src, uint8_t* dst, size_t n) { HWY_DYNAMIC_DISPATCH(SrgbBytes)(src, dst, n); }

float srgb_float_threshold(int b) {
  // The smallest float at or above the boundary (every float is a double).
  const double t = srgb_byte_threshold(b);
  const float f = static_cast<float>(t);
  return double(f) < t ? std::nextafter(f, 2.0f) : f;
}

}  // namespace pelt::raster
#endif  // HWY_ONCE
