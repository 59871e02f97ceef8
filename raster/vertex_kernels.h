// Vertex stage of the front end: clip position, outcode and snapped position of every
// vertex of a draw, N vertices per SIMD vector (vertex_kernels.cc).
#pragma once

#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "raster/clip.h"
#include "raster/setup.h"

namespace pelt::raster {

// Per vertex: what set-up and binning read of every triangle's vertices in one 32-byte
// record (the vertices of a dense mesh come from all over memory, so one line per vertex
// instead of three).
struct FrontVertex {
  SnappedVertex snap;  // valid when code has no kClipPlaneBits or kNonFinite
  uint32_t code;       // vertex_outcode
  float w;             // clip w, for the translucent sort key
};
static_assert(sizeof(FrontVertex) == 32);

// For v in [first, first + count):
//   clip[v]       = clip_from_object * vec4(positions[v], 1)  (glm's float arithmetic)
//   front[v].code = vertex_outcode(clip[v], bounds)
//   front[v].w    = clip[v].w
//   front[v].snap = snap_vertex(clip[v], vp) when the code has no kClipPlaneBits and no
//                   kNonFinite, else all zero.
// Bit for bit what transform_vertices_reference writes, on every Highway target.
// Reads only positions[first, first + count). Called per vertex job (4096 vertices).
void transform_vertices(const glm::mat4& clip_from_object, const glm::vec3* positions,
                        uint32_t first, uint32_t count, const Viewport& vp,
                        const ClipBounds& bounds, glm::vec4* clip, FrontVertex* front);

// The scalar definition of the above (one vertex at a time, through vertex_outcode and
// snap_vertex). For the tests.
void transform_vertices_reference(const glm::mat4& clip_from_object, const glm::vec3* positions,
                                  uint32_t first, uint32_t count, const Viewport& vp,
                                  const ClipBounds& bounds, glm::vec4* clip, FrontVertex* front);

}  // namespace pelt::raster
