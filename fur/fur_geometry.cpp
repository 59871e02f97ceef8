#include "fur/fur_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/geometric.hpp>

#include "raster/vertex_groups.h"

namespace pelt::fur {
namespace {

bool finite3(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Unit normal of a triangle; (0,1,0) for a degenerate one, the same fallback as
// pelt::compute_vertex_normals, so later code never divides by zero.
glm::vec3 triangle_normal(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  glm::vec3 n = glm::cross(b - a, c - a);
  float len = glm::length(n);
  if (!(len > 0.0f) || !std::isfinite(len)) return {0.0f, 1.0f, 0.0f};
  return n / len;
}

// The unit direction g, or (when it lies lower than kMinFurElevation above the tangent plane of
// the unit normal n) the direction at that elevation with g's heading along the surface. n when
// g has no heading (it points straight in): any tilt would be made up.
glm::vec3 above_surface(const glm::vec3& g, const glm::vec3& n) {
  const glm::dvec3 gd(g), nd(n);
  const double e = glm::dot(gd, nd);
  if (e >= std::sin(kMinFurElevation)) return g;
  const glm::dvec3 along = gd - e * nd;
  const double len = glm::length(along);
  if (!(len > 1e-6) || !std::isfinite(len)) return n;
  return glm::vec3(nd * std::sin(kMinFurElevation) + along * (std::cos(kMinFurElevation) / len));
}

// Fur has no hard edges: where a mesh splits a vertex to give each face its own normal, shells
// grown along the copies' normals would open a crack along the edge (each face's shells a slab
// of its own). Copies at one position whose normals differ all take their normalised sum, when
// that sum stands at least kMinFurElevation above every copy's face, the fur's own rule;
// otherwise (a two-sided sheet's near-opposite copies, whose sum points anywhere) each keeps
// its own. Only copies with a face count: a copy that only zero-area triangles name (whose
// normal a file made up, as a glTF flat normal is +y there) takes what its faced copies give.
// Vertices without copies, and copies that already agree, are left bit for bit.
// Twice the area of the triangle whose first index is indices[t], in double.
double twice_area(const Mesh& m, size_t t) {
  const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]), c(m.positions[m.indices[t + 2]]);
  return glm::length(glm::cross(b - a, c - a));
}

void join_hard_edges(const Mesh& base, std::vector<glm::vec3>& normals) {
  const size_t n = base.positions.size();
  std::vector<char> faced(n, 0);
  for (size_t t = 0; t + 2 < base.indices.size(); t += 3) {
    const double area = twice_area(base, t);
    if (area > 0.0 && std::isfinite(area))
      for (int k = 0; k < 3; ++k) faced[base.indices[t + k]] = 1;
  }
  const std::vector<uint32_t> first = same_position_vertices(base.positions);
  // Per group (at its first vertex): the first faced copy, the sum of the faced copies' normals,
  // and whether they differ.
  std::vector<uint32_t> ref(n, UINT32_MAX);
  std::vector<glm::dvec3> sum(n, glm::dvec3(0.0));
  std::vector<char> differ(n, 0), join(n, 1);
  for (size_t i = 0; i < n; ++i) {
    if (!faced[i]) continue;
    const uint32_t f = first[i];
    if (ref[f] == UINT32_MAX) ref[f] = uint32_t(i);
    sum[f] += glm::dvec3(normals[i]);
    if (normals[i] != normals[ref[f]]) differ[f] = 1;
  }
  for (size_t i = 0; i < n; ++i) {
    const uint32_t f = first[i];
    if (!faced[i] || !differ[f]) continue;
    const double lean = glm::dot(sum[f], glm::dvec3(normals[i]));
    if (!(lean >= std::sin(kMinFurElevation) * glm::length(sum[f]))) join[f] = 0;
  }
  // Every value read below is a group's: copies change only after all of them were read.
  std::vector<glm::vec3> to(n);
  std::vector<char> set(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t f = first[i];
    if (ref[f] == UINT32_MAX) continue;  // no copy at this position has a face
    const double len = glm::length(sum[f]);
    if (differ[f] && join[f] && len > 0.0 && std::isfinite(len)) {
      to[i] = glm::vec3(sum[f] / len), set[i] = 1;
    } else if (!faced[i] && !differ[f]) {
      to[i] = normals[ref[f]], set[i] = 1;  // the faced copies agree: a faceless copy follows them
    }
  }
  for (size_t i = 0; i < n; ++i)
    if (set[i]) normals[i] = to[i];
}

// The mesh's surface area, in double.
double mesh_area(const Mesh& m) {
  double a = 0.0;
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) a += 0.5 * twice_area(m, t);
  return a;
}

// The area of the mesh's triangles laid out by `uv(i)` (either winding counts alike; overlapping
// islands count once each), in double.
template <class Uv>
double triangle_area_2d(const std::vector<uint32_t>& indices, Uv uv) {
  double a = 0.0;
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::dvec2 t0 = uv(indices[t]), d1 = uv(indices[t + 1]) - t0, d2 = uv(indices[t + 2]) - t0;
    a += 0.5 * std::abs(d1.x * d2.y - d1.y * d2.x);
  }
  return a;
}

}  // namespace

double mesh_uv_area(const Mesh& mesh) {
  return triangle_area_2d(mesh.indices, [&](uint32_t i) { return glm::dvec2(mesh.uvs[i]); });
}

BoundingSphere bounding_sphere(const Mesh& mesh) {
  BoundingSphere s;
  if (mesh.positions.empty()) return s;
  glm::vec3 lo = mesh.positions[0], hi = mesh.positions[0];
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  s.centre = (lo + hi) * 0.5f;
  for (const glm::vec3& p : mesh.positions) s.radius = std::max(s.radius, glm::length(p - s.centre));
  return s;
}

std::vector<uint32_t> same_strand_vertices(const std::vector<glm::vec3>& positions,
                                           const std::vector<glm::vec3>& normals,
                                           const std::vector<glm::vec3>& growth) {
  return first_with_equal_key<9>(positions.size(), [&](uint32_t i) {
    const glm::vec3 &p = positions[i], &nn = normals[i], &g = growth[i];
    return std::array<float, 9>{p.x, p.y, p.z, nn.x, nn.y, nn.z, g.x, g.y, g.z};
  });
}

std::vector<FurEdge> mesh_edges(const Mesh& mesh, const std::vector<uint32_t>& same_as) {
  // (a, b, face) for every triangle side, sorted so that equal edges are adjacent and
  // their faces come in index order.
  struct Side {
    uint32_t a, b, face;
  };
  const size_t F = mesh.triangle_count();
  std::vector<Side> sides;
  sides.reserve(3 * F);
  const auto vertex = [&](size_t k) { return same_as.empty() ? mesh.indices[k] : same_as[mesh.indices[k]]; };
  for (size_t f = 0; f < F; ++f) {
    for (int k = 0; k < 3; ++k) {
      uint32_t a = vertex(3 * f + k), b = vertex(3 * f + (k + 1) % 3);
      if (a == b) continue;  // a collapsed side is no edge
      sides.push_back({std::min(a, b), std::max(a, b), uint32_t(f)});
    }
  }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return x.face < y.face;
  });
  std::vector<FurEdge> edges;
  for (size_t i = 0; i < sides.size();) {
    FurEdge e{sides[i].a, sides[i].b, sides[i].face, kNoFace};
    size_t j = i + 1;
    for (; j < sides.size() && sides[j].a == e.a && sides[j].b == e.b; ++j) {
      // A triangle naming the same edge twice (a degenerate one) is not a second face.
      if (e.face1 == kNoFace && sides[j].face != e.face0) e.face1 = sides[j].face;
    }
    edges.push_back(e);
    i = j;
  }
  return edges;
}

FurCounts fur_counts(size_t base_vertices, size_t base_faces, size_t edges, int layers, FinMode fins) {
  FurCounts c;
  const size_t S = size_t(std::max(layers, 0));
  c.base_vertices = base_vertices;
  c.shell_vertices = base_vertices * S;
  c.fin_vertices = fins != FinMode::off ? c.shell_vertices : 0;  // the same vertices, when there are fins
  c.total_vertices = c.base_vertices + c.shell_vertices;
  c.base_faces = base_faces;
  c.shell_faces = base_faces * S;
  c.fin_faces = S > 1 && fins != FinMode::off ? 2 * edges * (S - 1) : 0;
  c.total_faces = c.base_faces + c.shell_faces + c.fin_faces;
  c.edges = edges;
  return c;
}

std::vector<glm::vec3> uv_comb_directions(const Mesh& base, const std::vector<glm::vec3>& normals,
                                          glm::vec2 uv_direction) {
  const size_t n = base.positions.size();
  std::vector<glm::dvec3> tu, tv;
  uv_derivatives(base, tu, tv);
  std::vector<glm::dvec3> along(n);
  for (size_t i = 0; i < n; ++i) along[i] = double(uv_direction.x) * tu[i] + double(uv_direction.y) * tv[i];
  // The copies of a split seam each see one side's triangles: a one-sided difference, tilted
  // by half the surface's turn between neighbours, so the two copies would grow apart. Where
  // every copy at a position combs the way its first copy does (a seam where u wraps), each
  // takes their sum, as a welded vertex would. Where one disagrees (a mirrored uv island; a UV
  // sphere's pole, whose copies each comb along their own meridian) the uvs give the position no
  // one direction, and its copies keep their normal: copies combed apart would open a crack
  // between the shells of their triangles.
  const std::vector<uint32_t> first = same_position_vertices(base.positions);
  std::vector<glm::dvec3> joined(along);
  std::vector<char> agree(n, 1);
  for (size_t i = 0; i < n; ++i) {
    if (first[i] == i) continue;
    if (!(glm::dot(along[i], along[first[i]]) > 0.0)) agree[first[i]] = 0;
    joined[first[i]] += along[i];
  }
  std::vector<glm::vec3> out(n, glm::vec3(0.0f));
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 n0(normals[i]);
    const double nl = glm::length(n0);
    if (!(nl > 0.0) || !std::isfinite(nl)) continue;
    const glm::dvec3 nn = n0 / nl;
    const glm::dvec3 acc = agree[first[i]] ? joined[first[i]] : glm::dvec3(0.0);
    const glm::dvec3 t = acc - glm::dot(acc, nn) * nn;  // into the tangent plane
    const double len = glm::length(t);
    if (len > 1e-30 && std::isfinite(len)) out[i] = glm::vec3(t / len);
  }
  return out;
}

glm::vec3 growth_direction(const glm::vec3& normal, const std::optional<CombParams>& comb) {
  if (!comb || comb->weight <= 0.0f) return normal;
  const float dl = glm::length(comb->direction);
  if (!(dl > 0.0f) || !std::isfinite(dl)) return normal;
  const glm::vec3 d = comb->direction / dl;
  const glm::vec3 g = (1.0f - comb->weight) * normal + comb->weight * d;
  const float gl = glm::length(g);
  // The blend cancels where d is nearly -n: keep the normal rather than a random tilt.
  if (!(gl > 1e-4f)) return normal;
  return above_surface(g / gl, normal);
}

namespace {

// The mesh's own checks, before any of it is read.
std::optional<ParamError> check_mesh(const Mesh& base) {
  const size_t N = base.positions.size();
  if (N == 0) return ParamError{"mesh.positions", "the base mesh has no vertices"};
  if (base.indices.size() % 3 != 0) {
    return ParamError{"mesh.indices", "size " + std::to_string(base.indices.size()) +
                                          " is not a multiple of 3"};
  }
  if (base.indices.empty()) return ParamError{"mesh.indices", "the base mesh has no triangles"};
  for (size_t k = 0; k < base.indices.size(); ++k) {
    if (base.indices[k] >= N) {
      return ParamError{"mesh.indices", "index " + std::to_string(k) + " = " +
                                            std::to_string(base.indices[k]) + " >= " +
                                            std::to_string(N) + " vertices"};
    }
  }
  for (size_t i = 0; i < N; ++i) {
    if (!finite3(base.positions[i])) {
      return ParamError{"mesh.positions", "vertex " + std::to_string(i) + " is not finite"};
    }
  }
  if (!base.normals.empty() && base.normals.size() != N) {
    return ParamError{"mesh.normals", "has " + std::to_string(base.normals.size()) +
                                          " entries for " + std::to_string(N) + " positions"};
  }
  if (!base.uvs.empty() && base.uvs.size() != N) {
    return ParamError{"mesh.uvs", "has " + std::to_string(base.uvs.size()) + " entries for " +
                                      std::to_string(N) + " positions"};
  }
  return std::nullopt;
}

// The fur's unit normal per vertex: the mesh's own (renormalised only when more than 1e-6 off
// unit length; the copies of a hard edge's vertex joined, since fur has no hard edges), or
// computed per position like the rest of pelt.
std::optional<ParamError> fur_normals(const Mesh& base, std::vector<glm::vec3>& out) {
  if (base.normals.empty()) {
    Mesh copy;
    copy.positions = base.positions;
    copy.indices = base.indices;
    compute_vertex_normals(copy, NormalSharing::per_position);
    out = std::move(copy.normals);
    return std::nullopt;
  }
  out.resize(base.positions.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const glm::vec3 n = base.normals[i];
    const float len = glm::length(n);
    if (!finite3(n) || !(len > 0.0f)) {
      return ParamError{"mesh.normals", "normal " + std::to_string(i) + " is zero or not finite"};
    }
    out[i] = std::fabs(len - 1.0f) <= 1e-6f ? n : n / len;
  }
  join_hard_edges(base, out);
  return std::nullopt;
}

// StrandCoordinates::box's planes: the texture's (u, v) along two scene axes, for a triangle
// facing axis 0 (x), 1 (y) or 2 (z).
glm::dvec2 box_plane(const glm::dvec3& q, uint8_t axis) {
  switch (axis) {
    case 0: return {-q.z, q.y};
    case 1: return {q.x, -q.z};
    default: return {q.x, q.y};
  }
}

// StrandCoordinates::box. Each triangle takes the axis it faces most, judged by the sum of its
// corners' fur normals, so that a smooth surface's regions meet along smooth borders rather than
// along every facet that tips over 45 degrees; ties go to the lower axis. A projection on axis a
// keeps |n_a| of a triangle's area (n its unit normal), so where that axis leaves a facet tilted
// from its neighbours facing it by less than kBoxLeast, the facet takes the axis of its own normal
// instead (whose share is at least 1/sqrt(3)): no strand is stretched more than 1 / kBoxLeast
// times. Not at 1/sqrt(3) itself: facets near the cube's diagonals, all close to it, would flip
// for nothing and cut the strands along many small islands (the bunny: 615 copies against 569).
// A vertex on triangles of two or three axes is copied once per further axis whose plane gives it
// another coordinate (q = p - centre). The copies come after the mesh's own vertices, which keep
// their indices; they grow the same strand, so they are joined as a texture seam's are (no fin
// along the border, no crack). A vertex no triangle names takes y.
constexpr double kBoxLeast = 0.5;

struct AxisSplit {
  std::vector<uint32_t> indices;  // the mesh's triangles on the split vertices
  std::vector<uint32_t> source;   // per split vertex: the mesh vertex it is, or copies
  std::vector<uint8_t> axis;      // per split vertex
};

uint8_t largest_axis(const glm::dvec3& v) {
  const glm::dvec3 a = glm::abs(v);  // NaN falls to z
  return a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
}

uint8_t facing_axis(const Mesh& m, const std::vector<glm::vec3>& normals, size_t t) {
  glm::dvec3 sum(0.0);
  for (int k = 0; k < 3; ++k) sum += glm::dvec3(normals[m.indices[t + k]]);
  const uint8_t axis = largest_axis(sum);
  const glm::dvec3 p0(m.positions[m.indices[t]]);
  const glm::dvec3 face =
      glm::cross(glm::dvec3(m.positions[m.indices[t + 1]]) - p0, glm::dvec3(m.positions[m.indices[t + 2]]) - p0);
  const double len = glm::length(face);
  if (!(len > 0.0) || !std::isfinite(len)) return axis;  // no facet to stretch
  return std::abs(face[axis]) >= kBoxLeast * len ? axis : largest_axis(face);
}

// `normals`: the fur's, one per mesh vertex.
AxisSplit split_by_facing_axis(const Mesh& m, const std::vector<glm::vec3>& normals, const glm::dvec3& centre) {
  const size_t n = m.positions.size();
  AxisSplit out;
  out.indices = m.indices;
  out.source.resize(n);
  for (size_t i = 0; i < n; ++i) out.source[i] = uint32_t(i);
  out.axis.assign(n, 1);
  std::vector<char> named(n, 0);
  std::vector<uint32_t> copy_of(3 * n, UINT32_MAX);  // (vertex, axis) -> the vertex that carries it
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const uint8_t axis = facing_axis(m, normals, t);
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.indices[t + k];
      uint32_t& c = copy_of[3 * size_t(v) + axis];
      if (c == UINT32_MAX && !named[v]) {
        named[v] = 1;
        out.axis[v] = axis;
        c = v;
      }
      // A copy only where the new plane moves the coordinate (not where two planes agree, as on
      // the line x = -z for x's and z's).
      const glm::dvec3 q = glm::dvec3(m.positions[v]) - centre;
      for (uint8_t b = 0; b < 3 && c == UINT32_MAX; ++b) {
        const uint32_t other = copy_of[3 * size_t(v) + b];
        if (other != UINT32_MAX && box_plane(q, b) == box_plane(q, axis)) c = other;
      }
      if (c == UINT32_MAX) {
        c = uint32_t(out.source.size());
        out.source.push_back(v);
        out.axis.push_back(axis);
      }
      out.indices[t + k] = c;
    }
  }
  return out;
}

// values[source[i]] for every i.
template <class T>
std::vector<T> gathered(std::span<const T> values, const std::vector<uint32_t>& source) {
  std::vector<T> out(source.size());
  for (size_t i = 0; i < source.size(); ++i) out[i] = values[source[i]];
  return out;
}

// sqrt(reference / area): the factor that lays `area` of texture as `reference`; 1 when within
// 0.1 % of it (no rounding noise on coordinates already at that scale); nothing when the area is
// none, or so small that scaled it would outrun a float's precision (a ratio above 1e5).
std::optional<double> strand_ratio(double area, double reference) {
  const double ratio = area > 0.0 && reference > 0.0 ? std::sqrt(reference / area) : 0.0;
  if (!std::isfinite(ratio) || !(ratio > 0.0) || ratio > 1e5) return std::nullopt;
  return std::abs(ratio - 1.0) <= 1e-3 ? 1.0 : ratio;
}

// How the strands are laid on a mesh (FurParams::texture_coordinates, resolved), at one strand
// scale: the llvmpipe harness's projection lays k1 texture units per scene unit along the body
// diagonal's plane; the mesh's uvs and the box's planes are scaled to lay as much texture on the
// mesh as it does, or a quarter of the mesh's area at k1 if that is more (a sheet seen nearly
// edge-on from the diagonal would otherwise get strands as wide as the projection is thin); all
// times texture_repeat. A layout spanning [0, 1] once, as an atlas does, would otherwise make each
// strand texel a patch of the whole surface.
struct StrandLayout {
  StrandCoordinates coordinates = StrandCoordinates::box;
  double k1 = 0.0;     // the projection's texture units per scene unit, before texture_repeat
  double scale = 0.0;  // the factor on the coordinates, texture_repeat included
  bool uvs_cover_no_area = false;
  AxisSplit split;     // the box's split (empty otherwise)
  glm::dvec3 centre{0.0};
  glm::dvec2 diagonal(const glm::vec3& p, double s) const {
    static const glm::dvec3 e1 = glm::normalize(glm::dvec3(1, -1, 0)), e2 = glm::normalize(glm::dvec3(1, 1, -2));
    const glm::dvec3 q = glm::dvec3(p) - centre;
    return {s * glm::dot(q, e1), s * glm::dot(q, e2)};
  }
};

std::optional<ParamError> lay_strands(const Mesh& input, const std::vector<glm::vec3>& normals,
                                      const FurParams& params, const BoundingSphere& bounds, StrandLayout& out) {
  const double R = bounds.radius > 0.0f ? double(bounds.radius) : 1.0;
  out.k1 = 2.449490 * std::sqrt(3.0) / R;
  out.centre = glm::dvec3(bounds.centre);
  const double k1 = out.k1, repeat = double(params.texture_repeat);
  const double reference =
      std::max(triangle_area_2d(input.indices, [&](uint32_t i) { return out.diagonal(input.positions[i], k1); }),
               0.25 * (k1 * k1) * mesh_area(input));
  out.coordinates = params.texture_coordinates.value_or(input.uvs.empty() ? StrandCoordinates::box
                                                                          : StrandCoordinates::mesh);
  out.scale = k1 * repeat;
  if (out.coordinates == StrandCoordinates::mesh) {
    if (input.uvs.empty())
      return ParamError{"texture_coordinates", "\"mesh\" lays the strands by the mesh's texture coordinates, and "
                                               "this mesh has none: use \"box\" or \"projected\""};
    const double uv_area = mesh_uv_area(input);
    if (const std::optional<double> ratio = strand_ratio(uv_area, reference)) {
      out.scale = *ratio * repeat;
    } else if (params.texture_coordinates) {
      return ParamError{"texture_coordinates", "the mesh's texture coordinates (or its triangles) cover no area, so "
                                               "they cannot lay the strands: use \"box\" or \"projected\""};
    } else {
      // Uvs collapsed to a point (an exporter's `vt 0 0` at every corner) were never meant to lay
      // strands: the mesh is treated as having none, and the caller tells the user (uvs_cover_no_area).
      out.coordinates = StrandCoordinates::box;
      out.uvs_cover_no_area = true;
    }
  }
  if (out.coordinates == StrandCoordinates::box) {
    out.split = split_by_facing_axis(input, normals, out.centre);
    const AxisSplit& split = out.split;
    const double box_area = triangle_area_2d(split.indices, [&](uint32_t i) {
      return k1 * box_plane(glm::dvec3(input.positions[split.source[i]]) - out.centre, split.axis[i]);
    });
    // A mesh of no area keeps k1: there is nothing to spread the strands over.
    out.scale = k1 * strand_ratio(box_area, reference).value_or(1.0) * repeat;
  }
  return std::nullopt;
}

// Everything build_fur_geometry checks and decides before it builds: the parameters and the mesh,
// the fur's normals, its bounds and reach, and where the strands lie (with the box's copies). The
// memory estimate's count (fur_base_vertex_count) takes the same steps, so it cannot disagree.
std::optional<ParamError> prepare(const Mesh& input, const FurParams& params, std::vector<glm::vec3>& normals,
                                  BoundingSphere& bounds, StrandLayout& layout) {
  if (auto e = validate(params)) return e;
  if (auto e = check_mesh(input)) return e;
  if (input.positions.size() * size_t(params.shells) > size_t(UINT32_MAX)) {
    return ParamError{"mesh.positions", std::to_string(input.positions.size()) + " vertices x " +
                                            std::to_string(params.shells) + " shells overflow 32-bit indices"};
  }
  if (auto e = fur_normals(input, normals)) return e;
  bounds = bounding_sphere(input);
  // Fur out to 1e18 scene units from the origin keeps every squared distance (lighting, lengths)
  // within a float's range; beyond it the bounding radius itself overflowed (a vertex at 1e21 gave
  // an infinite radius, and every fur vertex sat at infinity, silently drawn as nothing).
  double radius = 0.0;  // in double: the float one is what overflowed
  for (const glm::vec3& p : input.positions)
    radius = std::max(radius, glm::length(glm::dvec3(p) - glm::dvec3(bounds.centre)));
  const double reach = radius * (1.0 + double(params.length)) + glm::length(glm::dvec3(bounds.centre));
  if (!(reach <= kMaxFurReach)) {
    char text[160];
    std::snprintf(text, sizeof text, "the mesh and its fur reach %.3g scene units from the origin; fur needs them "
                  "within %.0e, where squared distances stay within 32-bit floats", reach, kMaxFurReach);
    return ParamError{"mesh.positions", text};
  }
  return lay_strands(input, normals, params, bounds, layout);
}

}  // namespace

void collapse_face_shells(FurGeometry& g, size_t face) {
  if (g.layers == 0) return;
  const size_t faces = g.shell_indices.size() / (3 * size_t{g.layers});
  for (uint32_t s = 0; s < g.layers; ++s) {
    uint32_t* tri = g.shell_indices.data() + (size_t{s} * faces + face) * 3;
    tri[1] = tri[2] = tri[0];
  }
}

size_t fur_base_vertex_count(const Mesh& mesh, const FurParams& params) {
  std::vector<glm::vec3> normals;
  BoundingSphere bounds;
  StrandLayout layout;
  if (prepare(mesh, params, normals, bounds, layout)) return mesh.positions.size();
  return layout.coordinates == StrandCoordinates::box ? layout.split.source.size() : mesh.positions.size();
}

std::optional<ParamError> build_fur_geometry(const Mesh& input, const FurParams& params,
                                             FurGeometry& out, std::span<const float> length_scale,
                                             std::span<const glm::vec2> map_uvs) {
  std::vector<glm::vec3> normals;
  StrandLayout layout;
  if (auto e = prepare(input, params, normals, out.bounds, layout)) return e;
  out.strand_coordinates = layout.coordinates;
  out.strand_uv_scale = layout.scale;
  out.uvs_cover_no_area = layout.uvs_cover_no_area;
  const bool box = layout.coordinates == StrandCoordinates::box;
  // The box's copies, as a mesh of their own: its normals are left out (the fur's are base_normals).
  Mesh split;
  if (box) {
    split.positions = gathered<glm::vec3>(input.positions, layout.split.source);
    if (!input.uvs.empty()) split.uvs = gathered<glm::vec2>(input.uvs, layout.split.source);
    split.indices = std::move(layout.split.indices);
  }
  const Mesh& base = box ? split : input;
  out.base_normals = box ? gathered<glm::vec3>(normals, layout.split.source) : std::move(normals);

  const size_t N = base.positions.size();
  if (N * size_t(params.shells) > size_t(UINT32_MAX)) {
    return ParamError{"mesh.positions", std::to_string(input.positions.size()) + " vertices and " +
                                            std::to_string(N - input.positions.size()) +
                                            " copies where the box mapping's planes meet x " +
                                            std::to_string(params.shells) + " shells overflow 32-bit indices"};
  }
  const uint32_t S = uint32_t(params.shells);
  const size_t F = base.triangle_count();
  out.base_vertex_count = uint32_t(N);
  out.layers = S;
  out.fur_length = params.length * out.bounds.radius;
  out.layer_distance = out.fur_length / float(S - 1);

  out.mesh_uvs.clear();
  out.length_scale.clear();
  out.bald_faces = 0;
  if (!map_uvs.empty()) {
    if (map_uvs.size() != input.positions.size())
      return ParamError{"mesh.uvs", std::to_string(map_uvs.size()) + " map coordinates for " +
                                        std::to_string(input.positions.size()) + " vertices"};
    out.mesh_uvs = box ? gathered(map_uvs, layout.split.source) : std::vector<glm::vec2>(map_uvs.begin(), map_uvs.end());
  } else if (params.use_color_map) {
    if (base.uvs.size() != N)
      return ParamError{"use_color_map", "the colour map is read at the mesh's texture coordinates, and this mesh has none"};
    out.mesh_uvs = base.uvs;
  }

  out.growth.resize(N);
  if (params.comb && params.comb->field == CombField::uv) {
    if (base.uvs.size() != N)
      return ParamError{"comb.field", "\"uv\" combs along the mesh's texture coordinates, and this mesh has none"};
    const std::vector<glm::vec3> d = uv_comb_directions(base, out.base_normals, params.comb->uv_direction);
    CombParams at = *params.comb;
    for (size_t i = 0; i < N; ++i) {
      at.direction = d[i];
      out.growth[i] = d[i] == glm::vec3(0.0f) ? out.base_normals[i] : growth_direction(out.base_normals[i], at);
    }
  } else {
    for (size_t i = 0; i < N; ++i) out.growth[i] = growth_direction(out.base_normals[i], params.comb);
  }

  // Per base vertex: the strand uv (the same in every layer) and the fin's u, the harness's
  // coordinate u = k q.(1,2,3)/sqrt14 (FurGeometry::fin_uvs).
  const double k = layout.k1 * double(params.texture_repeat);
  const glm::dvec3 ef = glm::normalize(glm::dvec3(1, 2, 3));
  std::vector<glm::vec2> base_uv(N);
  std::vector<float> fin_u(N);
  for (uint32_t i = 0; i < N; ++i) {
    const glm::vec3& p = base.positions[i];
    const glm::dvec3 q = glm::dvec3(p) - layout.centre;
    switch (layout.coordinates) {
      case StrandCoordinates::mesh: base_uv[i] = glm::vec2(glm::dvec2(base.uvs[i]) * layout.scale); break;
      case StrandCoordinates::projected: base_uv[i] = glm::vec2(layout.diagonal(p, layout.scale)); break;
      case StrandCoordinates::box: base_uv[i] = glm::vec2(layout.scale * box_plane(q, layout.split.axis[i])); break;
    }
    fin_u[i] = float(k * glm::dot(q, ef));
  }

  // Copies of one strand (same position, normal and growth) grow it at one length: the mean of
  // their scales, which a map read at two sides of a uv seam gives slightly apart. Apart, the
  // copies would be two strands, cracking the shells and doubling the fins along every seam.
  const std::vector<uint32_t> same_as = same_strand_vertices(base.positions, out.base_normals, out.growth);
  if (!length_scale.empty()) {
    if (length_scale.size() != input.positions.size())
      return ParamError{"length_map", std::to_string(length_scale.size()) + " lengths for " +
                                          std::to_string(input.positions.size()) + " vertices"};
    for (size_t i = 0; i < length_scale.size(); ++i)
      if (!(length_scale[i] >= 0.0f && length_scale[i] <= 1.0f))
        return ParamError{"length_map", "vertex " + std::to_string(i) + "'s length must be in [0, 1], got " +
                                            std::to_string(length_scale[i])};
    const std::vector<float> own = box ? gathered(length_scale, layout.split.source)
                                       : std::vector<float>(length_scale.begin(), length_scale.end());
    std::vector<double> sum(N, 0.0);
    std::vector<uint32_t> copies(N, 0);
    for (size_t i = 0; i < N; ++i) sum[same_as[i]] += own[i], ++copies[same_as[i]];
    out.length_scale.resize(N);
    for (size_t i = 0; i < N; ++i) out.length_scale[i] = float(sum[same_as[i]] / double(copies[same_as[i]]));
  }

  // Eq. 1: one array for shells and fins.
  const size_t V = N * S;
  out.positions.resize(V);
  out.shell_uvs.resize(V);
  // Without fins nothing draws or reads the fin coordinates and triangles: they are not made.
  const bool fins = params.fins != FinMode::off;
  if (fins) out.fin_uvs.resize(V);
  out.layer.resize(V);
  for (uint32_t s = 0; s < S; ++s) {
    const float offset = out.layer_distance * float(s);
    const float fv = float(s) / float(S - 1);
    for (size_t i = 0; i < N; ++i) {
      const size_t I = i + size_t(s) * N;
      out.positions[I] = base.positions[i] + out.growth[i] * (out.length_scale.empty() ? offset : offset * out.length_scale[i]);
      out.shell_uvs[I] = base_uv[i];
      if (fins) out.fin_uvs[I] = {fin_u[i], fv};
      out.layer[I] = uint16_t(s);
    }
  }

  out.face_normals.resize(F);
  for (size_t f = 0; f < F; ++f) {
    out.face_normals[f] =
        triangle_normal(base.positions[base.indices[3 * f]], base.positions[base.indices[3 * f + 1]],
                        base.positions[base.indices[3 * f + 2]]);
  }

  // A shell triangle names, for each corner, the first copy equal to it in everything the shells
  // are drawn from: the same strand (position, normal and growth, so the same in every pose) and
  // the same texture coordinate. Such copies (a flat-shaded file's corners once their fur normals
  // are joined, a hard edge whose faces share uvs) are one vertex to the fur. Named by one index,
  // the triangles on either side share an edge for the rasterizer, which packs their lanes into
  // shared blocks and takes one level of detail across them, as on the mesh welded; named by two,
  // the fur was drawn as if cut along them.
  // With a map read at the mesh uvs (a colour map, a cut-out's), copies split at a uv seam of the
  // mesh stay apart even where the strand uvs agree (the box mapping's): joined, a triangle would
  // read the map across the whole atlas.
  const bool by_mesh_uv = !out.mesh_uvs.empty();
  const std::vector<uint32_t> same_shell = first_with_equal_bits<5>(N, [&](uint32_t i) {
    const glm::vec2 m = by_mesh_uv ? out.mesh_uvs[i] : glm::vec2(0.0f);
    return std::array<uint32_t, 5>{same_as[i], key_bits(base_uv[i].x), key_bits(base_uv[i].y), key_bits(m.x),
                                   key_bits(m.y)};
  });
  out.shell_indices.resize(size_t(S) * F * 3);
  for (uint32_t s = 0; s < S; ++s) {
    const uint32_t shift = uint32_t(s * N);
    uint32_t* dst = out.shell_indices.data() + size_t(s) * F * 3;
    for (size_t k3 = 0; k3 < 3 * F; ++k3) dst[k3] = same_shell[base.indices[k3]] + shift;
  }
  // A face whose three corners grow no fur has no shells, or its layers would lie on the base and
  // blend its strands over bare skin.
  if (!out.length_scale.empty())
    for (size_t f = 0; f < F; ++f) {
      const uint32_t* t = &base.indices[3 * f];
      if (out.length_scale[t[0]] != 0.0f || out.length_scale[t[1]] != 0.0f || out.length_scale[t[2]] != 0.0f)
        continue;
      collapse_face_shells(out, f);
      ++out.bald_faces;
    }

  out.edges = mesh_edges(base, same_as);
  // The fins read the map at their ends' mesh uvs too: an edge names the first copy of
  // each end, which may lie on another island of the map (a seam's other side) and would spread
  // the map across the atlas over the fin. Its face0's own copies grow the same strand (the
  // same pose, light and fin), so the fin takes those.
  if (by_mesh_uv)
    for (FurEdge& e : out.edges) {
      const uint32_t* t = &base.indices[3 * size_t{e.face0}];
      uint32_t a = e.a, b = e.b;
      for (int k = 0; k < 3; ++k) {
        if (same_as[t[k]] == e.a) a = same_shell[t[k]];
        if (same_as[t[k]] == e.b) b = same_shell[t[k]];
      }
      e.a = a, e.b = b;
    }
  const size_t E = out.edges.size();
  if (fins) {
    out.fin_indices.resize(size_t(S - 1) * E * 6);
    uint32_t* fi = out.fin_indices.data();
    for (uint32_t s = 0; s + 1 < S; ++s)
      for (const FurEdge& e : out.edges) {
        fin_quad_indices(e, uint32_t(N), s, s + 1, fi);
        fi += 6;
      }
  }
  out.counts = fur_counts(N, F, E, int(S), params.fins);
  for (size_t i = 0; i < N; ++i) out.counts.joined_vertices += same_as[i] != i;
  return std::nullopt;
}

float fin_weight(const glm::vec3& face_normal_a, const std::optional<glm::vec3>& face_normal_b,
                 const glm::vec3& view_dir, FinMode mode) {
  if (mode == FinMode::off) return 0.0f;
  if (mode == FinMode::all) return 1.0f;
  const float vl = glm::length(view_dir);
  if (!(vl > 0.0f) || !std::isfinite(vl)) return 1.0f;
  const glm::vec3 v = view_dir / vl;
  const float ca = glm::dot(face_normal_a, v);
  if (!std::isfinite(ca)) return 1.0f;
  float c = std::fabs(ca);
  if (face_normal_b) {
    const float cb = glm::dot(*face_normal_b, v);
    if (!std::isfinite(cb)) return 1.0f;
    if ((ca > 0.0f && cb < 0.0f) || (ca < 0.0f && cb > 0.0f)) return 1.0f;  // silhouette edge
    c = std::min(c, std::fabs(cb));
  }
  const float x = std::clamp(c / 0.5f, 0.0f, 1.0f);
  return 1.0f - x * x * (3.0f - 2.0f * x);
}

}  // namespace pelt::fur
