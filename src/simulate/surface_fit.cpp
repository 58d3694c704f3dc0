#include "simulate/surface_fit.h"

#include <fmt/core.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "common/error.h"
#include "mesh/closest_point.h"
#include "mesh/operators.h"

namespace flatmorph {
namespace {

// Steps each start is given before the best is chosen and the most points they are taken at; the
// steps the best then gets to converge on more points, and then on all (point-to-point fits
// converge linearly: most steps are taken on a sample, the last ones on every vertex).
constexpr int kTrialSteps = 10;
constexpr size_t kTrialPoints = 200;
constexpr size_t kFitPoints = 4000;
constexpr int kMaxSteps = 200;
constexpr int kMaxFinalSteps = 50;
// Converged when a step lowers the mean squared distance by less than this share of it, or by
// less than the square of this share of the target's diagonal (a fit sliding along a surface it
// nearly matches, a strip along a cylinder, lowers it by ever smaller amounts that no figure
// shows).
constexpr double kRelativeTolerance = 1e-10;
constexpr double kLengthTolerance = 1e-7;

void check_surface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const char* what) {
  if (V.cols() != 3 || !V.allFinite() || F.rows() == 0 ||
      (F.size() > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows()))) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("the {} must be a triangle mesh with finite 3D coordinates", what));
  }
  if (!(face_areas(V, F).sum() > 0)) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("the {} has no face of positive area", what));
  }
}

Eigen::VectorXd stacked(const Eigen::MatrixXd& V) {
  const Eigen::MatrixXd rows = V.transpose();
  return Eigen::Map<const Eigen::VectorXd>(rows.data(), rows.size());
}

Eigen::MatrixXd moved(const Eigen::MatrixXd& X, const RigidFit& fit) {
  return (X * fit.rotation.transpose()).rowwise() + fit.translation.transpose();
}

// The weighted centroid and the principal axes (columns, greatest spread first, a proper
// rotation) of points with weights.
void principal_frame(const Eigen::MatrixXd& X, const Eigen::VectorXd& mass,
                     Eigen::Vector3d& centroid, Eigen::Matrix3d& axes) {
  centroid = (X.transpose() * mass) / mass.sum();
  const Eigen::MatrixXd centred = X.rowwise() - centroid.transpose();
  const Eigen::Matrix3d spread = centred.transpose() * mass.asDiagonal() * centred;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(spread);
  axes = eig.eigenvectors().rowwise().reverse();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
}

// The 24 rotations that map the coordinate axes onto themselves (in any order and sign).
std::vector<Eigen::Matrix3d> axis_rotations() {
  std::vector<Eigen::Matrix3d> out;
  std::array<int, 3> order{0, 1, 2};
  do {
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d d = Eigen::Matrix3d::Zero();
      for (int i = 0; i < 3; ++i) d(i, order[i]) = (signs >> i) & 1 ? -1 : 1;
      if (d.determinant() > 0) out.push_back(d);
    }
  } while (std::next_permutation(order.begin(), order.end()));
  return out;
}

// Σ m_v |R x_v + t − y_v|² / Σ m_v with y_v the nearest surface points, and those points.
double mean_squared_distance(const TriangleTree& tree, const Eigen::MatrixXd& X,
                             const Eigen::VectorXd& mass, const RigidFit& fit,
                             Eigen::MatrixXd& nearest) {
  const Eigen::MatrixXd Y = moved(X, fit);
  nearest.resize(X.rows(), 3);
  double sum = 0;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    const SurfacePoint q = closest_surface_point(tree, Y.row(v).transpose());
    nearest.row(v) = q.point.transpose();
    sum += mass(v) * q.distance * q.distance;
  }
  return sum / mass.sum();
}

// Iterative closest points from `fit`, at most `steps` steps: each step fits the points rigidly
// onto their nearest surface points, and is kept while it brings them nearer. Returns the mean
// squared distance at the fit returned.
double refine(const TriangleTree& tree, const Eigen::MatrixXd& X, const Eigen::VectorXd& mass,
              int steps, double floor, RigidFit& fit, int& iterations) {
  const Eigen::VectorXd x = stacked(X);
  Eigen::MatrixXd nearest;
  double error = mean_squared_distance(tree, X, mass, fit, nearest);
  for (int step = 0; step < steps && error > 0; ++step) {
    const RigidFit next = weighted_rigid_fit(x, stacked(nearest), mass);
    Eigen::MatrixXd next_nearest;
    const double next_error = mean_squared_distance(tree, X, mass, next, next_nearest);
    if (!(next_error < error)) break;
    const bool converged = error - next_error <= std::max(kRelativeTolerance * error, floor);
    fit = next;
    nearest = std::move(next_nearest);
    error = next_error;
    ++iterations;
    if (converged) break;
  }
  return error;
}

}  // namespace

SurfaceFit closest_point_rigid_fit(const Eigen::MatrixXd& shape, const Eigen::MatrixXi& shape_F,
                                   const Eigen::MatrixXd& target_V,
                                   const Eigen::MatrixXi& target_F) {
  check_surface(shape, shape_F, "shape");
  check_surface(target_V, target_F, "target");
  const Eigen::VectorXd mass = lumped_mass(shape, shape_F);
  const TriangleTree tree = triangle_tree(target_V, target_F);
  const double diagonal = (target_V.colwise().maxCoeff() - target_V.colwise().minCoeff()).norm();
  const double floor = std::pow(kLengthTolerance * diagonal, 2);  // mm²

  // Starts: as it is, and the principal frames matched every way.
  Eigen::Vector3d shape_centre, target_centre;
  Eigen::Matrix3d shape_axes, target_axes;
  principal_frame(shape, mass, shape_centre, shape_axes);
  principal_frame(target_V, lumped_mass(target_V, target_F), target_centre, target_axes);
  std::vector<RigidFit> starts(1);
  for (const Eigen::Matrix3d& d : axis_rotations()) {
    RigidFit start;
    start.rotation = target_axes * d * shape_axes.transpose();
    start.translation = target_centre - start.rotation * shape_centre;
    starts.push_back(start);
  }

  // Each start is tried for a few steps on a few of the vertices, the best (the first of equals)
  // converges on more of them and then on all: queries from a far start are the costly ones.
  std::vector<Eigen::Index> used;  // the vertices faces use
  for (Eigen::Index v = 0; v < shape.rows(); ++v) {
    if (mass(v) > 0) used.push_back(v);
  }
  // At most `count` of them, evenly spread in their order.
  auto subset = [&](size_t count, Eigen::MatrixXd& points, Eigen::VectorXd& weights) {
    std::vector<Eigen::Index> some;
    const size_t stride = (used.size() + count - 1) / count;
    for (size_t i = 0; i < used.size(); i += stride) some.push_back(used[i]);
    points = shape(some, Eigen::all);
    weights = mass(some);
  };
  Eigen::MatrixXd points;
  Eigen::VectorXd weights;
  subset(kTrialPoints, points, weights);
  RigidFit best = starts.front();
  double best_error = std::numeric_limits<double>::infinity();
  for (RigidFit start : starts) {
    int steps = 0;
    const double error = refine(tree, points, weights, kTrialSteps, floor, start, steps);
    if (error < best_error) {
      best_error = error;
      best = start;
    }
  }
  SurfaceFit out;
  subset(kFitPoints, points, weights);
  refine(tree, points, weights, kMaxSteps, floor, best, out.iterations);
  if (used.size() > kFitPoints)
    refine(tree, shape, mass, kMaxFinalSteps, floor, best, out.iterations);
  out.fit = best;
  out.aligned = moved(shape, best);
  ShapeDistance& d = out.distance;
  d.per_vertex_mm.resize(shape.rows());
  for (Eigen::Index v = 0; v < shape.rows(); ++v) {
    d.per_vertex_mm(v) = closest_surface_point(tree, out.aligned.row(v).transpose()).distance;
  }
  d.mean_mm = d.per_vertex_mm.mean();
  d.max_mm = d.per_vertex_mm.maxCoeff();
  d.diagonal_mm = diagonal;
  if (d.diagonal_mm > 0) {
    d.mean_percent = 100 * d.mean_mm / d.diagonal_mm;
    d.max_percent = 100 * d.max_mm / d.diagonal_mm;
  }
  return out;
}

}  // namespace flatmorph
