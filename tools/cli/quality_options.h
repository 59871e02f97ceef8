// The quality flags shared by the commands that render: `--quality PRESET` and one flag per
// knob (`--shells 32`, `--multiple-scattering reference`, ...). They apply on top of the
// scene's own `quality` block: the scene first, then the preset, then each knob flag.
#pragma once

#include <iterator>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "tools/io/input_error.h"
#include "tools/io/quality.h"
#include "tools/io/scene.h"

namespace pelt::cli {

struct QualityFlags {
  std::string preset;
  std::string values[std::size(io::kKnobs)];  // per knob of io::kKnobs; empty: not given
};

void add_quality_options(CLI::App& sub, QualityFlags& flags);
// One knob's flag (`--multiple-scattering` for multiple_scattering) into `value`; the help is
// `what` followed by the knob's values (io::knob_sweep).
void add_knob_option(CLI::App& sub, std::string_view knob, std::string& value, const std::string& what);
// Sets the knob from its flag's value (nothing when empty). Throws io::InputError naming the
// flag for a bad value.
void apply_knob_flag(io::Quality& q, std::string_view knob, const std::string& value);
// The quality to render `scene` at. Throws io::InputError naming the flag for an unknown
// preset or a bad knob value.
io::Quality resolve_quality(const io::Scene& scene, const QualityFlags& flags);

// The flag that set a value the renderer refused, when one did: SceneRenderer checks the
// resolved quality and size and names the scene's fields (`quality.shells`, `quality.spp`,
// `image.width`), but a value a flag gave is named by its flag, with no file. `width` and
// `height` are the --width and --height flags (0: not given). Other errors come back as they are.
io::InputError name_flag_origin(const io::InputError& e, const io::Scene& scene, const QualityFlags& flags,
                                int width, int height);

// Returns make()'s result (the SceneRenderer a command builds), its refusal rethrown named by
// name_flag_origin. A template, so this library need not link the renderer.
template <class Make>
auto naming_flag_origin(const io::Scene& scene, const QualityFlags& flags, int width, int height, Make&& make) {
  try {
    return make();
  } catch (const io::InputError& e) {
    throw name_flag_origin(e, scene, flags, width, height);
  }
}

}  // namespace pelt::cli
