#include "tools/io/mesh_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <glm/geometric.hpp>

#include "tools/io/input_error.h"
#include "tools/io/mesh_loader_detail.h"

namespace pelt::io {
namespace {

const char* non_finite_name(float a, float b, float c = 0.0f) {
  for (float v : {a, b, c}) {
    if (std::isnan(v)) return "NaN";
    if (std::isinf(v)) return "infinite";
  }
  return nullptr;
}

}  // namespace

namespace detail {

void add_library_warnings(LoadedMesh& out, const std::string& text) {
  std::istringstream lines(text);
  for (std::string w; std::getline(lines, w);) {
    while (!w.empty() && (w.back() == '\r' || w.back() == ' ' || w.back() == ':')) w.pop_back();
    if (!w.empty()) out.warnings.push_back(w);
  }
}

void finish_normals(LoadedMesh& out, bool has_normals, bool any_normals, NormalSharing sharing,
                    const std::vector<uint64_t>& smoothing) {
  Mesh& m = out.mesh;
  if (has_normals && m.normals.size() == m.positions.size()) {
    for (auto& n : m.normals) {
      const float len = glm::length(n);
      if (!(len > 0.0f)) {
        has_normals = false;
        break;
      }
      n /= len;
    }
    if (has_normals) return;
    out.warnings.push_back("some normals have zero length: all normals computed from the triangles");
  } else if (any_normals) {
    out.warnings.push_back("not every vertex has a normal: all normals computed from the triangles");
  }
  // A file with no normals at all (a scan such as the bunny) gets them computed without a
  // warning: nothing the file says is replaced, and the README documents it.
  compute_vertex_normals(m, sharing, smoothing);
}

void check_face_budget(uint64_t triangles, const Budget& budget, const std::string& file,
                       const std::string& field) {
  if (triangles > budget.max_faces)
    throw InputError(file, field,
                     (triangles == UINT64_MAX ? std::string("2^64 or more") : std::to_string(triangles)) +
                         " triangles, " + over_budget(std::to_string(budget.max_faces), kMaxFacesFlag));
}

}  // namespace detail

void validate_mesh(const Mesh& m, const std::string& file) {
  const size_t n = m.positions.size();
  if (!m.normals.empty() && m.normals.size() != n)
    throw InputError(file, "normals", std::to_string(m.normals.size()) + " normals for " +
                                          std::to_string(n) + " vertices");
  if (!m.uvs.empty() && m.uvs.size() != n)
    throw InputError(file, "uvs", std::to_string(m.uvs.size()) + " uvs for " + std::to_string(n) +
                                      " vertices");
  for (size_t i = 0; i < n; ++i) {
    const std::string where = "vertex " + std::to_string(i);
    if (const char* bad = non_finite_name(m.positions[i].x, m.positions[i].y, m.positions[i].z))
      throw InputError(file, where, std::string("position is ") + bad);
    if (!m.normals.empty())
      if (const char* bad = non_finite_name(m.normals[i].x, m.normals[i].y, m.normals[i].z))
        throw InputError(file, where, std::string("normal is ") + bad);
    if (!m.uvs.empty())
      if (const char* bad = non_finite_name(m.uvs[i].x, m.uvs[i].y))
        throw InputError(file, where, std::string("uv is ") + bad);
  }
  if (m.indices.size() % 3 != 0)
    throw InputError(file, "indices", std::to_string(m.indices.size()) +
                                          " indices is not a whole number of triangles");
  if (m.indices.empty()) throw InputError(file, "", "the mesh has no triangles");
  for (size_t k = 0; k < m.indices.size(); ++k)
    if (m.indices[k] >= n)
      throw InputError(file, "triangle " + std::to_string(k / 3),
                       "index " + std::to_string(m.indices[k]) + " out of range (" +
                           std::to_string(n) + " vertices)");
}

namespace detail {

uint32_t add_map_set(std::vector<MeshMaps>& sets, MeshMaps set) {
  const auto same_image = [](const TextureRef& a, const TextureRef& b) {
    return a.path == b.path && a.pixels == b.pixels && a.placement == b.placement;
  };
  for (size_t k = 0; k < sets.size(); ++k)
    if (same_image(sets[k].color_map, set.color_map) && same_image(sets[k].normal_map, set.normal_map) &&
        sets[k].alpha_mode == set.alpha_mode && sets[k].alpha_cutoff == set.alpha_cutoff &&
        sets[k].alpha_factor == set.alpha_factor)
      return uint32_t(k);
  sets.push_back(std::move(set));
  return uint32_t(sets.size() - 1);
}

void note_uvless(std::vector<std::string>& names, const std::string& name) {
  if (names.size() < 4 && std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
}

void settle_uvs(LoadedMesh& out, std::vector<uint8_t> missing, const std::string& what,
                const std::vector<std::string>& names) {
  Mesh& m = out.mesh;
  // Counted by triangles: a vertex no triangle uses (an empty primitive's) decides nothing.
  size_t without = 0;
  for (size_t t = 0; t < m.triangle_count(); ++t) without += lacks_uv(m, missing, t);
  if (without == 0) return;
  if (without == m.triangle_count()) {
    m.uvs.clear();
    return;
  }
  out.uv_missing = std::move(missing);
  // At most three names, and "..." when there are more.
  const size_t shown = std::min<size_t>(3, names.size());
  std::string where = what;
  for (size_t k = 0; k < shown; ++k)
    where += (k == 0 ? " " : k + 1 == shown && names.size() <= 3 ? " and " : ", ") + names[k];
  if (names.size() > 3) where += ", ...";
  out.warnings.push_back(std::to_string(without) + " of " + std::to_string(m.triangle_count()) +
                         " triangles have no texture coordinates (" + where +
                         "): no map may be drawn on them, and fur on the mesh cannot lay its strands by the uvs");
}

}  // namespace detail

const MeshMaps& LoadedMesh::set(size_t k) const {
  static const MeshMaps kNoMaps{};
  return maps.empty() && k == 0 ? kNoMaps : maps.at(k);
}

LoadedMesh load_mesh_file(const std::filesystem::path& path, const Budget& budget) {
  const std::string file = path.string();
  if (const std::string reason = unreadable_file_reason(path); !reason.empty())
    throw InputError(file, "", reason == kFileNotFound ? "file not found" : reason + ", not a mesh file");
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  LoadedMesh out;
  if (ext == ".obj") out = detail::load_obj(path, budget);
  else if (ext == ".gltf") out = detail::load_gltf(path, false, budget);
  else if (ext == ".glb") out = detail::load_gltf(path, true, budget);
  else
    throw InputError(file, "", "unsupported mesh file extension `" + path.extension().string() +
                                   "` (expected .obj, .gltf or .glb)");
  out.format = ext == ".obj" ? MeshFormat::obj : MeshFormat::gltf;
  validate_mesh(out.mesh, file);
  // The renderer draws a part per set: each set has a triangle, and each triangle a set.
  if (out.maps.size() > 1) {
    std::vector<char> used(out.maps.size(), 0);
    bool in_range = true;
    for (const uint32_t k : out.triangle_maps) {
      in_range &= k < used.size();
      if (in_range) used[k] = 1;
    }
    if (!in_range || out.triangle_maps.size() != out.mesh.triangle_count() ||
        std::count(used.begin(), used.end(), 1) != std::ptrdiff_t(used.size()))
      throw std::logic_error("load_mesh_file: each triangle's map set expected, and a triangle of each set");
  } else if (!out.triangle_maps.empty()) {
    throw std::logic_error("load_mesh_file: triangle_maps without two sets");
  }
  return out;
}

}  // namespace pelt::io
