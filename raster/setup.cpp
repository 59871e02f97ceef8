#include "raster/setup.h"

#include <algorithm>
#include <cmath>

#include "raster/config.h"

namespace pelt::raster {
namespace {

// Floor division by 256 of a possibly negative integer.
inline int64_t floor_div_subpixel(int64_t v) { return v >> kSubPixelBits; }

EdgeEq make_edge(const SnappedVertex& i, const SnappedVertex& j) {
  const int64_t a = static_cast<int64_t>(i.y) - j.y;
  const int64_t b = static_cast<int64_t>(j.x) - i.x;
  const int64_t cross = static_cast<int64_t>(i.x) * j.y - static_cast<int64_t>(j.x) * i.y;
  // Our triangles are oriented with positive area in y-down pixel space, so the interior
  // is where E > 0; a "left" edge has the interior to its right (a > 0) and a "top" edge
  // is horizontal with the interior below (a == 0, b > 0). Those own their pixels.
  const bool top_left = a > 0 || (a == 0 && b > 0);
  const int64_t k = (kSubPixelScale / 2) * (a + b) + cross - (top_left ? 0 : 1);
  return {static_cast<int32_t>(a), static_cast<int32_t>(b), floor_div_subpixel(k)};
}

// The four planes of a triangle (depth, 1/w, b1/w, b2/w) from their values at the three
// vertices f[k][plane]: the gradient of the linear function through them and its value at
// the centre of pixel (x0, y0). Plane-major arrays so the loop runs as SIMD over the planes.
void make_planes(const double f[3][4], const double x[3], const double y[3], double inv_area2,
                 int32_t x0, int32_t y0, Plane* const out[4]) {
  const double ex1 = x[1] - x[0], ex2 = x[2] - x[0], ey1 = y[1] - y[0], ey2 = y[2] - y[0];
  const double ox = x0 + 0.5 - x[0], oy = y0 + 0.5 - y[0];
  double ref[4], dx[4], dy[4];
  for (int p = 0; p < 4; ++p) {
    const double d1 = f[1][p] - f[0][p], d2 = f[2][p] - f[0][p];
    dx[p] = (d1 * ey2 - d2 * ey1) * inv_area2;
    dy[p] = (d2 * ex1 - d1 * ex2) * inv_area2;
    ref[p] = f[0][p] + dx[p] * ox + dy[p] * oy;
  }
  for (int p = 0; p < 4; ++p)
    *out[p] = {static_cast<float>(ref[p]), static_cast<float>(dx[p]), static_cast<float>(dy[p])};
}

}  // namespace

SnappedVertex snap_vertex(const ClipVertex& v, const Viewport& vp) {
  const double inv_w = 1.0 / v.w;
  const double sx = (v.x * inv_w * 0.5 + 0.5) * vp.width;
  const double sy = (0.5 - v.y * inv_w * 0.5) * vp.height;
  // Clipping leaves vertices on the guard band up to rounding; clamping keeps the
  // fixed-point range promise of config.h without visibly moving anything.
  const double lo = -kGuardBand;
  const double sxc = std::clamp(sx, lo, static_cast<double>(vp.width + kGuardBand));
  const double syc = std::clamp(sy, lo, static_cast<double>(vp.height + kGuardBand));
  const double depth = std::clamp(v.z * inv_w * 0.5 + 0.5, 0.0, 1.0);
  // lrint rounds half to even under the default rounding mode: deterministic, and one
  // instruction with -fno-math-errno.
  return {static_cast<int32_t>(std::lrint(sxc * kSubPixelScale)),
          static_cast<int32_t>(std::lrint(syc * kSubPixelScale)), depth, inv_w};
}

bool setup_triangle(const ClipVertex& cv0, const ClipVertex& cv1, const ClipVertex& cv2,
                    const Viewport& vp, CullMode cull, TriSetup& out) {
  const double b1[3] = {cv0.b1, cv1.b1, cv2.b1}, b2[3] = {cv0.b2, cv1.b2, cv2.b2};
  return setup_snapped(snap_vertex(cv0, vp), snap_vertex(cv1, vp), snap_vertex(cv2, vp), b1, b2, vp,
                       cull, out);
}

bool setup_snapped(const SnappedVertex& s0, const SnappedVertex& s1, const SnappedVertex& s2,
                   const double vb1[3], const double vb2[3], const Viewport& vp, CullMode cull,
                   TriSetup& out) {
  SnappedVertex s[3] = {s0, s1, s2};
  int order[3] = {0, 1, 2};
  int64_t area2 = (static_cast<int64_t>(s[1].x) - s[0].x) * (static_cast<int64_t>(s[2].y) - s[0].y) -
                  (static_cast<int64_t>(s[1].y) - s[0].y) * (static_cast<int64_t>(s[2].x) - s[0].x);
  if (area2 == 0) return false;
  // Counter-clockwise in NDC (y up) is clockwise in y-down pixels: negative area here.
  const bool front = area2 < 0;
  if ((cull == CullMode::Back && !front) || (cull == CullMode::Front && front)) return false;
  if (area2 < 0) {
    std::swap(s[1], s[2]);
    std::swap(order[1], order[2]);
    area2 = -area2;
  }

  // Pixel px is reachable iff its centre 256 px + 128 lies within the snapped extent.
  const int32_t minx = std::min({s[0].x, s[1].x, s[2].x}), maxx = std::max({s[0].x, s[1].x, s[2].x});
  const int32_t miny = std::min({s[0].y, s[1].y, s[2].y}), maxy = std::max({s[0].y, s[1].y, s[2].y});
  const int64_t half = kSubPixelScale / 2;
  int64_t bx0 = -floor_div_subpixel(-(minx - half));  // ceil((minx - 128) / 256)
  int64_t by0 = -floor_div_subpixel(-(miny - half));
  int64_t bx1 = floor_div_subpixel(maxx - half);
  int64_t by1 = floor_div_subpixel(maxy - half);
  bx0 = std::max<int64_t>(bx0, 0);
  by0 = std::max<int64_t>(by0, 0);
  bx1 = std::min<int64_t>(bx1, vp.width - 1);
  by1 = std::min<int64_t>(by1, vp.height - 1);
  if (bx0 > bx1 || by0 > by1) return false;

  out.edge[0] = make_edge(s[0], s[1]);
  out.edge[1] = make_edge(s[1], s[2]);
  out.edge[2] = make_edge(s[2], s[0]);
  out.x0 = static_cast<int32_t>(bx0);
  out.y0 = static_cast<int32_t>(by0);
  out.xmax = static_cast<int32_t>(bx1);
  out.ymax = static_cast<int32_t>(by1);

  const double x[3] = {s[0].x / double(kSubPixelScale), s[1].x / double(kSubPixelScale),
                       s[2].x / double(kSubPixelScale)};
  const double y[3] = {s[0].y / double(kSubPixelScale), s[1].y / double(kSubPixelScale),
                       s[2].y / double(kSubPixelScale)};
  const double inv_area = double(kSubPixelScale * kSubPixelScale) / double(area2);
  double f[3][4];
  for (int k = 0; k < 3; ++k) {
    const double iw = s[k].inv_w;
    f[k][0] = s[k].depth;
    f[k][1] = iw;
    f[k][2] = vb1[order[k]] * iw;
    f[k][3] = vb2[order[k]] * iw;
  }
  Plane* const planes[4] = {&out.z, &out.inv_w, &out.b1w, &out.b2w};
  make_planes(f, x, y, inv_area, out.x0, out.y0, planes);
  return true;
}

}  // namespace pelt::raster
