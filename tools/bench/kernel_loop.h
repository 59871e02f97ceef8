// What the kernel benchmarks share: the SoA batch buffers and the timing loop (dispatch
// restricted to one Highway target, 0: no restriction, for scalar references; the kernel
// called once per iteration on the same batch; a lanes-per-second counter).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <benchmark/benchmark.h>
#include <hwy/aligned_allocator.h>
#include <hwy/targets.h>

namespace pelt::bench {

// `count` arrays of `lanes` floats each, 64-byte aligned (the kernels' SoA contract), zeroed.
class AlignedArrays {
 public:
  AlignedArrays(size_t count, size_t lanes) {
    for (size_t k = 0; k < count; ++k) {
      arrays_.push_back(hwy::AllocateAligned<float>(lanes));
      std::fill(arrays_.back().get(), arrays_.back().get() + lanes, 0.0f);
    }
  }
  float* operator[](size_t k) const { return arrays_[k].get(); }

 private:
  std::vector<hwy::AlignedFreeUniquePtr<float[]>> arrays_;
};

template <class Kernel>
void time_lanes(benchmark::State& state, int64_t target, size_t lanes_per_call, Kernel&& kernel) {
  if (target != 0) hwy::SetSupportedTargetsForTest(target);
  for (auto _ : state) {
    kernel();
    benchmark::ClobberMemory();
  }
  state.counters["lanes/s"] =
      benchmark::Counter(double(state.iterations()) * double(lanes_per_call), benchmark::Counter::kIsRate);
  hwy::SetSupportedTargetsForTest(0);
}

}  // namespace pelt::bench
