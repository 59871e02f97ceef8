// The per-target loop of the SIMD kernels' tests: every kernel is compared with its
// reference on each compiled Highway target this CPU runs, not only on the best one.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <hwy/targets.h>

namespace pelt::test {

// Runs fn(target name) once per compiled target this CPU supports, with dispatch forced to
// it, and restores dispatch to the best target afterwards.
inline void for_each_target(const std::function<void(const std::string&)>& fn) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (int64_t t : targets) {
    hwy::SetSupportedTargetsForTest(t);
    fn(hwy::TargetName(t));
  }
  hwy::SetSupportedTargetsForTest(0);
}

}  // namespace pelt::test
