// Three-component float vectors of SIMD lanes, shared by the shading kernels (skin_kernels.cc,
// fur_lighting.cc, normal_map_kernels.cc). A Highway per-target header: included after hwy/foreach_target.h, it is
// compiled once for every target by the toggle guard below.
//
// Dot products are evaluated as (x x + y y) + z z, each product rounded, in that order: the
// kernels' tolerances against their double references were set with exactly this rounding.

#if defined(PELT_SHADING_VEC3_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PELT_SHADING_VEC3_INL_H_
#undef PELT_SHADING_VEC3_INL_H_
#else
#define PELT_SHADING_VEC3_INL_H_
#endif

#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace pelt::shading::HWY_NAMESPACE::vec3 {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

struct V3 {
  V x, y, z;
};

HWY_INLINE V Dot(const V3& a, const V3& b) {
  return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}
HWY_INLINE V3 Select(M m, const V3& a, const V3& b) {
  return {hn::IfThenElse(m, a.x, b.x), hn::IfThenElse(m, a.y, b.y), hn::IfThenElse(m, a.z, b.z)};
}
HWY_INLINE V3 Load3(D d, const float* const p[3], size_t i) {
  return {hn::Load(d, p[0] + i), hn::Load(d, p[1] + i), hn::Load(d, p[2] + i)};
}
HWY_INLINE V3 LoadU3(D d, const float* const p[3], size_t i) {
  return {hn::LoadU(d, p[0] + i), hn::LoadU(d, p[1] + i), hn::LoadU(d, p[2] + i)};
}
HWY_INLINE V3 Scale(const V3& a, V s) { return {hn::Mul(a.x, s), hn::Mul(a.y, s), hn::Mul(a.z, s)}; }
HWY_INLINE V3 Cross(const V3& a, const V3& b) {
  return {hn::Sub(hn::Mul(a.y, b.z), hn::Mul(a.z, b.y)), hn::Sub(hn::Mul(a.z, b.x), hn::Mul(a.x, b.z)),
          hn::Sub(hn::Mul(a.x, b.y), hn::Mul(a.y, b.x))};
}
HWY_INLINE V Clamp(V x, V lo, V hi) { return hn::Min(hn::Max(x, lo), hi); }

}  // namespace pelt::shading::HWY_NAMESPACE::vec3
HWY_AFTER_NAMESPACE();

#endif  // PELT_SHADING_VEC3_INL_H_
