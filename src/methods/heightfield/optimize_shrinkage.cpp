#include "methods/heightfield/optimize_shrinkage.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.h"
#include "common/stopwatch.h"
#include "mesh/operators.h"
#include "methods/heightfield/shrinkage_field.h"
#include "numerics/newton.h"
#include "numerics/sparse_cholesky.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "simulate/distance.h"
#include "simulate/plate_energy.h"
#include "simulate/rigid_frame.h"

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

// Everything that stays fixed while σ changes. Equilibria live in a frame where the plate's central
// face has its first vertex at the origin, its first edge along +x and lies in the xy plane, so
// that the 3-2-1 constraint fixes coordinates that are exactly zero (simulate.h).
class ShrinkageSolver {
 public:
  ShrinkageSolver(const ShrinkageProblem& problem, const OptimizeShrinkageOptions& options)
      : options_(options), problem_(&problem), curve_(require_thickness_curve(problem.material)) {
    const int nv = static_cast<int>(problem.plate.rows());
    const int nf = static_cast<int>(problem.F.rows());
    if (problem.target.rows() != nv || problem.target.cols() != 3 ||
        problem.direction.size() != nf || problem.plate.cols() != 2 ||
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
    nv_ = nv;
    std::tie(least_, most_) = reachable_shrinkage(curve_);
    range_ = most_ - least_;
    std::vector<Eigen::Triplet<double>> triplets;
    for (int f = 0; f < nf; ++f) {
      for (int k = 0; k < 3; ++k) triplets.emplace_back(f, problem.F(f, k), 1.0 / 3);
    }
    face_average_.resize(nf, nv);
    face_average_.setFromTriplets(triplets.begin(), triplets.end());

    const Eigen::VectorXd middle = Eigen::VectorXd::Constant(nv, 0.5 * (least_ + most_));
    const RestForms rest = laminate(stack(middle));
    energy_ = make_plate_energy(problem.plate, problem.F, rest);
    newton_tolerance_ =
        options.forward.relative_tolerance * unit_strain_energy(problem.plate, problem.F, rest);
    frame_ = central_face_frame(problem.plate, problem.F, problem.target, "the target");
    target_ = flatmorph::to_frame(frame_, problem.target);

    // Normalization (optimize_theta2.h): the distance in units of 0.3 % of the bounding-box
    // diagonal, averaged over the target's area; σ in units of the reachable range.
    mass_ = lumped_mass(problem.target, problem.F);
    const double area = mass_.sum();
    const double diagonal =
        (problem.target.colwise().maxCoeff() - problem.target.colwise().minCoeff()).norm();
    const double length = 0.003 * diagonal;
    distance_weight_ = 1.0 / (area * length * length);
    laplacian_ = cotan_laplacian(problem.target, problem.F);
    smoothness_weight_ = options.w_L / (range_ * range_);

    is_fixed_.assign(3 * nv, false);
    for (int i : frame_.fixed_variables) is_fixed_[i] = true;
    const Eigen::SparseMatrix<double>& pattern = energy_.hessian_pattern;
    for (int col = 0; col < pattern.outerSize(); ++col) {
      for (int k = pattern.outerIndexPtr()[col]; k < pattern.outerIndexPtr()[col + 1]; ++k) {
        const int row = pattern.innerIndexPtr()[k];
        if (is_fixed_[row] || is_fixed_[col]) fixed_entries_.push_back({k, row == col});
      }
    }
    configure_sparse_cholesky(solver_);
  }

  double least() const { return least_; }
  double most() const { return most_; }
  const Eigen::VectorXd& target() const { return target_; }

  Eigen::VectorXd project(const Eigen::VectorXd& sigma) const {
    return sigma.cwiseMax(least_).cwiseMin(most_);
  }

  // A shape (#V x 3, any rigid placement) in its own central-face frame: the fixed coordinates
  // are exactly zero, as the 3-2-1 constraint needs.
  Eigen::VectorXd to_frame(const Eigen::MatrixXd& V) const {
    return flatmorph::to_frame(central_face_frame(problem_->plate, problem_->F, V, "the start"), V);
  }

  // The equilibrium x (stacked, in the frame) moved by the best rigid motion onto the target.
  Eigen::MatrixXd aligned(const Eigen::VectorXd& x) const {
    return rigidly_aligned(from_frame(frame_, x), problem_->target);
  }
  Eigen::MatrixXd in_target_frame(const Eigen::VectorXd& x) const { return from_frame(frame_, x); }

  LayerStack stack(const Eigen::VectorXd& vertex_sigma) const {
    // Within the range (the caller projects), so nothing is clamped and λ1 = 1 − σ exactly.
    return thickness_controlled_layer_stack(problem_->direction, face_average_ * vertex_sigma,
                                            problem_->material)
        .stack;
  }

  // The equilibrium for σ (per vertex) from `start` (in the frame). Line-search trials pass
  // `trial`: their own iteration cap.
  NewtonResult forward(const Eigen::VectorXd& sigma, Eigen::VectorXd start, bool trial = false) {
    stack_ = stack(sigma);
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

  // The two terms of E at the equilibrium x.
  Eigen::Vector2d objective_terms(const Eigen::VectorXd& x, const Eigen::VectorXd& sigma) const {
    const RigidFit fit = weighted_rigid_fit(x, target_, mass_);
    double distance = 0;
    for (int v = 0; v < nv_; ++v) {
      distance += mass_(v) *
                  (fit.rotation * x.segment<3>(3 * v) + fit.translation - target_.segment<3>(3 * v))
                      .squaredNorm();
    }
    return {distance_weight_ * distance, smoothness_weight_ * sigma.dot(laplacian_ * sigma)};
  }

  // Factorizes H at x with the fixed variables decoupled (unit rows and columns), and builds
  // J = ∂²W/∂x∂σ (3V x V, fixed rows zero) from the exact derivative of each face's laminate
  // (λ1 = 1 − σ, h = h(σ): dh/dσ = −1/λ1'(h)). Reuses the last forward solve's factorization when
  // x is its converged result.
  bool linearize(const Eigen::VectorXd& x) {
    const int nf = stack_.num_faces();
    LayerShrinkRates rates;
    Eigen::VectorXd thickness_rate(nf);
    const Eigen::VectorXd& height = stack_.layers.front().printed_thickness;
    for (int f = 0; f < nf; ++f) thickness_rate(f) = -1.0 / curve_slope(curve_, height(f));
    for (int k = 0; k < stack_.num_layers(); ++k) {
      rates.lambda1.push_back(Eigen::VectorXd::Constant(nf, -1.0));
      rates.printed_thickness.push_back(thickness_rate);
    }
    LaminateDerivative derivative;
    laminate(stack_, rates, derivative);
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
      // Near a buckling point H is nearly singular: shift by growing multiples of its largest
      // diagonal entry (the sensitivities are then approximate).
      const double scale = hessian_.diagonal().cwiseAbs().maxCoeff();
      for (double s = 1e-12; solver_.info() != Eigen::Success && s <= 1e-4; s *= 100) {
        solver_.setShift(s * scale);
        factorize(solver_, hessian_);
      }
      if (solver_.info() != Eigen::Success) return false;
    }
    return true;
  }

  Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
    return use_forward_factorization_ ? workspace_.solve(b) : solver_.solve(b);
  }

  // ∂D/∂x at x: by the envelope theorem the best rigid motion's own change drops out.
  Eigen::VectorXd distance_gradient(const Eigen::VectorXd& x) const {
    const RigidFit fit = weighted_rigid_fit(x, target_, mass_);
    Eigen::VectorXd r(3 * nv_);
    for (int v = 0; v < nv_; ++v) {
      r.segment<3>(3 * v) =
          2 * distance_weight_ * mass_(v) * fit.rotation.transpose() *
          (fit.rotation * x.segment<3>(3 * v) + fit.translation - target_.segment<3>(3 * v));
    }
    for (int i : frame_.fixed_variables) r(i) = 0;
    return r;
  }

  // dE/dσ (after linearize at the equilibrium x).
  Eigen::VectorXd gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& sigma) const {
    return -(sensitivity_rhs_t_ * solve(distance_gradient(x))) + regularizer_product(sigma);
  }

  Eigen::VectorXd regularizer_product(const Eigen::VectorXd& v) const {
    return 2 * smoothness_weight_ * (laplacian_ * v);
  }

  // S v = dx/dσ · v = −H⁻¹ J v.
  Eigen::VectorXd sensitivity(const Eigen::VectorXd& v) const {
    return -solve(sensitivity_rhs_ * v);
  }

  // (Sᵀ 2D S + 2 w_L L / Δ²) v, D the distance term's diagonal (the rigid fit held fixed: a
  // rotation keeps |dx|).
  Eigen::VectorXd gauss_newton_product(const Eigen::VectorXd& v) const {
    Eigen::VectorXd dx = sensitivity(v);
    for (int u = 0; u < nv_; ++u) dx.segment<3>(3 * u) *= 2 * distance_weight_ * mass_(u);
    for (int i : frame_.fixed_variables) dx(i) = 0;
    return -(sensitivity_rhs_t_ * solve(dx)) + regularizer_product(v);
  }

  double forward_seconds() const { return forward_seconds_; }
  int shifted_factorizations() const { return shifted_factorizations_; }

 private:
  const OptimizeShrinkageOptions& options_;
  const ShrinkageProblem* problem_;
  const ThicknessCurve& curve_;
  int nv_ = 0;
  double least_ = 0, most_ = 0, range_ = 1;
  PlateEnergy energy_;
  LayerStack stack_;  // printed for the energy's current σ
  double newton_tolerance_ = 0;
  RigidFrame frame_;
  std::vector<bool> is_fixed_;
  std::vector<std::pair<int, bool>> fixed_entries_;
  Eigen::VectorXd target_, mass_;
  double distance_weight_ = 0, smoothness_weight_ = 0;
  Eigen::SparseMatrix<double> laplacian_, face_average_;
  Eigen::SparseMatrix<double> hessian_, sensitivity_rhs_, sensitivity_rhs_t_;
  SparseCholesky solver_;
  bool analyzed_ = false;
  NewtonWorkspace workspace_;
  Eigen::VectorXd forward_x_;
  bool use_forward_factorization_ = false;
  double forward_seconds_ = 0;
  int shifted_factorizations_ = 0;
};

// Whether a forward solve reached an equilibrium (as optimize_theta2 decides): converged, or a line
// search stalled at the rounding limit after an exact-Hessian step.
bool forward_ok(const NewtonResult& r) {
  if (r.status == NewtonStatus::kConverged) return true;
  if (r.status != NewtonStatus::kLineSearchFailed || r.history.empty()) return false;
  const NewtonIteration& last = r.history.back();
  return last.exact_hessian && last.decrement <= 1e-10 * std::abs(r.energy);
}

// Conjugate gradients on the SPD system A d = b from d = 0 (every iterate a descent direction).
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

int count_at_bound(const Eigen::VectorXd& sigma, double least, double most) {
  return static_cast<int>(
      ((sigma.array() <= least + 1e-12) || (sigma.array() >= most - 1e-12)).count());
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
  ShrinkageSolver solver(problem, options);
  if (vertex_shrinkage.size() != problem.plate.rows()) {
    throw std::invalid_argument(fmt::format("{} shrinkages for {} vertices: give one per vertex",
                                            vertex_shrinkage.size(), problem.plate.rows()));
  }
  const Eigen::MatrixXd& from = start.size()           ? start
                                : problem.start.size() ? problem.start
                                                       : problem.target;
  const NewtonResult r = solver.forward(vertex_shrinkage, solver.to_frame(from));
  ShrinkageEvaluation out;
  out.forward_converged = forward_ok(r);
  const Eigen::Vector2d terms = solver.objective_terms(r.x, vertex_shrinkage);
  out.objective = terms.sum();
  out.distance_term = terms(0);
  out.V = solver.in_target_frame(r.x);
  if (with_gradient && solver.linearize(r.x)) out.gradient = solver.gradient(r.x, vertex_shrinkage);
  return out;
}

ShrinkageResult optimize_shrinkage(const ShrinkageProblem& problem,
                                   const Eigen::VectorXd& vertex_shrinkage_start,
                                   const OptimizeShrinkageOptions& options) {
  const auto t0 = Clock::now();
  ShrinkageSolver solver(problem, options);
  const int nv = static_cast<int>(problem.plate.rows());
  if (vertex_shrinkage_start.size() != nv) {
    throw std::invalid_argument(
        fmt::format("{} starting shrinkages for {} vertices: give one per vertex",
                    vertex_shrinkage_start.size(), nv));
  }
  Eigen::VectorXd sigma = solver.project(vertex_shrinkage_start);
  const double least = solver.least(), most = solver.most();
  ShrinkageResult out;
  const NewtonResult initial = solver.forward(
      sigma, problem.start.size() ? solver.to_frame(problem.start) : solver.target());
  out.initial_forward_converged = forward_ok(initial);
  Eigen::VectorXd x = initial.x;
  out.initial_V = solver.aligned(x);
  out.initial_seconds = seconds_since(t0);
  Eigen::Vector2d terms = solver.objective_terms(x, sigma);
  double objective = terms.sum();
  out.initial_objective = objective;
  out.initial_distance_term = terms(0);
  out.stop_reason = fmt::format(
      "stopped after {} iterations while still improving; the best shrinkage found is used",
      options.max_iterations);
  if (!out.initial_forward_converged) {
    // Gradients and steps at a state that is not an equilibrium mean nothing.
    out.stop_reason = fmt::format(
        "the risen shape of the starting shrinkage was not found ({}), so it is kept unoptimized; "
        "a printing graph without needle triangles (edges far shorter than their neighbours) "
        "usually simulates",
        initial.warning.empty() ? std::string(to_string(initial.status)) : initial.warning);
  }
  double trust_radius = options.max_step;
  int forward_iterations = 0;  // of the line searches, against options.max_forward_iterations
  for (int iteration = 0; out.initial_forward_converged && iteration < options.max_iterations;
       ++iteration) {
    ShrinkageIteration record;
    record.iteration = iteration;
    record.objective = objective;
    record.distance_term = terms(0);
    auto finish = [&](bool converged, std::string reason) {
      out.converged = converged;
      out.stop_reason = std::move(reason);
      record.vertices_at_bound = count_at_bound(sigma, least, most);
      record.elapsed_seconds = seconds_since(t0);
      out.history.push_back(record);
      if (options.progress) options.progress(record);
    };
    if (!solver.linearize(x)) {
      finish(false,
             "the risen shape is not a stable equilibrium (its Hessian cannot be factorized, "
             "even shifted), so no step can be computed; the best shrinkage found is used");
      break;
    }
    const Eigen::VectorXd g = solver.gradient(x, sigma);
    if (!g.allFinite() || !std::isfinite(objective)) {
      finish(false,
             "the distance or its gradient became NaN or infinite, so the last finite shrinkage "
             "is used; check the material's thickness curve and shrink ratios");
      break;
    }
    // A vertex at a bound whose descent points out of the range keeps its σ: the step is solved
    // on the others.
    Eigen::VectorXd free = Eigen::VectorXd::Ones(nv);
    for (int v = 0; v < nv; ++v) {
      if ((sigma(v) <= least + 1e-12 && g(v) > 0) || (sigma(v) >= most - 1e-12 && g(v) < 0)) {
        free(v) = 0;
      }
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
      finish(true, "no descent direction (a stationary point within the reachable range)");
      break;
    }
    if (record.decrement < options.decrement_tolerance) {
      finish(true, "predicted decrease below tolerance");
      break;
    }
    const double direction_max = direction.cwiseAbs().maxCoeff();
    double step = std::min(1.0, trust_radius / direction_max);
    bool accepted = false;
    for (int k = 0; k < options.max_line_search_steps && step * direction_max >= options.min_step &&
                    forward_iterations < options.max_forward_iterations;
         ++k, step *= 0.5) {
      const Eigen::VectorXd trial_sigma = solver.project(sigma + step * direction);
      // Warm start at the linear prediction x + s S Δσ.
      const NewtonResult trial = solver.forward(trial_sigma, x + step * dx, true);
      ++record.line_search_trials;
      record.forward_iterations += trial.iterations;
      forward_iterations += trial.iterations;
      if (!forward_ok(trial)) continue;
      const Eigen::Vector2d trial_terms = solver.objective_terms(trial.x, trial_sigma);
      if (trial_terms.sum() <= objective + options.armijo_constant * g.dot(trial_sigma - sigma)) {
        accepted = true;
        sigma = trial_sigma;
        x = trial.x;
        terms = trial_terms;
        trust_radius = std::min(options.max_step, (k == 0 ? 2.0 : 1.0) * step * direction_max);
        break;
      }
    }
    record.step = accepted ? step : 0;
    if (!accepted) {
      finish(false,
             forward_iterations >= options.max_forward_iterations
                 ? fmt::format("the budget of {} Newton iterations of forward solves ran out in "
                               "a line search; the best shrinkage found is used",
                               options.max_forward_iterations)
             : step * direction_max < options.min_step
                 ? fmt::format("stalled: every step changing σ by more than {:g} left the "
                               "equilibrium branch or moved away from the target; the best "
                               "shrinkage found is used",
                               options.min_step)
                 : fmt::format("no step lowered the distance in {} halvings; the best shrinkage "
                               "found is used",
                               options.max_line_search_steps));
      break;
    }
    ++out.iterations;
    const double decrease = record.objective - terms.sum();
    objective = terms.sum();
    record.vertices_at_bound = count_at_bound(sigma, least, most);
    record.elapsed_seconds = seconds_since(t0);
    out.history.push_back(record);
    if (options.progress) options.progress(record);
    if (decrease < options.relative_decrease * record.objective) {
      out.converged = true;
      out.stop_reason = "relative decrease below tolerance";
      break;
    }
    if (forward_iterations >= options.max_forward_iterations) {
      out.stop_reason = fmt::format(
          "stopped after {} Newton iterations of forward solves (the budget) while still "
          "improving; the best shrinkage found is used",
          forward_iterations);
      break;
    }
  }
  out.vertex_shrinkage = sigma;
  out.face_shrinkage = vertex_to_face_average(problem.F, sigma);
  out.V = solver.aligned(x);
  out.objective = objective;
  out.distance_term = terms(0);
  out.vertices_at_bound = count_at_bound(sigma, least, most);
  out.forward_seconds = solver.forward_seconds();
  out.shifted_factorizations = solver.shifted_factorizations();
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace flatmorph
