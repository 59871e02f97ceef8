#include "fur/fur_params.h"

#include <cmath>
#include <cstdio>

namespace pelt::fur {
namespace {

std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Checks lo <= v <= hi (or lo < v when lo_open); NaN fails every comparison, so it is
// caught here too.
std::optional<ParamError> check_range(const std::string& field, double v, double lo, double hi,
                                      bool lo_open = false) {
  if (!std::isfinite(v)) return ParamError{field, "must be a finite number, got " + fmt(v)};
  bool ok = (lo_open ? v > lo : v >= lo) && v <= hi;
  if (ok) return std::nullopt;
  return ParamError{field, "must be in " + std::string(lo_open ? "(" : "[") + fmt(lo) + ", " +
                               fmt(hi) + "], got " + fmt(v)};
}

// A direction of squared length len2 (summed in double, where no float's square underflows):
// a short one is told the bound and its length, not that it is zero. `why` ends the bound.
std::optional<ParamError> check_length(const std::string& field, double len2, const std::string& why) {
  if (len2 == 0.0) return ParamError{field, "must be a non-zero vector"};
  if (!(len2 > 1e-12))
    return ParamError{field, "must have a length above 1e-06" + why + ", got length " + fmt(std::sqrt(len2))};
  return std::nullopt;
}

std::optional<ParamError> check_direction(const std::string& field, const glm::vec3& d) {
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(d[k])) {
      return ParamError{field + "[" + std::to_string(k) + "]",
                        "must be a finite number, got " + fmt(d[k])};
    }
  }
  // Below the bound the normalised direction would be dominated by rounding.
  return check_length(field, double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z,
                      " (it is normalised, and a shorter one would be mostly rounding)");
}

std::optional<ParamError> check_color(const std::string& field, const glm::vec3& c) {
  for (int k = 0; k < 3; ++k) {
    if (auto e = check_range(field + "[" + std::to_string(k) + "]", c[k], 0.0, 1.0)) return e;
  }
  return std::nullopt;
}

}  // namespace

std::optional<ParamError> validate(const FurParams& p) {
  if (p.shells < 2 || p.shells > 128) {
    return ParamError{"shells", "must be an integer in [2, 128] (layer 0 sits on the base "
                                "surface, so fur needs at least 2), got " +
                                    std::to_string(p.shells)};
  }
  if (p.authored_shells != 0 && (p.authored_shells < 2 || p.authored_shells > 128))
    return ParamError{"authored_shells", "must be 0 or an integer in [2, 128], got " + std::to_string(p.authored_shells)};
  if (auto e = check_range("length", p.length, 0.0, 2.0, true)) return e;
  if (auto e = check_range("density", p.density, 0.0, 100.0, true)) return e;
  if (p.texture_size < 16 || p.texture_size > 4096 ||
      (p.texture_size & (p.texture_size - 1)) != 0) {
    return ParamError{"texture_size", "must be a power of two in [16, 4096], got " +
                                          std::to_string(p.texture_size)};
  }
  if (auto e = check_range("texture_repeat", p.texture_repeat, 0.0, 1000.0, true)) return e;
  if (p.texture_coordinates && to_string(*p.texture_coordinates) == "invalid")
    return ParamError{"texture_coordinates", kStrandCoordinatesChoice};
  // Fewer than one strand root would leave the textures empty.
  double roots = double(p.density) / 100.0 * double(p.texture_size) * double(p.texture_size);
  if (std::lround(roots) < 1) {
    return ParamError{"density", "gives no strand at texture_size " +
                                     std::to_string(p.texture_size) + " (needs >= 1 root texel)"};
  }
  if (p.fins != FinMode::off && p.fins != FinMode::all && p.fins != FinMode::silhouette) {
    return ParamError{"fins", "must be \"off\", \"all\" or \"silhouette\""};
  }
  if (auto e = check_color("root_color", p.root_color)) return e;
  if (auto e = check_color("tip_color", p.tip_color)) return e;
  if (p.gravity) {
    const GravityParams& g = *p.gravity;
    if (auto e = check_direction("gravity.direction", g.direction)) return e;
    if (auto e = check_range("gravity.strength", g.strength, 0.0, 1e3)) return e;
    if (auto e = check_range("gravity.stability", g.stability, 0.0, 1e9, true)) return e;
  }
  if (p.wind) {
    const WindParams& w = *p.wind;
    if (auto e = check_direction("wind.direction", w.direction)) return e;
    if (auto e = check_range("wind.strength", w.strength, 0.0, 1e3)) return e;
    if (auto e = check_range("wind.gust_frequency", w.gust_frequency, 0.0, 1e3)) return e;
    if (auto e = check_range("wind.gust_scale", w.gust_scale, 0.0, 1.0)) return e;
  }
  if (p.comb) {
    if (auto e = check_direction("comb.direction", p.comb->direction)) return e;
    if (auto e = check_range("comb.weight", p.comb->weight, 0.0, 1.0)) return e;
    const glm::vec2 uvd = p.comb->uv_direction;
    if (!std::isfinite(uvd.x) || !std::isfinite(uvd.y))
      return ParamError{"comb.uv_direction", "must be finite, got [" + fmt(uvd.x) + ", " + fmt(uvd.y) + "]"};
    // The bound the comb's other direction has; d scales with it, and a d that vanishes keeps the normal.
    if (auto e = check_length("comb.uv_direction", double(uvd.x) * uvd.x + double(uvd.y) * uvd.y, "")) return e;
  }
  return std::nullopt;
}

namespace {

// Each enum's names, one table each, read both ways.
template <class E>
struct Named {
  E value;
  std::string_view name;
};
constexpr Named<FinMode> kFinModes[] = {
    {FinMode::off, "off"}, {FinMode::all, "all"}, {FinMode::silhouette, "silhouette"}};
constexpr Named<StrandCoordinates> kStrandCoordinates[] = {
    {StrandCoordinates::mesh, "mesh"}, {StrandCoordinates::projected, "projected"}, {StrandCoordinates::box, "box"}};

template <class E, size_t N>
std::string_view name_of(const Named<E> (&table)[N], E value) {
  for (const Named<E>& n : table)
    if (n.value == value) return n.name;
  return "invalid";
}

template <class E, size_t N>
std::optional<E> value_of(const Named<E> (&table)[N], std::string_view text) {
  for (const Named<E>& n : table)
    if (n.name == text) return n.value;
  return std::nullopt;
}

}  // namespace

std::string_view to_string(FinMode mode) { return name_of(kFinModes, mode); }
std::string_view to_string(StrandCoordinates coordinates) { return name_of(kStrandCoordinates, coordinates); }

std::optional<StrandCoordinates> strand_coordinates_from_string(std::string_view text) {
  return value_of(kStrandCoordinates, text);
}

std::optional<FinMode> fin_mode_from_string(std::string_view text) { return value_of(kFinModes, text); }

}  // namespace pelt::fur
