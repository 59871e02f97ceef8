// The quality flags shared by the commands that render: `--quality PRESET` and one flag per
// knob (`--shells 32`, `--multiple-scattering reference`, ...). They apply on top of the
// scene's own `quality` block: the scene first, then the preset, then each knob flag.
#pragma once

#include <string>
#include <iterator>

#include <CLI/CLI.hpp>

#include "tools/io/quality.h"
#include "tools/io/scene.h"

namespace pelt::cli {

struct QualityFlags {
  std::string preset;
  std::string values[std::size(io::kKnobs)];  // per knob of io::kKnobs; empty: not given
};

void add_quality_options(CLI::App& sub, QualityFlags& flags);
// The quality to render `scene` at. Throws io::InputError naming the flag for an unknown
// preset or a bad knob value.
io::Quality resolve_quality(const io::Scene& scene, const QualityFlags& flags);

}  // namespace pelt::cli
