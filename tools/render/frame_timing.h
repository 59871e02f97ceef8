// Wall-clock timing of frames for the benchmarks (`pelt bench fps`, `pelt tradeoff`), and the
// paired form that prices one setting against another on a shared, noisy machine: both draws
// of a pair run one right after the other, so they share the machine's phase, and their ratio
// holds still where either time alone drifts.
#pragma once

#include <chrono>
#include <utility>

namespace pelt::render {

// fn()'s wall time in milliseconds.
template <class Fn>
double time_ms(Fn&& fn) {
  const auto start = std::chrono::steady_clock::now();
  fn();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Times a() and b() one right after the other, a() first on an even `turn` and b() first on an
// odd one: taking turns, neither is always the one that finds the caches holding the other's
// data. Returns {a's ms, b's ms}.
template <class A, class B>
std::pair<double, double> time_side_by_side(int turn, A&& a, B&& b) {
  std::pair<double, double> ms;
  if (turn % 2 != 0) ms.second = time_ms(b);
  ms.first = time_ms(a);
  if (turn % 2 == 0) ms.second = time_ms(b);
  return ms;
}

}  // namespace pelt::render
