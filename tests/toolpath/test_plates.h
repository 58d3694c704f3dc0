// Procedural plates and direction fields for the toolpath tests: a disk and a rectangle evenly
// triangulated (edges about `edge` mm, counter-clockwise), with fields given as functions of x, y.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace flatmorph::toolpath_testing {

struct TestPlate {
  Eigen::MatrixXd V;  // #V x 2, mm
  Eigen::MatrixXi F;
};

// A disk of the given diameter centred on the origin: concentric rings about `edge` apart,
// stitched by angle.
inline TestPlate disk_plate(double diameter, double edge) {
  const double R = diameter / 2;
  const int rings = static_cast<int>(std::ceil(R / edge));
  std::vector<Eigen::Vector2d> points{Eigen::Vector2d::Zero()};
  std::vector<int> ring_start{0}, ring_size{1};
  for (int i = 1; i <= rings; ++i) {
    const double r = R * i / rings;
    const int n = std::max(6, static_cast<int>(std::lround(2 * std::numbers::pi * r / edge)));
    ring_start.push_back(static_cast<int>(points.size()));
    ring_size.push_back(n);
    for (int k = 0; k < n; ++k) {
      const double a = 2 * std::numbers::pi * k / n;
      points.emplace_back(r * std::cos(a), r * std::sin(a));
    }
  }
  std::vector<Eigen::Vector3i> faces;
  for (int i = 1; i <= rings; ++i) {
    const int m = ring_size[i - 1], n = ring_size[i];
    const auto inner = [&](int k) { return ring_start[i - 1] + k % m; };
    const auto outer = [&](int k) { return ring_start[i] + k % n; };
    int a = 0, b = 0;
    while (b < n || (m > 1 && a < m)) {
      const double next_inner = m == 1 ? 1e9 : 2 * std::numbers::pi * (a + 1) / m;
      const double next_outer = 2 * std::numbers::pi * (b + 1) / n;
      if (b < n && (a == m || m == 1 || next_outer < next_inner)) {
        faces.emplace_back(inner(a), outer(b), outer(b + 1));
        ++b;
      } else {
        faces.emplace_back(inner(a), outer(b), inner(a + 1));
        ++a;
      }
    }
  }
  TestPlate plate;
  plate.V.resize(static_cast<int>(points.size()), 2);
  for (size_t v = 0; v < points.size(); ++v) plate.V.row(v) = points[v].transpose();
  plate.F.resize(static_cast<int>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) plate.F.row(f) = faces[f].transpose();
  return plate;
}

// A width x height rectangle centred on the origin, a grid of squares split along alternating
// diagonals.
inline TestPlate rectangle_plate(double width, double height, double edge) {
  const int nx = static_cast<int>(std::ceil(width / edge));
  const int ny = static_cast<int>(std::ceil(height / edge));
  TestPlate plate;
  plate.V.resize((nx + 1) * (ny + 1), 2);
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      plate.V.row(j * (nx + 1) + i) << width * i / nx - width / 2, height * j / ny - height / 2;
    }
  }
  plate.F.resize(2 * nx * ny, 3);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int v00 = j * (nx + 1) + i, v10 = v00 + 1, v01 = v00 + nx + 1, v11 = v01 + 1;
      const int f = 2 * (j * nx + i);
      if ((i + j) % 2 == 0) {
        plate.F.row(f) << v00, v10, v11;
        plate.F.row(f + 1) << v00, v11, v01;
      } else {
        plate.F.row(f) << v00, v10, v01;
        plate.F.row(f + 1) << v10, v11, v01;
      }
    }
  }
  return plate;
}

using Field = std::function<double(double x, double y)>;

inline Eigen::VectorXd per_face(const TestPlate& plate, const Field& field) {
  Eigen::VectorXd values(plate.F.rows());
  for (int f = 0; f < plate.F.rows(); ++f) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int k = 0; k < 3; ++k) c += plate.V.row(plate.F(f, k)).transpose() / 3;
    values(f) = field(c.x(), c.y());
  }
  return values;
}

inline Eigen::VectorXd per_vertex(const TestPlate& plate, const Field& field) {
  Eigen::VectorXd values(plate.V.rows());
  for (int v = 0; v < plate.V.rows(); ++v) values(v) = field(plate.V(v, 0), plate.V(v, 1));
  return values;
}

}  // namespace flatmorph::toolpath_testing
