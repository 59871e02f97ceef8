#include "tools/render/length_map.h"

#include <cmath>
#include <cstdio>

#include "raster/texture.h"
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
  const std::string who = "in " + field + " of " + scene_file;
  const io::ImageRGBA img =
      asked_by(who, [&] { return io::read_image_rgba(image, io::ColorEncoding::linear, budget); });
  // Only the first channel counts: the others (an EXR's alpha, say) may hold anything.
  std::vector<float> rgba(img.rgba.size());
  for (size_t t = 0; t < rgba.size() / 4; ++t) {
    const float v = img.rgba[4 * t];
    if (!(v >= 0.0f && v <= 1.0f)) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", double(v));
      throw io::InputError(image.string(), "",
                           "texel (" + std::to_string(t % size_t(img.width)) + ", " +
                               std::to_string(t / size_t(img.width)) + ") of the first channel is " + value +
                               ": a length map's values must be in [0, 1] (" + who + ")");
    }
    rgba[4 * t] = rgba[4 * t + 1] = rgba[4 * t + 2] = v;
    rgba[4 * t + 3] = 1.0f;
  }
  raster::Texture tex;
  if (auto e = raster::Texture::from_linear_float(img.width, img.height, rgba.data(), raster::TexelEncoding::Linear, tex))
    throw io::InputError(image.string(), "", e->reason + " (" + who + ")");
  raster::SamplerState state;
  state.filter = raster::Filter::Bilinear;  // the full-size level: one point per vertex has no footprint
  // The sampler takes whole 4x4 blocks: the vertices in order, padded.
  const size_t lanes = (n + 15) / 16 * 16;
  std::vector<float> u(lanes, 0.0f), v(lanes, 0.0f);
  for (size_t i = 0; i < n; ++i) u[i] = mesh.uvs[i].x, v[i] = mesh.uvs[i].y;
  std::vector<double> out[4];
  for (auto& o : out) o.assign(lanes, 0.0);
  double* const outs[4] = {out[0].data(), out[1].data(), out[2].data(), out[3].data()};
  raster::sample_reference(tex, state, u.data(), v.data(), lanes, outs);
  std::vector<float> scale(n);
  // Non-finite uvs read inside the texture (the sampler's clamp); a sum of weights may round a
  // hair past 1.
  for (size_t i = 0; i < n; ++i) scale[i] = float(std::fmin(1.0, std::fmax(0.0, out[0][i])));
  return scale;
}

}  // namespace pelt::render
