// setup_snapped for a batch of triangles, side by side in double lanes (4 on AVX2, 8 on
// AVX-512). A dense mesh's front end spent most of its time setting triangles up one by
// one (a mispredicted cull branch per triangle and two-lane doubles at best); here the
// cull, bounds, edges and planes of several triangles are one instruction stream.
//
// Bit-exactness with setup_snapped (the scalar reference, tested side by side): snapped
// coordinates are below 2^23 in magnitude (config.h), so every integer quantity of set-up
// (differences, twice the area, edge cross products, the edge constant before its floor
// division) stays below 2^53 and is exact in double, and divisions by 256 are exact
// scalings. The planes use the same IEEE operations in the same order (no fused
// multiply-add: -ffp-contract=off, and Mul/Add here).

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/setup_kernels.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "raster/config.h"
#include "raster/setup.h"

HWY_BEFORE_NAMESPACE();
namespace pelt::raster {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

using DD = hn::ScalableTag<double>;
using VD = hn::Vec<DD>;

// Everything set-up computes, per batch entry, before it is written as TriSetup.
struct BatchResult {
  alignas(64) double ok[kSetupBatch];  // non-zero: the triangle has pixels and is not culled
  alignas(64) double bounds[4][kSetupBatch];  // x0, y0, xmax, ymax
  alignas(64) double a[3][kSetupBatch], b[3][kSetupBatch], c[3][kSetupBatch];
  alignas(64) float plane[4][3][kSetupBatch];  // (z, inv_w, b1w, b2w) x (ref, dx, dy)
};

struct Vertex {
  VD x, y, depth, inv_w;
};

// make_edge (setup.cpp) in double.
HWY_INLINE void Edge(const Vertex& i, const Vertex& j, double* a_out, double* b_out, double* c_out) {
  const DD dd;
  const VD a = hn::Sub(i.y, j.y), b = hn::Sub(j.x, i.x);
  const VD cross = hn::Sub(hn::Mul(i.x, j.y), hn::Mul(j.x, i.y));
  const auto zero = hn::Zero(dd);
  const auto top_left = hn::Or(hn::Gt(a, zero), hn::And(hn::Eq(a, zero), hn::Gt(b, zero)));
  const VD bias = hn::IfThenZeroElse(top_left, hn::Set(dd, 1.0));
  const VD k = hn::Sub(hn::Add(hn::Mul(hn::Set(dd, kSubPixelScale / 2), hn::Add(a, b)), cross), bias);
  hn::Store(a, dd, a_out);
  hn::Store(b, dd, b_out);
  hn::Store(hn::Floor(hn::Mul(k, hn::Set(dd, 1.0 / kSubPixelScale))), dd, c_out);
}

}  // namespace

uint32_t SetupSnappedBatch(const SnappedBatch& in, const Viewport& vp, CullMode cull, TriSetup* out,
                           uint8_t* index) {
  const DD dd;
  const hn::Rebind<int32_t, DD> di;
  const hn::Rebind<float, DD> df;
  const size_t n = hn::Lanes(dd);
  BatchResult r;
  const VD zero = hn::Zero(dd), half = hn::Set(dd, kSubPixelScale / 2);
  const VD inv_scale = hn::Set(dd, 1.0 / kSubPixelScale);
  for (size_t i = 0; i < in.count; i += n) {
    Vertex v[3];
    for (int k = 0; k < 3; ++k) {
      v[k].x = hn::PromoteTo(dd, hn::LoadU(di, in.x[k] + i));
      v[k].y = hn::PromoteTo(dd, hn::LoadU(di, in.y[k] + i));
      v[k].depth = hn::Load(dd, in.depth[k] + i);
      v[k].inv_w = hn::Load(dd, in.inv_w[k] + i);
    }
    const VD area2 = hn::Sub(hn::Mul(hn::Sub(v[1].x, v[0].x), hn::Sub(v[2].y, v[0].y)),
                             hn::Mul(hn::Sub(v[1].y, v[0].y), hn::Sub(v[2].x, v[0].x)));
    // Counter-clockwise in NDC is negative area in y-down pixels (setup_snapped).
    const auto front = hn::Lt(area2, zero);
    auto ok = hn::Ne(area2, zero);
    if (cull == CullMode::Back) ok = hn::And(ok, front);
    if (cull == CullMode::Front) ok = hn::AndNot(front, ok);
    // Negative area: vertices 1 and 2 swap, so the interior is where the edges are >= 0.
    const Vertex v1 = v[1];
    v[1] = {hn::IfThenElse(front, v[2].x, v[1].x), hn::IfThenElse(front, v[2].y, v[1].y),
            hn::IfThenElse(front, v[2].depth, v[1].depth), hn::IfThenElse(front, v[2].inv_w, v[1].inv_w)};
    v[2] = {hn::IfThenElse(front, v1.x, v[2].x), hn::IfThenElse(front, v1.y, v[2].y),
            hn::IfThenElse(front, v1.depth, v[2].depth), hn::IfThenElse(front, v1.inv_w, v[2].inv_w)};
    const VD area = hn::Abs(area2);

    // Reachable pixels: centres 256 px + 128 within the snapped extent, inside the viewport.
    const VD minx = hn::Min(v[0].x, hn::Min(v[1].x, v[2].x)), maxx = hn::Max(v[0].x, hn::Max(v[1].x, v[2].x));
    const VD miny = hn::Min(v[0].y, hn::Min(v[1].y, v[2].y)), maxy = hn::Max(v[0].y, hn::Max(v[1].y, v[2].y));
    const VD bx0 = hn::Max(hn::Ceil(hn::Mul(hn::Sub(minx, half), inv_scale)), zero);
    const VD by0 = hn::Max(hn::Ceil(hn::Mul(hn::Sub(miny, half), inv_scale)), zero);
    const VD bx1 = hn::Min(hn::Floor(hn::Mul(hn::Sub(maxx, half), inv_scale)), hn::Set(dd, vp.width - 1));
    const VD by1 = hn::Min(hn::Floor(hn::Mul(hn::Sub(maxy, half), inv_scale)), hn::Set(dd, vp.height - 1));
    ok = hn::And(ok, hn::And(hn::Le(bx0, bx1), hn::Le(by0, by1)));
    hn::Store(hn::IfThenElseZero(ok, hn::Set(dd, 1.0)), dd, r.ok + i);
    hn::Store(bx0, dd, r.bounds[0] + i);
    hn::Store(by0, dd, r.bounds[1] + i);
    hn::Store(bx1, dd, r.bounds[2] + i);
    hn::Store(by1, dd, r.bounds[3] + i);
    for (int k = 0; k < 3; ++k) Edge(v[k], v[(k + 1) % 3], r.a[k] + i, r.b[k] + i, r.c[k] + i);

    // make_planes (setup.cpp): positions in pixels, values at the three vertices.
    const VD x0 = hn::Mul(v[0].x, inv_scale), x1 = hn::Mul(v[1].x, inv_scale), x2 = hn::Mul(v[2].x, inv_scale);
    const VD y0 = hn::Mul(v[0].y, inv_scale), y1 = hn::Mul(v[1].y, inv_scale), y2 = hn::Mul(v[2].y, inv_scale);
    const VD inv_area2 = hn::Div(hn::Set(dd, double(kSubPixelScale) * kSubPixelScale), area);
    const VD ex1 = hn::Sub(x1, x0), ex2 = hn::Sub(x2, x0), ey1 = hn::Sub(y1, y0), ey2 = hn::Sub(y2, y0);
    const VD ox = hn::Sub(hn::Add(bx0, hn::Set(dd, 0.5)), x0), oy = hn::Sub(hn::Add(by0, hn::Set(dd, 0.5)), y0);
    // b1/w is 1/w at the original vertex 1 and 0 elsewhere (b2/w likewise at vertex 2);
    // after the swap the original vertex 1 sits at position 2.
    const VD f[4][3] = {
        {v[0].depth, v[1].depth, v[2].depth},
        {v[0].inv_w, v[1].inv_w, v[2].inv_w},
        {zero, hn::IfThenZeroElse(front, v[1].inv_w), hn::IfThenElseZero(front, v[2].inv_w)},
        {zero, hn::IfThenElseZero(front, v[1].inv_w), hn::IfThenZeroElse(front, v[2].inv_w)},
    };
    for (int p = 0; p < 4; ++p) {
      const VD d1 = hn::Sub(f[p][1], f[p][0]), d2 = hn::Sub(f[p][2], f[p][0]);
      const VD dx = hn::Mul(hn::Sub(hn::Mul(d1, ey2), hn::Mul(d2, ey1)), inv_area2);
      const VD dy = hn::Mul(hn::Sub(hn::Mul(d2, ex1), hn::Mul(d1, ex2)), inv_area2);
      const VD ref = hn::Add(hn::Add(f[p][0], hn::Mul(dx, ox)), hn::Mul(dy, oy));
      hn::StoreU(hn::DemoteTo(df, ref), df, r.plane[p][0] + i);
      hn::StoreU(hn::DemoteTo(df, dx), df, r.plane[p][1] + i);
      hn::StoreU(hn::DemoteTo(df, dy), df, r.plane[p][2] + i);
    }
  }

  uint32_t written = 0;
  for (uint32_t i = 0; i < in.count; ++i) {
    if (r.ok[i] == 0.0) continue;
    TriSetup& t = out[written];
    index[written++] = static_cast<uint8_t>(i);
    for (int k = 0; k < 3; ++k)
      t.edge[k] = {static_cast<int32_t>(r.a[k][i]), static_cast<int32_t>(r.b[k][i]), static_cast<int64_t>(r.c[k][i])};
    t.x0 = static_cast<int32_t>(r.bounds[0][i]);
    t.y0 = static_cast<int32_t>(r.bounds[1][i]);
    t.xmax = static_cast<int32_t>(r.bounds[2][i]);
    t.ymax = static_cast<int32_t>(r.bounds[3][i]);
    Plane* const planes[4] = {&t.z, &t.inv_w, &t.b1w, &t.b2w};
    for (int p = 0; p < 4; ++p) *planes[p] = {r.plane[p][0][i], r.plane[p][1][i], r.plane[p][2][i]};
  }
  return written;
}

}  // namespace HWY_NAMESPACE
}  // namespace pelt::raster
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::raster {
HWY_EXPORT(SetupSnappedBatch);

uint32_t setup_snapped_batch(const SnappedBatch& in, const Viewport& vp, CullMode cull, TriSetup* out,
                             uint8_t* index) {
  return HWY_DYNAMIC_DISPATCH(SetupSnappedBatch)(in, vp, cull, out, index);
}
}  // namespace pelt::raster
#endif
