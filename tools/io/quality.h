// The quality knobs: every setting that trades accuracy for time, as one plain struct that
// a scene's `quality` block, the CLI's flags and `pelt tradeoff` all write. Unset members
// keep what the scene itself says (its fur and skin blocks); the rest default to the
// renderer's normal behaviour, so an empty `quality` block changes nothing.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fur/fur_params.h"
#include "raster/texture.h"
#include "shading/skin_params.h"

namespace pelt::io {

// Order of the translucent fur triangles (tools/render/fur_object.h draws them so).
enum class SortQuality {
  none,   // all shells inner to outer, then all fins layer by layer (the paper's and the
          // harness's order)
  layer,  // shell s, then the fins between layers s and s+1, for s = 0, 1, ...
  tile,   // all shells, then the fins fin by fin (root to tip), back to front per tile by
          // the rasterizer, a fin's quads in runs of three (DrawCall::sort_group)
  surface,  // as `tile`, but each shell layer keyed after the layers below it that it leans
            // over (fur/surface_order.h): no seams on one continuous surface in wind
  exact,  // as `tile`, then every fragment sorted per pixel (the reference)
};
// How fins are drawn (fur/fin_spans.h): one quad per pair of layers (eq. 1), or merged into
// taller quads where the strands run straight (tile and exact sorts only; the default: the
// same error against the reference on the furry box at 1024 x 768, and faster, README's
// "What accuracy costs").
enum class FinQuads { layer, merged };
// Shading arithmetic: the SIMD float kernels, or the double-precision scalar references
// (shading/skin_reference.h, the fur lighting reference, raster::sample_reference).
enum class Precision { simd, double_precision };

inline constexpr int kMaxSppSide = 8;  // spp = n x n stratified samples, n in [1, 8]

struct Quality {
  std::optional<int> shells;             // "shells": every fur block's shell count, [2, 128]
  std::optional<fur::FinMode> fins;      // "fins": off | all | silhouette
  FinQuads fin_quads = FinQuads::merged;  // "fin_quads": layer | merged
  SortQuality sort = SortQuality::tile;  // "sort": none | layer | tile | surface | exact
  int spp = 1;                           // "spp": 1, 4, 9, ..., 64 (a square)
  raster::Filter filter = raster::Filter::Trilinear;  // "filter": nearest | bilinear | bilinear_mip | trilinear
  std::optional<shading::MultipleScattering> multiple_scattering;  // every skin material's
  std::optional<shading::SingleScattering> single_scattering;      // every skin material's
  Precision precision = Precision::simd;  // "precision": simd | double
  // Set by the `reference` preset only: skin Fresnel exact and the correct phase function
  // whatever the material says (the paper's variants are approximations of these).
  bool exact_physics = false;

  bool operator==(const Quality&) const = default;
};

// The knobs, in the order `pelt tradeoff` sweeps them and the CSV lists them.
inline constexpr std::string_view kKnobs[] = {"shells", "fins",   "fin_quads",           "sort",
                                              "spp",    "filter", "multiple_scattering", "single_scattering",
                                              "precision"};

// Sets `knob` (a name of kKnobs) to `value` as written in JSON or on the command line.
// Returns the reason when the knob or value is unknown or out of range (listing what is
// valid); `q` is then unchanged.
std::optional<std::string> set_knob(Quality& q, std::string_view knob, std::string_view value);
// The knob's current value as set_knob reads it, or "scene" for an unset override.
std::string knob_value(const Quality& q, std::string_view knob);
// The settings `pelt tradeoff` tries for `knob` (the list, e.g. shells 4..64).
std::vector<std::string> knob_sweep(std::string_view knob);

// Named presets: "default" (the renderer's normal behaviour), "fast", "balanced", "high",
// and "reference" (8x8 stratified samples, exact per-pixel sort, double precision, exact
// physics, level-0 textures filtered by the supersampling, 64 shells). nullopt for an
// unknown name.
std::optional<Quality> quality_preset(std::string_view name);
std::vector<std::string_view> quality_preset_names();
// One line per knob, "knob=value", for logs and `pelt tradeoff`'s table.
std::string describe(const Quality& q);

}  // namespace pelt::io
