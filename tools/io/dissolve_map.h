// An MTL material's `map_d` (its dissolve, a scalar map) drawn as the alpha of its colour map:
// pelt's surfaces blend by their colour map's alpha (MeshMaps::alpha_mode), so the OBJ loader
// hands the renderer one image, map_Kd's colour with its alpha times map_d's dissolve, as
// three.js's importer draws the pair.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/io/budget.h"
#include "tools/io/image.h"

namespace pelt::io {

// `color`'s texels (null: white, at the dissolve map's size) with their alpha multiplied by
// `dissolve`'s channel `channel` (three.js's alphaMap; where both name one file, its alpha is
// taken once): 'r', 'g', 'b', 'm' (the alpha), 'l' (Rec. 709 luminance), or 0 (not given: the
// alpha where the file has one, since an exporter's map_d is often the colour map's own RGBA
// file, else the luminance of a grey or colour file). The dissolve is data, read linear; where the
// sizes differ it is read bilinearly (clamped at the edges) at each colour texel's centre. Throws
// InputError naming the file that cannot be read, as read_image_rgba does, or the dissolve map
// when decoding both beside the `held` bytes of earlier pairs would exceed budget.max_memory_bytes;
// adds the returned image's bytes to `held`. A channel 'm' of a file without alpha is named in
// `warnings`.
ImageRGBA dissolved_color_map(const std::filesystem::path* color, const std::filesystem::path& dissolve, char channel,
                              const Budget& budget, std::vector<std::string>& warnings, uint64_t& held);

}  // namespace pelt::io
