#include "tools/render/length_map.h"

#include <cmath>
#include <cstdio>

#include <glm/vec2.hpp>

#include "fur/fur_geometry.h"
#include "tools/io/image_io.h"
#include "tools/io/input_error.h"
#include "tools/render/budget_check.h"

namespace pelt::render {

std::vector<float> read_length_map(const std::filesystem::path& image, const Mesh& mesh, const std::string& mesh_name,
                                   const std::string& scene_file, const std::string& field, const io::Budget& budget) {
  const size_t n = mesh.vertex_count();
  // Without uvs every vertex would read texel (0, 0): one length in place of the map.
  if (mesh.uvs.size() != n)
    throw io::InputError(scene_file, field,
                         "a length map is read at the mesh's texture coordinates, and mesh `" + mesh_name +
                             "` has none");
  // A mesh whose uvs cover no area (all at a point, or on a line) reads one texel or one line of
  // texels everywhere: a length the map does not hold, so it is refused as having none.
  if (!(fur::mesh_uv_area(mesh) > 0.0))
    throw io::InputError(scene_file, field,
                         "a length map is read at the mesh's texture coordinates, and those of mesh `" + mesh_name +
                             "` cover no area");
  const std::string who = "in " + field + " of " + scene_file;
  const io::ImageRGBA img =
      asked_by(who, [&] { return io::read_image_rgba(image, io::ColorEncoding::linear, budget, 1); });
  const size_t w = size_t(img.width), h = size_t(img.height);
  // Only the first channel counts: the others (an EXR's alpha, say) may hold anything.
  for (size_t t = 0; t < w * h; ++t) {
    const float v = img.rgba[4 * t];
    if (!(v >= 0.0f && v <= 1.0f)) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", double(v));
      throw io::InputError(image.string(), "",
                           "texel (" + std::to_string(t % w) + ", " + std::to_string(t / w) +
                               ") of the first channel is " + value + ": a length map's values must be in [0, 1] (" +
                               who + ")");
    }
  }
  // Bilinear on the file's own values, in double (the raster's textures hold 8 bits a channel, which
  // would turn a value below 1/510 into bare skin and flatten 16-bit and float maps), repeating, as
  // the sampler reads colour maps; a non-finite uv reads the first texel (the sampler keeps such
  // coordinates inside the texture).
  std::vector<float> scale(n);
  for (size_t i = 0; i < n; ++i) {
    const double value =
        io::bilinear_at(img, mesh.uvs[i].x, mesh.uvs[i].y, true, [](const float* texel) { return texel[0]; });
    scale[i] = float(std::fmin(1.0, std::fmax(0.0, value)));
  }
  return scale;
}

}  // namespace pelt::render
