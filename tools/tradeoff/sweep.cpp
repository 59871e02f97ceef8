#include "tools/tradeoff/sweep.h"

#include <algorithm>
#include <stdexcept>

#include "tools/io/input_error.h"

namespace pelt::tradeoff {
namespace {

std::string knob_names() {
  std::string s;
  for (std::string_view k : io::kKnobs) s += (s.empty() ? "" : ", ") + std::string(k);
  return s;
}

}  // namespace

std::vector<std::string> parse_knob_list(std::string_view list) {
  std::vector<std::string> knobs;
  size_t start = 0;
  while (true) {
    const size_t comma = list.find(',', start);
    const std::string_view name = list.substr(start, comma == std::string_view::npos ? list.npos : comma - start);
    if (name.empty())
      throw io::InputError("", "--knobs", "empty knob name in `" + std::string(list) + "` (" + knob_names() + ")");
    if (std::find(std::begin(io::kKnobs), std::end(io::kKnobs), name) == std::end(io::kKnobs))
      throw io::InputError("", "--knobs", "unknown knob `" + std::string(name) + "` (" + knob_names() + ")");
    if (std::find(knobs.begin(), knobs.end(), name) != knobs.end())
      throw io::InputError("", "--knobs", "knob `" + std::string(name) + "` is listed twice");
    knobs.emplace_back(name);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return knobs;
}

std::vector<Setting> plan_sweep(const io::Quality& base, const std::vector<std::string>& knobs) {
  std::vector<Setting> plan;
  const auto add = [&](std::string_view knob, std::string_view setting, const io::Quality& q) {
    Setting s{std::string(knob), std::string(setting), q, std::nullopt};
    for (size_t i = 0; i < plan.size() && !s.same_as; ++i)
      if (plan[i].quality == q) s.same_as = plan[i].same_as ? plan[i].same_as : i;
    plan.push_back(std::move(s));
  };
  add(kReferenceKnob, "reference", *io::quality_preset("reference"));
  add(kDefaultKnob, "scene", base);
  for (const std::string& knob : knobs) {
    for (const std::string& value : io::knob_sweep(knob)) {
      io::Quality q = base;
      // knob_sweep lists only values set_knob accepts; a refusal is a bug in quality.cpp.
      if (const auto why = io::set_knob(q, knob, value))
        throw std::logic_error("knob_sweep(" + knob + ") lists `" + value + "`: " + *why);
      add(knob, value, q);
    }
  }
  for (std::string_view name : kSweepPresets) add(kPresetKnob, name, *io::quality_preset(name));
  return plan;
}

std::vector<size_t> second_pass_order(const std::vector<Setting>& plan) {
  std::vector<size_t> order;
  for (size_t i = plan.size(); i-- > 0;)
    if (!plan[i].same_as && plan[i].knob != kReferenceKnob) order.push_back(i);
  return order;
}

}  // namespace pelt::tradeoff
