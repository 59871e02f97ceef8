// Transform/clip stage: homogeneous clipping of one triangle against the near and far
// planes, w > 0, and the x/y guard band. Inside the guard band x/y are never clipped:
// the rasterizer's scissor to the viewport does that for free.
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

namespace pelt::raster {

// A vertex of a clipped polygon: its clip-space position and its barycentric
// coordinates (b1, b2) in the ORIGINAL triangle (b0 = 1 - b1 - b2), so that varyings
// are always interpolated from the original three vertices.
struct ClipVertex {
  double x, y, z, w;
  double b1, b2;
};

// Seven planes can each add one vertex to a triangle.
inline constexpr int kMaxClipVertices = 3 + 7;

struct ClipPolygon {
  int count = 0;
  ClipVertex v[kMaxClipVertices];
};

// Guard-band limits in NDC units for a width x height viewport.
struct ClipBounds {
  double guard_x, guard_y;  // |x| <= guard_x * w keeps the pixel x inside the guard band
};
ClipBounds make_clip_bounds(int width, int height);

enum class ClipResult : uint8_t {
  Culled,     // wholly outside one plane, non-finite, or clipped away
  Unclipped,  // inside every plane: the polygon is the triangle itself
  Clipped,    // the polygon is a convex fan of `count` vertices
};

// The smallest w a vertex may keep. Only matters for matrices whose near plane does not
// already keep w away from zero (an orthographic-like or hand-made transform).
inline constexpr double kMinW = 1e-6;

// Outcode bits of vertex_outcode below; public so that the SIMD front end
// (vertex_kernels.cc) sets exactly the same ones.
enum PlaneBit : uint32_t {
  kNear = 1u << 0,    // z >= -w
  kFar = 1u << 1,     // z <= w
  kPosW = 1u << 2,    // w >= kMinW
  kGuardPX = 1u << 3, // x <= gx w
  kGuardNX = 1u << 4, // x >= -gx w
  kGuardPY = 1u << 5,
  kGuardNY = 1u << 6,
  // Viewport sides: used only to reject, never to clip.
  kViewPX = 1u << 7,
  kViewNX = 1u << 8,
  kViewPY = 1u << 9,
  kViewNY = 1u << 10,
};

// Per-vertex classification, computed once per vertex by the front end: bits 0-6 are the
// clip planes the vertex is outside of (kClipPlaneBits), bits 7-10 the viewport sides,
// kNonFinite a NaN or infinite coordinate. A triangle whose vertices share a bit is
// outside; one whose vertices have no kClipPlaneBits set needs no clipping.
inline constexpr uint32_t kClipPlaneBits = 0x7Fu;
inline constexpr uint32_t kNonFinite = 1u << 31;
uint32_t vertex_outcode(const glm::vec4& v, const ClipBounds& bounds);

// Called per triangle by the front end. Non-finite input coordinates cull the triangle:
// a mesh with NaN never reaches the rasterizer as garbage.
ClipResult clip_triangle(const glm::vec4& a, const glm::vec4& b, const glm::vec4& c,
                         const ClipBounds& bounds, ClipPolygon& out);

}  // namespace pelt::raster
