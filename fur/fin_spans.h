// Fins with fewer quads where the fur is straight (the `fin_quads: merged` quality). Eq. 1's
// fins are one quad per edge and pair of neighbouring layers: 15 thin quads a fin at 16
// shells, a few pixels each, so a frame's fins are mostly per-triangle work (set-up, binning,
// half-empty blocks). Where both chains of an edge run straight, one quad over several
// layers draws nearly the same fin on the same shared vertices: the fin texture's v and the
// root darkening are linear in the layer, and so is the quad.
//
// A chain may span layers s0..s1 when every node in between lies within `tolerance` of where
// the quad puts it: |p_k - lerp(p_s0, p_s1, (k - s0) / (s1 - s0))|, which bounds how far any
// texel of the fin moves, bends and uneven spacing alike. The renderer uses a quarter of the
// layer distance: below the shells' own sampling of the strand.
#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

namespace pelt::fur {

inline constexpr float kFinSpanTolerance = 0.25f;  // of FurGeometry::layer_distance
inline constexpr uint32_t kMaxFinSpan = 8;         // layer steps one quad may span

// Words of a chain's break mask: one bit per layer.
inline uint32_t fin_break_words(uint32_t layers) { return (layers + 63) / 64; }

// For each base vertex i in [begin, end) of a pose laid out as FurGeometry::positions
// (vertex i + s N), the layers at which its fin quads must end, as bits of
// breaks[i * fin_break_words(layers) ...]: layer 0, layer S-1, and greedily from the root the
// last layer each quad can reach within `tolerance` and `max_span` steps. Non-finite
// positions never merge. Allocates nothing; ranges of vertices write disjoint words.
void fin_chain_breaks(std::span<const glm::vec3> pose, uint32_t base_vertex_count, uint32_t layers,
                      float tolerance, uint32_t max_span, uint32_t begin, uint32_t end,
                      std::span<uint64_t> breaks);

// The layers at which the quads of the fin on edge (a, b) end, ascending (the first quad
// starts at layer 0, the last ends at S-1), written to `ends`, which has room for `layers`
// entries; returns their count. A quad runs between neighbouring breaks of either chain
// (`breaks` from fin_chain_breaks; on a sub-span of a chain's straight run every node lies
// within twice the tolerance of the sub-span's chord) and is cut further where the two
// chains fan out: a quad whose sides differ by the twist T = (b1 - b0) - (a1 - a0) is drawn
// as two triangles that put its middle |T| / 4 away from where the layers' quads put it, so
// each quad keeps |T| <= 4 tolerance (cut into parts of as many whole layer steps as the
// twist per step allows; it grows linearly with the steps along straight chains).
// A non-finite twist cuts the span into single layers. Allocates nothing.
uint32_t fin_quad_ends(std::span<const glm::vec3> pose, uint32_t base_vertex_count, uint32_t layers, uint32_t a,
                       uint32_t b, std::span<const uint64_t> breaks, float tolerance, uint32_t* ends);

}  // namespace pelt::fur
