#include "tools/cli/simd_option.h"

#include "raster/simd_targets.h"

namespace pelt::cli {

void add_simd_option(CLI::App& sub) {
  // Checked by the validator, pinned by the callback CLI11 calls once the value passed it.
  sub.add_option_function<std::string>(
         "--simd", [](const std::string& name) { raster::pin_simd_target(name); },
         "SIMD target of every kernel (default: auto, the best this CPU runs): " + raster::simd_target_choices() +
             "; pin one on a farm of mixed CPUs, so every node draws the same bytes")
      ->check(CLI::Validator(
          [](std::string& name) { return raster::simd_pin_refusal(name, raster::runnable_simd_targets()); }, "TARGET",
          "simd"));
}

std::string simd_in_use() { return raster::dispatched_simd_target(); }

std::string simd_runnable() { return raster::simd_target_names(raster::runnable_simd_targets()); }

}  // namespace pelt::cli
