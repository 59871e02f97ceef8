#include "shading/skin_params.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <utility>

namespace pelt::shading {

std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

namespace {

std::optional<ParamError> check(std::string_view field, float v, double lo, double hi) {
  if (!std::isfinite(v)) return ParamError{std::string(field), "must be a finite number, got " + format_number(v)};
  if (v < lo || v > hi)
    return ParamError{std::string(field),
                      "must be in [" + format_number(lo) + ", " + format_number(hi) + "], got " + format_number(v)};
  return std::nullopt;
}

// The kernels validate their parameters on every call (per batch, hundreds of times a frame),
// so the channel's name is built only for a value that fails.
std::optional<ParamError> check3(std::string_view field, const float (&v)[3], double lo, double hi) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(v[c]) || v[c] < lo || v[c] > hi)
      return check(std::string(field) + "[" + std::to_string(c) + "]", v[c], lo, hi);
  return std::nullopt;
}

template <class E, size_t N>
std::optional<ParamError> parse_with(const std::array<std::pair<std::string_view, E>, N>& names,
                                     std::string_view field, std::string_view text, E& out) {
  for (const auto& [name, value] : names)
    if (name == text) {
      out = value;
      return std::nullopt;
    }
  std::string valid;
  for (const auto& [name, value] : names) valid += (valid.empty() ? "" : ", ") + std::string(name);
  return ParamError{std::string(field),
                    "unknown value \"" + std::string(text) + "\"; valid values: " + valid};
}

template <class E, size_t N>
std::string_view name_of(const std::array<std::pair<std::string_view, E>, N>& names, E v) {
  for (const auto& [name, value] : names)
    if (value == v) return name;
  return "invalid";
}

constexpr std::array<std::pair<std::string_view, SingleScattering>, 3> kSingle{{
    {"off", SingleScattering::off}, {"paper", SingleScattering::paper}, {"correct", SingleScattering::correct}}};
constexpr std::array<std::pair<std::string_view, MultipleScattering>, 4> kMultiple{{
    {"off", MultipleScattering::off},
    {"paper", MultipleScattering::paper},
    {"normal_blur", MultipleScattering::normal_blur},
    {"reference", MultipleScattering::reference}}};
constexpr std::array<std::pair<std::string_view, Fresnel>, 2> kFresnel{{
    {"exact", Fresnel::exact}, {"efresnel", Fresnel::efresnel}}};
constexpr std::array<std::pair<std::string_view, Phase>, 2> kPhase{{
    {"correct", Phase::correct}, {"paper", Phase::paper}}};
constexpr std::array<std::pair<std::string_view, Specular>, 2> kSpecular{{
    {"phong", Specular::phong}, {"blinn", Specular::blinn}}};

template <class E, size_t N>
std::optional<ParamError> check_enum(std::string_view field,
                                     const std::array<std::pair<std::string_view, E>, N>& names, E v) {
  for (const auto& entry : names)
    if (entry.second == v) return std::nullopt;
  return ParamError{std::string(field), "is not a valid switch value (" +
                                            std::to_string(static_cast<uint32_t>(v)) + ")"};
}

}  // namespace

std::optional<ParamError> validate(const SkinParams& p) {
  if (auto e = check3("SkinColor", p.SkinColor, 0.0, 1.0)) return e;
  if (auto e = check3("SheenColor", p.SheenColor, 0.0, 1.0)) return e;
  if (auto e = check("Opacity", p.Opacity, 0.0, 1.0)) return e;
  if (auto e = check("AmbientCoeff", p.AmbientCoeff, 0.0, 1.0)) return e;
  if (auto e = check("Thickness", p.Thickness, 0.0, 1e6)) return e;
  if (auto e = check("Eta", p.Eta, 0.25, 4.0)) return e;
  if (auto e = check("SingleScatteringCoeff", p.SingleScatteringCoeff, 0.0, 100.0)) return e;
  if (auto e = check3("DiffusionColor", p.DiffusionColor, 0.0, 1.0)) return e;
  if (auto e = check("MultipleScatteringCoeff", p.MultipleScatteringCoeff, 0.0, 100.0)) return e;
  if (auto e = check("ClampCoeff", p.ClampCoeff, 0.0, 100.0)) return e;
  if (auto e = check("Power", p.Power, 1.0, 256.0)) return e;
  if (auto e = check("Specularity", p.Specularity, 0.0, 100.0)) return e;
  if (auto e = check("g", p.g, -1.0, 1.0)) return e;
  if (auto e = check_enum("single_scattering", kSingle, p.single_scattering)) return e;
  if (auto e = check_enum("multiple_scattering", kMultiple, p.multiple_scattering)) return e;
  if (auto e = check_enum("fresnel", kFresnel, p.fresnel)) return e;
  if (auto e = check_enum("phase", kPhase, p.phase)) return e;
  if (auto e = check_enum("specular", kSpecular, p.specular)) return e;
  if (auto e = check3("normal_blur_radius", p.normal_blur_radius, 0.0, 1e6)) return e;
  if (auto e = check3("normal_blur_mix", p.normal_blur_mix, 0.0, 1.0)) return e;
  return std::nullopt;
}

std::string_view to_string(SingleScattering v) { return name_of(kSingle, v); }
std::string_view to_string(MultipleScattering v) { return name_of(kMultiple, v); }
std::string_view to_string(Fresnel v) { return name_of(kFresnel, v); }
std::string_view to_string(Phase v) { return name_of(kPhase, v); }
std::string_view to_string(Specular v) { return name_of(kSpecular, v); }

std::optional<ParamError> parse(std::string_view field, std::string_view text, SingleScattering& out) {
  return parse_with(kSingle, field, text, out);
}
std::optional<ParamError> parse(std::string_view field, std::string_view text, MultipleScattering& out) {
  return parse_with(kMultiple, field, text, out);
}
std::optional<ParamError> parse(std::string_view field, std::string_view text, Fresnel& out) {
  return parse_with(kFresnel, field, text, out);
}
std::optional<ParamError> parse(std::string_view field, std::string_view text, Phase& out) {
  return parse_with(kPhase, field, text, out);
}
std::optional<ParamError> parse(std::string_view field, std::string_view text, Specular& out) {
  return parse_with(kSpecular, field, text, out);
}

}  // namespace pelt::shading
