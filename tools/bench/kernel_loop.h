// The timing loop the kernel benchmarks share: dispatch restricted to one Highway target (0: no
// restriction, for scalar references), the kernel called once per iteration on the same batch,
// and a lanes-per-second counter.
#pragma once

#include <cstddef>
#include <cstdint>

#include <benchmark/benchmark.h>
#include <hwy/targets.h>

namespace pelt::bench {

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
