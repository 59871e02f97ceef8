// The tile-sort keys of the `surface` fur order (tools/render/fur_object.h, FurSort::surface).
//
// The tile sort draws a tile's translucent triangles back to front, one key each. Keyed by its
// own mean depth, a shell quad whose strands lean far moves as a whole toward its neighbour:
// where its layer s leans over the neighbour, the neighbour's inner layers can be drawn after
// it, and show through as dark seams along the quad's edges (the `tile` order's known
// limitation, README). On one continuous surface the nearer of two fragments at a pixel is the
// higher layer, so these keys put every shell triangle after the layers below it that it
// covers: face f's layer s is keyed below (drawn after) f's own layer s - 1 and, across every
// edge that f's strands lean over on screen, below the neighbour's layer s - 1; a triangle no
// such rule holds back keeps its mean view depth, as in the `tile` order.
//
// The rules chain (layer s after the neighbour's s - 1, which is after its neighbour's s - 2):
// across a surface seen at a slant, layers are drawn nearly layer by layer, which is what the
// per-pixel sort does there. Where one part of a mesh lies in front of another that the chain
// reaches, the part behind can be pulled in front of it: on the teapot, whose lid sits inside
// the rim, `surface` is worse than `tile` (measured figures in the README).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "fur/fur_geometry.h"

namespace pelt::fur {

class SurfaceOrder {
 public:
  // Takes the shells' topology from `geo` (faces, their edges, the quads: faces 2k and 2k + 1
  // of a layer that share an edge take one key, as the rasterizer's own runs of two do).
  explicit SurfaceOrder(const FurGeometry& geo);

  // keys[s F + f] for shell triangle s F + f (FurGeometry::shell_indices), from every fur
  // vertex in clip space (clip[i] = clip_from_world * (pose[i], 1), layer-major as
  // FurGeometry::positions). Larger = farther = drawn earlier. A key from a non-finite depth
  // stays as it is and holds nothing back; an edge with a vertex at or behind the eye
  // (w <= 0) has no on-screen lean and adds no rule. Allocates only when `keys` grows.
  void compute(std::span<const glm::vec4> clip, std::vector<float>& keys);

 private:
  struct Edge {
    uint32_t a, b;          // base vertices
    uint32_t third;         // face0's vertex off the edge (tells face0's side of it)
    uint32_t face0, face1;  // the faces on either side
  };
  uint32_t n_ = 0, layers_ = 0, faces_ = 0;
  std::vector<uint32_t> base_indices_;  // layer 0's triangles (3 per face)
  std::vector<int32_t> partner_;        // the face sharing f's key, or -1
  std::vector<Edge> edges_;             // interior edges (two faces)
  std::vector<int8_t> lean_;            // per edge this frame: +1 face0 leans onto face1, -1 the reverse, 0 neither
  std::vector<float> raw_;              // one layer's mean depths
  std::vector<uint8_t> drawn_below_;    // per face: its triangle in layer s - 1 is drawn (not culled)
};

}  // namespace pelt::fur
