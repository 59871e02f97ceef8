// Wall-clock timing of frames for the benchmarks (`pelt bench fps`, `pelt tradeoff`), the
// paired form that prices one setting against another on a shared, noisy machine: both draws
// of a pair run one right after the other, so they share the machine's phase, and their ratio
// holds still where either time alone drifts, and the quantiles they report.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

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

// The q-quantile (0 <= q <= 1) of a sample, interpolated linearly between the two nearest
// ranks: q = 0.5 is the median, the mean of the middle two for an even count. Every figure a
// benchmark reports (bench fps, bench skin, tradeoff) uses this one rule, so their medians
// and quartiles compare. Throws std::invalid_argument for an empty sample.
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) throw std::invalid_argument("quantile of no values");
  std::sort(v.begin(), v.end());
  const double at = std::clamp(q, 0.0, 1.0) * double(v.size() - 1);
  const size_t lo = size_t(std::floor(at)), hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (at - double(lo)) * (v[hi] - v[lo]);
}

}  // namespace pelt::render
