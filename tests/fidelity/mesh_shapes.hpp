// Small closed meshes with known mass properties, for the fidelity tests.
#pragma once

#include "fidelity/triangle_mesh.hpp"

namespace mfdem::test {

// The unit cube [0, 1]^3, triangles counter-clockwise seen from outside.
inline fidelity::TriangleMesh unit_cube() {
  fidelity::TriangleMesh cube;
  for (int k = 0; k < 8; ++k) cube.vertices.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  // Corner k has x = bit 0, y = bit 1, z = bit 2.
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},   // z = 0, z = 1
                    {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},   // y = 0, y = 1
                    {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};  // x = 0, x = 1
  return cube;
}

// The right tetrahedron with corners 0, e_x, e_y, e_z.
inline fidelity::TriangleMesh right_tetrahedron() {
  fidelity::TriangleMesh tet;
  tet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return tet;
}

}  // namespace mfdem::test
