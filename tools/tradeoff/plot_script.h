// The plot script compiled into pelt_tradeoff by tools/io/embed_file.cmake, which writes
// its functions into pelt::io::embedded (see tools/tradeoff/CMakeLists.txt).
#pragma once

#include <string_view>

namespace pelt::io::embedded {

// tools/tradeoff/plot_tradeoff.py, byte for byte.
std::string_view plot_tradeoff_py();

}  // namespace pelt::io::embedded
