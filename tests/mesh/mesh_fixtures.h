// Small procedural meshes shared by the tests.
#pragma once

#include <Eigen/Core>
#include <cmath>

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

// A (nu x nv)-quad grid over parameters (u, v) in [0, 1]^2, mapped to 3D by `point` (returning an
// Eigen::Vector3d), each quad split along alternating diagonals; faces are counter-clockwise in
// (u, v).
template <typename Point>
Mesh grid_mesh(int nu, int nv, Point point) {
  Mesh mesh;
  mesh.V.resize((nu + 1) * (nv + 1), 3);
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      mesh.V.row(j * (nu + 1) + i) = point(double(i) / nu, double(j) / nv).transpose();
    }
  }
  mesh.F.resize(2 * nu * nv, 3);
  int f = 0;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const int a = j * (nu + 1) + i, b = a + 1, c = a + nu + 1, d = c + 1;
      if ((i + j) % 2 == 0) {
        mesh.F.row(f++) << a, b, d;
        mesh.F.row(f++) << a, d, c;
      } else {
        mesh.F.row(f++) << a, b, c;
        mesh.F.row(f++) << b, d, c;
      }
    }
  }
  return mesh;
}

// The regular icosahedron with vertices (0, ±1, ±φ) and their cyclic permutations; closed,
// outward normals.
inline Mesh icosahedron() {
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  Mesh m;
  m.V.resize(12, 3);
  m.V << -1, p, 0, 1, p, 0, -1, -p, 0, 1, -p, 0, 0, -1, p, 0, 1, p, 0, -1, -p, 0, 1, -p, p, 0, -1,
      p, 0, 1, -p, 0, -1, -p, 0, 1;
  m.F.resize(20, 3);
  m.F << 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7,
      1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8,
      1;
  return m;
}

}  // namespace flatmorph::testing
