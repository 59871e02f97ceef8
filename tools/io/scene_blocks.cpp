#include "tools/io/scene_blocks.h"

#include <limits>

namespace pelt::io::detail {
namespace {

using nlohmann::json;

constexpr long long kIntMin = std::numeric_limits<int>::min(), kIntMax = std::numeric_limits<int>::max();

float num(const JsonFields& js, const json& obj, const std::string& path, const char* key, float fallback) {
  const json* v = JsonFields::find(obj, key);
  return v ? static_cast<float>(js.number(*v, json_child(path, key))) : fallback;
}

void num3(const JsonFields& js, const json& obj, const std::string& path, const char* key, float out[3]) {
  if (const json* v = JsonFields::find(obj, key)) {
    const auto n = js.numbers(*v, json_child(path, key), 3, 3);
    for (int k = 0; k < 3; ++k) out[k] = static_cast<float>(n[k]);
  }
}

glm::vec3 vec(const JsonFields& js, const json& obj, const std::string& path, const char* key,
              glm::vec3 fallback) {
  const json* v = JsonFields::find(obj, key);
  return v ? js.vec3(*v, json_child(path, key)) : fallback;
}

template <class Enum>
void switch_value(const JsonFields& js, const json& obj, const std::string& path, const char* key, Enum& out) {
  const json* v = JsonFields::find(obj, key);
  if (!v) return;
  const std::string field = json_child(path, key);
  if (auto e = shading::parse(key, js.string(*v, field), out)) js.fail(field, e->reason);
}

}  // namespace

fur::FurParams parse_fur_block(const JsonFields& js, const json& j, const std::string& path) {
  js.expect_object(j, path,
                   {"shells", "length", "density", "texture_size", "texture_coordinates", "texture_repeat",
                    "seed", "fins", "root_color", "tip_color", "use_color_map", "length_map", "gravity", "wind",
                    "comb"});  // length_map: a path, read by parse_scene
  fur::FurParams p;
  // Counts are read over int's whole range, so that a value out of theirs gets
  // FurParams::validate's message (its range and why), not a generic bound.
  if (const json* v = JsonFields::find(j, "shells"))
    p.shells = static_cast<int>(js.integer(*v, json_child(path, "shells"), kIntMin, kIntMax));
  p.length = num(js, j, path, "length", p.length);
  p.density = num(js, j, path, "density", p.density);
  if (const json* v = JsonFields::find(j, "texture_size"))
    p.texture_size = static_cast<int>(js.integer(*v, json_child(path, "texture_size"), kIntMin, kIntMax));
  if (const json* v = JsonFields::find(j, "texture_coordinates")) {
    const std::string field = json_child(path, "texture_coordinates");
    const std::string text = js.string(*v, field);
    p.texture_coordinates = fur::strand_coordinates_from_string(text);
    if (!p.texture_coordinates)
      js.fail(field, std::string(fur::kStrandCoordinatesChoice).append(", got \"").append(text).append("\""));
  }
  p.texture_repeat = num(js, j, path, "texture_repeat", p.texture_repeat);
  if (const json* v = JsonFields::find(j, "seed"))
    p.seed = static_cast<uint32_t>(js.integer(*v, json_child(path, "seed"), 0, 4294967295ll));
  if (const json* v = JsonFields::find(j, "fins")) {
    const std::string field = json_child(path, "fins");
    const std::string text = js.string(*v, field);
    const auto mode = fur::fin_mode_from_string(text);
    if (!mode) js.fail(field, "must be \"off\", \"all\" or \"silhouette\", got \"" + text + "\"");
    p.fins = *mode;
  }
  p.root_color = vec(js, j, path, "root_color", p.root_color);
  p.tip_color = vec(js, j, path, "tip_color", p.tip_color);
  if (const json* v = JsonFields::find(j, "use_color_map"))
    p.use_color_map = js.boolean(*v, json_child(path, "use_color_map"));
  if (const json* v = JsonFields::find(j, "gravity")) {
    const std::string g = json_child(path, "gravity");
    js.expect_object(*v, g, {"direction", "strength", "stability"});
    fur::GravityParams gp;
    gp.direction = vec(js, *v, g, "direction", gp.direction);
    gp.strength = num(js, *v, g, "strength", gp.strength);
    gp.stability = num(js, *v, g, "stability", gp.stability);
    p.gravity = gp;
  }
  if (const json* v = JsonFields::find(j, "wind")) {
    const std::string w = json_child(path, "wind");
    js.expect_object(*v, w, {"direction", "strength", "gust_frequency", "gust_scale"});
    fur::WindParams wp;
    wp.direction = vec(js, *v, w, "direction", wp.direction);
    wp.strength = num(js, *v, w, "strength", wp.strength);
    wp.gust_frequency = num(js, *v, w, "gust_frequency", wp.gust_frequency);
    wp.gust_scale = num(js, *v, w, "gust_scale", wp.gust_scale);
    p.wind = wp;
  }
  if (const json* v = JsonFields::find(j, "comb")) {
    const std::string c = json_child(path, "comb");
    js.expect_object(*v, c, {"direction", "weight", "field", "uv_direction"});
    fur::CombParams cp;
    cp.direction = vec(js, *v, c, "direction", cp.direction);
    cp.weight = num(js, *v, c, "weight", cp.weight);
    if (const json* f = JsonFields::find(*v, "field")) {
      const std::string field = json_child(c, "field");
      const std::string text = js.string(*f, field);
      if (text == "uniform") cp.field = fur::CombField::uniform;
      else if (text == "uv") cp.field = fur::CombField::uv;
      else js.fail(field, "must be \"uniform\" or \"uv\", got \"" + text + "\"");
    }
    if (const json* d = JsonFields::find(*v, "uv_direction")) {
      const auto n = js.numbers(*d, json_child(c, "uv_direction"), 2, 2);
      cp.uv_direction = glm::vec2(float(n[0]), float(n[1]));
    }
    // Each field reads one of the two directions; the other, given, would be silently unused.
    if (cp.field == fur::CombField::uniform && JsonFields::find(*v, "uv_direction"))
      js.fail(json_child(c, "uv_direction"),
              "applies to a comb with \"field\": \"uv\"; this comb is uniform (it combs along `direction`)");
    if (cp.field == fur::CombField::uv && JsonFields::find(*v, "direction"))
      js.fail(json_child(c, "direction"),
              "applies to a uniform comb; a comb with \"field\": \"uv\" combs along the uvs (`uv_direction`)");
    p.comb = cp;
  }
  if (auto e = fur::validate(p)) js.fail(json_child(path, e->field), e->reason);
  return p;
}

shading::SkinParams parse_skin_block(const JsonFields& js, const json& j, const std::string& path) {
  js.expect_object(j, path,
                   {"SkinColor", "SheenColor", "Opacity", "AmbientCoeff", "Thickness", "Eta",
                    "SingleScatteringCoeff", "DiffusionColor", "MultipleScatteringCoeff", "ClampCoeff",
                    "Power", "Specularity", "g", "single_scattering", "multiple_scattering", "fresnel",
                    "phase", "specular", "normal_blur_radius", "normal_blur_mix"});
  shading::SkinParams p;
  num3(js, j, path, "SkinColor", p.SkinColor);
  num3(js, j, path, "SheenColor", p.SheenColor);
  p.Opacity = num(js, j, path, "Opacity", p.Opacity);
  p.AmbientCoeff = num(js, j, path, "AmbientCoeff", p.AmbientCoeff);
  p.Thickness = num(js, j, path, "Thickness", p.Thickness);
  p.Eta = num(js, j, path, "Eta", p.Eta);
  p.SingleScatteringCoeff = num(js, j, path, "SingleScatteringCoeff", p.SingleScatteringCoeff);
  num3(js, j, path, "DiffusionColor", p.DiffusionColor);
  p.MultipleScatteringCoeff = num(js, j, path, "MultipleScatteringCoeff", p.MultipleScatteringCoeff);
  p.ClampCoeff = num(js, j, path, "ClampCoeff", p.ClampCoeff);
  p.Power = num(js, j, path, "Power", p.Power);
  p.Specularity = num(js, j, path, "Specularity", p.Specularity);
  p.g = num(js, j, path, "g", p.g);
  switch_value(js, j, path, "single_scattering", p.single_scattering);
  switch_value(js, j, path, "multiple_scattering", p.multiple_scattering);
  switch_value(js, j, path, "fresnel", p.fresnel);
  switch_value(js, j, path, "phase", p.phase);
  switch_value(js, j, path, "specular", p.specular);
  num3(js, j, path, "normal_blur_radius", p.normal_blur_radius);
  num3(js, j, path, "normal_blur_mix", p.normal_blur_mix);
  if (auto e = shading::validate(p)) js.fail(json_child(path, e->field), e->reason);
  return p;
}

Quality parse_quality_block(const JsonFields& js, const json& j, const std::string& path) {
  js.expect_object(j, path,
                   {"preset", "shells", "fins", "fin_quads", "sort", "spp", "filter", "multiple_scattering",
                    "single_scattering", "precision"});
  Quality q;
  if (const json* v = JsonFields::find(j, "preset")) {
    const std::string field = json_child(path, "preset");
    const std::string name = js.string(*v, field);
    const auto preset = quality_preset(name);
    if (!preset) {
      std::string names;
      for (std::string_view n : quality_preset_names()) names += (names.empty() ? "" : ", ") + std::string(n);
      js.fail(field, "unknown preset `" + name + "` (" + names + ")");
    }
    q = *preset;
  }
  for (std::string_view knob : kKnobs) {
    const json* v = JsonFields::find(j, knob);
    if (!v) continue;
    const std::string field = json_child(path, knob);
    // shells and spp are counts, the others names.
    const std::string text = knob == "shells" || knob == "spp"
                                 ? std::to_string(js.integer(*v, field, kIntMin, kIntMax))
                                 : js.string(*v, field);
    if (auto e = set_knob(q, knob, text)) js.fail(field, *e);
  }
  return q;
}

}  // namespace pelt::io::detail
