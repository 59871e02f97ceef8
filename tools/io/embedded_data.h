// Data files compiled into pelt_io (generated at build time by embed_file.cmake).
#pragma once

#include <string_view>

namespace pelt::io::embedded {

// tools/data/teapot.bpt, byte for byte.
std::string_view teapot_bpt();

}  // namespace pelt::io::embedded
