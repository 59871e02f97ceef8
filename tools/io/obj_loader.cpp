// Wavefront OBJ through tinyobjloader.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <unordered_map>

#include <tiny_obj_loader.h>

#include "tools/io/input_error.h"
#include "tools/io/mesh_loader_detail.h"

namespace pelt::io::detail {
namespace {

struct TripleHash {
  size_t operator()(const tinyobj::index_t& i) const {
    uint64_t h = static_cast<uint32_t>(i.vertex_index) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<uint32_t>(i.texcoord_index) * 0xC2B2AE3D27D4EB4Full + (h >> 29);
    h ^= static_cast<uint32_t>(i.normal_index) * 0x165667B19E3779F9ull + (h >> 31);
    return static_cast<size_t>(h);
  }
};
struct TripleEq {
  bool operator()(const tinyobj::index_t& a, const tinyobj::index_t& b) const {
    return a.vertex_index == b.vertex_index && a.texcoord_index == b.texcoord_index &&
           a.normal_index == b.normal_index;
  }
};

const char* non_finite(const float* v, int n) {
  for (int k = 0; k < n; ++k) {
    if (std::isnan(v[k])) return "NaN";
    if (std::isinf(v[k])) return "infinite";
  }
  return nullptr;
}

// Names a face for error messages: its 1-based number among the file's faces, as a user
// counting `f` lines would.
std::string face_name(size_t face) { return "f " + std::to_string(face + 1); }

// What one pass over the file finds before tinyobjloader sees it.
struct ObjPrescan {
  // Triangles the faces make, each `f` line of k corners fan-triangulated into k - 2 (as
  // tinyobjloader's triangulation does); saturating.
  uint64_t triangles = 0;
  // The first malformed or non-finite number, or face of fewer than three corners (see
  // below), thrown only after the budget check so that an oversized file is refused for its
  // size whatever follows.
  std::optional<InputError> bad_record;
};

// tinyobjloader reads a malformed number ("nan", "1.2.3", "abc") as 0 without a word,
// so the numeric records are checked here first, numbered as the file numbers them
// (`v 3` is the third `v` record). Each value must be a complete number; NaN and
// infinities (including overflow such as 1e999) are reported by name. The same pass
// counts the triangles, one line in memory at a time, so the face budget is checked
// before anything proportional to the file is allocated. A face of one or two corners is
// reported too: tinyobjloader drops it without a word, leaving a hole in the mesh.
ObjPrescan prescan_obj(const std::filesystem::path& path, const std::string& file) {
  ObjPrescan out;
  std::ifstream in(path, std::ios::binary);
  std::string line, tok;
  size_t counts[3] = {0, 0, 0};  // v, vt, vn
  static const char* kWhat[3] = {"position", "texture coordinate", "normal"};
  size_t line_number = 0, faces = 0;
  while (std::getline(in, line)) {
    ++line_number;
    size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos) continue;
    if (line[i] == 'f' && (i + 1 == line.size() || line[i + 1] == ' ' || line[i + 1] == '\t' || line[i + 1] == '\r')) {
      uint64_t corners = 0;
      std::istringstream tokens(line.substr(i + 1));
      while (tokens >> tok && tok[0] != '#') ++corners;
      ++faces;
      if (corners >= 3)
        out.triangles = sat_add(out.triangles, corners - 2);
      else if (!out.bad_record)
        out.bad_record.emplace(file, face_name(faces - 1),
                               "a face needs at least 3 vertices, this one has " + std::to_string(corners) +
                                   " (line " + std::to_string(line_number) + ")");
      continue;
    }
    if (out.bad_record || line[i] != 'v') continue;
    int kind;
    if (i + 1 < line.size() && (line[i + 1] == ' ' || line[i + 1] == '\t')) kind = 0, i += 1;
    else if (line.compare(i, 3, "vt ") == 0 || line.compare(i, 3, "vt\t") == 0) kind = 1, i += 2;
    else if (line.compare(i, 3, "vn ") == 0 || line.compare(i, 3, "vn\t") == 0) kind = 2, i += 2;
    else continue;
    const std::string record = std::string(kind == 0 ? "v " : kind == 1 ? "vt " : "vn ") +
                               std::to_string(++counts[kind]);
    std::istringstream tokens(line.substr(i));
    while (tokens >> tok) {
      if (tok[0] == '#') break;
      char* end = nullptr;
      const double v = std::strtod(tok.c_str(), &end);
      if (end != tok.c_str() + tok.size()) {
        out.bad_record.emplace(file, record, "`" + tok + "` is not a number (line " + std::to_string(line_number) + ")");
        break;
      }
      if (std::isnan(v)) {
        out.bad_record.emplace(file, record, std::string(kWhat[kind]) + " is NaN");
        break;
      }
      if (std::isinf(v) || std::abs(v) > 3.4028234663852886e38) {
        out.bad_record.emplace(file, record, std::string(kWhat[kind]) + " is infinite");
        break;
      }
    }
  }
  return out;
}

}  // namespace

LoadedMesh load_obj(const std::filesystem::path& path, const Budget& budget) {
  const std::string file = path.string();
  {
    std::ifstream probe(path);
    if (!probe) throw InputError(file, "", "cannot open the file for reading");
  }
  const ObjPrescan pre = prescan_obj(path, file);
  check_face_budget(pre.triangles, budget, file, "");
  if (pre.bad_record) throw *pre.bad_record;
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  config.mtl_search_path = path.parent_path().string();
  tinyobj::ObjReader reader;
  const bool ok = reader.ParseFromFile(file, config);
  if (!ok) {
    std::string msg = reader.Error();
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == '\r')) msg.pop_back();
    throw InputError(file, "", "malformed OBJ: " + (msg.empty() ? std::string("parse failed") : msg));
  }

  LoadedMesh out;
  if (!reader.Warning().empty()) {
    std::string w = reader.Warning();
    while (!w.empty() && (w.back() == '\n' || w.back() == '\r')) w.pop_back();
    out.warnings.push_back(w);
  }

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const size_t nv = attrib.vertices.size() / 3, nt = attrib.texcoords.size() / 2,
               nn = attrib.normals.size() / 3;
  for (size_t i = 0; i < nv; ++i)
    if (const char* bad = non_finite(&attrib.vertices[3 * i], 3))
      throw InputError(file, "v " + std::to_string(i + 1), std::string("position is ") + bad);
  for (size_t i = 0; i < nt; ++i)
    if (const char* bad = non_finite(&attrib.texcoords[2 * i], 2))
      throw InputError(file, "vt " + std::to_string(i + 1), std::string("texture coordinate is ") + bad);
  for (size_t i = 0; i < nn; ++i)
    if (const char* bad = non_finite(&attrib.normals[3 * i], 3))
      throw InputError(file, "vn " + std::to_string(i + 1), std::string("normal is ") + bad);

  std::unordered_map<tinyobj::index_t, uint32_t, TripleHash, TripleEq> vertex_of;
  bool all_uvs = true, all_normals = true;
  Mesh& m = out.mesh;
  size_t face_number = 0;
  int material = -1;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const auto& mesh = shape.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f, ++face_number) {
      const unsigned corners = mesh.num_face_vertices[f];
      if (corners != 3)
        throw InputError(file, face_name(face_number),
                         "face has " + std::to_string(corners) + " vertices after triangulation");
      if (material < 0 && f < mesh.material_ids.size()) material = mesh.material_ids[f];
      for (unsigned c = 0; c < 3; ++c) {
        const tinyobj::index_t idx = mesh.indices[offset + c];
        if (idx.vertex_index < 0 || static_cast<size_t>(idx.vertex_index) >= nv)
          throw InputError(file, face_name(face_number),
                           "vertex index " + std::to_string(idx.vertex_index + 1) + " out of range (" +
                               std::to_string(nv) + " vertices)");
        if (idx.texcoord_index >= 0 && static_cast<size_t>(idx.texcoord_index) >= nt)
          throw InputError(file, face_name(face_number),
                           "texture coordinate index " + std::to_string(idx.texcoord_index + 1) +
                               " out of range (" + std::to_string(nt) + " texture coordinates)");
        if (idx.normal_index >= 0 && static_cast<size_t>(idx.normal_index) >= nn)
          throw InputError(file, face_name(face_number),
                           "normal index " + std::to_string(idx.normal_index + 1) + " out of range (" +
                               std::to_string(nn) + " normals)");
        auto [it, inserted] = vertex_of.try_emplace(idx, static_cast<uint32_t>(m.positions.size()));
        if (inserted) {
          const float* p = &attrib.vertices[3 * idx.vertex_index];
          m.positions.emplace_back(p[0], p[1], p[2]);
          if (idx.texcoord_index >= 0) {
            const float* t = &attrib.texcoords[2 * idx.texcoord_index];
            m.uvs.emplace_back(t[0], t[1]);
          } else {
            all_uvs = false;
            m.uvs.emplace_back(0.0f, 0.0f);  // dropped below unless every vertex has a uv
          }
          if (idx.normal_index >= 0) {
            const float* n = &attrib.normals[3 * idx.normal_index];
            m.normals.emplace_back(n[0], n[1], n[2]);
          } else {
            all_normals = false;
            m.normals.emplace_back(0.0f);
          }
        }
        m.indices.push_back(it->second);
      }
      offset += corners;
    }
  }
  if (m.indices.empty()) throw InputError(file, "", "the file has no faces");
  if (!all_uvs) {
    if (nt > 0) out.warnings.push_back("some vertices have no texture coordinate: uvs dropped");
    m.uvs.clear();
  }
  finish_normals(out, all_normals);

  const auto& materials = reader.GetMaterials();
  if (material >= 0 && static_cast<size_t>(material) < materials.size()) {
    const tinyobj::material_t& mat = materials[material];
    const std::filesystem::path dir = path.parent_path();
    if (!mat.diffuse_texname.empty()) out.color_map.path = dir / mat.diffuse_texname;
    if (!mat.normal_texname.empty()) out.normal_map.path = dir / mat.normal_texname;
    else if (!mat.bump_texname.empty()) out.normal_map.path = dir / mat.bump_texname;
  }
  return out;
}

}  // namespace pelt::io::detail
