#include "simulate/simulate.h"

#include <fmt/core.h>

#include <Eigen/LU>
#include <chrono>

#include "common/error.h"
#include "simulate/distance.h"
#include "simulate/rigid_frame.h"

namespace flatmorph {

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
      make_plate_energy(problem.plate, problem.F, problem.rest_forms);

  const RigidFrame frame = central_face_frame(problem.plate, problem.F, start, "the start shape");
  const Eigen::VectorXd x0 = to_frame(frame, start);

  NewtonProblem newton;
  newton.num_variables = 3 * nv;
  newton.evaluate = [&energy](const Eigen::VectorXd& x, Eigen::VectorXd* g,
                              Eigen::SparseMatrix<double>* h, bool project) {
    return evaluate_plate_energy(energy, x, g, h, project);
  };
  newton.fixed_variables = frame.fixed_variables;
  NewtonOptions newton_options;
  newton_options.max_iterations = options.max_iterations;
  newton_options.tolerance =
      options.relative_tolerance *
      unit_strain_energy(problem.plate, problem.F, problem.rest_forms);
  const NewtonResult r = newton_minimize(newton, x0, newton_options);

  SimulationResult out;
  out.V = from_frame(frame, r.x);
  out.energy = r.energy;
  const Eigen::Vector2d terms = plate_energy_terms(energy, r.x);
  out.membrane_energy = terms(0);
  out.bending_energy = terms(1);
  out.iterations = r.iterations;
  out.projected_iterations = r.projected_iterations;
  out.converged = r.converged();
  out.status = r.status;
  out.warning = r.warning;
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
