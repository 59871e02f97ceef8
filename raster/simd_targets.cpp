#include "raster/simd_targets.h"

#include <algorithm>

#include <hwy/targets.h>

namespace pelt::raster {
namespace {

// The mask pin_simd_target set (0: none, dispatch free to choose), restored by SimdTargetScope.
int64_t g_pinned_mask = 0;

// The targets dispatch may choose when `name` (a runnable target) is pinned: it and those
// below it; every lower bit is a better target.
int64_t mask_for(const std::string& name) {
  int64_t wanted = 0;
  for (const SimdTarget& t : runnable_simd_targets())
    if (name == t.name) wanted = t.hwy_bit;
  int64_t keep = HWY_SCALAR;
  for (const SimdTarget& t : runnable_simd_targets())
    if (t.hwy_bit >= wanted) keep |= t.hwy_bit;
  return keep;
}

// Every x86 target pelt's kernels may be compiled for, best first; the list is filtered by
// HWY_TARGETS, so a build that leaves one out (PELT_HWY_DISABLED_TARGETS) does not offer it.
constexpr SimdTarget kKnown[] = {
    {"avx512", HWY_AVX3, 16, true},
    {"avx2", HWY_AVX2, 8, true},
    {"sse4", HWY_SSE4, 4, false},
    {"scalar", HWY_SCALAR, 1, false},
};

}  // namespace

const std::vector<SimdTarget>& compiled_simd_targets() {
  static const std::vector<SimdTarget> compiled = [] {
    std::vector<SimdTarget> out;
    for (const SimdTarget& t : kKnown)
      if (HWY_TARGETS & t.hwy_bit) out.push_back(t);
    return out;
  }();
  return compiled;
}

const std::vector<SimdTarget>& runnable_simd_targets() {
  // Taken on the first call, which pin_simd_target makes before it disables anything: after a
  // pin, SupportedTargets() no longer lists the targets pinned out.
  static const std::vector<SimdTarget> runnable = [] {
    std::vector<SimdTarget> out;
    const int64_t supported = hwy::SupportedTargets();
    for (const SimdTarget& t : compiled_simd_targets())
      if (supported & t.hwy_bit) out.push_back(t);
    return out;
  }();
  return runnable;
}

SimdTarget active_simd_target() {
  // The CPU may support targets this build did not compile (AVX3_DL): dispatch chooses among
  // the compiled ones. x86 bits are ordered best first from the lowest, the fallback SCALAR
  // above them all, so the lowest set bit is dispatch's choice.
  const int64_t usable = hwy::SupportedTargets() & HWY_TARGETS;
  const int64_t best = usable & -usable;
  for (const SimdTarget& t : kKnown)
    if (t.hwy_bit == best) return t;
  return {hwy::TargetName(best), best, 0, false};
}

std::string simd_target_choices() {
  std::string out = "auto";
  for (const SimdTarget& t : compiled_simd_targets()) out += std::string("|") + t.name;
  return out;
}

std::string simd_pin_refusal(const std::string& name, const std::vector<SimdTarget>& runnable) {
  if (name == "auto") return "";
  const auto named = [&](const SimdTarget& t) { return name == t.name; };
  if (std::none_of(compiled_simd_targets().begin(), compiled_simd_targets().end(), named))
    return "`" + name + "` is not a SIMD target of this build (" + simd_target_choices() + ")";
  if (std::none_of(runnable.begin(), runnable.end(), named)) {
    std::string can;
    for (const SimdTarget& t : runnable) can += std::string(can.empty() ? "" : ", ") + t.name;
    return "this CPU cannot run `" + name + "` (it runs " + can + ")";
  }
  return "";
}

std::string pin_simd_target(const std::string& name) {
  const std::vector<SimdTarget>& runnable = runnable_simd_targets();
  if (std::string refusal = simd_pin_refusal(name, runnable); !refusal.empty()) return refusal;
  // Through SetSupportedTargetsForTest and not DisableTargets: in Debian's Highway 1.0.3 every
  // later call of SupportedTargets() resets dispatch to the CPU's best target while no test
  // mask is set (it updates the chosen target from the CPU's bits before masking them), so
  // reporting the target, as `bench fps` does before its frames, undid the pin.
  g_pinned_mask = name == "auto" ? 0 : mask_for(name);
  hwy::SetSupportedTargetsForTest(g_pinned_mask);
  return "";
}

SimdTargetScope::SimdTargetScope(const std::string& name) { hwy::SetSupportedTargetsForTest(mask_for(name)); }

SimdTargetScope::~SimdTargetScope() { hwy::SetSupportedTargetsForTest(g_pinned_mask); }

}  // namespace pelt::raster
