// Which Highway target the kernels dispatch to, by pelt's names. Every kernel dispatches
// dynamically to the best target that was compiled and that the CPU supports; a farm whose
// nodes differ pins one target for all of them, since targets of the two arithmetics (fused
// multiply-add or not) differ in the last bits and a sequence would flicker where shards meet
// (README, Design: SIMD).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pelt::raster {

// pelt's names, best first: "avx512" (Highway's AVX3), "avx2", "sse4", "portable" (Highway's
// fallback in plain C++: SCALAR, one lane, when GCC before 12.3 builds it, else EMU128).
struct SimdTarget {
  const char* name;  // pelt's name, as --simd takes it
  int64_t hwy_bit;   // the HWY_* bit
  // Highway's MulAdd is one fused operation on AVX2 and AVX-512 and a multiply then an add
  // below: targets that agree on this draw the same bytes (README, Design: SIMD).
  bool fused_multiply_add;
};

// The targets this build compiled, best first. The portable fallback is always among them.
const std::vector<SimdTarget>& compiled_simd_targets();

// The compiled targets this CPU can run, best first, whatever is pinned (the portable one last).
const std::vector<SimdTarget>& runnable_simd_targets();

// The target the kernels dispatch to now, as Highway reports it.
SimdTarget active_simd_target();

// The target a kernel dispatched now actually runs on (a Highway kernel that names its own
// compiled target): what a pin must change, whatever active_simd_target says.
std::string dispatched_simd_target();

// Pins `name`: every better target is disabled, so each kernel dispatches to it ("auto": no
// pin, or none any more). Not while kernels run. Returns "" on success, else why not (an
// unknown name, or one this build or CPU cannot run), naming what can be asked for.
std::string pin_simd_target(const std::string& name);

// Why `name` cannot be pinned when the CPU runs `runnable` ("" when it can, and for "auto").
std::string simd_pin_refusal(const std::string& name, const std::vector<SimdTarget>& runnable);

// Holds dispatch to another target while it lives (`bench fps --versus simd=sse4` draws every
// other frame so), then back to what was set before (a pin, an outer scope, or nothing). `name`
// must be one simd_pin_refusal accepts. Not while kernels run on other threads.
class SimdTargetScope {
 public:
  explicit SimdTargetScope(const std::string& name);
  ~SimdTargetScope();
  SimdTargetScope(const SimdTargetScope&) = delete;
  SimdTargetScope& operator=(const SimdTargetScope&) = delete;

 private:
  int64_t previous_;
};

// "avx512, avx2, portable": the targets' names joined.
std::string simd_target_names(const std::vector<SimdTarget>& targets);

// "auto|avx512|avx2|sse4|portable": the names --simd takes.
std::string simd_target_choices();

}  // namespace pelt::raster
