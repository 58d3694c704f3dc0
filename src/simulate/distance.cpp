#include "simulate/distance.h"

#include <fmt/core.h>

#include <Eigen/LU>
#include <Eigen/SVD>

#include "common/error.h"

namespace flatmorph {
namespace {

void check_same_size(const Eigen::MatrixXd& shape, const Eigen::MatrixXd& target) {
  if (shape.rows() != target.rows() || shape.cols() != 3 || target.cols() != 3) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("cannot compare a shape of {} vertices with a target of {}: both "
                                "must be 3D and have the same vertices in the same order",
                                shape.rows(), target.rows()));
  }
}

}  // namespace

ShapeDistance shape_distance(const Eigen::MatrixXd& shape, const Eigen::MatrixXd& target) {
  check_same_size(shape, target);
  ShapeDistance d;
  d.per_vertex_mm = (shape - target).rowwise().norm();
  if (target.rows() == 0) return d;
  d.mean_mm = d.per_vertex_mm.mean();
  d.max_mm = d.per_vertex_mm.maxCoeff();
  d.diagonal_mm = (target.colwise().maxCoeff() - target.colwise().minCoeff()).norm();
  if (d.diagonal_mm > 0) {
    d.mean_percent = 100 * d.mean_mm / d.diagonal_mm;
    d.max_percent = 100 * d.max_mm / d.diagonal_mm;
  }
  return d;
}

RigidFit best_rigid_fit(const Eigen::MatrixXd& shape, const Eigen::MatrixXd& target) {
  check_same_size(shape, target);
  RigidFit fit;
  if (shape.rows() == 0) return fit;
  const Eigen::RowVector3d cs = shape.colwise().mean(), ct = target.colwise().mean();
  const Eigen::MatrixXd s = shape.rowwise() - cs, t = target.rowwise() - ct;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(s.transpose() * t,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  // A proper rotation: flip the weakest axis if the best orthogonal map is a reflection.
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  fit.rotation = svd.matrixV() * d * svd.matrixU().transpose();
  fit.translation = ct.transpose() - fit.rotation * cs.transpose();
  return fit;
}

Eigen::MatrixXd rigidly_aligned(const Eigen::MatrixXd& shape, const Eigen::MatrixXd& target) {
  const RigidFit fit = best_rigid_fit(shape, target);
  return (shape * fit.rotation.transpose()).rowwise() + fit.translation.transpose();
}

}  // namespace flatmorph
