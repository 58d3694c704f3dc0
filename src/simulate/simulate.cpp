#include "simulate/simulate.h"

#include <fmt/core.h>

#include <Eigen/Geometry>
#include <chrono>
#include <limits>

#include "common/error.h"
#include "simulate/distance.h"

namespace flatmorph {
namespace {

// The face whose rest centroid is nearest the mean vertex (ties: the lowest index).
int central_face(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F) {
  const Eigen::RowVector2d center = plate.colwise().mean();
  int best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector2d c = (plate.row(F(f, 0)) + plate.row(F(f, 1)) + plate.row(F(f, 2))) / 3;
    const double d = (c - center).squaredNorm();
    if (d < best_distance) {
      best_distance = d;
      best = f;
    }
  }
  return best;
}

// The rotation whose rows are the frame of triangle (p0, p1, p2): first edge, in-plane normal to
// it, face normal. Applied to x − p0 it puts p0 at the origin, p1 on +x and p2 in the xy plane.
Eigen::Matrix3d face_frame(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                           const Eigen::Vector3d& p2) {
  const Eigen::Vector3d e1 = (p1 - p0).normalized();
  const Eigen::Vector3d e3 = (p1 - p0).cross(p2 - p0).normalized();
  Eigen::Matrix3d frame;
  frame.row(0) = e1.transpose();
  frame.row(1) = e3.cross(e1).transpose();
  frame.row(2) = e3.transpose();
  return frame;
}

}  // namespace

SimulationResult simulate(const PlateProblem& problem, const Eigen::MatrixXd& start,
                          const SimulationOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const int nv = static_cast<int>(problem.plate.rows());
  if (start.rows() != nv || start.cols() != 3) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("the start shape has {} x {} coordinates but the plate has {} "
                                "vertices: give one 3D position per plate vertex, in order",
                                start.rows(), start.cols(), nv));
  }
  if (!start.allFinite()) {
    throw UserError(ErrorCategory::kGeometry,
                    "the start shape has NaN or infinite coordinates: fix the input mesh");
  }
  const PlateEnergy energy =
      make_plate_energy(problem.plate, problem.F, problem.rest_forms, problem.stiffness);

  // 3-2-1 frame on the central face.
  const int f = central_face(problem.plate, problem.F);
  const int v0 = problem.F(f, 0), v1 = problem.F(f, 1), v2 = problem.F(f, 2);
  const Eigen::Vector3d origin = start.row(v0).transpose();
  const Eigen::Matrix3d frame =
      face_frame(origin, start.row(v1).transpose(), start.row(v2).transpose());
  if (!frame.allFinite()) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("the start shape's face {} (the plate's central face) is "
                                "degenerate: give a start shape without zero-area triangles",
                                f));
  }
  Eigen::VectorXd x0(3 * nv);
  for (int v = 0; v < nv; ++v) {
    x0.segment<3>(3 * v) = frame * (start.row(v).transpose() - origin);
  }
  // The fixed coordinates are exactly 0 in this frame.
  x0.segment<3>(3 * v0).setZero();
  x0.segment<2>(3 * v1 + 1).setZero();
  x0(3 * v2 + 2) = 0;

  double energy_scale = 0;
  for (int g = 0; g < problem.F.rows(); ++g) {
    Eigen::Matrix2d edges;
    edges << (problem.plate.row(problem.F(g, 1)) - problem.plate.row(problem.F(g, 0))).transpose(),
        (problem.plate.row(problem.F(g, 2)) - problem.plate.row(problem.F(g, 0))).transpose();
    energy_scale += 0.5 * edges.determinant() * problem.rest_forms.thickness(g);
  }
  energy_scale *= problem.stiffness.young_modulus_along;

  NewtonProblem newton;
  newton.num_variables = 3 * nv;
  newton.evaluate = [&energy](const Eigen::VectorXd& x, Eigen::VectorXd* g,
                              Eigen::SparseMatrix<double>* h, bool project) {
    return evaluate_plate_energy(energy, x, g, h, project);
  };
  newton.fixed_variables = {3 * v0, 3 * v0 + 1, 3 * v0 + 2, 3 * v1 + 1, 3 * v1 + 2, 3 * v2 + 2};
  NewtonOptions newton_options;
  newton_options.max_iterations = options.max_iterations;
  newton_options.tolerance = options.relative_tolerance * energy_scale;
  const NewtonResult r = newton_minimize(newton, x0, newton_options);

  SimulationResult out;
  out.V.resize(nv, 3);
  for (int v = 0; v < nv; ++v) {
    out.V.row(v) = (frame.transpose() * r.x.segment<3>(3 * v) + origin).transpose();
  }
  out.energy = r.energy;
  const Eigen::Vector2d terms = plate_energy_terms(energy, r.x);
  out.membrane_energy = terms(0);
  out.bending_energy = terms(1);
  out.iterations = r.iterations;
  out.projected_iterations = r.projected_iterations;
  out.converged = r.converged();
  out.status = r.status;
  out.assembly_seconds = r.assembly_seconds;
  out.factorization_seconds = r.factorization_seconds;
  out.solve_seconds = r.solve_seconds;
  out.line_search_seconds = r.line_search_seconds;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

Eigen::MatrixXd flat_start(const PlateProblem& problem) {
  const Eigen::MatrixXd& p = problem.plate;
  Eigen::Matrix2d mean_curvature = Eigen::Matrix2d::Zero();
  double total_area = 0;
  for (int f = 0; f < problem.F.rows(); ++f) {
    Eigen::Matrix2d edges;
    edges << (p.row(problem.F(f, 1)) - p.row(problem.F(f, 0))).transpose(),
        (p.row(problem.F(f, 2)) - p.row(problem.F(f, 0))).transpose();
    const double area = 0.5 * std::abs(edges.determinant());
    mean_curvature += area * problem.rest_forms.rest_second_fundamental_form[f];
    total_area += area;
  }
  if (total_area > 0) mean_curvature /= total_area;
  const Eigen::RowVector2d center = p.colwise().mean();
  const double kAmplitude = 0.01;  // a nudge, not a guess of the shape
  Eigen::MatrixXd start = Eigen::MatrixXd::Zero(p.rows(), 3);
  start.leftCols(2) = p;
  for (Eigen::Index v = 0; v < p.rows(); ++v) {
    const Eigen::Vector2d d = (p.row(v) - center).transpose();
    start(v, 2) = 0.5 * kAmplitude * d.dot(mean_curvature * d);
  }
  return start;
}

ForwardComparison simulate_from_start_and_flat(const PlateProblem& problem,
                                               const Eigen::MatrixXd& start,
                                               const SimulationOptions& options,
                                               double tolerance_percent) {
  ForwardComparison c;
  c.from_start = simulate(problem, start, options);
  c.from_flat = simulate(problem, flat_start(problem), options);
  const Eigen::MatrixXd aligned = rigidly_aligned(c.from_flat.V, c.from_start.V);
  const ShapeDistance d = shape_distance(aligned, c.from_start.V);
  c.max_difference_mm = d.max_mm;
  c.max_difference_percent = d.max_percent;
  c.multistable = d.max_percent > tolerance_percent;
  return c;
}

}  // namespace flatmorph
