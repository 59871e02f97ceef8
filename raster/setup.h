// Set-up stage: viewport transform, snapping to 8 sub-pixel bits, integer edge
// equations with the top-left rule, and the screen-space planes the tile kernels
// evaluate (depth, 1/w and the perspective barycentrics).
#pragma once

#include <cstdint>

#include "raster/clip.h"
#include "raster/pipeline.h"

namespace pelt::raster {

// Edge equation in PIXEL units: pixel (px, py) (centre at px + 0.5, py + 0.5) is inside
// the edge iff a * px + b * py + c >= 0. This is exact: with the snapped vertices Vi, Vj
// (integers in 1/256 pixel) the true edge function at the centre is
//   E = 256 * (a px + b py) + K,  K = 128 (a + b) + Vi x Vj - bias,
// (bias 1 for edges that are not top or left), and since a px + b py is an integer,
// E >= 0  <=>  a px + b py + floor(K / 256) >= 0. So c = K >> 8 and the per-pixel step is
// a, not 256 a: |a|, |b| < 2^24 and, over a 64x64 tile the edge crosses, every value fits
// in int32 (the fast path); only the value at a tile origin needs int64.
struct EdgeEq {
  int32_t a, b;
  int64_t c;
};

// f(px, py) = ref + (dx * float(px - x0) + dy * float(py - y0)) with (x0, y0) the
// triangle's reference pixel. The SIMD kernels and the scalar reference evaluate exactly
// this expression, so their results agree bit for bit.
struct Plane {
  float ref, dx, dy;
};

struct TriSetup {
  EdgeEq edge[3];
  int32_t x0, y0;          // reference pixel = bounding box minimum (inside the viewport)
  int32_t xmax, ymax;      // inclusive bounding box maximum (inside the viewport)
  Plane z;                 // window depth z/w * 0.5 + 0.5, linear in screen space
  Plane inv_w;             // 1/w
  Plane b1w, b2w;          // b1/w, b2/w: barycentrics of the original triangle over w
  uint32_t draw;           // index of the draw call
  uint32_t primitive;      // triangle index within the draw
  float sort_key;          // mean view depth of the original triangle or its quad: larger = farther
};

struct Viewport {
  int width, height;
};

// Snaps and sets up one triangle (three vertices of a clipped polygon, in order).
// Returns false when it covers no pixel centre of the viewport, has zero area after
// snapping, or is culled by `cull`. Called per triangle, per front-end chunk.
bool setup_triangle(const ClipVertex& v0, const ClipVertex& v1, const ClipVertex& v2,
                    const Viewport& vp, CullMode cull, TriSetup& out);

// Snapped sub-pixel position of a clip-space vertex (exposed for the reference tests).
// A vertex inside every clip plane snaps the same in every triangle that uses it, so the
// front end snaps such vertices once and sets their triangles up with setup_snapped.
struct SnappedVertex {
  int32_t x, y;  // 1/256 pixel, y down (row 0 at the top)
  double depth;  // window depth
  double inv_w;  // 1 / clip w
};
SnappedVertex snap_vertex(const ClipVertex& v, const Viewport& vp);

// setup_triangle from vertices already snapped; b1[k], b2[k] are vertex k's barycentrics
// in the original triangle.
bool setup_snapped(const SnappedVertex& s0, const SnappedVertex& s1, const SnappedVertex& s2,
                   const double b1[3], const double b2[3], const Viewport& vp, CullMode cull,
                   TriSetup& out);

// Triangles whose three vertices were snapped by the front end (no clipping needed), set
// up side by side: the SIMD form of setup_snapped with b1, b2 = the original triangle's own
// vertices. Plain SoA input, one entry per triangle in submission order.
inline constexpr uint32_t kSetupBatch = 64;
struct SnappedBatch {
  // Entries past `count` are read (whole vectors) and ignored: initialised so they are
  // defined values, never out of range.
  uint32_t count = 0;
  alignas(64) int32_t x[3][kSetupBatch] = {};
  alignas(64) int32_t y[3][kSetupBatch] = {};
  alignas(64) double depth[3][kSetupBatch] = {};
  // 1 / clip w of an unclipped vertex: w is a float of at least 1e-6, so 1/w lies in
  // [1 / FLT_MAX, 1e6] and no plane overflows a float.
  alignas(64) double inv_w[3][kSetupBatch] = {};
};

// Sets up the batch's triangles exactly as setup_snapped would (bit for bit: same IEEE
// operations, and every integer quantity is exact in double). Writes the survivors
// (edges, bounds and planes; not draw, primitive or sort_key) to out[0..n) and their
// batch indices to index[0..n), in batch order, and returns n. Called per front-end chunk.
uint32_t setup_snapped_batch(const SnappedBatch& in, const Viewport& vp, CullMode cull, TriSetup* out,
                             uint8_t* index);

inline float eval_plane(const Plane& p, int32_t x0, int32_t y0, int32_t px, int32_t py) {
  return p.ref + (p.dx * static_cast<float>(px - x0) + p.dy * static_cast<float>(py - y0));
}

// Window depth of a pixel: the z plane, clamped to [0, 1] (a steep plane evaluated at a
// pixel centre next to a vertex on the near or far plane can round just outside).
inline float eval_depth(const TriSetup& t, int32_t px, int32_t py) {
  const float z = eval_plane(t.z, t.x0, t.y0, px, py);
  return z < 0.0f ? 0.0f : (z > 1.0f ? 1.0f : z);
}

inline int64_t eval_edge(const EdgeEq& e, int64_t px, int64_t py) {
  return static_cast<int64_t>(e.a) * px + static_cast<int64_t>(e.b) * py + e.c;
}

}  // namespace pelt::raster
