// Small hand-made base meshes for the fur tests.
#pragma once

#include "raster/mesh.h"
#include "tests/raster/test_meshes.h"

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

using pelt::test::unit_square;

}  // namespace pelt::fur::test
