// Fur lighting: Kajiya-Kay diffuse and specular along the strand tangent, darkened toward the
// root (a self-shadowing approximation), on SoA batches of fur fragments (Highway kernels,
// dispatched once per call) with double-precision references beside them.
//
// Called by the renderer once per tile (or batch of visible fur fragments) after visibility, for
// shells and fins alike: 1-3 million lanes a frame, so the kernels allocate nothing (up to 16
// lights) and use no pow on the fast path: an integer shininess raises sin^2 by repeated squaring
// (and one square root for an odd shininess), any other shininess uses Highway's Exp and Log,
// about 1.6x slower.
//
// The model, per lane (all vectors world space):
//   T = normalize(tangent)   (the strand direction from the deformed chain)
//   N = normalize(normal)    (the base surface normal; NOT turned toward the viewer: fur grows on
//                             the outside, and a light behind the surface is what backlight_wrap
//                             is for)
//   V = normalize(eye - pos)
//   per light l: L = direction to the light (directional: the light's vector; point: toward its
//                position; point lights do not decay, as in shading/light.h), H = normalize(L + V)
//     diffuse_l  = diffuse * sin(T, L) * (wrap + (1 - wrap) max(0, N.L))
//     specular_l = specular * sin(T, H)^shininess * max(0, N.L)
//     where sin(T, X) = sqrt(max(0, 1 - (T.X)^2)).
//   ambient = sum of the ambient lights' colours
//   ao  = lerp(ambient_occlusion_root, 1, height), exact at both ends (height 0 gives exactly
//         ambient_occlusion_root, height 1 exactly 1)
//   rgb = ao * (texel.rgb * (ambient + sum_l colour_l diffuse_l) + sum_l colour_l specular_l)
//   a   = texel.a
//
// Numerical rules, shared by kernel and reference (so they agree everywhere except on the
// boundaries of these rules):
//   - A vector is degenerate when its squared length is below kDegenerateNormal2 (1e-30, from
//     skin_params.h) or overflows float (above FLT_MAX). The fallback direction F is N, else V,
//     else +z.
//   - Degenerate tangent (zero, tiny, denormal): T = F.
//   - Degenerate normal: N.L is taken as 1 (unshadowed, full wrap).
//   - Degenerate view (eye at the fragment): V = 0, so H = L.
//   - Point light at the fragment (degenerate L): L = F.
//   - |L + V|^2 below kDegenerateHalf2 (light exactly behind the fragment as seen from the eye,
//     where H has no direction): that light's specular is 0.
//   - sin^2(T, X) is evaluated as |T x X|^2 / ((T.X)^2 + |T x X|^2), which is exact in the scale
//     of T and X and keeps its relative precision both where T is parallel to X (the sine is
//     small: 1 - (T.X)^2 would cancel) and where the lobe peaks (sin near 1, raised to up to 512).
//   - Where a float evaluation is ill-conditioned, the kernel evaluates that light's term for
//     that lane again in double, from the lane's inputs, as the reference does: backlit lanes
//     (|L + V| < 0.2: H is a short difference of unit vectors, and an ulp in their lengths turns
//     H by 1e-7 / |L + V| radians, which a lobe of exponent up to 512 magnifies), grazing lanes
//     (|N.L| < 0.01) and strands nearly along the light (sin^2(T, L) < 1e-4). These are about
//     1-3% of random lanes and a thin band on a real surface; a light straight behind the fur
//     makes most lanes backlit and halves the kernel's speed (tools/bench/fur_lighting_bench).
//   - Specular lobes below kFurLobeFloor (1e-30) are flushed to 0 (the reference does not flush;
//     the difference is far below the tolerance), so no denormal is ever produced.
//   - texel rgba and height are clamped to [0, 1]; outputs are finite and non-negative for any
//     finite inputs.
#pragma once

#include <cstddef>
#include <optional>

#include "shading/light.h"
#include "shading/skin_params.h"

namespace pelt::shading {

// Error messages name these fields. No scene key sets them: the renderer uses these defaults.
struct FurLightParams {
  float ambient_occlusion_root = 0.35f;  // light factor at the root, in [0, 1]; 1 at the tip
  float diffuse = 1.0f;                  // Kajiya-Kay diffuse weight, in [0, 100]
  float specular = 0.25f;                // specular weight, in [0, 100] (lobe colour = light colour)
  float shininess = 40.0f;               // specular exponent, in [1, 512]
  float backlight_wrap = 0.25f;          // diffuse factor where N.L <= 0, in [0, 1]
};

inline constexpr float kDegenerateHalf2 = 1e-12f;  // |L + V|^2 below this: no specular
inline constexpr float kFurLobeFloor = 1e-30f;      // specular lobes below this are 0

// First out-of-range or non-finite field ("shininess: must be in [1, 512], got 0"), or nullopt.
std::optional<ParamError> validate(const FurLightParams& p);

// n lanes, n a multiple of 16, every pointer 64-byte aligned and non-null. Lanes the rasterizer
// did not cover may hold any finite values; their outputs are finite and otherwise unused.
struct FurSurfaceSoA {
  size_t n;
  const float* pos[3];      // world position of the fragment
  const float* tangent[3];  // strand tangent; need not be unit; may be zero or tiny (then N)
  const float* normal[3];   // base surface normal; need not be unit; may be zero (then N.L = 1)
  const float* height;      // 0 at the root .. 1 at the tip (clamped to [0, 1])
  const float* texel[4];    // sampled strand texture, linear straight-alpha RGBA in [0, 1]
};

// Straight alpha: rgb = lit colour, a = texel alpha. May not alias the inputs.
struct FurOutSoA {
  float* rgba[4];
};

// Checks n and the presence and alignment of the pointers a call reads and writes; names the
// field ("tangent[y]", "rgba[3]", "n"). needs_strand false (the llvmpipe lighting) skips pos,
// tangent and height, which that lighting does not read.
std::optional<ParamError> validate_batch(const FurSurfaceSoA& s, const FurOutSoA& o, bool needs_strand = true);

// The model above. Throws std::invalid_argument naming the bad field (a FurLightParams key,
// "lights[i].color[c]", "eye[1]", a batch field) before touching the outputs.
void shade_fur(const FurLightParams& params, const Light* lights, size_t light_count, const float eye[3],
               const FurSurfaceSoA& surface, const FurOutSoA& out);
// The same, lane by lane in double precision (float outputs); for tests: slow.
void shade_fur_reference(const FurLightParams& params, const Light* lights, size_t light_count,
                         const float eye[3], const FurSurfaceSoA& surface, const FurOutSoA& out);

// The llvmpipe harness's fixed lighting (shared/anchors/llvmpipe), for `pelt bench fps
// --match-llvmpipe`: rgb = texel.rgb * (0.35 + 0.65 max(N.L, 0)), a = texel.a, with N =
// normalize(normal) (N.L = 1 where the normal is degenerate, where the harness would give NaN)
// and L = normalize(light_dir), the direction TO the light (finite, non-zero). Texels are
// clamped to [0, 1] as above; tangent, height and pos are not read.
std::optional<ParamError> validate_light_dir(const float light_dir[3]);  // finite, |dir|^2 > 1e-12
void shade_fur_match_llvmpipe(const float light_dir[3], const FurSurfaceSoA& surface, const FurOutSoA& out);
void shade_fur_match_llvmpipe_reference(const float light_dir[3], const FurSurfaceSoA& surface,
                                        const FurOutSoA& out);

}  // namespace pelt::shading
