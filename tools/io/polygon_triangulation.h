// Splitting a mesh file's polygon faces into triangles.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace pelt::io {

// Appends exactly corners.size() - 2 triangles covering the polygon, as corner numbers
// (0 .. size - 1) in the polygon's own winding, to `out`. Never drops a triangle, whatever
// the input: a hole in the mesh would be a silent change of the user's model.
//
// - A triangle is itself.
// - A quad is split along its shorter diagonal (as tinyobjloader does), unless that
//   diagonal lies outside a non-convex quad; then along the other.
// - A larger polygon is ear-clipped in its plane (Newell's normal, projected along its
//   largest component), in double precision: the ear test rejects a reflex corner and any
//   triangle that holds another remaining corner. Where no ear exists (a self-intersecting
//   or numerically flat polygon) the first convex corner, or failing that the first
//   corner, is clipped anyway, so the count stays right and the result covers the
//   polygon's outline as well as a polygon without a proper inside can be covered.
//
// Why not tinyobjloader's triangulation: its 2.0.0~rc10 ear clipper tests each corner
// against a sign that depends on where the polygon lies, not on its winding, and gives up
// after a bounded number of tries, dropping what remains. In a throwaway program, 74 of
// 2000 random planar star-shaped polygons of 5-8 corners lost triangles; an L-shaped
// hexagon and a U-shaped octagon at small integer offsets kept 1 of 4 and 3 of 6
// (tests/tools/io/polygon_triangulation_test.cpp covers those shapes exactly).
void triangulate_polygon(std::span<const glm::vec3> corners, std::vector<uint32_t>& out);

}  // namespace pelt::io
