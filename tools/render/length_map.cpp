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
  // would turn a value below 1/510 into bare skin and flatten 16-bit and float maps): texel centres
  // at half-integers, repeat wrapping, v = 0 the top row, as the sampler reads colour maps.
  auto texel = [&](long long x, long long y) {
    const long long W = (long long)w, H = (long long)h;
    x = ((x % W) + W) % W;
    y = ((y % H) + H) % H;
    return double(img.rgba[4 * (size_t(y) * w + size_t(x))]);
  };
  std::vector<float> scale(n);
  for (size_t i = 0; i < n; ++i) {
    const glm::vec2 uv = mesh.uvs[i];
    // A non-finite uv reads the first texel (the sampler keeps such coordinates inside the texture).
    const double x = std::isfinite(uv.x) ? double(uv.x) * double(w) - 0.5 : 0.0;
    const double y = std::isfinite(uv.y) ? double(uv.y) * double(h) - 0.5 : 0.0;
    const double fx = std::floor(x), fy = std::floor(y);
    // Beyond 2^52 texels a coordinate has no fraction left; the wrap below stays exact.
    const long long x0 = (long long)std::fmod(fx, double(w)), y0 = (long long)std::fmod(fy, double(h));
    const double tx = x - fx, ty = y - fy;
    const double top = texel(x0, y0) * (1.0 - tx) + texel(x0 + 1, y0) * tx;
    const double bottom = texel(x0, y0 + 1) * (1.0 - tx) + texel(x0 + 1, y0 + 1) * tx;
    scale[i] = float(std::fmin(1.0, std::fmax(0.0, top * (1.0 - ty) + bottom * ty)));
  }
  return scale;
}

}  // namespace pelt::render
