#include "methods/shrink_morph/optimize_theta2.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/error.h"
#include "common/stopwatch.h"
#include "mesh/operators.h"
#include "numerics/newton.h"
#include "numerics/sparse_cholesky.h"
#include "plate/laminate.h"
#include "simulate/plate_energy.h"
#include "simulate/rigid_frame.h"

namespace flatmorph {
namespace {

// Everything that stays fixed while theta2 changes, in the frame of the target's central face
// (first vertex at the origin, first edge along +x, face in the xy plane), where the 3-2-1
// constraint fixes coordinates that are exactly zero.
class Theta2Solver {
 public:
  Theta2Solver(const Theta2Problem& problem, const OptimizeTheta2Options& options)
      : options_(options) {
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
    nv_ = nv;
    problem_ = &problem;
    for (int k = 1; k <= problem.num_layers; ++k) {
      theta2_rates_.push_back(shrink_morph_layer_weight(k, problem.num_layers));
    }
    const RestForms zero = laminate(theta2_layer_stack(problem, Eigen::VectorXd::Zero(nv)));
    energy_ = make_plate_energy(problem.plate, problem.F, zero);
    newton_tolerance_ =
        options.forward.relative_tolerance * unit_strain_energy(problem.plate, problem.F, zero);
    frame_ = central_face_frame(problem.plate, problem.F, problem.target, "the target");
    target_ = flatmorph::to_frame(frame_, problem.target);

    // Normalization (docs/design.md): distance in units of 0.3 % of the bounding-box diagonal,
    // averaged over the target's area; the mass term averaged over the area.
    mass_ = lumped_mass(problem.target, problem.F);
    area_ = mass_.sum();
    const double diagonal =
        (problem.target.colwise().maxCoeff() - problem.target.colwise().minCoeff()).norm();
    const double length = 0.003 * diagonal;
    distance_weight_ = 1.0 / (area_ * length * length);
    laplacian_ = cotan_laplacian(problem.target, problem.F);

    std::vector<Eigen::Triplet<double>> triplets;
    for (int f = 0; f < nf; ++f) {
      for (int k = 0; k < 3; ++k) triplets.emplace_back(f, problem.F(f, k), 1.0 / 3);
    }
    face_average_.resize(nf, nv);
    face_average_.setFromTriplets(triplets.begin(), triplets.end());

    is_fixed_.assign(3 * nv, false);
    for (int i : frame_.fixed_variables) is_fixed_[i] = true;
    const Eigen::SparseMatrix<double>& pat = energy_.hessian_pattern;
    for (int col = 0; col < pat.outerSize(); ++col) {
      for (int k = pat.outerIndexPtr()[col]; k < pat.outerIndexPtr()[col + 1]; ++k) {
        const int row = pat.innerIndexPtr()[k];
        if (is_fixed_[row] || is_fixed_[col]) fixed_entries_.push_back({k, row == col});
      }
    }
    configure_sparse_cholesky(solver_);
  }

  Eigen::VectorXd to_frame(const Eigen::MatrixXd& V) const {
    return flatmorph::to_frame(frame_, V);
  }
  Eigen::MatrixXd from_frame(const Eigen::VectorXd& x) const {
    return flatmorph::from_frame(frame_, x);
  }

  const Eigen::VectorXd& target() const { return target_; }

  // The equilibrium for theta2 (per vertex) from `start` (in the frame).
  // Line-search trials pass `trial`: their own iteration cap.
  NewtonResult forward(const Eigen::VectorXd& theta2, Eigen::VectorXd start, bool trial = false) {
    stack_ = theta2_layer_stack(*problem_, theta2);
    set_rest_forms(energy_, laminate(stack_));
    for (int i : frame_.fixed_variables) start(i) = 0;
    NewtonProblem newton;
    newton.num_variables = 3 * nv_;
    newton.evaluate = [this](const Eigen::VectorXd& x, Eigen::VectorXd* g,
                             Eigen::SparseMatrix<double>* h, bool project) {
      return evaluate_plate_energy(energy_, x, g, h, project);
    };
    newton.fixed_variables = frame_.fixed_variables;
    NewtonOptions newton_options;
    newton_options.max_iterations =
        trial ? options_.max_trial_forward_iterations : options_.forward.max_iterations;
    newton_options.tolerance = newton_tolerance_;
    const auto t0 = Clock::now();
    NewtonResult r = newton_minimize(newton, start, newton_options, &workspace_);
    forward_seconds_ += seconds_since(t0);
    forward_x_ = r.x;
    return r;
  }

  // The three terms of E at the equilibrium x.
  Eigen::Vector3d objective_terms(const Eigen::VectorXd& x, const Eigen::VectorXd& theta2) const {
    double distance = 0;
    for (int v = 0; v < nv_; ++v) {
      distance += mass_(v) * (x.segment<3>(3 * v) - target_.segment<3>(3 * v)).squaredNorm();
    }
    return {distance_weight_ * distance,
            options_.w_M * theta2.dot(mass_.cwiseProduct(theta2)) / area_,
            options_.w_L * theta2.dot(laplacian_ * theta2)};
  }

  // Factorizes H at x (the energy's current theta2) with the fixed variables decoupled (unit
  // rows/columns), and the sensitivity right-hand side J = ∂²W/∂x∂θ2 (3V x V, fixed rows zero).
  // When x is the converged result of the last forward solve, its final Newton factorization is
  // that of H at x already, and is reused.
  bool linearize(const Eigen::VectorXd& x) {
    LaminateDerivative derivative;
    laminate(stack_, theta2_rates_, derivative);
    Eigen::SparseMatrix<double> mixed =
        rest_forms_mixed_derivative(energy_, x, derivative) * face_average_;
    mixed.prune([this](Eigen::Index row, Eigen::Index, double) { return !is_fixed_[row]; });
    sensitivity_rhs_ = mixed;
    sensitivity_rhs_t_ = mixed.transpose();
    use_forward_factorization_ = workspace_.holds_exact_factorization() && x == forward_x_;
    if (use_forward_factorization_) return true;
    Eigen::VectorXd gradient;
    evaluate_plate_energy(energy_, x, &gradient, &hessian_, false);
    double* values = hessian_.valuePtr();
    for (const auto& [k, diagonal] : fixed_entries_) values[k] = diagonal ? 1.0 : 0.0;
    if (!analyzed_) {
      analyze_pattern(solver_, hessian_);
      analyzed_ = true;
    }
    solver_.setShift(0.0);
    factorize(solver_, hessian_);
    if (solver_.info() != Eigen::Success) {
      ++shifted_factorizations_;
      // A stable equilibrium has a positive definite H; near a buckling point it is nearly
      // singular, so shift by growing multiples of its largest diagonal entry.
      const double scale = hessian_.diagonal().cwiseAbs().maxCoeff();
      for (double s = 1e-12; solver_.info() != Eigen::Success && s <= 1e-4; s *= 100) {
        solver_.setShift(s * scale);
        factorize(solver_, hessian_);
      }
      if (solver_.info() != Eigen::Success) return false;
    }
    return true;
  }

  // H⁻¹ b for b zero at the fixed variables (the result is zero there too).
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
    return use_forward_factorization_ ? workspace_.solve(b) : solver_.solve(b);
  }

  // dE/dx at x (zero at the fixed variables).
  Eigen::VectorXd distance_gradient(const Eigen::VectorXd& x) const {
    Eigen::VectorXd r(3 * nv_);
    for (int v = 0; v < nv_; ++v) {
      r.segment<3>(3 * v) =
          2 * distance_weight_ * mass_(v) * (x.segment<3>(3 * v) - target_.segment<3>(3 * v));
    }
    for (int i : frame_.fixed_variables) r(i) = 0;
    return r;
  }

  // Eq. 14 (after linearize at the equilibrium x).
  Eigen::VectorXd gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& theta2) const {
    const Eigen::VectorXd adjoint = solve(distance_gradient(x));
    return -(sensitivity_rhs_t_ * adjoint) + regularizer_product(theta2);
  }

  // (2 w_M M / A + 2 w_L L) v.
  Eigen::VectorXd regularizer_product(const Eigen::VectorXd& v) const {
    return 2 * options_.w_M / area_ * mass_.cwiseProduct(v) + 2 * options_.w_L * (laplacian_ * v);
  }

  // S v = dx/dθ2 · v = −H⁻¹ J v.
  Eigen::VectorXd sensitivity(const Eigen::VectorXd& v) const {
    return -solve(sensitivity_rhs_ * v);
  }

  // (Sᵀ 2D S + 2 w_M M / A + 2 w_L L) v, D the distance term's diagonal.
  Eigen::VectorXd gauss_newton_product(const Eigen::VectorXd& v) const {
    Eigen::VectorXd dx = sensitivity(v);
    for (int u = 0; u < nv_; ++u) dx.segment<3>(3 * u) *= 2 * distance_weight_ * mass_(u);
    for (int i : frame_.fixed_variables) dx(i) = 0;
    return -(sensitivity_rhs_t_ * solve(dx)) + regularizer_product(v);
  }

  double forward_seconds() const { return forward_seconds_; }
  int shifted_factorizations() const { return shifted_factorizations_; }

 private:
  const OptimizeTheta2Options& options_;
  int nv_ = 0;
  PlateEnergy energy_;
  const Theta2Problem* problem_ = nullptr;
  std::vector<double> theta2_rates_;  // d theta^k / d theta2 of each layer
  LayerStack stack_;                  // printed for the energy's current theta2
  double newton_tolerance_ = 0;
  RigidFrame frame_;
  std::vector<bool> is_fixed_;
  std::vector<std::pair<int, bool>> fixed_entries_;  // Hessian nonzeros in a fixed row/column
  Eigen::VectorXd target_, mass_;
  double area_ = 0, distance_weight_ = 0;
  Eigen::SparseMatrix<double> laplacian_, face_average_;
  Eigen::SparseMatrix<double> hessian_, sensitivity_rhs_, sensitivity_rhs_t_;
  SparseCholesky solver_;
  bool analyzed_ = false;
  NewtonWorkspace workspace_;
  Eigen::VectorXd forward_x_;  // the last forward solve's result
  bool use_forward_factorization_ = false;
  double forward_seconds_ = 0;
  int shifted_factorizations_ = 0;
};

// Whether a forward solve reached an equilibrium. Newton's own test is converged; a stalled line
// search counts only at the rounding limit: its last step used the exact Hessian H and predicted a
// decrease ½ gᵀH⁻¹g (the gradient's size in the H⁻¹ norm) below 1e-10 |W|, which W, a sum over
// thousands of faces, cannot resolve. A stall with a larger gradient is a failed solve (a fold of
// the equilibrium branch, a snap-through), not an equilibrium.
bool forward_ok(const NewtonResult& r) {
  if (r.status == NewtonStatus::kConverged) return true;
  if (r.status != NewtonStatus::kLineSearchFailed || r.history.empty()) return false;
  const NewtonIteration& last = r.history.back();
  return last.exact_hessian && last.decrement <= 1e-10 * std::abs(r.energy);
}

// Conjugate gradients on the SPD Gauss–Newton system A d = b, from d = 0 (so every iterate is a
// descent direction for E). Returns the iterations taken.
template <typename Product>
int conjugate_gradient(const Product& product, const Eigen::VectorXd& b, double tolerance,
                       int max_iterations, Eigen::VectorXd& d) {
  d.setZero(b.size());
  Eigen::VectorXd r = b, p = b;
  double rr = r.squaredNorm();
  const double stop = tolerance * tolerance * rr;
  int it = 0;
  for (; it < max_iterations && rr > stop; ++it) {
    const Eigen::VectorXd ap = product(p);
    const double pap = p.dot(ap);
    if (!(pap > 0)) break;
    const double alpha = rr / pap;
    d += alpha * p;
    r -= alpha * ap;
    const double rr_new = r.squaredNorm();
    p = r + (rr_new / rr) * p;
    rr = rr_new;
  }
  return it;
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

Theta2Evaluation evaluate_theta2_objective(const Theta2Problem& problem,
                                           const Eigen::VectorXd& theta2,
                                           const Eigen::MatrixXd& start,
                                           const OptimizeTheta2Options& options,
                                           bool with_gradient) {
  Theta2Solver solver(problem, options);
  const NewtonResult r = solver.forward(theta2, solver.to_frame(start));
  Theta2Evaluation out;
  out.forward_converged = forward_ok(r);
  out.objective = solver.objective_terms(r.x, theta2).sum();
  out.V = solver.from_frame(r.x);
  if (with_gradient && solver.linearize(r.x)) out.gradient = solver.gradient(r.x, theta2);
  return out;
}

Theta2Result optimize_theta2(const Theta2Problem& problem, const Eigen::VectorXd& theta2_start,
                             const OptimizeTheta2Options& options) {
  const auto t0 = Clock::now();
  Theta2Solver solver(problem, options);
  const int nv = static_cast<int>(problem.plate.rows());
  Eigen::VectorXd theta2 =
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
  auto project = [bound](Eigen::VectorXd t) { return t.cwiseMax(-bound).cwiseMin(bound); };
  theta2 = project(theta2);
  Theta2Result out;
  const NewtonResult initial = solver.forward(
      theta2, problem.start.size() ? solver.to_frame(problem.start) : solver.target());
  out.initial_forward_converged = forward_ok(initial);
  Eigen::VectorXd x = initial.x;
  out.initial_V = solver.from_frame(x);
  out.initial_seconds = seconds_since(t0);
  Eigen::Vector3d terms = solver.objective_terms(x, theta2);
  double objective = terms.sum();
  out.initial_objective = objective;
  out.stop_reason = fmt::format(
      "stopped after {} iterations while still improving; the best theta2 found is used, and a "
      "coarser design mesh (--faces) gets further in as many iterations",
      options.max_iterations);
  double trust_radius = options.max_step_rad;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    Theta2Iteration record;
    record.iteration = iteration;
    record.objective = objective;
    record.distance_term = terms(0);
    const int shifted_before = solver.shifted_factorizations();
    const bool linearized = solver.linearize(x);
    record.shifted_hessian = solver.shifted_factorizations() > shifted_before;
    if (!linearized) {
      out.stop_reason =
          "the plate's equilibrium is not stable (its Hessian cannot be factorized, even "
          "shifted), so no step can be computed; the best theta2 found is used, and a finer mesh "
          "(--faces) or a smaller --width usually helps";
      break;
    }
    const Eigen::VectorXd g = solver.gradient(x, theta2);
    if (!g.allFinite() || !std::isfinite(objective)) {
      // Keep the last finite state rather than report a stationary point of NaNs.
      out.stop_reason =
          "the distance or its gradient became NaN or infinite, so the last finite theta2 is "
          "used; check the material's shrink ratios (flatmorph materials) or use a finer mesh "
          "(--faces)";
      out.history.push_back(record);
      break;
    }
    // A vertex at the bound whose descent points outward keeps its θ2: the step is solved on the
    // others (the Gauss–Newton system restricted to them).
    Eigen::VectorXd free = Eigen::VectorXd::Ones(nv);
    for (int v = 0; v < nv; ++v) {
      if (std::abs(theta2(v)) >= bound * (1 - 1e-12) && g(v) * theta2(v) < 0) free(v) = 0;
    }
    const auto t_cg = Clock::now();
    Eigen::VectorXd direction;
    record.cg_iterations = conjugate_gradient(
        [&](const Eigen::VectorXd& v) {
          return Eigen::VectorXd(
              solver.gauss_newton_product(v.cwiseProduct(free)).cwiseProduct(free));
        },
        -g.cwiseProduct(free), options.cg_tolerance, options.max_cg_iterations, direction);
    const Eigen::VectorXd dx = solver.sensitivity(direction);
    out.cg_seconds += seconds_since(t_cg);
    const double slope = g.dot(direction);
    record.decrement = -0.5 * slope;
    if (!(slope < 0)) {
      out.converged = true;
      out.stop_reason = "no descent direction (stationary point)";
      record.elapsed_seconds = seconds_since(t0);
      out.history.push_back(record);
      if (options.progress) options.progress(record);
      break;
    }
    if (record.decrement < options.decrement_tolerance) {
      out.converged = true;
      out.stop_reason = "predicted decrease below tolerance";
      record.elapsed_seconds = seconds_since(t0);
      out.history.push_back(record);
      if (options.progress) options.progress(record);
      break;
    }
    // A step that turns some θ2 by more than max_step_rad leaves the range where the linear
    // prediction warm-starts the forward solve well (soft modes make S Δθ huge): shorten it.
    // The length accepted last time is remembered (a trust radius), so that the trials it took
    // to find it are not repeated at every iteration.
    const double direction_max = direction.cwiseAbs().maxCoeff();
    double step = std::min(1.0, trust_radius / direction_max);
    bool accepted = false;
    for (int k = 0;
         k < options.max_line_search_steps && step * direction_max >= options.min_step_rad;
         ++k, step *= 0.5) {
      // Projected onto the bound, which only shortens some components of the step.
      const Eigen::VectorXd trial_theta2 = project(theta2 + step * direction);
      // Warm start at the linear prediction x + s S Δθ.
      const NewtonResult trial = solver.forward(trial_theta2, x + step * dx, true);
      ++record.line_search_trials;
      record.forward_iterations += trial.iterations;
      if (!forward_ok(trial)) continue;
      const Eigen::Vector3d trial_terms = solver.objective_terms(trial.x, trial_theta2);
      const double trial_objective = trial_terms.sum();
      if (trial_objective <= objective + options.armijo_constant * g.dot(trial_theta2 - theta2)) {
        accepted = true;
        theta2 = trial_theta2;
        x = trial.x;
        terms = trial_terms;
        trust_radius = std::min(options.max_step_rad, (k == 0 ? 2.0 : 1.0) * step * direction_max);
        break;
      }
    }
    // The accepted trial was the last forward solve, so the energy holds its b̄ for the next
    // linearization.
    record.step = accepted ? step : 0;
    record.elapsed_seconds = seconds_since(t0);
    out.history.push_back(record);
    if (options.progress) options.progress(record);
    if (!accepted) {
      // Every step longer than min_step_rad leaves the current equilibrium branch (the forward
      // solve of each trial turns unstable): the equilibrium sits near a fold, and the shapes
      // closer to the target lie beyond it. Solving such a trial to the end (a snap) took the hat
      // 200 Newton iterations without settling, so the optimization stops here.
      out.stop_reason =
          step * direction_max < options.min_step_rad
              ? fmt::format(
                    "stalled at a fold of the plate's equilibrium branch: every step "
                    "longer than {:g} rad left it or moved away from the target, so the "
                    "best theta2 found is used; printing the other side up (--side) or a "
                    "finer mesh (--faces) may get past it",
                    options.min_step_rad)
              : fmt::format(
                    "no step lowered the distance in {} halvings, so the best theta2 "
                    "found is used; stronger regularization (--wM, --wL) makes the "
                    "problem smoother",
                    options.max_line_search_steps);
      break;
    }
    ++out.iterations;
    const double decrease = record.objective - terms.sum();
    objective = terms.sum();
    if (decrease < options.relative_decrease * record.objective) {
      out.converged = true;
      out.stop_reason = "relative decrease below tolerance";
      break;
    }
  }
  out.theta2 = theta2;
  out.theta2_bound = bound;
  out.vertices_at_bound = static_cast<int>((theta2.array().abs() >= bound * (1 - 1e-12)).count());
  out.V = solver.from_frame(x);
  out.objective = objective;
  out.distance_term = terms(0);
  out.forward_seconds = solver.forward_seconds();
  out.shifted_factorizations = solver.shifted_factorizations();
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace flatmorph
