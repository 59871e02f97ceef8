// Pieces shared by the OBJ and glTF loaders (internal to pelt_io).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/io/mesh_loader.h"

namespace pelt::io::detail {

LoadedMesh load_obj(const std::filesystem::path& path, const Budget& budget);
LoadedMesh load_gltf(const std::filesystem::path& path, bool binary, const Budget& budget);

// The refusal of a mesh whose triangle count is over budget.max_faces.
void check_face_budget(uint64_t triangles, const Budget& budget, const std::string& file,
                       const std::string& field);

// Adds a library's warning text (tinyobjloader's, tinygltf's) to out.warnings, one warning
// per line, trimmed, so that each line the user sees names the file it is about.
void add_library_warnings(LoadedMesh& out, const std::string& text);

// Fills in normals when the loader had none for some vertex (has_normals false), or when
// a given normal has zero length; normalises the rest. Adds a warning when normals the
// file gives (any_normals) are replaced by computed ones.
// `sharing`: how computed normals join split vertices (the OBJ loader joins copies at one
// position, as its vertices are split only where a texture coordinate changes; glTF's vertices
// are split on purpose, as the file's author meant them). `smoothing`: one key per vertex, or
// empty (compute_vertex_normals: an OBJ's smoothing groups).
void finish_normals(LoadedMesh& out, bool has_normals, bool any_normals, NormalSharing sharing,
                    const std::vector<uint64_t>& smoothing = {});

// The index of `set` in `sets`: of the first set that draws alike (the same images, placed
// alike, and the same alpha), else of `set` appended. Both loaders give each face its set so.
uint32_t add_map_set(std::vector<MeshMaps>& sets, MeshMaps set);

// Adds `name` to `names` unless it is there or four are (settle_uvs shows three and "...").
void note_uvless(std::vector<std::string>& names, const std::string& name);

// Settles the texture coordinates a loader read (out.mesh.uvs, (0, 0) where missing[v] = 1), by
// triangles (a triangle lacks uvs when a corner does): none kept when every triangle lacks them;
// otherwise kept, with out.uv_missing set when some triangle lacks them and a warning naming the
// file's elements without uvs, `what` then `names` (note_uvless): "faces of material `a` and no
// material", "no TEXCOORD_0 in meshes[0].primitives[1]".
void settle_uvs(LoadedMesh& out, std::vector<uint8_t> missing, const std::string& what,
                const std::vector<std::string>& names);

}  // namespace pelt::io::detail
