// Pieces shared by the OBJ and glTF loaders (internal to pelt_io).
#pragma once

#include <filesystem>
#include <string>

#include "tools/io/mesh_loader.h"

namespace pelt::io::detail {

LoadedMesh load_obj(const std::filesystem::path& path);
LoadedMesh load_gltf(const std::filesystem::path& path, bool binary);

// Fills in normals when the loader had none for some vertex (has_normals false), or when
// a given normal has zero length; normalises the rest. Adds a warning when it computes.
void finish_normals(LoadedMesh& out, bool has_normals);

}  // namespace pelt::io::detail
