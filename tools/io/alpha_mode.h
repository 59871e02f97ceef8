// How a material's alpha draws: read by the mesh loaders (glTF's alphaMode), drawn by the
// material shader and the rasterizer's draw state.
#pragma once

namespace pelt::io {

// The base colour map's alpha times the factor's is ignored (opaque), cuts the surface out
// where it is below the cutoff (mask), or blends it over what lies behind (blend). OBJ
// materials are opaque.
enum class AlphaMode { opaque, mask, blend };

}  // namespace pelt::io
