// Mesh files: Wavefront OBJ (tinyobjloader) and glTF 2.0 / GLB (tinygltf).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "raster/mesh.h"
#include "tools/io/alpha_mode.h"
#include "tools/io/budget.h"
#include "tools/io/image.h"
#include "tools/io/map_placement.h"

namespace pelt::io {

// A texture a mesh file refers to: either a file to load (path resolved relative to the
// mesh file) or pixels decoded from inside the mesh file (GLB buffer view, data URI).
// Both empty when the file names no such texture.
struct TextureRef {
  std::filesystem::path path;
  // Linear: sRGB-decoded for colour maps, as stored for normal maps; shared by the map sets
  // that draw one image.
  std::shared_ptr<const ImageRGBA> pixels;
  // The files `pixels` were read from, when a loader read them (an OBJ's map_Kd and map_d): inputs
  // an output may not overwrite.
  std::vector<std::filesystem::path> files;
  MapPlacement placement;  // in the file's own uv space (OBJ: v from the bottom)

  bool present() const { return !path.empty() || pixels != nullptr; }
  // Of `files`: the OBJ map_d whose dissolve `pixels` carry as alpha (the last), and the map_Kd
  // whose colour they hold beside it (the first, when there are two); null where there is none.
  const std::filesystem::path* dissolve_file() const { return files.empty() ? nullptr : &files.back(); }
  const std::filesystem::path* dissolved_color_file() const { return files.size() > 1 ? &files.front() : nullptr; }
};

// What a mesh came from: its uvs' and maps' conventions follow (OBJ counts v from the bottom of
// the image; glTF tells loaders to ignore a PNG's gamma).
enum class MeshFormat { builtin, obj, gltf };

// MeshMaps::material of faces that name no material.
inline constexpr const char* kNoMaterial = "(no material)";

// The maps and alpha a material of the file draws, as far as pelt reads a material: faces of
// two materials naming the same maps (the same images, placed alike) and alpha share one set.
struct MeshMaps {
  TextureRef color_map;   // glTF baseColorTexture / OBJ map_Kd (with map_d: its alpha, io/dissolve_map.h)
  TextureRef normal_map;  // glTF normalTexture / OBJ norm (a bump map is only warned of)
  // The first material drawn with these maps, as the file names it, or kNoMaterial (messages).
  std::string material;
  AlphaMode alpha_mode = AlphaMode::opaque;
  float alpha_cutoff = 0.5f;  // mask: the least alpha kept
  float alpha_factor = 1.0f;  // mask, blend: times the colour map's alpha (glTF baseColorFactor's)

  // Whether the faces draw otherwise than with no map.
  bool any() const { return color_map.present() || normal_map.present() || alpha_mode != AlphaMode::opaque; }
};

struct LoadedMesh {
  MeshFormat format = MeshFormat::builtin;  // set by load_mesh_file
  Mesh mesh;               // all triangles of the file in one mesh, in file order
  // The map sets the faces are drawn with, in the order of their first face; empty when no
  // face's material names a map or draws its alpha. A set may hold neither (faces of no
  // material, or of a plain one, beside faces with maps).
  std::vector<MeshMaps> maps;
  // Per triangle, its set in `maps`; empty when every triangle takes maps[0] (or there is none).
  std::vector<uint32_t> triangle_maps;
  // Per vertex, 1 where the file gave no texture coordinate though others have one: such a
  // vertex holds uv (0, 0) in mesh.uvs, so a map may not be drawn on its faces, and fur lays its
  // strands by the box mapping (a warning names where). Empty when every vertex has a uv, or none
  // has (mesh.uvs is then empty). Until 2026-11-27 one primitive or face without uvs dropped the
  // whole mesh's, and every map of the file with them.
  std::vector<uint8_t> uv_missing;
  // Things that were accepted but changed or ignored, to be shown to the user (e.g. "not
  // every vertex has a normal: all normals computed from the triangles").
  std::vector<std::string> warnings;

  // Map set k; for k = 0 of a mesh without sets, an empty one (the whole mesh draws no map).
  const MeshMaps& set(size_t k) const;
  // The first face's maps (an empty reference when it has none): the whole mesh's when it has
  // one set.
  const TextureRef& color_map() const { return set(0).color_map; }
  const TextureRef& normal_map() const { return set(0).normal_map; }
  // The set of triangle t.
  uint32_t maps_of(size_t t) const { return triangle_maps.empty() ? 0 : triangle_maps[t]; }
};

// Whether a corner of triangle t of `mesh` has no texture coordinate (LoadedMesh::uv_missing of
// the file it was loaded from; the mesh may have left the LoadedMesh).
inline bool lacks_uv(const Mesh& mesh, const std::vector<uint8_t>& uv_missing, size_t t) {
  if (uv_missing.empty()) return false;
  const uint32_t* c = &mesh.indices[3 * t];
  return (uv_missing[c[0]] | uv_missing[c[1]] | uv_missing[c[2]]) != 0;
}

// Loads .obj, .gltf or .glb (by extension, case-insensitive). OBJ: normals are used when every
// vertex has one, otherwise computed with pelt::compute_vertex_normals, per position within the
// face's smoothing group when the file has `s` records (with a warning when the file gave some
// that are replaced). glTF: a primitive's NORMAL is used, and a
// primitive without one gets flat normals (each triangle its own corners), as the specification
// asks. A zero-length normal has all of the mesh's normals computed, with a warning;
// UVs are kept when any vertex has one (LoadedMesh::uv_missing marks the others).
//
// OBJ: each `f` record split into triangles by triangulate_polygon (faces of 3 to 255
// corners); one vertex per distinct (v, vt, vn) triple, in first-use order (and smoothing group,
// where normals are computed from groups). Errors name a
// face as the file numbers its `f` records (`f 3`), with its line where the prescan finds it.
// glTF: every mesh instance of the default scene (scene 0 when none is set), with its
// node's world transform baked into positions and normals (normals by the inverse
// transpose; triangles flipped under mirroring transforms); triangle lists, strips and
// fans; indices of any type; the uv set its material's maps name (TEXCOORD_0 by default).
// Each face (OBJ) or primitive (glTF) keeps its material's maps (LoadedMesh::maps).
//
// Throws InputError naming the file and the first bad element: unreadable or malformed
// file, unsupported extension, non-finite values (`v 12: position is NaN`, or a glTF
// accessor path), index out of range, no triangles.
//
// Budgets, checked before the mesh arrays are built: the triangle count against
// budget.max_faces (OBJ: counted from the `f` lines, polygons fan-triangulated, before
// tinyobjloader parses the file; glTF: from the accessors' counts for every mesh instance
// of the scene, before any accessor is read), and every glTF image's width and height
// against budget.max_texture_side, read from its PNG or JPEG header before it is decoded.
// What is allocated before those checks is bounded by the file size: the OBJ check reads
// one line at a time; tinygltf reads the JSON and the buffers (the .glb, external .bin
// files, data URIs) whole before it calls us.
LoadedMesh load_mesh_file(const std::filesystem::path& path, const Budget& budget = Budget{});

// Checks a mesh for the problems every consumer assumes away: attribute arrays of the
// wrong length, non-finite positions, normals or uvs, indices out of range, an index
// count not a multiple of 3, no triangles. Elements are named 0-based ("vertex 12",
// "triangle 3"). Throws InputError(file, element, reason).
void validate_mesh(const Mesh& mesh, const std::string& file);

}  // namespace pelt::io
