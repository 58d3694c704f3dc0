// Shapes fitted to simulated points, for the tests that measure a predicted shape.
#pragma once

#include <Eigen/Dense>
#include <cmath>

namespace flatmorph::testing {

// Curvature of the best-fit circle through points that lie near a plane (Kasa fit in the plane of
// the two main principal axes), and the circle's centre in 3D.
inline double fitted_circle_curvature(const Eigen::MatrixXd& P, Eigen::Vector3d& center) {
  const Eigen::RowVector3d mean = P.colwise().mean();
  const Eigen::MatrixXd Q = P.rowwise() - mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Q.transpose() * Q);
  const Eigen::Vector3d u = eig.eigenvectors().col(2), v = eig.eigenvectors().col(1);
  Eigen::MatrixXd A(P.rows(), 3);
  Eigen::VectorXd rhs(P.rows());
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const double x = Q.row(i).dot(u), y = Q.row(i).dot(v);
    A.row(i) << x, y, 1;
    rhs(i) = -(x * x + y * y);
  }
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(rhs);
  const double cx = -s(0) / 2, cy = -s(1) / 2;
  center = mean.transpose() + cx * u + cy * v;
  return 1.0 / std::sqrt(cx * cx + cy * cy - s(2));
}

}  // namespace flatmorph::testing
