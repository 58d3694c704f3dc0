#include "simulate/simulate.h"

#include <fmt/core.h>

#include <Eigen/LU>
#include <cmath>

#include "common/error.h"
#include "common/stopwatch.h"
#include "simulate/distance.h"
#include "simulate/rigid_frame.h"

namespace flatmorph {

namespace {

// Along one direction a face's membrane energy is ∝ (μ − 1)² in its squared stretch μ = s² relative
// to the rest metric, whose second derivative in s, 4 (3 s² − 1), is negative below μ = 1/3: a face
// squeezed past that softens, and one squeezed much further collapses (on the 80 mm radial disk
// solved at once, μ went 0.31, 0.16, 0.002 in three iterations). A collapsed face lets its
// neighbours fold over it at no bending cost (φ_e = θ_e 2A/ℓ_e vanishes with its area A): the plate
// creases instead of bending, and Newton crawls along the folds with steps of 1e-4 to 1e-14. Sound
// equilibria do squeeze faces past 1/3 (a disk of concentric paths to 0.31), not to a tenth.
constexpr double kCollapsedRatio = 0.1;
// A solve is abandoned when a face stays collapsed this many states in a row: a Newton step that
// overshoots through a collapse opens it again at once (the paper's hat from flat, for two states,
// then converges as it always did).
constexpr int kCollapsedStates = 3;
// The smallest part of the stimulus one step applies while steps are halved; a step this small
// goes on even if a face collapses (the plate then creases: the equilibrium has folds).
constexpr double kSmallestStimulusStep = 1.0 / 8;

// The rest forms `fraction` of the way from the start shape's own forms to the plate's (the
// stiffness stays the plate's).
void blend_rest_forms(const std::vector<Vector6d>& start_forms, const RestForms& full,
                      double fraction, RestForms& out) {
  for (size_t f = 0; f < start_forms.size(); ++f) {
    const Vector6d rest = (1 - fraction) * start_forms[f] +
                          fraction * rest_vector(full.rest_first_fundamental_form[f],
                                                 full.rest_second_fundamental_form[f]);
    out.rest_first_fundamental_form[f] << rest(0), rest(2), rest(2), rest(1);
    out.rest_second_fundamental_form[f] << rest(3), rest(5), rest(5), rest(4);
  }
}

}  // namespace

SimulationResult simulate(const PlateProblem& problem, const Eigen::MatrixXd& start,
                          const SimulationOptions& options) {
  const auto t0 = Clock::now();
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
  PlateEnergy energy = make_plate_energy(problem.plate, problem.F, problem.rest_forms);

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
  newton_options.tolerance =
      options.relative_tolerance * unit_strain_energy(problem.plate, problem.F, problem.rest_forms);

  SimulationResult out;
  // One Newton solve within what is left of both budgets; `guarded`: abandoned (kStopped) once a
  // face stays collapsed.
  auto solve = [&](const Eigen::VectorXd& from, bool guarded) {
    newton_options.max_iterations = options.max_iterations - out.iterations;
    newton_options.max_seconds = options.max_seconds - seconds_since(t0);
    newton.stop_at = nullptr;
    if (guarded) {
      newton.stop_at = [&energy, in_a_row = 0](const Eigen::VectorXd& x) mutable {
        in_a_row = smallest_metric_ratio(energy, x) < kCollapsedRatio ? in_a_row + 1 : 0;
        return in_a_row >= kCollapsedStates;
      };
    }
    NewtonResult r = newton_minimize(newton, from, newton_options);
    out.iterations += r.iterations;
    out.projected_iterations += r.projected_iterations;
    out.assembly_seconds += r.assembly_seconds;
    out.factorization_seconds += r.factorization_seconds;
    out.solve_seconds += r.solve_seconds;
    out.line_search_seconds += r.line_search_seconds;
    if (r.status == NewtonStatus::kTimeLimit) {
      // Newton's own sentence names what was left of the budget for its call.
      r.warning = fmt::format(
          "the simulation reached its time budget of {:.3g} s after {} Newton iterations; the "
          "best state found is used; allow it more time, or use a finer mesh (more faces), a "
          "smaller plate width, or shrink ratios (lambda) closer to 1",
          options.max_seconds, out.iterations);
    }
    return r;
  };

  NewtonResult r = solve(x0, true);
  if (r.status == NewtonStatus::kStopped) {
    // In steps from the start shape's own forms, at which it has zero energy. Each step starts
    // from the last equilibrium extrapolated along the last two (a secant: a quarter fewer Newton
    // iterations on the radial disks). A step in which a face stays collapsed is tried again at
    // half its size; one that goes through lets the next be twice as large.
    const std::vector<Vector6d> start_forms = plate_forms(energy, x0);
    RestForms forms = problem.rest_forms;
    Eigen::VectorXd x = x0, previous = x0;  // the last two equilibria
    double applied = 0, previous_applied = 0, step = 0.5;
    out.stimulus_steps = 0;
    while (applied < 1) {
      const double next = std::min(1.0, applied + step);
      blend_rest_forms(start_forms, problem.rest_forms, next, forms);
      set_rest_forms(energy, forms);
      Eigen::VectorXd guess = x;
      if (applied > 0) guess += (next - applied) / (applied - previous_applied) * (x - previous);
      r = solve(guess, step > kSmallestStimulusStep);
      if (r.status == NewtonStatus::kStopped) {
        step = (next - applied) / 2;
        continue;
      }
      if (!r.converged()) {
        // Out of budget before its first iteration, the extrapolated guess may not even be a
        // state of finite energy: the last equilibrium is then the best one.
        if (!std::isfinite(r.energy)) r.x = x;
        break;
      }
      previous = x;
      previous_applied = applied;
      x = r.x;
      applied = next;
      ++out.stimulus_steps;
      step = std::min(2 * step, 1 - applied);
    }
    if (applied < 1) {
      set_rest_forms(energy, problem.rest_forms);
      r.energy = evaluate_plate_energy(energy, r.x, nullptr, nullptr, false);
      r.warning +=
          fmt::format(" (the stimulus was being applied in steps, {:.0f} % of it in {} steps)",
                      100 * applied, out.stimulus_steps);
    }
  }

  out.V = from_frame(frame, r.x);
  out.energy = r.energy;
  const Eigen::Vector2d terms = plate_energy_terms(energy, r.x);
  out.membrane_energy = terms(0);
  out.bending_energy = terms(1);
  out.converged = r.converged();
  out.status = r.status;
  out.warning = r.warning;
  out.seconds = seconds_since(t0);
  return out;
}

std::string stop_reason(const SimulationResult& result) {
  if (result.converged) return "converged";
  return result.warning.empty() ? std::string(to_string(result.status)) : result.warning;
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
