#include "tools/io/polygon_triangulation.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace pelt::io {
namespace {

using P2 = glm::dvec2;

// Twice the signed area of o, a, b: positive when they turn counter-clockwise.
double turn(P2 o, P2 a, P2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// p inside the counter-clockwise triangle abc or on its boundary: a corner on a clipped
// diagonal would leave the rest of the polygon touching itself.
bool in_triangle(P2 p, P2 a, P2 b, P2 c) { return turn(a, b, p) >= 0 && turn(b, c, p) >= 0 && turn(c, a, p) >= 0; }

glm::dvec3 newell_normal(std::span<const glm::vec3> c) {
  glm::dvec3 n(0.0);
  for (size_t i = 0; i < c.size(); ++i) {
    const glm::dvec3 a(c[i]), b(c[(i + 1) % c.size()]);
    n.x += (a.y - b.y) * (a.z + b.z);
    n.y += (a.z - b.z) * (a.x + b.x);
    n.z += (a.x - b.x) * (a.y + b.y);
  }
  return n;
}

void emit(std::vector<uint32_t>& out, uint32_t a, uint32_t b, uint32_t c) {
  out.push_back(a);
  out.push_back(b);
  out.push_back(c);
}

// Whether triangle (a, b, c) of the corners faces the polygon's way.
bool faces(std::span<const glm::vec3> c, glm::dvec3 n, int a, int b, int d) {
  const glm::dvec3 pa(c[a]);
  return glm::dot(glm::cross(glm::dvec3(c[b]) - pa, glm::dvec3(c[d]) - pa), n) > 0.0;
}

void split_quad(std::span<const glm::vec3> c, glm::dvec3 n, std::vector<uint32_t>& out) {
  // The diagonal test in float, operation for operation as tinyobjloader's, so that a
  // convex quad splits as it did before pelt triangulated faces itself.
  const glm::vec3 e02 = c[2] - c[0], e13 = c[3] - c[1];
  const float sqr02 = e02.x * e02.x + e02.y * e02.y + e02.z * e02.z;
  const float sqr13 = e13.x * e13.x + e13.y * e13.y + e13.z * e13.z;
  bool along02 = sqr02 < sqr13;
  const bool ok02 = faces(c, n, 0, 1, 2) && faces(c, n, 0, 2, 3);
  const bool ok13 = faces(c, n, 0, 1, 3) && faces(c, n, 1, 2, 3);
  if (along02 && !ok02 && ok13) along02 = false;
  if (!along02 && !ok13 && ok02) along02 = true;
  if (along02) {
    emit(out, 0, 1, 2);
    emit(out, 0, 2, 3);
  } else {
    emit(out, 0, 1, 3);
    emit(out, 1, 2, 3);
  }
}

}  // namespace

void triangulate_polygon(std::span<const glm::vec3> corners, std::vector<uint32_t>& out) {
  const size_t k = corners.size();
  if (k < 3) return;
  if (k == 3) {
    emit(out, 0, 1, 2);
    return;
  }
  const glm::dvec3 n = newell_normal(corners);
  if (k == 4) {
    split_quad(corners, n, out);
    return;
  }

  // Project along the normal's largest component, mirrored if need be so that the
  // polygon winds counter-clockwise: an ear is then a left turn.
  const glm::dvec3 an = glm::abs(n);
  const int drop = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
  const int u = drop == 0 ? 1 : 0, v = drop == 2 ? 1 : 2;
  std::vector<P2> p(k);
  double area = 0.0;
  for (size_t i = 0; i < k; ++i) p[i] = P2(corners[i][u], corners[i][v]);
  for (size_t i = 0; i < k; ++i) area += turn(P2(0.0), p[i], p[(i + 1) % k]);
  if (area < 0.0)
    for (P2& q : p) q.x = -q.x;

  std::vector<uint32_t> left(k);
  for (size_t i = 0; i < k; ++i) left[i] = static_cast<uint32_t>(i);
  size_t cursor = 0;
  while (left.size() > 3) {
    const size_t m = left.size();
    size_t ear = m, fallback = m;
    for (size_t step = 0; step < m && ear == m; ++step) {
      const size_t i = (cursor + step) % m;
      const uint32_t a = left[(i + m - 1) % m], b = left[i], c = left[(i + 1) % m];
      if (turn(p[a], p[b], p[c]) <= 0.0) continue;  // reflex or flat
      if (fallback == m) fallback = i;
      bool holds = false;
      for (size_t j = 0; j < m && !holds; ++j) {
        const uint32_t q = left[j];
        if (q == a || q == b || q == c) continue;
        // A corner repeated at the same place (a polygon touching itself at a point) does
        // not block the ear it is a corner of.
        if (p[q] == p[a] || p[q] == p[b] || p[q] == p[c]) continue;
        holds = in_triangle(p[q], p[a], p[b], p[c]);
      }
      if (!holds) ear = i;
    }
    // No ear: the polygon crosses itself or is flat to double precision. Clipping a convex
    // corner (or any) keeps every remaining corner covered by some triangle.
    if (ear == m) ear = fallback != m ? fallback : cursor % m;
    emit(out, left[(ear + m - 1) % m], left[ear], left[(ear + 1) % m]);
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(ear));
    cursor = ear == 0 ? 0 : ear - 1;
  }
  emit(out, left[0], left[1], left[2]);
}

}  // namespace pelt::io
