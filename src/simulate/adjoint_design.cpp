#include "simulate/adjoint_design.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "common/stopwatch.h"
#include "mesh/operators.h"
#include "numerics/sparse_cholesky.h"
#include "simulate/distance.h"
#include "simulate/plate_energy.h"
#include "simulate/rigid_frame.h"

namespace flatmorph {
namespace {

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

// E at an equilibrium: its distance term D and the whole.
struct ObjectiveValue {
  double distance = 0;
  double total = 0;
};

// Everything that stays fixed while the variables change, in the frame of the target's central
// face (first vertex at the origin, first edge along +x, face in the xy plane), where the 3-2-1
// constraint fixes coordinates that are exactly zero.
class AdjointDesignSolver {
 public:
  // `perturbation` (may be null: the nominal stack) changes every stack printed for the variables.
  AdjointDesignSolver(const AdjointDesignProblem& problem, const AdjointDesignOptions& options,
                      const std::function<void(LayerStack&)>* perturbation = nullptr)
      : problem_(problem), options_(options), perturbation_(perturbation) {
    nv_ = static_cast<int>(problem.plate.rows());
    const RestForms reference = laminate(problem.layer_stack(problem.reference_variables));
    energy_ = make_plate_energy(problem.plate, problem.F, reference);
    newton_tolerance_ = options.forward.relative_tolerance *
                        unit_strain_energy(problem.plate, problem.F, reference);
    frame_ = central_face_frame(problem.plate, problem.F, problem.target, "the target");
    target_ = flatmorph::to_frame(frame_, problem.target);

    // Normalization: the distance in units of 0.3 % of the bounding-box diagonal, averaged over
    // the target's area; the mass term averaged over the area.
    mass_ = lumped_mass(problem.target, problem.F);
    area_ = mass_.sum();
    const double diagonal =
        (problem.target.colwise().maxCoeff() - problem.target.colwise().minCoeff()).norm();
    const double length = 0.003 * diagonal;
    distance_weight_ = 1.0 / (area_ * length * length);
    laplacian_ = cotan_laplacian(problem.target, problem.F);
    face_average_ = face_average_matrix(problem.F, nv_);

    is_fixed_.assign(3 * nv_, false);
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

  // A start shape (#V x 3, mm; empty: the target) as stacked coordinates in the frame.
  Eigen::VectorXd start_in_frame(const Eigen::MatrixXd& start) const {
    if (start.size() == 0) return target_;
    if (!options_.start_anywhere) return flatmorph::to_frame(frame_, start);
    // In its own central-face frame, its fixed coordinates are exactly zero.
    return flatmorph::to_frame(central_face_frame(problem_.plate, problem_.F, start, "the start"),
                               start);
  }

  Eigen::MatrixXd from_frame(const Eigen::VectorXd& x) const {
    return flatmorph::from_frame(frame_, x);
  }

  Eigen::VectorXd project(const Eigen::VectorXd& p) const {
    return p.cwiseMax(problem_.bounds.lower).cwiseMin(problem_.bounds.upper);
  }

  int count_at_bound(const Eigen::VectorXd& p) const {
    return static_cast<int>(((p.array() <= problem_.bounds.lower_reached) ||
                             (p.array() >= problem_.bounds.upper_reached))
                                .count());
  }

  // The equilibrium for p from `start` (in the frame). Line-search trials pass `trial`: their own
  // iteration cap.
  NewtonResult forward(const Eigen::VectorXd& p, Eigen::VectorXd start, bool trial = false) {
    stack_ = problem_.layer_stack(p);
    if (perturbation_ != nullptr) (*perturbation_)(stack_);
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
    newton_options.max_seconds = options_.forward.max_seconds;
    newton_options.tolerance = newton_tolerance_;
    const auto t0 = Clock::now();
    NewtonResult r = newton_minimize(newton, start, newton_options, &workspace_);
    forward_seconds_ += seconds_since(t0);
    forward_x_ = r.x;
    return r;
  }

  // D at the equilibrium x.
  double distance(const Eigen::VectorXd& x) const {
    double distance = 0;
    if (options_.best_rigid_motion) {
      const RigidFit fit = weighted_rigid_fit(x, target_, mass_);
      for (int v = 0; v < nv_; ++v) {
        distance += mass_(v) * (fit.rotation * x.segment<3>(3 * v) + fit.translation -
                                target_.segment<3>(3 * v))
                                   .squaredNorm();
      }
    } else {
      for (int v = 0; v < nv_; ++v) {
        distance += mass_(v) * (x.segment<3>(3 * v) - target_.segment<3>(3 * v)).squaredNorm();
      }
    }
    return distance_weight_ * distance;
  }

  // E from its distance term D. The terms are summed in the order D, mass, Laplacian.
  ObjectiveValue objective(double distance, const Eigen::VectorXd& p) const {
    ObjectiveValue value;
    value.distance = distance;
    value.total = value.distance;
    if (options_.mass_weight != 0) {
      value.total += options_.mass_weight * p.dot(mass_.cwiseProduct(p)) / area_;
    }
    value.total += options_.laplacian_weight * p.dot(laplacian_ * p);
    return value;
  }

  ObjectiveValue objective(const Eigen::VectorXd& x, const Eigen::VectorXd& p) const {
    return objective(distance(x), p);
  }

  // Factorizes H at x (the energy's current variables) with the fixed variables decoupled (unit
  // rows/columns), and the sensitivity right-hand side J = ∂²W/∂x∂p (3V x V, fixed rows zero).
  // When x is the converged result of the last forward solve, its final Newton factorization is
  // that of H at x already, and is reused.
  bool linearize(const Eigen::VectorXd& x) {
    const LaminateDerivative derivative = problem_.laminate_derivative(stack_);
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
      // singular, so shift by growing multiples of its largest diagonal entry (the sensitivities
      // are then approximate).
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

  // ∂D/∂x at x (zero at the fixed variables). After the best rigid motion, by the envelope
  // theorem the motion's own change drops out.
  Eigen::VectorXd distance_gradient(const Eigen::VectorXd& x) const {
    Eigen::VectorXd r(3 * nv_);
    if (options_.best_rigid_motion) {
      const RigidFit fit = weighted_rigid_fit(x, target_, mass_);
      for (int v = 0; v < nv_; ++v) {
        r.segment<3>(3 * v) =
            2 * distance_weight_ * mass_(v) * fit.rotation.transpose() *
            (fit.rotation * x.segment<3>(3 * v) + fit.translation - target_.segment<3>(3 * v));
      }
    } else {
      for (int v = 0; v < nv_; ++v) {
        r.segment<3>(3 * v) =
            2 * distance_weight_ * mass_(v) * (x.segment<3>(3 * v) - target_.segment<3>(3 * v));
      }
    }
    for (int i : frame_.fixed_variables) r(i) = 0;
    return r;
  }

  // Shrink & Morph Eq. 14: dE/dp = −Jᵀ H⁻¹ ∂D/∂x + regularizer (after linearize at x).
  Eigen::VectorXd gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& p) const {
    const Eigen::VectorXd adjoint = solve(distance_gradient(x));
    return -(sensitivity_rhs_t_ * adjoint) + regularizer_product(p);
  }

  // (2 w_M M / A + 2 w_L L) v: the regularizer's Hessian times v (its gradient at v).
  Eigen::VectorXd regularizer_product(const Eigen::VectorXd& v) const {
    if (options_.mass_weight == 0) return 2 * options_.laplacian_weight * (laplacian_ * v);
    return 2 * options_.mass_weight / area_ * mass_.cwiseProduct(v) +
           2 * options_.laplacian_weight * (laplacian_ * v);
  }

  // S v = dx/dp · v = −H⁻¹ J v.
  Eigen::VectorXd sensitivity(const Eigen::VectorXd& v) const {
    return -solve(sensitivity_rhs_ * v);
  }

  // (Sᵀ 2D S + 2 w_M M / A + 2 w_L L) v, D the distance term's diagonal (a rigid fit held fixed:
  // a rotation keeps |dx|).
  Eigen::VectorXd gauss_newton_product(const Eigen::VectorXd& v) const {
    Eigen::VectorXd dx = sensitivity(v);
    for (int u = 0; u < nv_; ++u) dx.segment<3>(3 * u) *= 2 * distance_weight_ * mass_(u);
    for (int i : frame_.fixed_variables) dx(i) = 0;
    return -(sensitivity_rhs_t_ * solve(dx)) + regularizer_product(v);
  }

  double forward_seconds() const { return forward_seconds_; }
  int shifted_factorizations() const { return shifted_factorizations_; }

 private:
  const AdjointDesignProblem& problem_;
  const AdjointDesignOptions& options_;
  const std::function<void(LayerStack&)>* perturbation_;
  int nv_ = 0;
  PlateEnergy energy_;
  LayerStack stack_;  // printed for the energy's current variables
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

// The nominal stack and each perturbed one (AdjointDesignProblem::perturbations), each with its
// own equilibrium followed along the optimization: D, its gradient and the Gauss–Newton product
// are their means. With no perturbation this is the nominal solver alone, bit for bit.
class DesignScenarios {
 public:
  DesignScenarios(const AdjointDesignProblem& problem, const AdjointDesignOptions& options) {
    solvers_.push_back(std::make_unique<AdjointDesignSolver>(problem, options));
    for (const auto& perturbation : problem.perturbations) {
      solvers_.push_back(std::make_unique<AdjointDesignSolver>(problem, options, &perturbation));
    }
  }

  int size() const { return static_cast<int>(solvers_.size()); }
  AdjointDesignSolver& nominal() { return *solvers_.front(); }

  // Every scenario's equilibrium for p, scenario j from starts[j] (in the frame); the results.
  std::vector<NewtonResult> forward(const Eigen::VectorXd& p,
                                    const std::vector<Eigen::VectorXd>& starts, bool trial) {
    std::vector<NewtonResult> results(size());
    each_scenario([&](int j) { results[j] = solvers_[j]->forward(p, starts[j], trial); });
    return results;
  }

  ObjectiveValue objective(const std::vector<Eigen::VectorXd>& x, const Eigen::VectorXd& p) const {
    double distance = solvers_[0]->distance(x[0]);
    for (int j = 1; j < size(); ++j) distance += solvers_[j]->distance(x[j]);
    return solvers_[0]->objective(distance / size(), p);
  }

  bool linearize(const std::vector<Eigen::VectorXd>& x) {
    std::vector<char> ok(size());
    each_scenario([&](int j) { ok[j] = solvers_[j]->linearize(x[j]); });
    return std::all_of(ok.begin(), ok.end(), [](char k) { return k != 0; });
  }

  // The mean of the scenarios' gradients (each carries the same regularizer's).
  Eigen::VectorXd gradient(const std::vector<Eigen::VectorXd>& x, const Eigen::VectorXd& p) const {
    Eigen::VectorXd g = solvers_[0]->gradient(x[0], p);
    for (int j = 1; j < size(); ++j) g += solvers_[j]->gradient(x[j], p);
    return g / size();
  }

  Eigen::VectorXd gauss_newton_product(const Eigen::VectorXd& v) const {
    std::vector<Eigen::VectorXd> products(size());
    each_scenario([&](int j) { products[j] = solvers_[j]->gauss_newton_product(v); });
    for (int j = 1; j < size(); ++j) products[0] += products[j];
    return products[0] / size();
  }

  // Each scenario's S v.
  std::vector<Eigen::VectorXd> sensitivity(const Eigen::VectorXd& v) const {
    std::vector<Eigen::VectorXd> dx(size());
    each_scenario([&](int j) { dx[j] = solvers_[j]->sensitivity(v); });
    return dx;
  }

  double forward_seconds() const {
    double seconds = 0;
    for (const auto& solver : solvers_) seconds += solver->forward_seconds();
    return seconds;
  }
  int shifted_factorizations() const {
    int count = 0;
    for (const auto& solver : solvers_) count += solver->shifted_factorizations();
    return count;
  }

 private:
  // The scenarios share nothing but the problem they read: one per core, and the results are
  // combined in their order, so the bits do not depend on the cores.
  template <typename Work>
  void each_scenario(const Work& work) const {
    if (size() == 1) {
      work(0);
      return;
    }
    tbb::parallel_for(0, size(), [&](int j) { work(j); });
  }

  std::vector<std::unique_ptr<AdjointDesignSolver>> solvers_;
};

}  // namespace

std::string_view to_string(AdjointStop stop) {
  switch (stop) {
    case AdjointStop::kNone:
      return "not stopped";
    case AdjointStop::kIterationLimit:
      return "stopped at the iteration limit while still improving";
    case AdjointStop::kNoInitialEquilibrium:
      return "the first equilibrium was not found";
    case AdjointStop::kUnstable:
      return "the equilibrium is not stable (its Hessian cannot be factorized, even shifted)";
    case AdjointStop::kNotFinite:
      return "the objective or its gradient became NaN or infinite";
    case AdjointStop::kStationary:
      return "no descent direction (stationary point)";
    case AdjointStop::kSmallDecrement:
      return "predicted decrease below tolerance";
    case AdjointStop::kSmallDecrease:
      return "relative decrease below tolerance";
    case AdjointStop::kStalled:
      return "stalled: every step longer than the smallest one failed";
    case AdjointStop::kNoDecrease:
      return "no step lowered the objective in the halvings allowed";
    case AdjointStop::kBudgetInLineSearch:
      return "the budget of forward Newton iterations ran out in a line search";
    case AdjointStop::kBudgetAfterStep:
      return "stopped at the budget of forward Newton iterations while still improving";
  }
  return "unknown stop";
}

Eigen::SparseMatrix<double> face_average_matrix(const Eigen::MatrixXi& F, int num_vertices) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) triplets.emplace_back(f, F(f, k), 1.0 / 3);
  }
  Eigen::SparseMatrix<double> average(F.rows(), num_vertices);
  average.setFromTriplets(triplets.begin(), triplets.end());
  return average;
}

AdjointEvaluation evaluate_adjoint_design(const AdjointDesignProblem& problem,
                                          const Eigen::VectorXd& variables,
                                          const Eigen::MatrixXd& start,
                                          const AdjointDesignOptions& options, bool with_gradient) {
  DesignScenarios scenarios(problem, options);
  AdjointDesignSolver& solver = scenarios.nominal();
  const std::vector<NewtonResult> r = scenarios.forward(
      variables,
      std::vector<Eigen::VectorXd>(scenarios.size(),
                                   solver.start_in_frame(start.size() ? start : problem.start)),
      false);
  AdjointEvaluation out;
  out.forward_converged =
      std::all_of(r.begin(), r.end(), [](const NewtonResult& e) { return forward_ok(e); });
  std::vector<Eigen::VectorXd> x;
  for (const NewtonResult& e : r) x.push_back(e.x);
  const ObjectiveValue value = scenarios.objective(x, variables);
  out.objective = value.total;
  out.distance_term = value.distance;
  out.V = solver.from_frame(x.front());
  if (with_gradient && scenarios.linearize(x)) out.gradient = scenarios.gradient(x, variables);
  return out;
}

AdjointDesignResult optimize_adjoint_design(const AdjointDesignProblem& problem,
                                            const Eigen::VectorXd& variables,
                                            const AdjointDesignOptions& options) {
  const auto t0 = Clock::now();
  DesignScenarios scenarios(problem, options);
  AdjointDesignSolver& solver = scenarios.nominal();
  const int nv = static_cast<int>(problem.plate.rows());
  const DesignBounds& bounds = problem.bounds;
  Eigen::VectorXd p = solver.project(variables);
  AdjointDesignResult out;
  const std::vector<NewtonResult> initial = scenarios.forward(
      p, std::vector<Eigen::VectorXd>(scenarios.size(), solver.start_in_frame(problem.start)),
      false);
  out.initial_forward_converged = std::all_of(initial.begin(), initial.end(),
                                              [](const NewtonResult& r) { return forward_ok(r); });
  out.initial_forward_status = initial.front().status;
  out.initial_forward_warning = initial.front().warning;
  std::vector<Eigen::VectorXd> x;
  for (const NewtonResult& r : initial) x.push_back(r.x);
  out.initial_V = solver.from_frame(x.front());
  out.initial_seconds = seconds_since(t0);
  ObjectiveValue value = scenarios.objective(x, p);
  out.initial_objective = value.total;
  out.initial_distance_term = value.distance;
  out.stop = AdjointStop::kIterationLimit;
  if (!out.initial_forward_converged && options.require_initial_equilibrium) {
    out.stop = AdjointStop::kNoInitialEquilibrium;
  }
  double trust_radius = options.max_step;
  for (int iteration = 0;
       out.stop == AdjointStop::kIterationLimit && iteration < options.max_iterations;
       ++iteration) {
    AdjointIteration record;
    record.iteration = iteration;
    record.objective = value.total;
    record.distance_term = value.distance;
    // Every record goes to the history and to progress, with the stop it ended on, if any.
    auto report = [&](AdjointStop stop) {
      record.stop = stop;
      record.vertices_at_bound = solver.count_at_bound(p);
      record.elapsed_seconds = seconds_since(t0);
      out.history.push_back(record);
      if (options.progress) options.progress(record);
      if (stop != AdjointStop::kNone) out.stop = stop;
    };
    const int shifted_before = scenarios.shifted_factorizations();
    const bool linearized = scenarios.linearize(x);
    record.shifted_hessian = scenarios.shifted_factorizations() > shifted_before;
    if (!linearized) {
      report(AdjointStop::kUnstable);
      break;
    }
    const Eigen::VectorXd g = scenarios.gradient(x, p);
    if (!g.allFinite() || !std::isfinite(value.total)) {
      // Keep the last finite state rather than report a stationary point of NaNs.
      report(AdjointStop::kNotFinite);
      break;
    }
    // A variable at a bound whose descent points out of the box keeps its value: the step is
    // solved on the others (the Gauss–Newton system restricted to them).
    Eigen::VectorXd free = Eigen::VectorXd::Ones(nv);
    for (int v = 0; v < nv; ++v) {
      if ((p(v) <= bounds.lower_reached && g(v) > 0) ||
          (p(v) >= bounds.upper_reached && g(v) < 0)) {
        free(v) = 0;
      }
    }
    const auto t_cg = Clock::now();
    Eigen::VectorXd direction;
    record.cg_iterations = conjugate_gradient(
        [&](const Eigen::VectorXd& v) {
          return Eigen::VectorXd(
              scenarios.gauss_newton_product(v.cwiseProduct(free)).cwiseProduct(free));
        },
        -g.cwiseProduct(free), options.cg_tolerance, options.max_cg_iterations, direction);
    const std::vector<Eigen::VectorXd> dx = scenarios.sensitivity(direction);
    out.cg_seconds += seconds_since(t_cg);
    const double slope = g.dot(direction);
    record.decrement = -0.5 * slope;
    if (!(slope < 0)) {
      report(AdjointStop::kStationary);
      break;
    }
    if (record.decrement < options.decrement_tolerance) {
      report(AdjointStop::kSmallDecrement);
      break;
    }
    // A step that changes some variable by more than the trust radius leaves the range where the
    // linear prediction warm-starts the forward solve well (soft modes make S Δp huge): shorten
    // it. The length accepted last time is remembered, so that the trials it took to find it are
    // not repeated at every iteration.
    const double direction_max = direction.cwiseAbs().maxCoeff();
    double step = std::min(1.0, trust_radius / direction_max);
    bool accepted = false;
    for (int k = 0; k < options.max_line_search_steps && step * direction_max >= options.min_step &&
                    out.forward_iterations < options.max_forward_iterations;
         ++k, step *= 0.5) {
      // Projected onto the bounds, which only shortens some components of the step.
      const Eigen::VectorXd trial_p = solver.project(p + step * direction);
      // Warm start at the linear prediction x + s S Δp.
      std::vector<Eigen::VectorXd> starts;
      for (int j = 0; j < scenarios.size(); ++j) starts.push_back(x[j] + step * dx[j]);
      const std::vector<NewtonResult> trial = scenarios.forward(trial_p, starts, true);
      ++record.line_search_trials;
      bool trial_ok = true;
      std::vector<Eigen::VectorXd> trial_x;
      for (const NewtonResult& r : trial) {
        record.forward_iterations += r.iterations;
        out.forward_iterations += r.iterations;
        trial_ok = trial_ok && forward_ok(r);
        trial_x.push_back(r.x);
      }
      if (!trial_ok) continue;
      const ObjectiveValue trial_value = scenarios.objective(trial_x, trial_p);
      if (trial_value.total <= value.total + options.armijo_constant * g.dot(trial_p - p)) {
        accepted = true;
        p = trial_p;
        x = std::move(trial_x);
        value = trial_value;
        trust_radius = std::min(options.max_step, (k == 0 ? 2.0 : 1.0) * step * direction_max);
        break;
      }
    }
    // The accepted trial was the last forward solve, so the energy holds its stack for the next
    // linearization.
    record.step = accepted ? step : 0;
    if (!accepted) {
      // Every step longer than min_step leaves the current equilibrium branch (the forward solve
      // of each trial turns unstable) or moves away from the target: the equilibrium sits near a
      // fold, and the shapes closer to the target lie beyond it. Solving such a trial to the end
      // (a snap) took Shrink & Morph's hat 200 Newton iterations without settling.
      report(out.forward_iterations >= options.max_forward_iterations
                 ? AdjointStop::kBudgetInLineSearch
             : step * direction_max < options.min_step ? AdjointStop::kStalled
                                                       : AdjointStop::kNoDecrease);
      break;
    }
    ++out.iterations;
    const double decrease = record.objective - value.total;
    report(decrease < options.relative_decrease * record.objective ? AdjointStop::kSmallDecrease
           : out.forward_iterations >= options.max_forward_iterations
               ? AdjointStop::kBudgetAfterStep
               : AdjointStop::kNone);
  }
  out.converged = out.stop == AdjointStop::kStationary ||
                  out.stop == AdjointStop::kSmallDecrement ||
                  out.stop == AdjointStop::kSmallDecrease;
  out.variables = p;
  out.V = solver.from_frame(x.front());
  out.objective = value.total;
  out.distance_term = value.distance;
  out.vertices_at_bound = solver.count_at_bound(p);
  out.forward_seconds = scenarios.forward_seconds();
  out.shifted_factorizations = scenarios.shifted_factorizations();
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace flatmorph
