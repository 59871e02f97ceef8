// A block's 16-bit lane mask (bit l = lane l, FragmentBatch::mask) as vector masks, shared by
// the tile and texture kernels. A Highway per-target header: included after
// hwy/foreach_target.h, it is compiled once for every target by the toggle guard below.

#if defined(PELT_RASTER_BLOCK_MASK_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PELT_RASTER_BLOCK_MASK_INL_H_
#undef PELT_RASTER_BLOCK_MASK_INL_H_
#else
#define PELT_RASTER_BLOCK_MASK_INL_H_
#endif

#include "hwy/highway.h"
#include "raster/config.h"

HWY_BEFORE_NAMESPACE();
namespace pelt::raster::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The bits of one vector group of a block mask: N lanes (N <= 16; one AVX-512 vector is a block).
HWY_INLINE uint32_t GroupBits() {
  const size_t n = hn::Lanes(hn::ScalableTag<float>());
  return n >= size_t(kBlockLanes) ? 0xFFFFu : (1u << n) - 1u;
}

// Lanes [g N, g N + N) of block mask `bits` as a float vector mask.
HWY_INLINE hn::Mask<hn::ScalableTag<float>> BitsToMask(uint32_t bits, size_t g) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const auto lane_bits = hn::LoadU(di, kLaneBit + g * hn::Lanes(di));
  return hn::RebindMask(df, hn::Ne(hn::And(hn::Set(di, static_cast<int32_t>(bits)), lane_bits), hn::Zero(di)));
}

}  // namespace pelt::raster::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // PELT_RASTER_BLOCK_MASK_INL_H_ toggle
