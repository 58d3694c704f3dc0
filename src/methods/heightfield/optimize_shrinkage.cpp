#include "methods/heightfield/optimize_shrinkage.h"

#include <fmt/core.h>

#include <stdexcept>
#include <string>

#include "common/error.h"
#include "methods/heightfield/shrinkage_field.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "simulate/adjoint_design.h"
#include "simulate/distance.h"

namespace flatmorph {
namespace {

// dλ1/dh of the curve (1/mm) at layer height h (mm).
double curve_slope(const ThicknessCurve& curve, double h) {
  double slope = 0, power = 1;
  for (size_t i = 1; i < curve.lambda1_coefficients.size(); ++i) {
    slope += static_cast<double>(i) * curve.lambda1_coefficients[i] * power;
    power *= h;
  }
  return slope;
}

// Throws UserError without a thickness curve or with a negative weight, std::invalid_argument on
// sizes that differ.
void check_shrinkage_problem(const ShrinkageProblem& problem,
                             const OptimizeShrinkageOptions& options) {
  require_thickness_curve(problem.material);
  const int nv = static_cast<int>(problem.plate.rows());
  const int nf = static_cast<int>(problem.F.rows());
  if (problem.target.rows() != nv || problem.target.cols() != 3 || problem.direction.size() != nf ||
      problem.plate.cols() != 2 ||
      (problem.start.size() != 0 && (problem.start.rows() != nv || problem.start.cols() != 3))) {
    throw std::invalid_argument(
        fmt::format("shrink optimization: a target of {} x {}, {} directions and a start of {} "
                    "x {} for a plate of {} vertices and {} faces: give one 3D position per "
                    "vertex and one direction per face",
                    problem.target.rows(), problem.target.cols(), problem.direction.size(),
                    problem.start.rows(), problem.start.cols(), nv, nf));
  }
  if (!(options.w_L >= 0)) {
    throw UserError(ErrorCategory::kOption, "shrink optimization: w_L must be non-negative");
  }
}

// σ as the shared solver's design variable: each face prints the mean of its corners' σ at the
// curve's layer height, λ1 = 1 − σ (thickness_controlled_layer_stack), so the laminate's
// derivative moves every layer's λ1 at dλ1/dσ = −1 and its printed thickness at
// dh/dσ = −1 / λ1'(h), the thickness curve's slope at the face's layer height. σ stays within the
// curve's reachable range [least, most], and the first equilibrium may start anywhere.
AdjointDesignProblem shrinkage_design_problem(const ShrinkageProblem& problem) {
  const ThicknessCurve& curve = require_thickness_curve(problem.material);
  const auto [least, most] = reachable_shrinkage(curve);
  const int nv = static_cast<int>(problem.plate.rows());
  AdjointDesignProblem design;
  design.plate = problem.plate;
  design.F = problem.F;
  design.target = problem.target;
  design.layer_stack =
      [&problem, average = face_average_matrix(problem.F, nv)](const Eigen::VectorXd& sigma) {
        // Within the range (the optimizer projects), so nothing is clamped and λ1 = 1 − σ exactly.
        return thickness_controlled_layer_stack(problem.direction, average * sigma,
                                                problem.material, problem.num_layers)
            .stack;
      };
  design.laminate_derivative = [&curve](const LayerStack& stack) {
    const int nf = stack.num_faces();
    LayerShrinkRates rates;
    Eigen::VectorXd thickness_rate(nf);
    const Eigen::VectorXd& height = stack.layers.front().printed_thickness;
    for (int f = 0; f < nf; ++f) thickness_rate(f) = -1.0 / curve_slope(curve, height(f));
    for (int k = 0; k < stack.num_layers(); ++k) {
      rates.lambda1.push_back(Eigen::VectorXd::Constant(nf, -1.0));
      rates.printed_thickness.push_back(thickness_rate);
    }
    LaminateDerivative derivative;
    laminate(stack, rates, derivative);
    return derivative;
  };
  design.reference_variables = Eigen::VectorXd::Constant(nv, 0.5 * (least + most));
  // A vertex within 1e-12 of a bound is held there.
  design.bounds = {least, most, least + 1e-12, most - 1e-12};
  design.start = problem.start;
  return design;
}

// The smoothness term w_L (σ/Δ)ᵀ L (σ/Δ), Δ the width of the reachable range (so that σ/Δ is
// dimensionless and of order 1), the distance after the best rigid motion, and the budget.
AdjointDesignOptions shrinkage_design_options(const ShrinkageProblem& problem,
                                              const OptimizeShrinkageOptions& options) {
  const auto [least, most] = reachable_shrinkage(require_thickness_curve(problem.material));
  const double range = most - least;
  AdjointDesignOptions design;
  design.laplacian_weight = options.w_L / (range * range);
  design.best_rigid_motion = true;
  design.start_anywhere = true;
  design.require_initial_equilibrium = true;
  design.max_iterations = options.max_iterations;
  design.max_forward_iterations = options.max_forward_iterations;
  design.decrement_tolerance = options.decrement_tolerance;
  design.relative_decrease = options.relative_decrease;
  design.max_cg_iterations = options.max_cg_iterations;
  design.cg_tolerance = options.cg_tolerance;
  design.armijo_constant = options.armijo_constant;
  design.max_line_search_steps = options.max_line_search_steps;
  design.max_step = options.max_step;
  design.min_step = options.min_step;
  design.max_trial_forward_iterations = options.max_trial_forward_iterations;
  design.forward = options.forward;
  return design;
}

ShrinkageIteration shrinkage_iteration(const AdjointIteration& record) {
  ShrinkageIteration it;
  it.iteration = record.iteration;
  it.objective = record.objective;
  it.distance_term = record.distance_term;
  it.step = record.step;
  it.decrement = record.decrement;
  it.cg_iterations = record.cg_iterations;
  it.forward_iterations = record.forward_iterations;
  it.line_search_trials = record.line_search_trials;
  it.vertices_at_bound = record.vertices_at_bound;
  it.elapsed_seconds = record.elapsed_seconds;
  return it;
}

std::string shrinkage_stop_reason(const AdjointDesignResult& result,
                                  const OptimizeShrinkageOptions& options) {
  switch (result.stop) {
    case AdjointStop::kIterationLimit:
      return fmt::format(
          "stopped after {} iterations while still improving; the best shrinkage found is used",
          options.max_iterations);
    case AdjointStop::kNoInitialEquilibrium:
      return fmt::format(
          "the risen shape of the starting shrinkage was not found ({}), so it is kept "
          "unoptimized; a printing graph without needle triangles (edges far shorter than their "
          "neighbours) usually simulates",
          result.initial_forward_warning.empty()
              ? std::string(to_string(result.initial_forward_status))
              : result.initial_forward_warning);
    case AdjointStop::kUnstable:
      return "the risen shape is not a stable equilibrium (its Hessian cannot be factorized, even "
             "shifted), so no step can be computed; the best shrinkage found is used";
    case AdjointStop::kNotFinite:
      return "the distance or its gradient became NaN or infinite, so the last finite shrinkage "
             "is used; check the material's thickness curve and shrink ratios";
    case AdjointStop::kStationary:
      return "no descent direction (a stationary point within the reachable range)";
    case AdjointStop::kStalled:
      return fmt::format(
          "stalled: every step changing σ by more than {:g} left the equilibrium branch or moved "
          "away from the target; the best shrinkage found is used",
          options.min_step);
    case AdjointStop::kNoDecrease:
      return fmt::format(
          "no step lowered the distance in {} halvings; the best shrinkage found is used",
          options.max_line_search_steps);
    case AdjointStop::kBudgetInLineSearch:
      return fmt::format(
          "the budget of {} Newton iterations of forward solves ran out in a line search; the "
          "best shrinkage found is used",
          options.max_forward_iterations);
    case AdjointStop::kBudgetAfterStep:
      return fmt::format(
          "stopped after {} Newton iterations of forward solves (the budget) while still "
          "improving; the best shrinkage found is used",
          result.forward_iterations);
    default:  // the other converged stops
      return std::string(to_string(result.stop));
  }
}

}  // namespace

Eigen::VectorXd initial_vertex_shrinkage(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                         const Eigen::VectorXd& edge_shrinkage,
                                         const Material& material) {
  const auto [least, most] = reachable_shrinkage(require_thickness_curve(material));
  return vertex_shrinkage(mesh, plate, edge_shrinkage).cwiseMax(least).cwiseMin(most);
}

ShrinkageEvaluation evaluate_shrinkage_objective(const ShrinkageProblem& problem,
                                                 const Eigen::VectorXd& vertex_shrinkage,
                                                 const Eigen::MatrixXd& start,
                                                 const OptimizeShrinkageOptions& options,
                                                 bool with_gradient) {
  check_shrinkage_problem(problem, options);
  const AdjointDesignProblem design = shrinkage_design_problem(problem);
  if (vertex_shrinkage.size() != problem.plate.rows()) {
    throw std::invalid_argument(fmt::format("{} shrinkages for {} vertices: give one per vertex",
                                            vertex_shrinkage.size(), problem.plate.rows()));
  }
  const AdjointEvaluation evaluation = evaluate_adjoint_design(
      design, vertex_shrinkage, start, shrinkage_design_options(problem, options), with_gradient);
  ShrinkageEvaluation out;
  out.objective = evaluation.objective;
  out.distance_term = evaluation.distance_term;
  out.gradient = evaluation.gradient;
  out.V = evaluation.V;
  out.forward_converged = evaluation.forward_converged;
  return out;
}

ShrinkageResult optimize_shrinkage(const ShrinkageProblem& problem,
                                   const Eigen::VectorXd& vertex_shrinkage_start,
                                   const OptimizeShrinkageOptions& options) {
  check_shrinkage_problem(problem, options);
  const int nv = static_cast<int>(problem.plate.rows());
  if (vertex_shrinkage_start.size() != nv) {
    throw std::invalid_argument(
        fmt::format("{} starting shrinkages for {} vertices: give one per vertex",
                    vertex_shrinkage_start.size(), nv));
  }
  AdjointDesignOptions design_options = shrinkage_design_options(problem, options);
  if (options.progress) {
    design_options.progress = [&options](const AdjointIteration& record) {
      options.progress(shrinkage_iteration(record));
    };
  }
  const AdjointDesignResult r = optimize_adjoint_design(shrinkage_design_problem(problem),
                                                        vertex_shrinkage_start, design_options);

  ShrinkageResult out;
  out.vertex_shrinkage = r.variables;
  out.face_shrinkage = vertex_to_face_average(problem.F, r.variables);
  // Moved by the best rigid motion, as the prediction reports them.
  out.V = rigidly_aligned(r.V, problem.target);
  out.initial_V = rigidly_aligned(r.initial_V, problem.target);
  out.objective = r.objective;
  out.initial_objective = r.initial_objective;
  out.distance_term = r.distance_term;
  out.initial_distance_term = r.initial_distance_term;
  out.iterations = r.iterations;
  out.converged = r.converged;
  out.stop_reason = shrinkage_stop_reason(r, options);
  for (const AdjointIteration& record : r.history) {
    out.history.push_back(shrinkage_iteration(record));
  }
  out.seconds = r.seconds;
  out.initial_seconds = r.initial_seconds;
  out.forward_seconds = r.forward_seconds;
  out.cg_seconds = r.cg_seconds;
  out.initial_forward_converged = r.initial_forward_converged;
  out.shifted_factorizations = r.shifted_factorizations;
  out.vertices_at_bound = r.vertices_at_bound;
  return out;
}

}  // namespace flatmorph
