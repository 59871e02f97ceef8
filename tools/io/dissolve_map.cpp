#include "tools/io/dissolve_map.h"

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "tools/io/image_io.h"
#include "tools/io/input_error.h"

namespace pelt::io {
namespace {

// Channel `c` of a texel as a dissolve.
float dissolve_of(const float* p, char c) {
  switch (c) {
    case 'r': return p[0];
    case 'g': return p[1];
    case 'b': return p[2];
    case 'm': return p[3];
    default: return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
  }
}

}  // namespace

ImageRGBA dissolved_color_map(const std::filesystem::path* color, const std::filesystem::path& dissolve, char channel,
                              const Budget& budget, std::vector<std::string>& warnings, uint64_t& held) {
  const ImageHeader dh = read_image_header(dissolve);
  const bool has_alpha = dh.channels == 2 || dh.channels >= 4;
  if (channel == 0) channel = has_alpha ? 'm' : 'l';
  if (channel == 'm' && !has_alpha)
    warnings.push_back("`map_d -imfchan m` reads the alpha of " + dissolve.filename().string() +
                       ", which has none (its alpha reads 1): the faces are drawn opaque");
  // Both images are decoded here, as the mesh loads, before the render's memory estimate: a large
  // dissolve map shrunk to a small colour map would otherwise pass a budget its decoding exceeds.
  // The pairs read before this one are still held (`held`), and without a colour map the white
  // image is made while the dissolve map is alive.
  const auto texels = [](const ImageHeader& h) { return uint64_t(h.width) * uint64_t(h.height); };
  const auto decoded = [&](const ImageHeader& h) {
    return sat_mul(texels(h), 4 * sizeof(float) + uint64_t(std::max(h.channels, 1)) * uint64_t(h.bytes_per_channel));
  };
  const std::optional<ImageHeader> ch = color ? std::optional(read_image_header(*color)) : std::nullopt;
  const uint64_t made = sat_mul(texels(ch ? *ch : dh), 4 * sizeof(float));
  const uint64_t peak =
      sat_add(sat_add(sat_add(held, decoded(dh)), ch ? decoded(*ch) : made), kProcessBaselineBytes);
  if (peak > budget.max_memory_bytes)
    throw InputError(dissolve.string(), "",
                     "reading it as a dissolve map" +
                         (color ? " beside its colour map " + color->filename().string() : std::string()) +
                         " holds about " + describe_bytes(peak) + " (both decoded as floats, the maps of the " +
                         "file's materials read before it, and the pelt process itself), " +
                         over_budget(describe_bytes(budget.max_memory_bytes), kMaxMemoryFlag));
  const ImageRGBA d = read_image_rgba(dissolve, ColorEncoding::linear, budget);
  ImageRGBA out;
  if (color) {
    out = read_image_rgba(*color, ColorEncoding::srgb_unless_linear, budget);
  } else {
    out.width = d.width;
    out.height = d.height;
    out.rgba.assign(size_t(d.width) * size_t(d.height) * 4, 1.0f);
  }
  // The dissolve multiplies the colour map's own alpha (three.js's alphaMap), but for the common
  // export that names one RGBA file as both: its alpha once, not squared.
  std::error_code same_error;
  const bool one_file = color && std::filesystem::equivalent(*color, dissolve, same_error);
  const bool same_size = out.width == d.width && out.height == d.height;
  const auto of = [channel](const float* texel) { return dissolve_of(texel, channel); };
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const float a = same_size ? of(d.pixel(x, y))
                                : float(bilinear_at(d, (double(x) + 0.5) / double(out.width),
                                                    (double(y) + 0.5) / double(out.height), false, of));
      float& alpha = out.rgba[(size_t(y) * size_t(out.width) + size_t(x)) * 4 + 3];
      alpha = one_file ? a : alpha * a;
    }
  held = sat_add(held, made);
  return out;
}

}  // namespace pelt::io
