#include "tools/io/builtin_meshes.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <sstream>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "tools/io/embedded_data.h"
#include "tools/io/input_error.h"
#include "tools/io/suggest.h"
#include "tools/io/weld.h"

namespace pelt::io {
namespace {

constexpr std::string_view kShapeNames[] = {"box", "teapot", "sphere", "plane"};

struct Triangles {
  std::vector<glm::dvec3> points;
  std::vector<uint32_t> indices;
};

// Quad (i,j) of a row-major (n+1)x(n+1) grid of point indices, split as the anchor
// harness does: (p00,p10,p11), (p00,p11,p01) with p10 one step in i.
void emit_grid_quads(const std::vector<uint32_t>& grid, int n, std::vector<uint32_t>& out) {
  const auto at = [&](int i, int j) { return grid[static_cast<size_t>(i) * (n + 1) + j]; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const uint32_t p00 = at(i, j), p10 = at(i + 1, j), p11 = at(i + 1, j + 1), p01 = at(i, j + 1);
      out.insert(out.end(), {p00, p10, p11, p00, p11, p01});
    }
}

// Drops triangles with a repeated index or exactly zero area (in double precision).
void drop_degenerate(Triangles& t) {
  std::vector<uint32_t> kept;
  kept.reserve(t.indices.size());
  for (size_t k = 0; k + 2 < t.indices.size(); k += 3) {
    const uint32_t a = t.indices[k], b = t.indices[k + 1], c = t.indices[k + 2];
    if (a == b || b == c || a == c) continue;
    const glm::dvec3 n = glm::cross(t.points[b] - t.points[a], t.points[c] - t.points[a]);
    if (glm::dot(n, n) == 0.0) continue;
    kept.insert(kept.end(), {a, b, c});
  }
  t.indices = std::move(kept);
}

// Keeps only referenced points, in their original order.
void remove_unreferenced(Triangles& t) {
  constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> remap(t.points.size(), kUnused);
  for (uint32_t i : t.indices) remap[i] = 0;
  std::vector<glm::dvec3> kept;
  for (size_t i = 0; i < t.points.size(); ++i)
    if (remap[i] != kUnused) {
      remap[i] = static_cast<uint32_t>(kept.size());
      kept.push_back(t.points[i]);
    }
  for (uint32_t& i : t.indices) i = remap[i];
  t.points = std::move(kept);
}

// Makes neighbouring triangles agree (each manifold edge used once in each direction),
// then flips every edge-connected component whose signed volume about `centre` is
// negative, so the winding is counter-clockwise seen from outside.
void orient_outward(Triangles& t, const glm::dvec3& centre) {
  const size_t tri_count = t.indices.size() / 3;
  std::unordered_map<uint64_t, std::vector<uint32_t>> edge_tris;
  const auto key = [](uint32_t a, uint32_t b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
  };
  for (uint32_t f = 0; f < tri_count; ++f)
    for (int e = 0; e < 3; ++e)
      edge_tris[key(t.indices[3 * f + e], t.indices[3 * f + (e + 1) % 3])].push_back(f);

  // Does triangle f traverse the directed edge a->b?
  const auto has_directed = [&](uint32_t f, uint32_t a, uint32_t b) {
    for (int e = 0; e < 3; ++e)
      if (t.indices[3 * f + e] == a && t.indices[3 * f + (e + 1) % 3] == b) return true;
    return false;
  };
  const auto flip = [&](uint32_t f) { std::swap(t.indices[3 * f + 1], t.indices[3 * f + 2]); };

  std::vector<int> component(tri_count, -1);
  int components = 0;
  for (uint32_t seed = 0; seed < tri_count; ++seed) {
    if (component[seed] >= 0) continue;
    std::vector<uint32_t> members{seed};
    component[seed] = components;
    std::queue<uint32_t> pending;
    pending.push(seed);
    while (!pending.empty()) {
      const uint32_t f = pending.front();
      pending.pop();
      for (int e = 0; e < 3; ++e) {
        const uint32_t a = t.indices[3 * f + e], b = t.indices[3 * f + (e + 1) % 3];
        const auto& around = edge_tris[key(a, b)];
        if (around.size() != 2) continue;  // boundary or non-manifold: no constraint
        const uint32_t g = around[0] == f ? around[1] : around[0];
        if (component[g] >= 0) continue;
        if (has_directed(g, a, b)) flip(g);  // a neighbour must run the shared edge b->a
        component[g] = components;
        members.push_back(g);
        pending.push(g);
      }
    }
    double volume = 0.0;
    for (uint32_t f : members) {
      const glm::dvec3 a = t.points[t.indices[3 * f]] - centre;
      const glm::dvec3 b = t.points[t.indices[3 * f + 1]] - centre;
      const glm::dvec3 c = t.points[t.indices[3 * f + 2]] - centre;
      volume += glm::dot(a, glm::cross(b, c));
    }
    if (volume < 0.0)
      for (uint32_t f : members) flip(f);
    ++components;
  }
}

glm::dvec3 bbox_centre(const std::vector<glm::dvec3>& pts) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const auto& p : pts) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return 0.5 * (lo + hi);
}

double radius_about(const std::vector<glm::dvec3>& pts, const glm::dvec3& centre) {
  double r = 0.0;
  for (const auto& p : pts) r = std::max(r, glm::distance(p, centre));
  return r;
}

Mesh to_mesh(const Triangles& t) {
  Mesh m;
  m.positions.reserve(t.points.size());
  for (const auto& p : t.points) m.positions.emplace_back(p);
  m.indices = t.indices;
  compute_vertex_normals(m);
  return m;
}

int parse_positive_int(std::string_view text, const std::string& file, const std::string& field,
                       std::string_view spec) {
  int value = 0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (text.empty())
    throw InputError(file, field, "built-in mesh `" + std::string(spec) +
                                      "` has no size: write NAME:N, e.g. `box:7`");
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec == std::errc::result_out_of_range)
    throw InputError(file, field, "built-in mesh `" + std::string(spec) + "`: size is too large");
  if (ec != std::errc() || ptr != last)
    throw InputError(file, field, "built-in mesh `" + std::string(spec) +
                                      "`: size must be a whole number, got `" + std::string(text) + "`");
  if (value <= 0)
    throw InputError(file, field, "built-in mesh `" + std::string(spec) +
                                      "`: size must be positive, got " + std::to_string(value));
  return value;
}

}  // namespace

bool looks_like_builtin_spec(std::string_view text) {
  const size_t colon = text.find(':');
  if (colon == std::string_view::npos || colon == 0) return false;
  for (size_t i = 0; i < colon; ++i)
    if (!(text[i] >= 'a' && text[i] <= 'z')) return false;
  return text.find_first_of("/\\.", colon) == std::string_view::npos;
}

BuiltinSpec parse_builtin_spec(std::string_view spec, const std::string& file,
                               const std::string& field) {
  const size_t colon = spec.find(':');
  const std::string_view name = spec.substr(0, colon);
  BuiltinSpec out{};
  if (name == "box") out.shape = BuiltinShape::box;
  else if (name == "teapot") out.shape = BuiltinShape::teapot;
  else if (name == "sphere") out.shape = BuiltinShape::sphere;
  else if (name == "plane") out.shape = BuiltinShape::plane;
  else
    throw InputError(file, field, "unknown built-in mesh `" + std::string(name) + "`" +
                                      did_you_mean(name, kShapeNames) +
                                      "; built-ins are box:N, teapot:N, sphere:N, plane:N");
  if (colon == std::string_view::npos)
    throw InputError(file, field, "built-in mesh `" + std::string(spec) +
                                      "` has no size: write NAME:N, e.g. `" + std::string(name) + ":8`");
  out.n = parse_positive_int(spec.substr(colon + 1), file, field, spec);
  int lo = 1, hi = 0;
  switch (out.shape) {
    case BuiltinShape::box: hi = kMaxBoxN; break;
    case BuiltinShape::teapot: hi = kMaxTeapotN; break;
    case BuiltinShape::sphere: lo = kMinSphereN; hi = kMaxSphereN; break;
    case BuiltinShape::plane: hi = kMaxPlaneN; break;
  }
  if (out.n < lo || out.n > hi)
    throw InputError(file, field, "built-in mesh `" + std::string(spec) + "`: size must be in [" +
                                      std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                                      std::to_string(out.n));
  return out;
}

Mesh make_builtin_mesh(const BuiltinSpec& spec) {
  switch (spec.shape) {
    case BuiltinShape::box: return make_box(spec.n);
    case BuiltinShape::teapot: return make_teapot(spec.n);
    case BuiltinShape::sphere: return make_sphere(spec.n);
    case BuiltinShape::plane: return make_plane(spec.n);
  }
  return {};  // unreachable: every enumerator is handled above
}

uint64_t builtin_triangle_count(const BuiltinSpec& spec) {
  const uint64_t n = spec.n > 0 ? uint64_t(spec.n) : 0;
  switch (spec.shape) {
    case BuiltinShape::box: return 12 * n * n;
    case BuiltinShape::teapot: return 64 * n * n;
    case BuiltinShape::sphere: return n / 2 >= 1 ? 2 * n * (n / 2 - 1) : 0;
    case BuiltinShape::plane: return 2 * n * n;
  }
  return 0;  // unreachable: every enumerator is handled above
}

Mesh make_builtin_mesh(const BuiltinSpec& spec, const Budget& budget, const std::string& file,
                       const std::string& field) {
  const uint64_t triangles = builtin_triangle_count(spec);
  if (triangles > budget.max_faces) {
    throw InputError(file, field,
                     "built-in mesh `" + std::string(kShapeNames[int(spec.shape)]) + ":" + std::to_string(spec.n) +
                         "` makes " + std::to_string(triangles) + " triangles, " +
                         over_budget(std::to_string(budget.max_faces), kMaxFacesFlag));
  }
  return make_builtin_mesh(spec);
}

Mesh make_builtin_mesh(std::string_view spec, const std::string& file, const std::string& field) {
  return make_builtin_mesh(parse_builtin_spec(spec, file, field));
}

void body_diagonal_uvs(Mesh& mesh, const glm::dvec3& centre, double radius) {
  const glm::dvec3 e1 = glm::dvec3(1.0, -1.0, 0.0) / std::sqrt(2.0);
  const glm::dvec3 e2 = glm::dvec3(1.0, 1.0, -2.0) / std::sqrt(6.0);
  const double k = 2.449490 * std::sqrt(3.0) / radius;
  mesh.uvs.resize(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::dvec3 q = glm::dvec3(mesh.positions[i]) - centre;
    mesh.uvs[i] = glm::vec2(static_cast<float>(k * glm::dot(q, e1)),
                            static_cast<float>(k * glm::dot(q, e2)));
  }
}

Mesh make_box(int n) {
  // Each face: outward normal f and in-face axes a, b with a x b = f, so the harness's
  // quad split is counter-clockwise seen from outside.
  struct Face {
    glm::dvec3 f, a, b;
  };
  const Face faces[6] = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
  };
  PointWelder welder(1e-5 * std::sqrt(3.0));
  Triangles t;
  std::vector<uint32_t> grid(static_cast<size_t>(n + 1) * (n + 1));
  for (const Face& face : faces) {
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const double s = -1.0 + 2.0 * i / n, r = -1.0 + 2.0 * j / n;
        grid[static_cast<size_t>(i) * (n + 1) + j] = welder.add(face.f + s * face.a + r * face.b);
      }
    emit_grid_quads(grid, n, t.indices);
  }
  t.points = welder.points();
  Mesh m = to_mesh(t);
  body_diagonal_uvs(m, glm::dvec3(0.0), std::sqrt(3.0));
  return m;
}

glm::dvec3 eval_bezier_patch(const BezierPatch& patch, double u, double v) {
  const auto bernstein = [](double t, double b[4]) {
    const double s = 1.0 - t;
    b[0] = s * s * s;
    b[1] = 3.0 * t * s * s;
    b[2] = 3.0 * t * t * s;
    b[3] = t * t * t;
  };
  double bu[4], bv[4];
  bernstein(u, bu);
  bernstein(v, bv);
  glm::dvec3 p(0.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) p += bu[r] * bv[c] * patch[r * 4 + c];
  return p;
}

std::vector<BezierPatch> parse_bpt(std::string_view text, const std::string& file) {
  std::istringstream in{std::string(text)};
  long long count = 0;
  if (!(in >> count)) throw InputError(file, "", "expected the patch count at the start of the file");
  if (count <= 0 || count > 100000)
    throw InputError(file, "", "patch count must be in [1, 100000], got " + std::to_string(count));
  std::vector<BezierPatch> patches(static_cast<size_t>(count));
  for (long long p = 0; p < count; ++p) {
    const std::string where = "patch " + std::to_string(p);
    int du = 0, dv = 0;
    if (!(in >> du >> dv)) throw InputError(file, where, "expected the degrees \"3 3\"");
    if (du != 3 || dv != 3)
      throw InputError(file, where, "only bicubic patches are supported, got degrees " +
                                        std::to_string(du) + " " + std::to_string(dv));
    for (int k = 0; k < 16; ++k) {
      glm::dvec3& q = patches[p][k];
      if (!(in >> q.x >> q.y >> q.z))
        throw InputError(file, where + " point " + std::to_string(k), "expected three numbers");
      if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
        throw InputError(file, where + " point " + std::to_string(k), "coordinate is not finite");
    }
  }
  std::string extra;
  if (in >> extra) throw InputError(file, "", "unexpected text after the last patch: `" + extra + "`");
  return patches;
}

const std::vector<BezierPatch>& teapot_patches() {
  static const std::vector<BezierPatch> patches =
      parse_bpt(embedded::teapot_bpt(), "tools/data/teapot.bpt (embedded)");
  return patches;
}

Mesh make_teapot(int n) {
  const auto& patches = teapot_patches();
  std::vector<glm::dvec3> control;
  for (const auto& patch : patches) control.insert(control.end(), patch.begin(), patch.end());
  const double cp_radius = radius_about(control, bbox_centre(control));

  PointWelder welder(1e-5 * cp_radius);
  Triangles t;
  std::vector<uint32_t> grid(static_cast<size_t>(n + 1) * (n + 1));
  for (const auto& patch : patches) {
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j)
        grid[static_cast<size_t>(i) * (n + 1) + j] =
            welder.add(eval_bezier_patch(patch, static_cast<double>(i) / n, static_cast<double>(j) / n));
    emit_grid_quads(grid, n, t.indices);
  }
  t.points = welder.points();
  drop_degenerate(t);
  remove_unreferenced(t);
  // (x,y,z) -> (x,z,-y) is a rotation, so it keeps the winding; centre after it.
  for (auto& p : t.points) p = glm::dvec3(p.x, p.z, -p.y);
  const glm::dvec3 centre = bbox_centre(t.points);
  for (auto& p : t.points) p -= centre;
  orient_outward(t, glm::dvec3(0.0));
  Mesh m = to_mesh(t);
  body_diagonal_uvs(m, glm::dvec3(0.0), radius_about(t.points, glm::dvec3(0.0)));
  return m;
}

Mesh make_sphere(int n) {
  const int rings = n / 2;
  const double pi = std::numbers::pi;
  // Split where u wraps, as exporters split a texture seam: the column s = n repeats column 0's
  // positions (bit for bit) with u = 1, so no triangle's u runs back across the whole texture
  // (which made a mipmapped map pick its coarsest levels there, a band down the meridian). Each
  // pole is n vertices, one per triangle of its fan, at the u of that triangle's middle. The fur's
  // fins treat coincident copies as one vertex (fur::same_strand_vertices), so the seam grows one
  // fin, not two, and the normals are summed over every copy at a position.
  Mesh m;
  const size_t row = static_cast<size_t>(n) + 1;
  m.positions.reserve(2 * static_cast<size_t>(n) + row * (rings - 1));
  m.uvs.reserve(m.positions.capacity());
  for (int s = 0; s < n; ++s) {
    m.positions.emplace_back(0.0f, 1.0f, 0.0f);
    m.uvs.emplace_back(static_cast<float>((s + 0.5) / n), 1.0f);
  }
  for (int k = 1; k < rings; ++k) {
    const double theta = pi * k / rings;
    const size_t first = m.positions.size();
    for (int s = 0; s < n; ++s) {
      const double phi = 2.0 * pi * s / n;
      m.positions.emplace_back(std::sin(theta) * std::cos(phi), std::cos(theta),
                               std::sin(theta) * std::sin(phi));
      m.uvs.emplace_back(static_cast<float>(static_cast<double>(s) / n),
                         static_cast<float>(1.0 - static_cast<double>(k) / rings));
    }
    m.positions.push_back(m.positions[first]);
    m.uvs.emplace_back(1.0f, m.uvs[first].y);
  }
  const auto south = static_cast<uint32_t>(m.positions.size());
  for (int s = 0; s < n; ++s) {
    m.positions.emplace_back(0.0f, -1.0f, 0.0f);
    m.uvs.emplace_back(static_cast<float>((s + 0.5) / n), 0.0f);
  }

  const auto ring_vertex = [n, row](int k, int s) {  // k in [1, rings-1], s in [0, n]
    return static_cast<uint32_t>(n + (k - 1) * row + s);
  };
  for (int s = 0; s < n; ++s)
    m.indices.insert(m.indices.end(), {static_cast<uint32_t>(s), ring_vertex(1, s + 1), ring_vertex(1, s)});
  for (int k = 1; k + 1 < rings; ++k)
    for (int s = 0; s < n; ++s) {
      const uint32_t a = ring_vertex(k, s), b = ring_vertex(k, s + 1);
      const uint32_t c = ring_vertex(k + 1, s + 1), d = ring_vertex(k + 1, s);
      m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
    }
  for (int s = 0; s < n; ++s)
    m.indices.insert(m.indices.end(),
                     {south + static_cast<uint32_t>(s), ring_vertex(rings - 1, s), ring_vertex(rings - 1, s + 1)});
  compute_vertex_normals(m, NormalSharing::per_position);
  return m;
}

Mesh make_plane(int n) {
  Mesh m;
  std::vector<uint32_t> grid(static_cast<size_t>(n + 1) * (n + 1));
  // Row i runs along z and column j along x, so the quad split faces +y.
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = -1.0 + 2.0 * j / n, z = -1.0 + 2.0 * i / n;
      grid[static_cast<size_t>(i) * (n + 1) + j] = static_cast<uint32_t>(m.positions.size());
      m.positions.emplace_back(static_cast<float>(x), 0.0f, static_cast<float>(z));
      m.uvs.emplace_back(static_cast<float>((x + 1.0) / 2.0), static_cast<float>((z + 1.0) / 2.0));
    }
  emit_grid_quads(grid, n, m.indices);
  compute_vertex_normals(m);
  return m;
}

}  // namespace pelt::io
