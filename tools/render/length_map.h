// The fur's length map (`fur.length_map`): an image whose first channel scales the fur's length,
// read once per furry object at its vertices' texture coordinates.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "raster/mesh.h"
#include "tools/io/budget.h"

namespace pelt::render {

// One scale per vertex of `mesh`, in [0, 1]: the map's first channel (red, or grey), read as
// linear data (not sRGB) at the file's own precision, bilinear with repeat wrapping, texel centres
// at half-integers and v = 0 the top row, as the colour maps are read. Throws io::InputError naming
// `field` (in `scene_file`) for a mesh without texture coordinates or whose coordinates cover no
// area, and naming the image for an image that cannot be read or holds a first channel outside
// [0, 1] or not finite.
std::vector<float> read_length_map(const std::filesystem::path& image, const Mesh& mesh, const std::string& mesh_name,
                                   const std::string& scene_file, const std::string& field, const io::Budget& budget);

}  // namespace pelt::render
