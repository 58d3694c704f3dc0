// Procedural flat plates for the plate and simulation tests: triangulated rectangles, disks and
// ellipses in the xy plane (mm), counter-clockwise triangles.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "../mesh/mesh_fixtures.h"
#include "plate/layer_stack.h"

namespace flatmorph::testing {

struct TestPlate {
  Eigen::MatrixXd V;  // #V x 2, mm
  Eigen::MatrixXi F;  // #F x 3, counter-clockwise
};

// A width x height rectangle centred at the origin, cells_x x cells_y cells, each cut along a
// diagonal that alternates like a chequerboard (no preferred diagonal direction overall).
inline TestPlate rectangle_plate(double width, double height, int cells_x, int cells_y) {
  const Mesh grid = grid_mesh(cells_x, cells_y, [&](double u, double v) {
    return Eigen::Vector3d(width * (u - 0.5), height * (v - 0.5), 0.0);
  });
  return {grid.V.leftCols(2), grid.F};
}

// A disk of the given radius centred at the origin: vertex 0 at the centre, then `rings` rings,
// ring i with 6i vertices at radius i/rings * radius starting at angle 0. Neighbouring rings are
// zipped by angle, so every triangle is counter-clockwise.
inline TestPlate disk_plate(double radius, int rings) {
  std::vector<Eigen::Vector2d> points{Eigen::Vector2d::Zero()};
  std::vector<std::vector<int>> ring_ids{{0}};
  std::vector<std::vector<double>> ring_angles{{0.0}};
  for (int i = 1; i <= rings; ++i) {
    std::vector<int> ids;
    std::vector<double> angles;
    for (int j = 0; j < 6 * i; ++j) {
      const double angle = 2 * M_PI * j / (6 * i);
      ids.push_back(static_cast<int>(points.size()));
      angles.push_back(angle);
      points.emplace_back(radius * i / rings * std::cos(angle),
                          radius * i / rings * std::sin(angle));
    }
    ring_ids.push_back(ids);
    ring_angles.push_back(angles);
  }
  std::vector<Eigen::Vector3i> faces;
  for (int i = 1; i <= rings; ++i) {
    const auto& in = ring_ids[i - 1];
    const auto& out = ring_ids[i];
    const auto& in_angle = ring_angles[i - 1];
    const auto& out_angle = ring_angles[i];
    const int m = static_cast<int>(in.size()), n = static_cast<int>(out.size());
    if (m == 1) {
      for (int j = 0; j < n; ++j) faces.emplace_back(in[0], out[j], out[(j + 1) % n]);
      continue;
    }
    int a = 0, b = 0;
    while (a < m || b < n) {
      const double next_a = a + 1 < m ? in_angle[a + 1] : 2 * M_PI;
      const double next_b = b + 1 < n ? out_angle[b + 1] : 2 * M_PI;
      if (b < n && (next_b <= next_a || a == m)) {
        faces.emplace_back(in[a % m], out[b], out[(b + 1) % n]);
        ++b;
      } else {
        faces.emplace_back(in[a % m], out[b % n], in[(a + 1) % m]);
        ++a;
      }
    }
  }
  TestPlate p;
  p.V.resize(points.size(), 2);
  for (size_t v = 0; v < points.size(); ++v) p.V.row(v) = points[v].transpose();
  p.F.resize(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) p.F.row(f) = faces[f].transpose();
  return p;
}

// An ellipse with semi-axes (a, b) along (x, y): the disk scaled.
inline TestPlate ellipse_plate(double semi_axis_x, double semi_axis_y, int rings) {
  TestPlate p = disk_plate(1.0, rings);
  p.V.col(0) *= semi_axis_x;
  p.V.col(1) *= semi_axis_y;
  return p;
}

// Embeds a flat plate at z = 0 as a flat (#V x 3) matrix.
inline Eigen::MatrixXd embed(const Eigen::MatrixXd& plate) {
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(plate.rows(), 3);
  X.leftCols(2) = plate;
  return X;
}

// #V x 3 <-> (x0, y0, z0, x1, ...).
inline Eigen::VectorXd flatten_positions(const Eigen::MatrixXd& X) {
  Eigen::VectorXd x(X.size());
  for (Eigen::Index v = 0; v < X.rows(); ++v) x.segment<3>(3 * v) = X.row(v).transpose();
  return x;
}

inline Eigen::MatrixXd unflatten_positions(const Eigen::VectorXd& x) {
  Eigen::MatrixXd X(x.size() / 3, 3);
  for (Eigen::Index v = 0; v < X.rows(); ++v) X.row(v) = x.segment<3>(3 * v).transpose();
  return X;
}

// One layer of a stiff shrinking material (PLA: E = 14, shrinking isotropically to `shrink`) on
// one of a soft one that does not shrink (TPU: E = 1), each 0.5 mm thick after heating, equally
// Poisson (ν = 0.4): the bilayer of Timoshenko (1925), over `num_faces` faces.
inline LayerStack pla_on_tpu_bilayer(int num_faces, double shrink) {
  Material pla, tpu;
  pla.lambda1 = pla.lambda2 = shrink;
  pla.lambda3 = 1.0;
  pla.delta_lambda1 = 0;
  pla.young_modulus_along = pla.young_modulus_across = 14.0;
  pla.poisson_ratio = tpu.poisson_ratio = 0.4;
  tpu.lambda1 = tpu.lambda2 = tpu.lambda3 = 1.0;
  tpu.delta_lambda1 = 0;
  tpu.young_modulus_along = tpu.young_modulus_across = 1.0;
  LayerStack stack;
  stack.materials = {pla, tpu};
  stack.layers.push_back(uniform_layer(num_faces, 1, tpu, 0.5));  // on the bed
  stack.layers.push_back(uniform_layer(num_faces, 0, pla, 0.5));
  return stack;
}

// Timoshenko's bilayer curvature: κ = 6 Δε (1 + m)² / (h (3 (1 + m)² + (1 + m n)(m² + 1/(m n))))
// with m the thickness ratio, n the stiffness ratio, h the total thickness (mm), Δε the mismatch.
inline double timoshenko_curvature(double m, double n, double h, double strain) {
  return 6 * strain * (1 + m) * (1 + m) /
         (h * (3 * (1 + m) * (1 + m) + (1 + m * n) * (m * m + 1 / (m * n))));
}

}  // namespace flatmorph::testing
