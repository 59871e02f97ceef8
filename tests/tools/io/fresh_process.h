// Process-wide state under test (a module loaded once, a pool sized once) needs a process of its
// own: a "threadsafe" death test re-executes the test binary for just that case.
#pragma once

#include <cstdlib>
#include <iostream>
#include <string>

#include <gtest/gtest.h>

namespace pelt::io {

// Runs `body` in a fresh process; it passes when body returns "" there, else prints why.
template <class Body>
void in_fresh_process(Body body) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        const std::string problem = body();
        if (!problem.empty()) std::cerr << problem << std::endl;
        std::exit(problem.empty() ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
}

}  // namespace pelt::io
