// Normal Blur SSS (seed 002): vertex normals blurred over the surface, once per mesh.
//
// Diffuse light that has travelled under the skin looks like lighting computed with a smoothed
// normal, so the shader mixes dot(N, L) with dot(N_blur, L) per colour channel (red, which
// travels farthest in skin, with the widest blur). This module computes N_blur.
//
// Neighbourhood: geodesic-ish. Distances are shortest paths along mesh edges (Dijkstra), cut at
// 3 sigma; the weight of a neighbour is exp(-d^2 / (2 sigma^2)) times its vertex area (a third of
// its triangles' areas, so the result does not depend on how densely a region is tessellated).
// Why not Euclidean: a Euclidean ball reaches across thin features (lips, eyelids, ear folds,
// fingers) and would mix normals of surfaces that light cannot cross; edge paths stay on the
// surface. Edge paths overestimate geodesic distance by a few percent on irregular meshes,
// which only narrows the blur slightly. Coincident vertices (UV seams) are welded first, so a
// seam is not a boundary and both copies get the same blurred normal; a welded position counts
// once, whatever its number of copies (copies with different normals, a crease, contribute the
// mean of their unit normals weighted by the areas of their own triangles).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "shading/skin_params.h"

namespace pelt::shading {

struct NormalBlurInput {
  const float* positions;  // xyz per vertex (3 * vertex_count floats; glm::vec3 arrays qualify)
  const float* normals;    // xyz per vertex, need not be unit
  size_t vertex_count;
  const uint32_t* indices;  // three per triangle
  size_t index_count;
};

struct BlurredNormals {
  // channel r, g, b: xyz per vertex (3 * vertex_count floats), unit length, except that a
  // channel with sigma 0, or a vertex whose weighted sum vanishes, keeps the input normal as is.
  std::vector<float> channel[3];
  // The (source, neighbour) pairs the searches were estimated to settle, the figure the budget
  // (NormalBlurBudget) was checked against: 0 when no channel blurs, set when refused as well
  // (a lower bound then if a sample stopped early). For the user to see a blur's cost beside
  // its budget before it runs for minutes.
  uint64_t pair_estimate = 0;
};

// Calls fn(i) once for every i in [0, count), in any order and possibly on several threads at
// once. blur_normals splits its vertices into such independent items (each writes only its
// own vertices' results), so the result is the same whatever runs them.
using ParallelFor = std::function<void(size_t count, const std::function<void(size_t)>& fn)>;

// The most work blur_normals may do. Each welded vertex's search settles every welded vertex
// within 3 x the largest sigma of it along the edges (itself included), and the blur's time is
// about proportional to the number of these (source, neighbour) pairs: W of them for a radius
// that reaches no neighbour, W^2 for one that reaches across the whole mesh (W welded
// vertices), and at a fixed radius on a finer mesh, W times a neighbourhood that grows with W.
// Over max_pairs, blur_normals refuses with a ParamError naming normal_blur_radius, and the
// result is empty. It asks before any blur search: it runs the searches of 64 evenly spaced
// vertices (every vertex when W <= 64), counting, and refuses when W times their mean (the
// result's pair_estimate) is over the budget (64 of the blur's W searches when it fits; at most
// 64 x min(W, 64 max_pairs / W + 64) settled vertices when it refuses, each sample stopping once
// it alone puts the estimate over). The blur's searches count as well and stop past the budget,
// for a mesh whose samples missed a dense part. Whether a mesh is refused depends only on the
// mesh, sigma and max_pairs, not on `parallel`.
struct NormalBlurBudget {
  uint64_t max_pairs = UINT64_MAX;
  std::string flag;  // when not empty, a refusal ends "(raise it with FLAG)"
  // Check and estimate only (`pelt info`): the result holds pair_estimate and no channel, and
  // no search runs past the 64 samples, so a blur of minutes is described in a moment. The
  // blur's own searches can still refuse a mesh denser where the samples missed it.
  bool estimate_only = false;
};

// sigma[c] >= 0 in scene units (SkinParams::normal_blur_radius); sigma 0 returns the input
// normals unchanged for that channel. Errors (bad index, non-finite value, negative sigma) are
// returned as a ParamError naming the field; the result is then empty. Without `parallel`
// the items run in order on the calling thread.
std::optional<ParamError> blur_normals(const NormalBlurInput& mesh, const float sigma[3], BlurredNormals& out,
                                       const ParallelFor& parallel = {}, const NormalBlurBudget& budget = {});

}  // namespace pelt::shading
