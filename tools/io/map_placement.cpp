#include "tools/io/map_placement.h"

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

// "a u + b v + c", leaving out zero terms and unit factors.
std::string affine(float a, float b, float c) {
  std::string out;
  const auto term = [&](float k, const char* var) {
    if (k == 0.0f) return;
    char buf[48];
    const bool first = out.empty();
    const float m = first ? k : (k < 0.0f ? -k : k);
    const char* sign = first ? "" : (k < 0.0f ? " - " : " + ");
    if (var[0] == '\0') std::snprintf(buf, sizeof buf, "%s%g", sign, double(m));
    else if (m == 1.0f) std::snprintf(buf, sizeof buf, "%s%s%s", sign, first && k < 0.0f ? "-" : "", var);
    else std::snprintf(buf, sizeof buf, "%s%g %s", sign, double(first ? k : m), var);
    out += buf;
  };
  term(a, "u");
  term(b, "v");
  term(c, "");
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
