#include "examples/ring_mesh.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace flatmorph {

Eigen::MatrixXi ring_mesh_faces(const std::vector<int>& ring_sizes) {
  if (ring_sizes.empty() || ring_sizes.front() < 3) {
    throw std::logic_error("ring_mesh_faces: the first ring needs at least 3 vertices");
  }
  std::vector<int> first(ring_sizes.size() + 1, 1);  // index of each ring's vertex 0
  int faces = ring_sizes.front();
  for (size_t i = 0; i < ring_sizes.size(); ++i) {
    first[i + 1] = first[i] + ring_sizes[i];
    if (i > 0) {
      if (ring_sizes[i] < ring_sizes[i - 1]) {
        throw std::logic_error("ring_mesh_faces: ring sizes must not decrease");
      }
      faces += ring_sizes[i - 1] + ring_sizes[i];
    }
  }
  Eigen::MatrixXi F(faces, 3);
  int f = 0;
  const int n1 = ring_sizes.front();
  for (int b = 0; b < n1; ++b) F.row(f++) << 0, first[0] + b, first[0] + (b + 1) % n1;
  for (size_t i = 0; i + 1 < ring_sizes.size(); ++i) {
    const int m = ring_sizes[i], n = ring_sizes[i + 1];
    auto inner = [&](int a) { return first[i] + a % m; };
    auto outer = [&](int b) { return first[i + 1] + b % n; };
    // Merge the two rings by fraction, closing the triangle toward whichever next vertex comes
    // first ((b+1)/n against (a+1)/m). A tie means both next vertices lie on the same ray;
    // advancing the inner ring first makes the edge between them the short radial one (on the
    // examples' rings of 6 i vertices, the hexagonal lattice).
    for (int a = 0, b = 0; a < m || b < n;) {
      if (a == m || (b < n && static_cast<long>(b + 1) * m < static_cast<long>(a + 1) * n)) {
        F.row(f++) << inner(a), outer(b), outer(b + 1);
        ++b;
      } else {
        F.row(f++) << inner(a), outer(b), inner(a + 1);
        ++a;
      }
    }
  }
  return F;
}

Mesh ring_disk(const std::vector<double>& radii) {
  const int rings = static_cast<int>(radii.size()) - 1;
  std::vector<int> sizes;
  for (int i = 1; i <= rings; ++i) sizes.push_back(6 * i);
  Mesh mesh;
  mesh.F = ring_mesh_faces(sizes);
  mesh.V.setZero(1 + 3 * rings * (rings + 1), 3);
  int v = 1;
  for (int i = 1; i <= rings; ++i) {
    for (int j = 0; j < 6 * i; ++j) {
      const double psi = 2.0 * std::numbers::pi * j / (6 * i);
      mesh.V.row(v++) << radii[i] * std::cos(psi), radii[i] * std::sin(psi), 0.0;
    }
  }
  return mesh;
}

}  // namespace flatmorph
