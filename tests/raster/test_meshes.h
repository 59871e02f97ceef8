// Small hand-made meshes shared by the tests of every area.
#pragma once

#include "raster/mesh.h"

namespace pelt::test {

// The unit square in the xz plane facing +y, two triangles: 4 vertices, 5 edges (4 on the
// boundary). u runs along +x, v along +z (so the top of the texture image, v = 0, is at
// z = 0: "up" in the image is -z).
inline Mesh unit_square() {
  Mesh m;
  m.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.normals.assign(4, {0, 1, 0});
  m.uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  return m;
}

}  // namespace pelt::test
