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

// The proper rotation R maximizing tr(R C) for the covariance C = Σ (x − x̄)(y − ȳ)ᵀ of two
// centred point sets (Kabsch).
Eigen::Matrix3d kabsch_rotation(const Eigen::Matrix3d& covariance) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  // A proper rotation: flip the weakest axis if the best orthogonal map is a reflection.
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  // Assigned rather than returned as an expression: Eigen evaluates a product it constructs a
  // matrix from in another order than one it assigns, and the fits have always been assigned.
  Eigen::Matrix3d rotation;
  rotation = svd.matrixV() * d * svd.matrixU().transpose();
  return rotation;
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
  fit.rotation = kabsch_rotation(s.transpose() * t);
  fit.translation = ct.transpose() - fit.rotation * cs.transpose();
  return fit;
}

RigidFit weighted_rigid_fit(const Eigen::VectorXd& x, const Eigen::VectorXd& y,
                            const Eigen::VectorXd& mass) {
  const Eigen::Index nv = mass.size();
  Eigen::Vector3d cx = Eigen::Vector3d::Zero(), cy = Eigen::Vector3d::Zero();
  const double total = mass.sum();
  for (Eigen::Index v = 0; v < nv; ++v) {
    cx += mass(v) * x.segment<3>(3 * v);
    cy += mass(v) * y.segment<3>(3 * v);
  }
  cx /= total;
  cy /= total;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (Eigen::Index v = 0; v < nv; ++v) {
    covariance += mass(v) * (x.segment<3>(3 * v) - cx) * (y.segment<3>(3 * v) - cy).transpose();
  }
  RigidFit fit;
  fit.rotation = kabsch_rotation(covariance);
  fit.translation = cy - fit.rotation * cx;
  return fit;
}

Eigen::MatrixXd rigidly_aligned(const Eigen::MatrixXd& shape, const Eigen::MatrixXd& target) {
  const RigidFit fit = best_rigid_fit(shape, target);
  return (shape * fit.rotation.transpose()).rowwise() + fit.translation.transpose();
}

}  // namespace flatmorph
