// Small hand-made base meshes for the fur tests.
#pragma once

#include "raster/mesh.h"

namespace pelt::fur::test {

// Regular-ish tetrahedron, outward counter-clockwise faces, closed: 4 vertices, 4
// faces, 6 edges.
inline Mesh tetrahedron() {
  Mesh m;
  m.positions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  m.indices = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
  compute_vertex_normals(m);
  m.uvs = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  return m;
}

// The unit square in the xz plane facing +y, two triangles: 4 vertices, 5 edges (4 on
// the boundary).
inline Mesh quad() {
  Mesh m;
  m.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.normals.assign(4, {0, 1, 0});
  m.uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  return m;
}

}  // namespace pelt::fur::test
