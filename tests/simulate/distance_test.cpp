// Tests of the weighted rigid fit (src/simulate/distance.h): it undoes a known rigid motion, its
// weights decide which vertices it fits, and with equal weights it is the unweighted fit.
#include "simulate/distance.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace flatmorph::distance_test {
namespace {

// Stacked coordinates (x0, y0, z0, x1, ...) of a #V x 3 shape.
Eigen::VectorXd stacked(const Eigen::MatrixXd& V) {
  const Eigen::MatrixXd rows = V.transpose();
  return Eigen::Map<const Eigen::VectorXd>(rows.data(), rows.size());
}

Eigen::MatrixXd points() {
  Eigen::MatrixXd V(5, 3);
  V << 0, 0, 0, 3, 0, 1, 0, 4, -1, 1, 1, 2, -2, 1, 0.5;
  return V;
}

TEST(WeightedRigidFit, UndoesARigidMotionWhateverTheWeights) {
  const Eigen::MatrixXd target = points();
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d shift(4, -1, 7);
  const Eigen::MatrixXd moved = (target * turn.transpose()).rowwise() + shift.transpose();
  Eigen::VectorXd mass(5);
  mass << 0.5, 2, 1, 3, 0.1;
  const RigidFit fit = weighted_rigid_fit(stacked(moved), stacked(target), mass);
  EXPECT_LT((fit.rotation - turn.transpose()).norm(), 1e-12);
  EXPECT_LT((fit.translation + turn.transpose() * shift).norm(), 1e-12);
  EXPECT_NEAR(fit.rotation.determinant(), 1, 1e-12);
}

// A shape that matches the target at three heavy vertices and not at two light ones is fitted
// onto the heavy ones; with equal weights the fit is best_rigid_fit's.
TEST(WeightedRigidFit, FitsTheHeavyVertices) {
  const Eigen::MatrixXd target = points();
  Eigen::MatrixXd shape = target;
  shape.row(3) += Eigen::RowVector3d(0.7, -0.4, 0.9);
  shape.row(4) += Eigen::RowVector3d(-0.5, 0.8, 0.3);
  Eigen::VectorXd heavy(5);
  heavy << 1, 1, 1, 1e-9, 1e-9;
  const RigidFit fit = weighted_rigid_fit(stacked(shape), stacked(target), heavy);
  EXPECT_LT((fit.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-6);
  EXPECT_LT(fit.translation.norm(), 1e-6);

  const RigidFit equal =
      weighted_rigid_fit(stacked(shape), stacked(target), Eigen::VectorXd::Ones(5));
  const RigidFit plain = best_rigid_fit(shape, target);
  EXPECT_GT((equal.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-3);
  EXPECT_LT((equal.rotation - plain.rotation).norm(), 1e-12);
  EXPECT_LT((equal.translation - plain.translation).norm(), 1e-12);
}

}  // namespace
}  // namespace flatmorph::distance_test
