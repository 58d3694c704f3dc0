#include "methods/shrink_morph/optimize_theta2.h"

#include <tbb/parallel_for.h>

#include <fmt/core.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/error.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "simulate/adjoint_design.h"

namespace flatmorph {
namespace {

void check_theta2_problem(const Theta2Problem& problem, const OptimizeTheta2Options& options) {
  const int nv = static_cast<int>(problem.plate.rows());
  const int nf = static_cast<int>(problem.F.rows());
  if (problem.target.rows() != nv || problem.target.cols() != 3 || problem.theta1.size() != nf) {
    throw std::invalid_argument(
        fmt::format("theta2 optimization: the target has {} x {} coordinates and "
                    "theta1 {} values for a plate of {} vertices and {} faces: give "
                    "one 3D position per vertex and one theta1 per face",
                    problem.target.rows(), problem.target.cols(), problem.theta1.size(), nv, nf));
  }
  if (!(options.w_M >= 0) || !(options.w_L >= 0)) {
    throw UserError(ErrorCategory::kOption,
                    "theta2 optimization: w_M and w_L must be non-negative");
  }
  if (!(options.path_error_rad >= 0 && options.path_error_rad < 1) ||
      options.path_error_samples < 0 || options.path_error_smoothing_passes < 0) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("theta2 optimization: a path error of {} rad in {} samples "
                                "smoothed {} times: give 0 to 1 rad (0: none), 0 or more samples "
                                "and 0 or more passes",
                                options.path_error_rad, options.path_error_samples,
                                options.path_error_smoothing_passes));
  }
}

// θ2 as the shared solver's design variable: each face prints the mean of its corners', and
// layer k of the stack turns by w_k θ2 (the stack builder's weights, plate/layer_stack.h), so the
// laminate's derivative turns each layer at the rate w_k.
// Per face and layer, seeded Gaussian angle errors of `rms` rad: one printing of the paths. With
// smoothing passes (each the mean over a face's corners of their faces' means) the errors are
// correlated over neighbouring faces, as a stripe pattern's drift is, then scaled back to `rms`.
Eigen::MatrixXd path_angle_errors(const Eigen::MatrixXi& F, int num_vertices, int num_layers,
                                  double rms, int smoothing_passes, int sample) {
  std::mt19937_64 random(0x5eed0000 + sample);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd errors(F.rows(), num_layers);
  for (int k = 0; k < num_layers; ++k) {
    for (int f = 0; f < F.rows(); ++f) errors(f, k) = normal(random);
  }
  if (smoothing_passes > 0) {
    const Eigen::SparseMatrix<double> to_faces = face_average_matrix(F, num_vertices);
    Eigen::SparseMatrix<double> to_vertices = to_faces.transpose();
    const Eigen::VectorXd count = to_vertices * Eigen::VectorXd::Ones(F.rows());
    to_vertices = count.cwiseInverse().asDiagonal() * to_vertices;
    for (int pass = 0; pass < smoothing_passes; ++pass) errors = to_faces * (to_vertices * errors);
  }
  const double current = std::sqrt(errors.squaredNorm() / static_cast<double>(errors.size()));
  return current > 0 ? Eigen::MatrixXd(errors * (rms / current)) : errors;
}

AdjointDesignProblem theta2_design_problem(const Theta2Problem& problem,
                                           const OptimizeTheta2Options& options) {
  AdjointDesignProblem design;
  design.plate = problem.plate;
  design.F = problem.F;
  design.target = problem.target;
  design.layer_stack = [&problem](const Eigen::VectorXd& theta2) {
    return theta2_layer_stack(problem, theta2);
  };
  std::vector<double> rates;
  for (int k = 1; k <= problem.num_layers; ++k) {
    rates.push_back(shrink_morph_layer_weight(k, problem.num_layers));
  }
  design.laminate_derivative = [rates](const LayerStack& stack) {
    LaminateDerivative derivative;
    laminate(stack, rates, derivative);
    return derivative;
  };
  design.reference_variables = Eigen::VectorXd::Zero(problem.plate.rows());
  design.start = problem.start;
  if (options.path_error_rad > 0) {
    for (int sample = 0; sample < options.path_error_samples; ++sample) {
      auto errors = std::make_shared<const Eigen::MatrixXd>(
          path_angle_errors(problem.F, static_cast<int>(problem.plate.rows()), problem.num_layers,
                            options.path_error_rad, options.path_error_smoothing_passes, sample));
      design.perturbations.push_back([errors](LayerStack& stack) {
        for (int k = 0; k < stack.num_layers(); ++k) stack.layers[k].theta += errors->col(k);
      });
    }
  }
  return design;
}

// Eq. 13's regularizer (w_M, w_L) and the optimization's settings; starts are registered to the
// target, and the distance is taken as registered (by the 3-2-1 frame).
AdjointDesignOptions theta2_design_options(const OptimizeTheta2Options& options) {
  AdjointDesignOptions design;
  design.mass_weight = options.w_M;
  design.laplacian_weight = options.w_L;
  design.max_iterations = options.max_iterations;
  design.decrement_tolerance = options.decrement_tolerance;
  design.relative_decrease = options.relative_decrease;
  design.max_cg_iterations = options.max_cg_iterations;
  design.cg_tolerance = options.cg_tolerance;
  design.armijo_constant = options.armijo_constant;
  design.max_line_search_steps = options.max_line_search_steps;
  design.max_step = options.max_step_rad;
  design.min_step = options.min_step_rad;
  design.max_trial_forward_iterations = options.max_trial_forward_iterations;
  design.max_forward_iterations = options.max_forward_iterations;
  design.forward = options.forward;
  return design;
}

Theta2Iteration theta2_iteration(const AdjointIteration& record) {
  Theta2Iteration it;
  it.iteration = record.iteration;
  it.objective = record.objective;
  it.distance_term = record.distance_term;
  it.step = record.step;
  it.decrement = record.decrement;
  it.cg_iterations = record.cg_iterations;
  it.forward_iterations = record.forward_iterations;
  it.line_search_trials = record.line_search_trials;
  it.shifted_hessian = record.shifted_hessian;
  it.elapsed_seconds = record.elapsed_seconds;
  return it;
}

// An iteration that failed before its Gauss–Newton step is not reported: progress reads a record
// without line-search trials as the converged one (design.cpp).
bool theta2_progress_reports(const AdjointIteration& record) {
  return record.stop != AdjointStop::kUnstable && record.stop != AdjointStop::kNotFinite;
}

std::string theta2_stop_reason(AdjointStop stop, const OptimizeTheta2Options& options) {
  switch (stop) {
    case AdjointStop::kIterationLimit:
      return fmt::format(
          "stopped after {} iterations while still improving; the best theta2 found is used, and "
          "a coarser design mesh (--faces) gets further in as many iterations",
          options.max_iterations);
    case AdjointStop::kUnstable:
      return "the plate's equilibrium is not stable (its Hessian cannot be factorized, even "
             "shifted), so no step can be computed; the best theta2 found is used, and a finer "
             "mesh (--faces) or a smaller --width usually helps";
    case AdjointStop::kNotFinite:
      return "the distance or its gradient became NaN or infinite, so the last finite theta2 is "
             "used; check the material's shrink ratios (flatmorph materials) or use a finer mesh "
             "(--faces)";
    case AdjointStop::kStalled:
      // At a fold of the equilibrium branch, the shapes closer to the target lie beyond it.
      return fmt::format(
          "stalled at a fold of the plate's equilibrium branch: every step longer than {:g} rad "
          "left it or moved away from the target, so the best theta2 found is used; printing "
          "the other side up (--side) or a finer mesh (--faces) may get past it",
          options.min_step_rad);
    case AdjointStop::kNoDecrease:
      return fmt::format(
          "no step lowered the distance in {} halvings, so the best theta2 found is used; "
          "stronger regularization (--wM, --wL) makes the problem smoother",
          options.max_line_search_steps);
    default:  // the converged stops; θ2 has neither a work budget nor a required first equilibrium
      return std::string(to_string(stop));
  }
}

}  // namespace

Theta2Problem theta2_problem(const FlatPlate& flat, const Material& material, int num_layers) {
  Theta2Problem problem;
  problem.plate = flat.plate;
  problem.F = flat.target.F;
  problem.target = flat.target.V;
  problem.theta1 = flat.theta1;
  problem.material = material;
  problem.num_layers = num_layers;
  return problem;
}

LayerStack theta2_layer_stack(const Theta2Problem& problem, const Eigen::VectorXd& theta2) {
  return shrink_morph_layer_stack(problem.theta1, vertex_to_face_average(problem.F, theta2),
                                  problem.material, problem.num_layers,
                                  problem.material.layer_height);
}

PlateProblem theta2_plate_problem(const Theta2Problem& problem, const Eigen::VectorXd& theta2) {
  PlateProblem plate;
  plate.plate = problem.plate;
  plate.F = problem.F;
  plate.rest_forms = laminate(theta2_layer_stack(problem, theta2));
  return plate;
}

std::vector<Eigen::MatrixXd> theta2_equilibria_under_path_errors(const Theta2Problem& problem,
                                                                 const Eigen::VectorXd& theta2,
                                                                 const PathErrorModel& model,
                                                                 const SimulationOptions& forward,
                                                                 const Eigen::MatrixXd& start) {
  const LayerStack nominal = theta2_layer_stack(problem, theta2);
  std::vector<Eigen::MatrixXd> equilibria(std::max(model.samples, 0));
  // The samples share nothing (their seeds are their indices): one per core, the same bits.
  tbb::parallel_for(0, static_cast<int>(equilibria.size()), [&](int i) {
    LayerStack stack = nominal;
    const Eigen::MatrixXd errors =
        path_angle_errors(problem.F, static_cast<int>(problem.plate.rows()), stack.num_layers(),
                          model.rms_rad, model.smoothing_passes, model.first_sample + i);
    for (int k = 0; k < stack.num_layers(); ++k) stack.layers[k].theta += errors.col(k);
    const PlateProblem plate{problem.plate, problem.F, laminate(stack)};
    equilibria[i] = simulate(plate, start.size() ? start : problem.target, forward).V;
  });
  return equilibria;
}

Theta2Evaluation evaluate_theta2_objective(const Theta2Problem& problem,
                                           const Eigen::VectorXd& theta2,
                                           const Eigen::MatrixXd& start,
                                           const OptimizeTheta2Options& options,
                                           bool with_gradient) {
  check_theta2_problem(problem, options);
  const AdjointEvaluation evaluation =
      evaluate_adjoint_design(theta2_design_problem(problem, options), theta2, start,
                              theta2_design_options(options), with_gradient);
  Theta2Evaluation out;
  out.objective = evaluation.objective;
  out.gradient = evaluation.gradient;
  out.V = evaluation.V;
  out.forward_converged = evaluation.forward_converged;
  return out;
}

Theta2Result optimize_theta2(const Theta2Problem& problem, const Eigen::VectorXd& theta2_start,
                             const OptimizeTheta2Options& options) {
  check_theta2_problem(problem, options);
  const int nv = static_cast<int>(problem.plate.rows());
  const Eigen::VectorXd theta2 =
      theta2_start.size() == 0 ? Eigen::VectorXd::Zero(nv) : Eigen::VectorXd(theta2_start);
  if (theta2.size() != nv) {
    throw std::invalid_argument(fmt::format(
        "theta2 start has {} values for {} vertices: give one per vertex", theta2.size(), nv));
  }
  const double bound = options.max_abs_theta2.value_or(kShrinkMorphTheta2Bound);
  if (!(bound > 0)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("theta2 bound {} rad: give a positive bound", bound));
  }
  AdjointDesignProblem design = theta2_design_problem(problem, options);
  // A vertex within a relative 1e-12 of ±bound is held there.
  design.bounds = {-bound, bound, -(bound * (1 - 1e-12)), bound * (1 - 1e-12)};
  AdjointDesignOptions design_options = theta2_design_options(options);
  if (options.progress) {
    design_options.progress = [&options](const AdjointIteration& record) {
      if (theta2_progress_reports(record)) options.progress(theta2_iteration(record));
    };
  }
  const AdjointDesignResult r = optimize_adjoint_design(design, theta2, design_options);

  Theta2Result out;
  out.theta2 = r.variables;
  out.V = r.V;
  out.initial_V = r.initial_V;
  out.objective = r.objective;
  out.initial_objective = r.initial_objective;
  out.distance_term = r.distance_term;
  out.iterations = r.iterations;
  out.converged = r.converged;
  out.stop_reason = theta2_stop_reason(r.stop, options);
  for (const AdjointIteration& record : r.history) {
    if (record.stop != AdjointStop::kUnstable) out.history.push_back(theta2_iteration(record));
  }
  out.seconds = r.seconds;
  out.initial_seconds = r.initial_seconds;
  out.cg_seconds = r.cg_seconds;
  out.forward_seconds = r.forward_seconds;
  out.initial_forward_converged = r.initial_forward_converged;
  out.initial_forward_warning = r.initial_forward_warning;
  out.shifted_factorizations = r.shifted_factorizations;
  out.theta2_bound = bound;
  out.vertices_at_bound = r.vertices_at_bound;
  return out;
}

}  // namespace flatmorph
