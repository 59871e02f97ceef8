// Batch shading kernels (Highway, dispatched once per call) and their scalar references.
//
// Each kernel shades a SurfaceSoA of n lanes (n a multiple of 16, 64-byte aligned pointers) for a
// list of lights seen from `eye`, writing a ShadeOutSoA. The *_reference functions compute the
// same outputs lane by lane in double precision (skin_reference.h) and exist for tests and for
// checking: they are slow. Every function validates its inputs once per call and throws
// std::invalid_argument naming the bad field (a SkinParams key, "lights[i].color[c]",
// "albedo[1]", "n", ...). Outputs are finite and non-negative for any finite inputs.
//
// Called by the renderer once per tile (or batch of visible pixels), after visibility.
#pragma once

#include <cstddef>

#include "shading/basic_params.h"
#include "shading/light.h"
#include "shading/skin_params.h"
#include "shading/surface.h"

namespace pelt::shading {

// The layered skin shader: sebum (specular), epidermis (multiple scattering), dermis (single
// scattering) and ambient; see skin_reference.h for every term and its bound.
void shade_skin(const SkinParams& params, const Light* lights, size_t light_count, const float eye[3],
                const SurfaceSoA& surface, const ShadeOutSoA& out);
void shade_skin_reference(const SkinParams& params, const Light* lights, size_t light_count,
                          const float eye[3], const SurfaceSoA& surface, const ShadeOutSoA& out);

// rgb = albedo (clamped to [0, 1]), alpha = 1; lights are ignored.
void shade_unlit(const Light* lights, size_t light_count, const float eye[3], const SurfaceSoA& surface,
                 const ShadeOutSoA& out);
void shade_unlit_reference(const Light* lights, size_t light_count, const float eye[3],
                           const SurfaceSoA& surface, const ShadeOutSoA& out);

// rgb = albedo * sum(ambient colours + colour * max(0, N.L)), alpha = 1.
void shade_lambert(const Light* lights, size_t light_count, const float eye[3], const SurfaceSoA& surface,
                   const ShadeOutSoA& out);
void shade_lambert_reference(const Light* lights, size_t light_count, const float eye[3],
                             const SurfaceSoA& surface, const ShadeOutSoA& out);

// Lambert plus specular * colour * max(0, N.H)^shininess for lights in front, alpha = 1.
void shade_blinn(const BasicParams& params, const Light* lights, size_t light_count, const float eye[3],
                 const SurfaceSoA& surface, const ShadeOutSoA& out);
void shade_blinn_reference(const BasicParams& params, const Light* lights, size_t light_count,
                           const float eye[3], const SurfaceSoA& surface, const ShadeOutSoA& out);

}  // namespace pelt::shading
