// --simd: the SIMD target every kernel of the run dispatches to (raster/simd_targets.h). A farm
// of mixed nodes pins one target so every node draws the same bytes; a researcher pins each in
// turn to see what vector width buys (`pelt bench fps --simd avx2`).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace pelt::cli {

// Registers --simd on `sub`. The target is pinned as the option is parsed, before any kernel
// runs; a name this build or CPU cannot run is a CLI::ValidationError naming what can be asked
// for (pelt exits 2), and pins nothing.
void add_simd_option(CLI::App& sub);

// The target kernels run on (a probe kernel dispatched now), as --simd names it ("avx512", ...),
// for the commands' reports.
std::string simd_in_use();

// Every target this build and CPU can run, best first: "avx512, avx2, sse4, portable".
std::string simd_runnable();

}  // namespace pelt::cli
