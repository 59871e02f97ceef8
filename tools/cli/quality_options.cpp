#include "tools/cli/quality_options.h"

#include <algorithm>
#include <optional>

#include "tools/io/input_error.h"

namespace pelt::cli {
namespace {

// `multiple_scattering` is spelled `--multiple-scattering` on the command line.
std::string flag_of(std::string_view knob) {
  std::string f = "--" + std::string(knob);
  for (char& c : f)
    if (c == '_') c = '-';
  return f;
}

}  // namespace

void add_quality_options(CLI::App& sub, QualityFlags& flags) {
  std::string presets;
  for (std::string_view n : io::quality_preset_names()) presets += (presets.empty() ? "" : " | ") + std::string(n);
  sub.add_option("--quality", flags.preset, "Quality preset: " + presets + " (default: the scene's `quality`)");
  for (size_t k = 0; k < std::size(io::kKnobs); ++k) add_knob_option(sub, io::kKnobs[k], flags.values[k], "Quality knob, e.g.");
}

void add_knob_option(CLI::App& sub, std::string_view knob, std::string& value, const std::string& what) {
  std::string help = what;
  for (const std::string& v : io::knob_sweep(knob)) {
    help += help.size() == what.size() ? " " : " | ";
    help += v;
  }
  sub.add_option(flag_of(knob), value, help);
}

void apply_knob_flag(io::Quality& q, std::string_view knob, const std::string& value) {
  if (value.empty()) return;
  if (auto e = io::set_knob(q, knob, value)) throw io::InputError("", flag_of(knob), *e);
}

io::Quality resolve_quality(const io::Scene& scene, const QualityFlags& flags) {
  io::Quality q = scene.quality;
  if (!flags.preset.empty()) {
    const auto p = io::quality_preset(flags.preset);
    if (!p) {
      std::string names;
      for (std::string_view n : io::quality_preset_names()) names += (names.empty() ? "" : ", ") + std::string(n);
      throw io::InputError("", "--quality", "unknown preset `" + flags.preset + "` (" + names + ")");
    }
    q = *p;
  }
  for (size_t k = 0; k < std::size(io::kKnobs); ++k) apply_knob_flag(q, io::kKnobs[k], flags.values[k]);
  return q;
}

io::InputError name_flag_origin(const io::InputError& e, const io::Scene& scene, const QualityFlags& flags,
                                int width, int height) {
  if (e.file != scene.file.string()) return e;
  // A knob's flag, or the preset's when it changed the knob from the scene's own value.
  auto knob_origin = [&](std::string_view knob, bool preset_changed_it) -> std::string {
    const size_t k = size_t(std::find(std::begin(io::kKnobs), std::end(io::kKnobs), knob) - std::begin(io::kKnobs));
    if (k < std::size(io::kKnobs) && !flags.values[k].empty()) return flag_of(knob);
    if (!flags.preset.empty() && preset_changed_it) return "--quality";
    return {};
  };
  std::string flag;
  if (e.field == "image.width") {
    flag = width > 0 ? "--width" : height > 0 ? "--height" : "";
  } else if (e.field == "quality.shells") {
    const std::optional<io::Quality> preset = io::quality_preset(flags.preset);
    flag = knob_origin("shells", preset && preset->shells != scene.quality.shells);
  } else if (e.field == "quality.spp") {
    const std::optional<io::Quality> preset = io::quality_preset(flags.preset);
    flag = knob_origin("spp", preset && preset->spp != scene.quality.spp);
  }
  return flag.empty() ? e : io::InputError("", flag, e.reason);
}

}  // namespace pelt::cli
