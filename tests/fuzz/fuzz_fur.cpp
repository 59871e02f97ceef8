// libFuzzer target: see run_fur in fuzz_entries.h. Rejections (io::InputError, or the fur's
// ParamError) are caught there; anything that escapes terminates the run and is a crash to fix.
#include <cstddef>
#include <cstdint>

#include "tests/fuzz/fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pelt::fuzz::run_fur(data, size);
  return 0;
}
