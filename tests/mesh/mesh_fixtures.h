// Small procedural meshes shared by the mesh tests.
#pragma once

#include "mesh/mesh.h"

namespace flatmorph::testing {

// nx x ny unit squares in the z = 0 plane, two counter-clockwise triangles each (normals +z).
// Vertex (i, j) is j * (nx + 1) + i; square (i, j) holds faces 2 (j nx + i) and 2 (j nx + i) + 1.
inline Mesh grid(int nx, int ny) {
  Mesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) m.V.row(j * (nx + 1) + i) << i, j, 0.0;
  }
  m.F.resize(2 * nx * ny, 3);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int v00 = j * (nx + 1) + i, v10 = v00 + 1, v01 = v00 + nx + 1, v11 = v01 + 1;
      m.F.row(2 * (j * nx + i)) << v00, v10, v11;
      m.F.row(2 * (j * nx + i) + 1) << v00, v11, v01;
    }
  }
  return m;
}

}  // namespace flatmorph::testing
