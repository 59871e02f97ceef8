// The target table, the pin and a probe kernel that names the target it was compiled for.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/simd_targets.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>

#include "raster/simd_targets.h"

HWY_BEFORE_NAMESPACE();
namespace pelt::raster::HWY_NAMESPACE {

int64_t CompiledTarget() { return HWY_TARGET; }

}  // namespace pelt::raster::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pelt::raster {
namespace {

// Highway's plain C++ fallback: SCALAR where EMU128 is broken (GCC before 12.3), else EMU128.
constexpr int64_t kPortableBit = (HWY_TARGETS & HWY_EMU128) ? HWY_EMU128 : HWY_SCALAR;

// Every x86 target pelt's kernels may be compiled for, best first; the list is filtered by
// HWY_TARGETS, so a build that leaves one out (PELT_HWY_DISABLED_TARGETS) does not offer it.
constexpr SimdTarget kKnown[] = {
    {"avx512", HWY_AVX3, true},
    {"avx2", HWY_AVX2, true},
    {"sse4", HWY_SSE4, false},
    {"portable", kPortableBit, false},
};

// What is set now: 0 (dispatch free to choose), the pin's mask, or a scope's.
int64_t g_current_mask = 0;

void set_mask(int64_t mask) {
  // Through SetSupportedTargetsForTest and not DisableTargets: in Highway 1.0.3 (and upstream
  // through 1.2.0) every later call of SupportedTargets() resets dispatch to the CPU's best
  // target while no test mask is set (it updates the chosen target from the CPU's bits before
  // masking them), so reporting the target, as `bench fps` does before its frames, undid a
  // DisableTargets pin. The test mask is returned as is and reaches dispatch.
  g_current_mask = mask;
  hwy::SetSupportedTargetsForTest(mask);
}

// The targets dispatch may choose when `name` (a runnable target) is pinned: it and those
// below it (every lower bit is a better target), and the fallback.
int64_t mask_for(const std::string& name) {
  int64_t wanted = 0;
  for (const SimdTarget& t : runnable_simd_targets())
    if (name == t.name) wanted = t.hwy_bit;
  int64_t keep = kPortableBit;
  for (const SimdTarget& t : runnable_simd_targets())
    if (t.hwy_bit >= wanted) keep |= t.hwy_bit;
  return keep;
}

SimdTarget target_of_bit(int64_t bit) {
  for (const SimdTarget& t : kKnown)
    if (t.hwy_bit == bit) return t;
  return {hwy::TargetName(bit), bit, false};
}

}  // namespace

HWY_EXPORT(CompiledTarget);

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
  // pin, SupportedTargets() no longer lists the targets pinned out. Highway always supports
  // its fallback.
  static const std::vector<SimdTarget> runnable = [] {
    std::vector<SimdTarget> out;
    const int64_t supported = hwy::SupportedTargets() | kPortableBit;
    for (const SimdTarget& t : compiled_simd_targets())
      if (supported & t.hwy_bit) out.push_back(t);
    return out;
  }();
  return runnable;
}

SimdTarget active_simd_target() {
  // The CPU may support targets this build did not compile (AVX3_DL): dispatch chooses among
  // the compiled ones. x86 bits are ordered best first from the lowest, the fallbacks above
  // them all, so the lowest set bit is dispatch's choice.
  const int64_t usable = hwy::SupportedTargets() & HWY_TARGETS;
  return target_of_bit(usable & -usable);
}

std::string dispatched_simd_target() { return target_of_bit(HWY_DYNAMIC_DISPATCH(CompiledTarget)()).name; }

std::string simd_target_names(const std::vector<SimdTarget>& targets) {
  std::string out;
  for (const SimdTarget& t : targets) out += std::string(out.empty() ? "" : ", ") + t.name;
  return out;
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
  if (std::none_of(runnable.begin(), runnable.end(), named))
    return "this CPU cannot run `" + name + "` (it runs " + simd_target_names(runnable) + ")";
  return "";
}

std::string pin_simd_target(const std::string& name) {
  if (std::string refusal = simd_pin_refusal(name, runnable_simd_targets()); !refusal.empty()) return refusal;
  set_mask(name == "auto" ? 0 : mask_for(name));
  return "";
}

SimdTargetScope::SimdTargetScope(const std::string& name) : previous_(g_current_mask) { set_mask(mask_for(name)); }

SimdTargetScope::~SimdTargetScope() { set_mask(previous_); }

}  // namespace pelt::raster
#endif  // HWY_ONCE
