// The vertex stage of the front end, written once with Highway and compiled for every
// target. Each step repeats the IEEE operations of the scalar code (glm's mat4 * vec4,
// vertex_outcode, snap_vertex) in the same order; with -ffp-contract=off nothing is fused,
// so every target writes exactly what transform_vertices_reference writes (in the same
// floating-point mode: the renderer's workers set FTZ/DAZ, which both honour).

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/vertex_kernels.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <bit>
#include <cstddef>
#include <cstring>

#include "raster/config.h"
#include "raster/vertex_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace pelt::raster {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The outcode and the snap need double, so the double vector sets the width: N vertices
// per step, their floats in half a vector.
using DD = hn::ScalableTag<double>;
using DF = hn::Rebind<float, DD>;
using DU = hn::RebindToUnsigned<DD>;  // one 64-bit word of N FrontVertex records
using DI32 = hn::Rebind<int32_t, DD>;
using DU32 = hn::Rebind<uint32_t, DD>;
using VD = hn::Vec<DD>;
using VF = hn::Vec<DF>;
using VU = hn::Vec<DU>;

// std::clamp. Min and Max may differ from it only for NaN and for +0 against -0, and
// neither reaches a lane that is snapped: its coordinates are finite, w >= kMinW, and the
// only zero bound is depth's, where a + 0.5 is never -0.
HWY_INLINE VD Clamp(VD v, VD lo, VD hi) { return hn::Min(hn::Max(v, lo), hi); }

// Vertices [0, N) of the arrays: positions xyz and clip xyzw interleaved, and each
// FrontVertex as four 64-bit words {snap.x | snap.y << 32, depth, inv_w, code | w << 32}.
HWY_INLINE void TransformStep(const float* HWY_RESTRICT m, const float* HWY_RESTRICT pos,
                              Viewport vp, ClipBounds b, float* HWY_RESTRICT clip,
                              uint64_t* HWY_RESTRICT words) {
  const DD dd;
  const DF df;
  const DU du;
  VF px, py, pz;
  hn::LoadInterleaved3(df, pos, px, py, pz);
  // glm's mat4 * vec4 (type_mat4x4.inl): (m[0] x + m[1] y) + (m[2] z + m[3] * 1) per row;
  // GCC folds m[3] * 1.0f to m[3], and so do we.
  const auto row = [&](int r) {
    return hn::Add(hn::Add(hn::Mul(hn::Set(df, m[r]), px), hn::Mul(hn::Set(df, m[4 + r]), py)),
                   hn::Add(hn::Mul(hn::Set(df, m[8 + r]), pz), hn::Set(df, m[12 + r])));
  };
  const VF cx = row(0), cy = row(1), cz = row(2), cw = row(3);
  hn::StoreInterleaved4(cx, cy, cz, cw, df, clip);

  // vertex_outcode. Lanes with a non-finite coordinate compute garbage here (no traps:
  // FP exceptions stay masked) and are overwritten with kNonFinite below.
  const VD x = hn::PromoteTo(dd, cx), y = hn::PromoteTo(dd, cy);
  const VD z = hn::PromoteTo(dd, cz), w = hn::PromoteTo(dd, cw);
  const VD zero = hn::Zero(dd);
  const VD gx = hn::Mul(hn::Set(dd, b.guard_x), w), gy = hn::Mul(hn::Set(dd, b.guard_y), w);
  VU code = hn::Zero(du);
  const auto set_if = [&](hn::Mask<DD> outside, uint32_t bit) {
    code = hn::Or(code, hn::IfThenElseZero(hn::RebindMask(du, outside), hn::Set(du, bit)));
  };
  set_if(hn::Lt(hn::Add(z, w), zero), kNear);
  set_if(hn::Lt(hn::Sub(w, z), zero), kFar);
  set_if(hn::Lt(hn::Sub(w, hn::Set(dd, kMinW)), zero), kPosW);
  set_if(hn::Lt(hn::Sub(gx, x), zero), kGuardPX);
  set_if(hn::Lt(hn::Add(gx, x), zero), kGuardNX);
  set_if(hn::Lt(hn::Sub(gy, y), zero), kGuardPY);
  set_if(hn::Lt(hn::Add(gy, y), zero), kGuardNY);
  set_if(hn::Gt(x, w), kViewPX);
  set_if(hn::Lt(x, hn::Neg(w)), kViewNX);
  set_if(hn::Gt(y, w), kViewPY);
  set_if(hn::Lt(y, hn::Neg(w)), kViewNY);
  // x - x is 0 for a finite x and NaN for an infinite or NaN one, which poisons the sum.
  const auto finite = hn::Eq(hn::Add(hn::Add(hn::Sub(x, x), hn::Sub(y, y)),
                                     hn::Add(hn::Sub(z, z), hn::Sub(w, w))),
                             zero);
  code = hn::IfThenElse(hn::RebindMask(du, finite), code, hn::Set(du, kNonFinite));
  const auto snapped = hn::RebindMask(
      dd, hn::Eq(hn::And(code, hn::Set(du, kClipPlaneBits | kNonFinite)), hn::Zero(du)));

  // snap_vertex. Lanes that are not snapped may hold NaN or values beyond int32 (w = 0,
  // w < 0, huge x): they are zeroed before the conversion to int, which is undefined for
  // those in the portable targets, and their snap is written as zeros. Round is lrint in
  // the default rounding mode, to nearest with ties to even, on every target.
  const VD half = hn::Set(dd, 0.5);
  const VD inv_w = hn::Div(hn::Set(dd, 1.0), w);
  const VD sx = hn::Mul(hn::Add(hn::Mul(hn::Mul(x, inv_w), half), half),
                        hn::Set(dd, static_cast<double>(vp.width)));
  const VD sy = hn::Mul(hn::Sub(half, hn::Mul(hn::Mul(y, inv_w), half)),
                        hn::Set(dd, static_cast<double>(vp.height)));
  const VD lo = hn::Set(dd, static_cast<double>(-kGuardBand));
  const VD sxc = Clamp(sx, lo, hn::Set(dd, static_cast<double>(vp.width + kGuardBand)));
  const VD syc = Clamp(sy, lo, hn::Set(dd, static_cast<double>(vp.height + kGuardBand)));
  const VD depth = Clamp(hn::Add(hn::Mul(hn::Mul(z, inv_w), half), half), zero, hn::Set(dd, 1.0));
  const VD scale = hn::Set(dd, static_cast<double>(kSubPixelScale));
  const DI32 di32;
  const auto ix = hn::DemoteTo(di32, hn::Round(hn::IfThenElseZero(snapped, hn::Mul(sxc, scale))));
  const auto iy = hn::DemoteTo(di32, hn::Round(hn::IfThenElseZero(snapped, hn::Mul(syc, scale))));

  const auto widen = [&](auto v32) { return hn::PromoteTo(du, hn::BitCast(DU32(), v32)); };
  hn::StoreInterleaved4(hn::Or(widen(ix), hn::ShiftLeft<32>(widen(iy))),
                        hn::BitCast(du, hn::IfThenElseZero(snapped, depth)),
                        hn::BitCast(du, hn::IfThenElseZero(snapped, inv_w)),
                        hn::Or(code, hn::ShiftLeft<32>(widen(cw))), du, words);
}

void TransformVertices(const float* HWY_RESTRICT m, const float* HWY_RESTRICT pos, size_t count,
                       Viewport vp, ClipBounds b, float* HWY_RESTRICT clip,
                       FrontVertex* HWY_RESTRICT front) {
  // vp and b by value: the stores through clip and front could otherwise alias them, and
  // the loop would reload and convert them every step.
  const size_t n = hn::Lanes(DD());
  uint64_t* words = reinterpret_cast<uint64_t*>(front);
  size_t i = 0;
  for (; i + n <= count; i += n) TransformStep(m, pos + 3 * i, vp, b, clip + 4 * i, words + 4 * i);
  if (i == count) return;
  // The last partial vector runs on a zero-padded copy: the loads and stores of whole
  // vectors never touch memory past the draw's last vertex.
  constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
  const size_t rest = count - i;
  float pos_pad[3 * kMaxLanes] = {};
  float clip_pad[4 * kMaxLanes];
  uint64_t words_pad[4 * kMaxLanes];
  std::memcpy(pos_pad, pos + 3 * i, rest * 3 * sizeof(float));
  TransformStep(m, pos_pad, vp, b, clip_pad, words_pad);
  std::memcpy(clip + 4 * i, clip_pad, rest * 4 * sizeof(float));
  std::memcpy(words + 4 * i, words_pad, rest * sizeof(FrontVertex));
}

}  // namespace HWY_NAMESPACE
}  // namespace pelt::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::raster {

// TransformStep's view of the data.
static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::vec4) == 4 * sizeof(float));
static_assert(sizeof(glm::mat4) == 16 * sizeof(float));  // column-major: m[4 c + r]
static_assert(std::endian::native == std::endian::little);
static_assert(offsetof(FrontVertex, snap) == 0 && offsetof(SnappedVertex, x) == 0 &&
              offsetof(SnappedVertex, y) == 4 && offsetof(SnappedVertex, depth) == 8 &&
              offsetof(SnappedVertex, inv_w) == 16 && offsetof(FrontVertex, code) == 24 &&
              offsetof(FrontVertex, w) == 28);

HWY_EXPORT(TransformVertices);

void transform_vertices(const glm::mat4& clip_from_object, const glm::vec3* positions,
                        uint32_t first, uint32_t count, const Viewport& vp,
                        const ClipBounds& bounds, glm::vec4* clip, FrontVertex* front) {
  if (count == 0) return;
  HWY_DYNAMIC_DISPATCH(TransformVertices)(&clip_from_object[0][0], &positions[first].x, count, vp,
                                          bounds, &clip[first].x, front + first);
}

void transform_vertices_reference(const glm::mat4& clip_from_object, const glm::vec3* positions,
                                  uint32_t first, uint32_t count, const Viewport& vp,
                                  const ClipBounds& bounds, glm::vec4* clip, FrontVertex* front) {
  for (uint32_t v = first; v < first + count; ++v) {
    const glm::vec4 c = clip_from_object * glm::vec4(positions[v], 1.0f);
    clip[v] = c;
    FrontVertex& f = front[v];
    f.code = vertex_outcode(c, bounds);
    f.w = c.w;
    // Snapped once here for every triangle that shares the vertex and needs no clipping.
    f.snap = (f.code & (kClipPlaneBits | kNonFinite))
                 ? SnappedVertex{}
                 : snap_vertex(ClipVertex{c.x, c.y, c.z, c.w, 0.0, 0.0}, vp);
  }
}

}  // namespace pelt::raster
#endif  // HWY_ONCE
