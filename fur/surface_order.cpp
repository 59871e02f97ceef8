#include "fur/surface_order.h"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "raster/frame.h"

namespace pelt::fur {
namespace {

// Keys `key` below `bound` (drawn after it). Non-finite keys and bounds take no part: set-up
// culls such triangles anyway, and one must not drag its neighbours to infinity. A key already
// below the bound keeps its value (the float just below the bound would not be lower), so
// nextafter, a library call, runs only where a rule moves a key.
void key_below(float& key, float bound) {
  if (!(bound <= key) || !std::isfinite(key) || !std::isfinite(bound)) return;
  key = std::nextafter(bound, -std::numeric_limits<float>::infinity());
}

// Whether triangle t of a layer whose clip positions start at `layer` may be drawn: wound
// counter-clockwise on screen, as the shells' back-face culling keeps (CullMode::Back, OpenGL's
// convention). A corner at or behind the eye gives no winding on screen, and the clipper may
// still draw part of the triangle: it counts as drawn (its rules hold, as before culled shells
// were told apart).
bool faces_viewer(const glm::vec4* layer, const uint32_t* t) {
  const glm::vec4 a = layer[t[0]], b = layer[t[1]], c = layer[t[2]];
  if (!(a.w > 0.0f && b.w > 0.0f && c.w > 0.0f)) return true;
  const glm::vec2 pa(a.x / a.w, a.y / a.w), pb(b.x / b.w, b.y / b.w), pc(c.x / c.w, c.y / c.w);
  return (pb.x - pa.x) * (pc.y - pa.y) - (pc.x - pa.x) * (pb.y - pa.y) > 0.0f;
}

}  // namespace

SurfaceOrder::SurfaceOrder(const FurGeometry& geo)
    : n_(geo.base_vertex_count),
      layers_(geo.layers),
      faces_(static_cast<uint32_t>(geo.counts.base_faces)),
      base_indices_(geo.shell_indices.begin(), geo.shell_indices.begin() + 3 * size_t{faces_}),
      partner_(faces_, -1) {
  // The rasterizer's runs of two (DrawCall::sort_group) pair triangles 2k, 2k + 1 of the
  // draw; a layer's copy pairs the same faces whenever F is even, the usual quad mesh.
  for (uint32_t f = 0; f + 1 < faces_; f += 2)
    if (raster::triangles_share_edge(&base_indices_[3 * f], &base_indices_[3 * f + 3])) {
      partner_[f] = int32_t(f + 1);
      partner_[f + 1] = int32_t(f);
    }
  for (const FurEdge& e : geo.edges) {
    if (e.face1 == kNoFace) continue;
    // The corner of face0 off the edge, by position: the edge names the first copy of each end
    // (same_strand_vertices) and the face may name another copy of it (a texture seam's, or
    // the box mapping's), which by index would pass for the third corner and leave no side.
    const uint32_t* t = &base_indices_[3 * size_t{e.face0}];
    const glm::vec3 pa = geo.positions[e.a], pb = geo.positions[e.b];
    uint32_t third = t[0];
    for (int k = 0; k < 3; ++k)
      if (geo.positions[t[k]] != pa && geo.positions[t[k]] != pb) third = t[k];
    edges_.push_back({e.a, e.b, third, e.face0, e.face1});
  }
  lean_.resize(edges_.size());
  raw_.resize(faces_);
  drawn_below_.resize(faces_);
}

void SurfaceOrder::compute(std::span<const glm::vec4> clip, std::vector<float>& keys) {
  const uint32_t F = faces_, S = layers_;
  keys.resize(size_t{S} * F);
  if (F == 0 || S == 0) return;
  const size_t top = size_t{S - 1} * n_;
  // Which way each edge's strands lean on screen: the mean displacement of its two chains from
  // root to tip, against the edge's normal on screen pointing from face0 to face1.
  for (size_t i = 0; i < edges_.size(); ++i) {
    const Edge& e = edges_[i];
    lean_[i] = 0;
    const glm::vec4 ca = clip[e.a], cb = clip[e.b], cc = clip[e.third], ta = clip[e.a + top], tb = clip[e.b + top];
    if (!(ca.w > 0.0f && cb.w > 0.0f && cc.w > 0.0f && ta.w > 0.0f && tb.w > 0.0f)) continue;
    auto screen = [](const glm::vec4& c) { return glm::vec2(c.x / c.w, c.y / c.w); };
    const glm::vec2 a = screen(ca), b = screen(cb), c = screen(cc);
    glm::vec2 toward1(a.y - b.y, b.x - a.x);
    const float side = glm::dot(toward1, c - a);
    if (!(side != 0.0f)) continue;  // face0 edge-on (or NaN): no side to lean from
    if (side > 0.0f) toward1 = -toward1;
    const float lean = glm::dot(screen(ta) - a + screen(tb) - b, toward1);
    lean_[i] = lean > 0.0f ? 1 : lean < 0.0f ? -1 : 0;
  }
  for (uint32_t s = 0; s < S; ++s) {
    const size_t first = size_t{s} * n_;
    for (uint32_t f = 0; f < F; ++f) {
      const uint32_t* t = &base_indices_[3 * size_t{f}];
      raw_[f] = clip[first + t[0]].w + clip[first + t[1]].w + clip[first + t[2]].w;
    }
    float* k = keys.data() + size_t{s} * F;
    for (uint32_t f = 0; f < F; ++f) {
      const int32_t p = partner_[f];
      k[f] = p < 0 ? raw_[f] * (1.0f / 3.0f) : (raw_[f] + raw_[p]) * (1.0f / 6.0f);
    }
    if (s == 0) continue;
    const float* below = k - F;  // layer s - 1, final
    // Only a triangle that is drawn holds another back. A culled one draws nothing to be
    // covered, yet its key would pass the chain on: across a silhouette or a fold (the teapot's
    // rim), from the hidden side to the visible one, pulling it in front of parts of the mesh
    // that lie before it.
    const size_t prev = size_t{s - 1} * n_;
    for (uint32_t f = 0; f < F; ++f) drawn_below_[f] = faces_viewer(&clip[prev], &base_indices_[3 * size_t{f}]);
    for (uint32_t f = 0; f < F; ++f)
      if (drawn_below_[f]) key_below(k[f], below[f]);
    for (size_t i = 0; i < edges_.size(); ++i) {
      const Edge& e = edges_[i];
      if (lean_[i] > 0 && drawn_below_[e.face1]) key_below(k[e.face0], below[e.face1]);
      if (lean_[i] < 0 && drawn_below_[e.face0]) key_below(k[e.face1], below[e.face0]);
    }
    // A quad keeps one key (its halves stay together in the sorted list and share blocks):
    // the lower, which keeps both halves' rules.
    for (uint32_t f = 0; f < F; ++f) {
      const int32_t p = partner_[f];
      if (p > int32_t(f) && std::isfinite(k[f]) && std::isfinite(k[p])) k[f] = k[p] = std::min(k[f], k[p]);
    }
  }
}

}  // namespace pelt::fur
