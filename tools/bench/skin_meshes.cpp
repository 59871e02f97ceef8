#include "tools/bench/skin_meshes.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <string>
#include <system_error>
#include <unordered_map>

#include <meshoptimizer.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include "tools/io/input_error.h"
#include "tools/io/mesh_loader.h"

namespace pelt::bench {
namespace {

constexpr std::string_view kHeadRelative = "tools/data/LeePerrySmith/LeePerrySmith.glb";

// The key of a position's exact bit pattern: welding compares bits, not values, so -0 and
// +0 stay apart (the scan has none) and no tolerance decides which copies merge.
struct PositionKey {
  uint32_t x, y, z;
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  size_t operator()(const PositionKey& k) const {
    uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h ^= (h >> 29) + k.y * 0xBF58476D1CE4E5B9ull;
    h ^= (h >> 31) + k.z * 0x94D049BB133111EBull;
    return size_t(h ^ (h >> 32));
  }
};
PositionKey key_of(const glm::vec3& p) {
  return {std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y), std::bit_cast<uint32_t>(p.z)};
}

uint64_t edge_key(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

// Index of each vertex's welded representative (the lowest index with the same bits) and
// the number of distinct positions.
std::vector<uint32_t> weld_map(const std::vector<glm::vec3>& positions, uint32_t& unique) {
  std::unordered_map<PositionKey, uint32_t, PositionKeyHash> first;
  first.reserve(positions.size());
  std::vector<uint32_t> remap(positions.size());
  unique = 0;
  for (size_t i = 0; i < positions.size(); ++i) {
    auto [it, inserted] = first.emplace(key_of(positions[i]), unique);
    if (inserted) ++unique;
    remap[i] = it->second;
  }
  return remap;
}

bool zero_area(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::dvec3 n = glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
  return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
}

// Drops vertices no triangle uses, keeping the rest in order of first use by the triangles.
Mesh compact_positions(const std::vector<glm::vec3>& positions, std::vector<uint32_t> indices) {
  constexpr uint32_t kUnused = ~0u;
  std::vector<uint32_t> remap(positions.size(), kUnused);
  Mesh out;
  for (uint32_t& i : indices) {
    if (remap[i] == kUnused) {
      remap[i] = uint32_t(out.positions.size());
      out.positions.push_back(positions[i]);
    }
    i = remap[i];
  }
  out.indices = std::move(indices);
  return out;
}

void require_position_only(const Mesh& mesh, std::string_view what) {
  if (mesh.indices.size() % 3 != 0)
    throw io::InputError("", std::string(what), "index count " + std::to_string(mesh.indices.size()) +
                                                    " is not a multiple of 3");
  for (size_t i = 0; i < mesh.indices.size(); ++i)
    if (mesh.indices[i] >= mesh.positions.size())
      throw io::InputError("", std::string(what),
                           "triangle " + std::to_string(i / 3) + ": index " + std::to_string(mesh.indices[i]) +
                               " >= vertex count " + std::to_string(mesh.positions.size()));
}

// meshoptimizer 0.18 does not check that a collapse keeps the surface manifold: on the
// head it leaves a few small closed pockets hanging on an edge of the surface (two
// triangles folded back to back on the same three vertices, or the four faces of a
// tetrahedron), whose edges are then used by three or four triangles. Triangles are
// joined across edges used by exactly two; the largest piece so joined is the surface
// and is kept, in its order, and the pockets go.
void keep_largest_manifold_piece(std::vector<uint32_t>& indices) {
  const size_t nt = indices.size() / 3;
  struct EdgeUse {
    uint32_t count = 0;
    uint32_t tri[2] = {0, 0};
  };
  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(nt * 2);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      EdgeUse& e = edges[edge_key(indices[3 * t + k], indices[3 * t + (k + 1) % 3])];
      if (e.count < 2) e.tri[e.count] = uint32_t(t);
      ++e.count;
    }
  std::vector<uint32_t> parent(nt);
  for (size_t t = 0; t < nt; ++t) parent[t] = uint32_t(t);
  const auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& [key, e] : edges)
    if (e.count == 2) {
      const uint32_t a = find(e.tri[0]), b = find(e.tri[1]);
      // The lower root wins, so the roots do not depend on the map's order.
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<uint32_t> size(nt, 0);
  for (size_t t = 0; t < nt; ++t) ++size[find(uint32_t(t))];
  // Largest piece; among equals, the one holding the earliest triangle.
  uint32_t best = 0;
  for (size_t t = 0; t < nt; ++t)
    if (size[t] > size[best]) best = uint32_t(t);
  size_t out = 0;
  for (size_t t = 0; t < nt; ++t)
    if (find(uint32_t(t)) == best) {
      for (int k = 0; k < 3; ++k) indices[3 * out + k] = indices[3 * t + k];
      ++out;
    }
  indices.resize(out * 3);
}

}  // namespace

const std::array<SkinBenchRow, 3>& skin_bench_rows() {
  // Table 1 of the skin paper (seed 000): render times in whole seconds as printed.
  static const std::array<SkinBenchRow, 3> rows{{
      {"Face", 17244, 2.0, 1.0, 3.0, 0},
      {"Male body", 103381, 7.0, 6.0, 7.0, 103381},
      {"Female body", 120518, 7.0, 6.0, 7.0, 120518},
  }};
  return rows;
}

Mesh weld_positions(const Mesh& mesh) {
  require_position_only(mesh, "weld");
  uint32_t unique = 0;
  const std::vector<uint32_t> remap = weld_map(mesh.positions, unique);
  std::vector<glm::vec3> positions(unique);
  for (size_t i = 0; i < mesh.positions.size(); ++i) positions[remap[i]] = mesh.positions[i];  // copies are equal
  std::vector<uint32_t> indices;
  indices.reserve(mesh.indices.size());
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t a = remap[mesh.indices[3 * t]], b = remap[mesh.indices[3 * t + 1]],
                   c = remap[mesh.indices[3 * t + 2]];
    // A triangle whose corners weld together has no area to subdivide.
    if (a == b || b == c || a == c) continue;
    indices.insert(indices.end(), {a, b, c});
  }
  Mesh out;
  out.positions = std::move(positions);
  out.indices = std::move(indices);
  return out;
}

Mesh loop_subdivide(const Mesh& mesh) {
  require_position_only(mesh, "loop_subdivide");
  const size_t nv = mesh.positions.size(), nt = mesh.triangle_count();

  struct Edge {
    uint32_t a, b;
    uint32_t faces = 0;
    uint32_t opposite[2] = {0, 0};
  };
  std::vector<Edge> edges;
  edges.reserve(nt * 3 / 2 + 16);
  std::unordered_map<uint64_t, uint32_t> edge_id;
  edge_id.reserve(nt * 2);
  std::vector<uint32_t> tri_edges(nt * 3);
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = mesh.indices[3 * t + k], b = mesh.indices[3 * t + (k + 1) % 3];
      const uint32_t c = mesh.indices[3 * t + (k + 2) % 3];
      auto [it, inserted] = edge_id.emplace(edge_key(a, b), uint32_t(edges.size()));
      if (inserted) edges.push_back({std::min(a, b), std::max(a, b)});
      Edge& e = edges[it->second];
      if (e.faces < 2) e.opposite[e.faces] = c;
      ++e.faces;
      tri_edges[3 * t + k] = it->second;
    }
  }

  // Per old vertex: sum and count of all neighbours, and of crease neighbours.
  std::vector<glm::dvec3> ring_sum(nv, glm::dvec3(0.0)), crease_sum(nv, glm::dvec3(0.0));
  std::vector<uint32_t> valence(nv, 0), creases(nv, 0);
  for (const Edge& e : edges) {
    const glm::dvec3 pa(mesh.positions[e.a]), pb(mesh.positions[e.b]);
    ring_sum[e.a] += pb;
    ring_sum[e.b] += pa;
    ++valence[e.a];
    ++valence[e.b];
    if (e.faces != 2) {
      crease_sum[e.a] += pb;
      crease_sum[e.b] += pa;
      ++creases[e.a];
      ++creases[e.b];
    }
  }

  Mesh out;
  out.positions.resize(nv + edges.size());
  for (size_t v = 0; v < nv; ++v) {
    const glm::dvec3 p(mesh.positions[v]);
    glm::dvec3 q = p;
    if (creases[v] == 0 && valence[v] >= 3) {
      const double n = valence[v];
      const double beta = valence[v] == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n);
      q = (1.0 - n * beta) * p + beta * ring_sum[v];
    } else if (creases[v] == 2) {
      q = 0.75 * p + 0.125 * crease_sum[v];
    }
    // Corners (one crease edge, or more than two) and isolated vertices stay put.
    out.positions[v] = glm::vec3(q);
  }
  for (size_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    const glm::dvec3 pa(mesh.positions[e.a]), pb(mesh.positions[e.b]);
    glm::dvec3 q;
    if (e.faces == 2) {
      q = 0.375 * (pa + pb) +
          0.125 * (glm::dvec3(mesh.positions[e.opposite[0]]) + glm::dvec3(mesh.positions[e.opposite[1]]));
    } else {
      q = 0.5 * (pa + pb);
    }
    out.positions[nv + i] = glm::vec3(q);
  }

  out.indices.reserve(nt * 12);
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1], c = mesh.indices[3 * t + 2];
    const uint32_t ab = uint32_t(nv + tri_edges[3 * t]), bc = uint32_t(nv + tri_edges[3 * t + 1]),
                   ca = uint32_t(nv + tri_edges[3 * t + 2]);
    out.indices.insert(out.indices.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
  }
  return out;
}

Mesh decimate_to(const Mesh& mesh, uint64_t target_triangles, std::string_view what) {
  require_position_only(mesh, what);
  if (target_triangles == 0 || target_triangles > mesh.triangle_count())
    throw io::InputError("", std::string(what),
                         "target of " + std::to_string(target_triangles) + " triangles is not in 1.." +
                             std::to_string(mesh.triangle_count()) + " (the mesh to decimate)");
  const auto within = [&](uint64_t n) {
    return std::abs(double(n) - double(target_triangles)) <= kTriangleCountTolerance * double(target_triangles);
  };
  // An error bound of 1 is the whole mesh's extent: no bound, the count alone stops it.
  constexpr float kNoErrorBound = 1.0f;
  std::vector<uint32_t> dst(mesh.indices.size());
  int64_t ask = int64_t(target_triangles);
  size_t got = 0;
  for (int attempt = 0; attempt < 8; ++attempt) {
    got = meshopt_simplify(dst.data(), mesh.indices.data(), mesh.indices.size(), &mesh.positions[0].x,
                           mesh.positions.size(), sizeof(glm::vec3), size_t(ask) * 3, kNoErrorBound, 0,
                           nullptr);
    std::vector<uint32_t> result(dst.begin(), dst.begin() + got);
    keep_largest_manifold_piece(result);
    got = result.size() / 3;
    if (within(got)) return compact_positions(mesh.positions, std::move(result));
    // Move the request by the miss: simplify stops at the first collapse that reaches the
    // request, so its overshoot is stable and this converges in one or two steps.
    ask += int64_t(target_triangles) - int64_t(got);
    ask = std::clamp<int64_t>(ask, 1, int64_t(mesh.triangle_count()));
  }
  throw io::InputError("", std::string(what),
                       "meshopt_simplify reached " + std::to_string(got) + " triangles, not within " +
                           std::to_string(int(kTriangleCountTolerance * 100)) + "% of " +
                           std::to_string(target_triangles));
}

std::vector<SkinBenchMesh> make_skin_bench_meshes(const std::filesystem::path& head_glb) {
  io::LoadedMesh head = io::load_mesh_file(head_glb);
  Mesh refined;  // built once, shared by both decimated rows
  std::vector<SkinBenchMesh> out;
  for (const SkinBenchRow& row : skin_bench_rows()) {
    if (row.target_triangles == 0) {
      out.push_back({&row, head.mesh});
      continue;
    }
    if (refined.indices.empty()) refined = loop_subdivide(loop_subdivide(weld_positions(head.mesh)));
    Mesh m = decimate_to(refined, row.target_triangles, row.name);
    compute_vertex_normals(m);
    out.push_back({&row, std::move(m)});
  }
  return out;
}

SkinBenchView skin_bench_view(const Mesh& mesh, int width, int height) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec3 extent = hi - lo;
  constexpr float kFovyDeg = 30.0f, kFill = 0.8f;
  const float tan_half = std::tan(glm::radians(kFovyDeg) * 0.5f);
  const float aspect = float(width) / float(height);
  // Distance from the box's centre plane at which its half-height is kFill of the half-view.
  const float dist = std::max(extent.y / (2.0f * kFill * tan_half), extent.x / (2.0f * kFill * tan_half * aspect));
  return {0.5f * (lo + hi), kFovyDeg, dist, 0.5f * std::max(1e-4f * dist, dist - extent.z), 2.0f * (dist + extent.z)};
}

std::filesystem::path find_head_scan(std::string_view option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto exists = [&](const fs::path& p) { return fs::is_regular_file(p, ec); };
  std::vector<fs::path> tried;
  if (const char* src = std::getenv("PELT_SOURCE_DIR"); src && *src) {
    const fs::path p = fs::path(src) / kHeadRelative;
    if (exists(p)) return p;
    tried.push_back(p);
  }
  const auto walk_up = [&](fs::path dir) -> fs::path {
    for (int depth = 0; depth < 8 && !dir.empty(); ++depth) {
      const fs::path p = dir / kHeadRelative;
      if (exists(p)) return p;
      if (dir == dir.parent_path()) break;
      dir = dir.parent_path();
    }
    return {};
  };
  const fs::path cwd = fs::current_path(ec);
  if (!ec) {
    if (fs::path p = walk_up(cwd); !p.empty()) return p;
    tried.push_back(cwd / kHeadRelative);
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    if (fs::path p = walk_up(exe.parent_path()); !p.empty()) return p;
    tried.push_back(exe.parent_path() / kHeadRelative);
  }
  // Each place once (the working directory is often the program's folder), and the parents said
  // as such: the message lists the first place of each walk.
  std::string list;
  for (size_t i = 0; i < tried.size(); ++i)
    if (std::find(tried.begin(), tried.begin() + long(i), tried[i]) == tried.begin() + long(i))
      list += (list.empty() ? "" : ", ") + tried[i].string();
  throw io::InputError("", std::string(option),
                       "the head scan " + std::string(kHeadRelative) +
                           " was not found under $PELT_SOURCE_DIR (the source tree), the working directory, the "
                           "program's folder or any of their parents up to 8 levels (tried " + list +
                           " and the same under each parent); pass its path");
}

MeshTopology mesh_topology(const Mesh& mesh) {
  MeshTopology t;
  for (const glm::vec3& p : mesh.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) ++t.nonfinite_values;
  for (const glm::vec3& n : mesh.normals)
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) ++t.nonfinite_values;
  uint32_t unique = 0;
  const std::vector<uint32_t> remap = weld_map(mesh.positions, unique);
  std::unordered_map<uint64_t, uint32_t> uses, directed;
  uses.reserve(mesh.indices.size());
  directed.reserve(mesh.indices.size());
  for (size_t tri = 0; tri < mesh.triangle_count(); ++tri) {
    const uint32_t* idx = &mesh.indices[3 * tri];
    if (idx[0] >= mesh.positions.size() || idx[1] >= mesh.positions.size() || idx[2] >= mesh.positions.size()) {
      ++t.bad_indices;
      continue;
    }
    const uint32_t a = remap[idx[0]], b = remap[idx[1]], c = remap[idx[2]];
    if (a == b || b == c || a == c ||
        zero_area(mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]]))
      ++t.degenerate_triangles;
    ++uses[edge_key(a, b)];
    ++uses[edge_key(b, c)];
    ++uses[edge_key(c, a)];
    ++directed[(uint64_t(a) << 32) | b];
    ++directed[(uint64_t(b) << 32) | c];
    ++directed[(uint64_t(c) << 32) | a];
  }
  t.bad_indices += mesh.indices.size() % 3;
  for (const auto& [key, n] : uses) {
    if (n == 1) ++t.boundary_edges;
    if (n >= 3) ++t.nonmanifold_edges;
  }
  for (const auto& [key, n] : directed)
    if (n >= 2) ++t.winding_conflicts;
  return t;
}

}  // namespace pelt::bench
