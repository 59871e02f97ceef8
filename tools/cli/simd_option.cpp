#include "tools/cli/simd_option.h"

#include "raster/simd_targets.h"

namespace pelt::cli {

void add_simd_option(CLI::App& sub) {
  sub.add_option_function<std::string>(
         "--simd", [](const std::string&) {},
         "SIMD target of every kernel (default: auto, the best this CPU runs): " + raster::simd_target_choices() +
             "; pin one on a farm of mixed CPUs, so every node draws the same bytes")
      ->check(CLI::Validator([](std::string& name) { return raster::pin_simd_target(name); }, "TARGET", "simd"));
}

std::string simd_in_use() { return raster::active_simd_target().name; }

std::string simd_runnable() {
  std::string out;
  for (const raster::SimdTarget& t : raster::runnable_simd_targets()) out += std::string(out.empty() ? "" : ", ") + t.name;
  return out;
}

}  // namespace pelt::cli
