// What `pelt tradeoff` renders: the reference, the scene as written, each knob's settings
// one at a time on top of the scene's quality, and the named presets.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tools/io/quality.h"

namespace pelt::tradeoff {

// Row labels that are not knobs of io::kKnobs.
inline constexpr std::string_view kReferenceKnob = "reference";  // setting "reference"
inline constexpr std::string_view kDefaultKnob = "default";      // setting "scene"
inline constexpr std::string_view kPresetKnob = "preset";        // setting: the preset's name
// The presets measured as combinations, in this order.
inline constexpr std::string_view kSweepPresets[] = {"fast", "balanced", "high"};

struct Setting {
  std::string knob, setting;
  io::Quality quality;
  // Index of an earlier setting with exactly the same io::Quality: its measurement is
  // reused (the renders would be the same work on the same input).
  std::optional<size_t> same_as;
};

// Parses --knobs: a comma-separated list of names from io::kKnobs, no repeats, at least
// one. Throws io::InputError("", "--knobs", reason) naming the bad entry and the valid
// names.
std::vector<std::string> parse_knob_list(std::string_view list);

// The sweep, in order: reference (preset "reference"), default (`base`, the scene's own
// quality), then for each knob each of io::knob_sweep(knob) applied on top of `base`, then
// the presets of kSweepPresets. `same_as` is filled for every repeated quality.
std::vector<Setting> plan_sweep(const io::Quality& base, const std::vector<std::string>& knobs);

// The settings timed a second time, in the order they are timed: every rendered setting
// (no `same_as`) except the reference, last to first. The first pass goes through the plan
// in order right after the reference's long render, so its first rows run in whatever state
// that load leaves the machine in; on the way back each row has a different neighbour and
// a different distance from the reference (see combine_passes).
std::vector<size_t> second_pass_order(const std::vector<Setting>& plan);

}  // namespace pelt::tradeoff
