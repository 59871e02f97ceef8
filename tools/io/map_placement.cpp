#include "tools/io/map_placement.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pelt::io {
namespace {

const char* wrap_name(raster::Wrap w) {
  switch (w) {
    case raster::Wrap::Repeat: return "repeat";
    case raster::Wrap::Clamp: return "clamp";
    case raster::Wrap::Mirror: return "mirror";
  }
  return "?";
}

// "a u + b v + c" to 6 digits, leaving out zero terms (and those a million times smaller than
// the row's largest, which a rotation's cosine of 90 degrees leaves) and unit factors.
std::string affine(float a, float b, float c) {
  const float k[3] = {a, b, c};
  const char* var[3] = {"u", "v", ""};
  const float largest = std::max({std::abs(a), std::abs(b), std::abs(c)});
  std::string out;
  for (int i = 0; i < 3; ++i) {
    if (k[i] == 0.0f || std::abs(k[i]) < 1e-6f * largest) continue;
    const float m = std::abs(k[i]);
    out += out.empty() ? (k[i] < 0.0f ? "-" : "") : (k[i] < 0.0f ? " - " : " + ");
    char buf[32];
    if (var[i][0] != '\0' && m == 1.0f) buf[0] = '\0';
    else std::snprintf(buf, sizeof buf, var[i][0] != '\0' ? "%.6g " : "%.6g", double(m));
    out += buf;
    out += var[i];
  }
  return out.empty() ? "0" : out;
}

}  // namespace

std::string describe(const MapPlacement& p) {
  std::string wraps;
  for (const auto& [w, axis] : {std::pair{p.wrap_u, "u"}, std::pair{p.wrap_v, "v"}}) {
    if (w == raster::Wrap::Repeat) continue;
    if (!wraps.empty()) wraps += ", ";
    wraps += std::string(wrap_name(w)) + " " + axis;
  }
  if (!p.transforms()) return wraps.empty() ? "as the uvs say" : wraps;
  const std::string uv = "u' = " + affine(p.m[0], p.m[1], p.m[2]) + ", v' = " + affine(p.m[3], p.m[4], p.m[5]);
  return wraps.empty() ? uv : wraps + "; " + uv;
}

}  // namespace pelt::io
