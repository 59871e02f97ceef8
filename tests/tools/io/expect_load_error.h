// A mesh file the loader must refuse, and what its error must name.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tools/io/input_error.h"
#include "tools/io/mesh_loader.h"

namespace pelt::io::testing {

inline void expect_load_error(const std::filesystem::path& file, const std::string& field,
                              const std::string& reason_part) {
  try {
    load_mesh_file(file);
    FAIL() << file << " was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, file.string());
    EXPECT_EQ(e.field, field) << e.what();
    EXPECT_NE(e.reason.find(reason_part), std::string::npos) << e.what();
  }
}

}  // namespace pelt::io::testing
