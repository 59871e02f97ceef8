// How a material's alpha draws: read by the mesh loaders (glTF's alphaMode), drawn by the
// material shader and the rasterizer's draw state.
#pragma once

namespace pelt::io {

// The base colour map's alpha times the factor's is ignored (opaque), cuts the surface out
// where it is below the cutoff (mask), or blends it over what lies behind (blend). OBJ
// materials are opaque.
enum class AlphaMode { opaque, mask, blend };

// MASK's test where a shader makes it (a translucent skin's part, the fur over a cut-out): kept
// where the alpha times the factor reaches the cutoff; a NaN alpha is cut.
inline bool mask_keeps(float alpha, float factor, float cutoff) { return factor * alpha >= cutoff; }

}  // namespace pelt::io
