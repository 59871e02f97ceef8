// Tangent-space normal mapping on SoA batches: the interpolated vertex frame turned into the
// shading normal a sampled map texel encodes (a Highway kernel, dispatched once per call), with
// the double-precision reference beside it.
//
// Called by the material shader once per fragment batch, before the shading kernels, which
// normalise the result (so its length does not matter) and handle a zero normal.
//
// The model, per lane (perturb_normals_reference is the definition, in double precision):
//   N  = normal, T = tangent.xyz (interpolated: neither need be unit or orthogonal)
//   if N != 0: T -= (T.N / N.N) N          (Gram-Schmidt: interpolation shortens and skews
//                                            the frame)
//   if T == 0 after that (a zero tangent, or one along N): out = N, unnormalised
//   otherwise, with Tu = T / |T|, Nu = N / |N| (0 when N = 0),
//              B = (tangent.w < 0 ? -1 : 1) Nu x Tu   (-0 and 0 count as +1),
//              m = 2 clamp(texel.rgb, 0, 1) - 1:
//     out = m.x Tu + m.y B + m.z Nu
// This is exact arithmetic's reading of the material shader's former float loop, which squared N
// and T in float: outside lengths of about [1e-19, 1e19] those squares lost precision, then
// underflowed or overflowed, and the loop dropped N or T from the frame (a tangent shorter than
// 1e-23 passed N through, one longer than 1e20 gave m.z Nu). Here any finite input gives the
// model's answer, with one reading of "input": the renderer's workers run with flush-to-zero and
// denormals-are-zero (raster/parallel.h), so there a denormal component is read as 0 (a normal
// (1e-40, 0, 1e-40) is N = 0, a tangent of denormals is T = 0 and passes N through), where the
// double reference, run without DAZ, sees a direction. Texels are clamped because a map encodes
// unit directions in [0, 1]^3 (a float map may hold anything finite): the clamp keeps every
// output finite.
//
// Output bounds: out = N exactly (bit for bit) where T vanishes; elsewhere |out| <= |m| (1 + 2^-20)
// <= sqrt(3) (1 + 2^-20): the frame (Tu, B, Nu) is orthonormal to within a few roundings, and
// B = 0, Nu = 0 where N = 0 (then out = m.x Tu). Every output is finite for finite inputs.
//
// Precision (tests/shading/normal_map_test.cpp): each component within 1e-5 of the reference
// relative, or 2^-21 of the reference's length |ref| absolute (4 float ulps of a unit vector: a
// float component of a sum of terms of size |m| cannot do better where the terms cancel), and
// identical where the reference passes N through. The kernel scales N and T by powers of two
// (exact) so that no square overflows or underflows, and orthogonalises twice (the second pass
// removes the first's rounding along N). Where T lies within about 7 degrees of +-N
// (|T_orthogonalised|^2 < |T|^2 / 64), float rounding of the projection would turn Tu by up to
// 1e-7 / sin(angle); those lanes are evaluated again by perturb_normals_reference (about 0.8% of
// random frames; a mesh's tangents are orthogonal to its normals at the vertices, so only a frame
// twisted across a triangle comes near), and the degenerate case is decided by the same double
// code in both.
#pragma once

#include <cstddef>
#include <optional>

#include "shading/skin_params.h"

namespace pelt::shading {

// n lanes, any n (0 included); the pointers need not be aligned (the renderer's are), and none
// may be null.
struct NormalMapSoA {
  size_t n;
  const float* normal[3];   // interpolated vertex normal, world space
  const float* tangent[4];  // interpolated vertex tangent xyz, world space, and its handedness w
  const float* texel[3];    // sampled normal map, linear rgb in [0, 1] (clamped)
};

// Checks the pointers; names the field ("tangent[w]", "texel[2]", "out[x]").
std::optional<ParamError> validate_batch(const NormalMapSoA& in, float* const out[3]);

// The perturbed normal of every lane into out[0..2][0, n). out may not overlap the inputs.
// Throws std::invalid_argument naming the bad field before writing anything.
void perturb_normals(const NormalMapSoA& in, float* const out[3]);
// The same, lane by lane in double precision (float outputs); the definition, and the kernel's
// evaluation of its ill-conditioned lanes.
void perturb_normals_reference(const NormalMapSoA& in, float* const out[3]);

}  // namespace pelt::shading
