// libFuzzer target: see run_sampler in fuzz_entries.h. It never rejects
// an input; anything that escapes terminates the run and is a crash to fix.
#include <cstddef>
#include <cstdint>

#include "tests/fuzz/fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pelt::fuzz::run_sampler(data, size);
  return 0;
}
