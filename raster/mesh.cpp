#include "raster/mesh.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "raster/vertex_groups.h"

namespace pelt {

std::vector<uint32_t> same_position_vertices(const std::vector<glm::vec3>& positions) {
  return first_with_equal_key<3>(positions.size(), [&](uint32_t i) {
    const glm::vec3& p = positions[i];
    return std::array<float, 3>{p.x, p.y, p.z};
  });
}

void compute_vertex_normals(Mesh& mesh, NormalSharing sharing, const std::vector<uint64_t>& smoothing) {
  const size_t n_vertices = mesh.positions.size();
  // Each vertex sums into its group's first vertex: itself, or the first copy at its position
  // (with its smoothing key).
  std::vector<uint32_t> group;
  if (!smoothing.empty() && smoothing.size() != n_vertices)
    throw std::invalid_argument(std::string("compute_vertex_normals: ")
                                    .append(std::to_string(smoothing.size()))
                                    .append(" smoothing keys for ")
                                    .append(std::to_string(n_vertices))
                                    .append(" vertices"));
  if (sharing == NormalSharing::per_position) {
    group = first_with_equal_bits<5>(n_vertices, [&](uint32_t i) {
      const glm::vec3& p = mesh.positions[i];
      const uint64_t key = smoothing.empty() ? 0 : smoothing[i];
      return std::array<uint32_t, 5>{key_bits(p.x), key_bits(p.y), key_bits(p.z), uint32_t(key), uint32_t(key >> 32)};
    });
  } else {
    group.resize(n_vertices);
    for (size_t i = 0; i < n_vertices; ++i) group[i] = uint32_t(i);
  }
  std::vector<glm::dvec3> sum(n_vertices, glm::dvec3(0.0));
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const glm::dvec3 pa(mesh.positions[a]), pb(mesh.positions[b]), pc(mesh.positions[c]);
    const glm::dvec3 n = glm::cross(pb - pa, pc - pa);
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) continue;  // degenerate: contributes nothing
    const glm::dvec3 u = n / len;
    sum[group[a]] += u;
    sum[group[b]] += u;
    sum[group[c]] += u;
  }
  mesh.normals.resize(n_vertices);
  for (size_t i = 0; i < n_vertices; ++i) {
    const glm::dvec3& s = sum[group[i]];
    const double len = glm::length(s);
    mesh.normals[i] = (len > 1e-12) ? glm::vec3(s / len) : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

void uv_derivatives(const Mesh& mesh, std::vector<glm::dvec3>& dpdu, std::vector<glm::dvec3>& dpdv) {
  uv_derivatives(mesh, mesh.uvs, dpdu, dpdv);
}

void uv_derivatives(const Mesh& mesh, const std::vector<glm::vec2>& uvs, std::vector<glm::dvec3>& dpdu,
                    std::vector<glm::dvec3>& dpdv) {
  const size_t n = mesh.positions.size();
  dpdu.assign(n, glm::dvec3(0.0));
  dpdv.assign(n, glm::dvec3(0.0));
  if (uvs.size() != n) return;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
    const glm::dvec3 e1 = glm::dvec3(mesh.positions[i1]) - glm::dvec3(mesh.positions[i0]);
    const glm::dvec3 e2 = glm::dvec3(mesh.positions[i2]) - glm::dvec3(mesh.positions[i0]);
    const glm::dvec2 d1 = glm::dvec2(uvs[i1]) - glm::dvec2(uvs[i0]);
    const glm::dvec2 d2 = glm::dvec2(uvs[i2]) - glm::dvec2(uvs[i0]);
    // e = dP/du du + dP/dv dv for both edges; solving divides by det, multiplying through by
    // |det| instead weights the triangle by its uv area and never divides by zero.
    const double det = d1.x * d2.y - d2.x * d1.y;
    if (!(std::abs(det) > 1e-20)) continue;
    const double sign = det > 0.0 ? 1.0 : -1.0;
    const glm::dvec3 du = (e1 * d2.y - e2 * d1.y) * sign;
    const glm::dvec3 dv = (e2 * d1.x - e1 * d2.x) * sign;
    for (uint32_t i : {i0, i1, i2}) {
      dpdu[i] += du;
      dpdv[i] += dv;
    }
  }
}

std::vector<glm::vec4> compute_vertex_tangents(const Mesh& mesh) { return compute_vertex_tangents(mesh, mesh.uvs); }

std::vector<glm::vec4> compute_vertex_tangents(const Mesh& mesh, const std::vector<glm::vec2>& uvs) {
  const size_t n = mesh.positions.size();
  std::vector<glm::dvec3> tu, tv;
  uv_derivatives(mesh, uvs, tu, tv);
  std::vector<glm::vec4> out(n);
  for (size_t i = 0; i < n; ++i) {
    glm::dvec3 N = i < mesh.normals.size() ? glm::dvec3(mesh.normals[i]) : glm::dvec3(0, 1, 0);
    const double nl = glm::length(N);
    N = nl > 0.0 && std::isfinite(nl) ? N / nl : glm::dvec3(0, 1, 0);
    glm::dvec3 T = tu[i] - glm::dot(tu[i], N) * N;
    double tl = glm::length(T);
    if (!(tl > 1e-30) || !std::isfinite(tl)) {
      // Any direction in the tangent plane: the axis least aligned with N, made orthogonal.
      const glm::dvec3 a = std::abs(N.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
      T = a - glm::dot(a, N) * N;
      tl = glm::length(T);
      out[i] = glm::vec4(glm::vec3(T / tl), 1.0f);
      continue;
    }
    T /= tl;
    // The image's "up" is toward decreasing v, so the bitangent should point along -dP/dv.
    const double w = glm::dot(glm::cross(N, T), -tv[i]) < 0.0 ? -1.0 : 1.0;
    out[i] = glm::vec4(glm::vec3(T), float(w));
  }
  return out;
}

}  // namespace pelt
