#include "raster/clip.h"

#include <cmath>

#include "raster/config.h"

namespace pelt::raster {
namespace {

constexpr uint32_t kClipPlanes = kNear | kFar | kPosW | kGuardPX | kGuardNX | kGuardPY | kGuardNY;
static_assert(kClipPlanes == kClipPlaneBits);
constexpr int kNumClipPlanes = 7;

// Signed distance to clip plane i; inside where >= 0.
inline double plane_distance(int i, const ClipVertex& v, const ClipBounds& b) {
  switch (i) {
    case 0: return v.z + v.w;
    case 1: return v.w - v.z;
    case 2: return v.w - kMinW;
    case 3: return b.guard_x * v.w - v.x;
    case 4: return b.guard_x * v.w + v.x;
    case 5: return b.guard_y * v.w - v.y;
    default: return b.guard_y * v.w + v.y;
  }
}

uint32_t outcode(const ClipVertex& v, const ClipBounds& b) {
  const double gx = b.guard_x * v.w, gy = b.guard_y * v.w;
  return (v.z + v.w < 0.0 ? kNear : 0u) | (v.w - v.z < 0.0 ? kFar : 0u) |
         (v.w - kMinW < 0.0 ? kPosW : 0u) | (gx - v.x < 0.0 ? kGuardPX : 0u) |
         (gx + v.x < 0.0 ? kGuardNX : 0u) | (gy - v.y < 0.0 ? kGuardPY : 0u) |
         (gy + v.y < 0.0 ? kGuardNY : 0u) | (v.x > v.w ? kViewPX : 0u) |
         (v.x < -v.w ? kViewNX : 0u) | (v.y > v.w ? kViewPY : 0u) | (v.y < -v.w ? kViewNY : 0u);
}

ClipVertex lerp(const ClipVertex& p, const ClipVertex& q, double t) {
  return {p.x + (q.x - p.x) * t, p.y + (q.y - p.y) * t, p.z + (q.z - p.z) * t,
          p.w + (q.w - p.w) * t, p.b1 + (q.b1 - p.b1) * t, p.b2 + (q.b2 - p.b2) * t};
}

bool finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

}  // namespace

uint32_t vertex_outcode(const glm::vec4& v, const ClipBounds& bounds) {
  if (!finite(v)) return kNonFinite;
  return outcode(ClipVertex{v.x, v.y, v.z, v.w, 0.0, 0.0}, bounds);
}

ClipBounds make_clip_bounds(int width, int height) {
  return {1.0 + 2.0 * kGuardBand / width, 1.0 + 2.0 * kGuardBand / height};
}

ClipResult clip_triangle(const glm::vec4& a, const glm::vec4& b, const glm::vec4& c,
                         const ClipBounds& bounds, ClipPolygon& out) {
  if (!finite(a) || !finite(b) || !finite(c)) return ClipResult::Culled;
  out.count = 3;
  out.v[0] = {a.x, a.y, a.z, a.w, 0.0, 0.0};
  out.v[1] = {b.x, b.y, b.z, b.w, 1.0, 0.0};
  out.v[2] = {c.x, c.y, c.z, c.w, 0.0, 1.0};
  const uint32_t c0 = outcode(out.v[0], bounds), c1 = outcode(out.v[1], bounds),
                 c2 = outcode(out.v[2], bounds);
  if (c0 & c1 & c2) return ClipResult::Culled;
  const uint32_t any = (c0 | c1 | c2) & kClipPlanes;
  if (!any) return ClipResult::Unclipped;

  // Sutherland-Hodgman, only against the planes some vertex violates.
  ClipVertex tmp[kMaxClipVertices];
  ClipVertex* src = out.v;
  ClipVertex* dst = tmp;
  int n = 3;
  for (int i = 0; i < kNumClipPlanes; ++i) {
    if (!(any & (1u << i))) continue;
    int m = 0;
    for (int k = 0; k < n; ++k) {
      const ClipVertex& p = src[k];
      const ClipVertex& q = src[(k + 1) % n];
      const double dp = plane_distance(i, p, bounds), dq = plane_distance(i, q, bounds);
      if (dp >= 0.0) dst[m++] = p;
      if ((dp >= 0.0) != (dq >= 0.0)) {
        // Interpolate from the inside vertex so the new vertex lands on the plane's inner side
        // up to rounding, whichever way the edge is walked.
        ClipVertex v = dp >= 0.0 ? lerp(p, q, dp / (dp - dq)) : lerp(q, p, dq / (dq - dp));
        // On the near and far planes exactly: rounding in the lerp could leave z/w just
        // outside [-1, 1] and a depth just outside [0, 1].
        if (i == 0) v.z = -v.w;
        if (i == 1) v.z = v.w;
        dst[m++] = v;
      }
    }
    n = m;
    std::swap(src, dst);
    if (n < 3) return ClipResult::Culled;
  }
  if (src != out.v)
    for (int k = 0; k < n; ++k) out.v[k] = src[k];
  out.count = n;
  return ClipResult::Clipped;
}

}  // namespace pelt::raster
