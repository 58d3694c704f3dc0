#include "numerics/newton.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/core.h>

#include "common/stopwatch.h"
#include "numerics/sparse_cholesky.h"

namespace flatmorph {
// Named rather than anonymous: NewtonWorkspace::State, a type the header declares, holds one.
namespace newton_internal {

// The Hessian restricted to the free variables, built once from the full lower-triangular pattern:
// entries are copied by index, so each iteration costs one pass over the nonzeros.
class ReducedHessian {
 public:
  ReducedHessian(const Eigen::SparseMatrix<double>& full, const std::vector<int>& reduced_index,
                 int num_free) {
    std::vector<Eigen::Triplet<double>> triplets;
    for (int col = 0; col < full.outerSize(); ++col) {
      if (reduced_index[col] < 0) continue;
      for (Eigen::SparseMatrix<double>::InnerIterator it(full, col); it; ++it) {
        if (reduced_index[it.row()] < 0) continue;
        // Column-major, rows ascending within a column: the reduced matrix has its nonzeros in the
        // same relative order, so the k-th kept entry lands in slot k.
        kept_.push_back(static_cast<int>(&it.value() - full.valuePtr()));
        triplets.emplace_back(reduced_index[it.row()], reduced_index[col], 0.0);
      }
    }
    matrix_.resize(num_free, num_free);
    matrix_.setFromTriplets(triplets.begin(), triplets.end());
    matrix_.makeCompressed();
    full_nonzeros_ = full.nonZeros();
  }

  bool matches(const Eigen::SparseMatrix<double>& full) const {
    return full.nonZeros() == full_nonzeros_;
  }

  const Eigen::SparseMatrix<double>& update(const Eigen::SparseMatrix<double>& full) {
    double* out = matrix_.valuePtr();
    const double* in = full.valuePtr();
    for (size_t k = 0; k < kept_.size(); ++k) out[k] = in[kept_[k]];
    return matrix_;
  }

 private:
  std::vector<int> kept_;
  Eigen::SparseMatrix<double> matrix_;
  Eigen::Index full_nonzeros_ = 0;
};

}  // namespace newton_internal

using newton_internal::ReducedHessian;

namespace {

bool all_finite(const Eigen::VectorXd& v) { return v.allFinite(); }

}  // namespace

std::string_view to_string(NewtonStatus status) {
  switch (status) {
    case NewtonStatus::kConverged:
      return "converged";
    case NewtonStatus::kIterationLimit:
      return "iteration limit reached";
    case NewtonStatus::kLineSearchFailed:
      return "line search failed";
    case NewtonStatus::kNonFinite:
      return "non-finite energy, gradient or step";
    case NewtonStatus::kFactorizationFailed:
      return "Hessian factorization failed";
    case NewtonStatus::kDiverged:
      return "energy or state exploded";
    case NewtonStatus::kTimeLimit:
      return "time budget reached";
    case NewtonStatus::kStalled:
      return "stalled";
    case NewtonStatus::kStopped:
      return "stopped by the caller";
  }
  return "unknown";
}

namespace {

// What went wrong and what to change, for NewtonResult::warning.
std::string advice(const NewtonResult& r, const NewtonOptions& options) {
  const std::string change =
      "use a finer mesh (more faces), a smaller plate width, or shrink ratios (lambda) closer to "
      "1";
  switch (r.status) {
    case NewtonStatus::kConverged:
      return "";
    case NewtonStatus::kIterationLimit:
      return fmt::format(
          "Newton did not converge in {} iterations (last predicted decrease {:.3g}, "
          "tolerance {:.3g}); the best state found is used; {}",
          r.iterations, r.history.empty() ? 0.0 : r.history.back().decrement, options.tolerance,
          change);
    case NewtonStatus::kLineSearchFailed:
      return fmt::format(
          "Newton stalled after {} iterations (no step lowered the energy; gradient "
          "norm {:.3g}); the best state found is used; this is usually a rounding "
          "limit and harmless, otherwise {}",
          r.iterations, r.gradient_norm, change);
    case NewtonStatus::kNonFinite:
      return fmt::format(
          "the energy or its gradient became NaN or infinite after {} iterations; "
          "the last finite state is used; check the input for degenerate (zero-area) "
          "triangles, or {}",
          r.iterations, change);
    case NewtonStatus::kFactorizationFailed:
      return fmt::format(
          "the Hessian could not be factorized after {} iterations; the best state "
          "found is used; {}",
          r.iterations, change);
    case NewtonStatus::kDiverged:
      return fmt::format(
          "the energy kept falling without bound (the state exploded) after {} "
          "iterations; the last state before that is used; {}",
          r.iterations, change);
    case NewtonStatus::kTimeLimit:
      return fmt::format(
          "Newton reached its time budget of {:.3g} s after {} iterations (last predicted "
          "decrease {:.3g}, tolerance {:.3g}); the best state found is used; allow more time, or "
          "{}",
          options.max_seconds, r.iterations, r.history.empty() ? 0.0 : r.history.back().decrement,
          options.tolerance, change);
    case NewtonStatus::kStalled:
      return fmt::format(
          "Newton stalled: its last {} of {} iterations lowered the energy by less than the "
          "tolerance {:.3g} each on average; the best state found is used; {}",
          options.stall_iterations, r.iterations, options.tolerance, change);
    case NewtonStatus::kStopped:
      return fmt::format("stopped by the caller after {} iterations", r.iterations);
  }
  return "";
}

}  // namespace

struct NewtonWorkspace::State {
  int num_variables = -1;
  std::vector<int> fixed_variables;
  std::vector<int> reduced_index;  // per variable: its index among the free ones, or -1
  std::vector<int> free_variables;
  std::unique_ptr<ReducedHessian> reduced;
  SparseCholesky solver;
  bool analyzed = false;
  bool exact_at_result = false;

  State() { configure_sparse_cholesky(solver); }

  void prepare(const NewtonProblem& problem) {
    std::vector<int> fixed = problem.fixed_variables;
    std::sort(fixed.begin(), fixed.end());
    fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
    exact_at_result = false;
    if (problem.num_variables == num_variables && fixed == fixed_variables) return;
    num_variables = problem.num_variables;
    fixed_variables = std::move(fixed);
    reduced_index.assign(num_variables, 0);
    for (int v : fixed_variables) reduced_index[v] = -1;
    free_variables.clear();
    for (int i = 0; i < num_variables; ++i) {
      if (reduced_index[i] == 0) {
        reduced_index[i] = static_cast<int>(free_variables.size());
        free_variables.push_back(i);
      }
    }
    reduced.reset();
    analyzed = false;
  }
};

NewtonWorkspace::NewtonWorkspace() : state_(std::make_unique<State>()) {}
NewtonWorkspace::~NewtonWorkspace() = default;

bool NewtonWorkspace::holds_exact_factorization() const { return state_->exact_at_result; }

Eigen::VectorXd NewtonWorkspace::solve(const Eigen::VectorXd& b) const {
  const State& s = *state_;
  Eigen::VectorXd free_b(s.free_variables.size());
  for (size_t i = 0; i < s.free_variables.size(); ++i) free_b(i) = b(s.free_variables[i]);
  const Eigen::VectorXd free_x = s.solver.solve(free_b);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(s.num_variables);
  for (size_t i = 0; i < s.free_variables.size(); ++i) x(s.free_variables[i]) = free_x(i);
  return x;
}

namespace {

NewtonResult minimize(const NewtonProblem& problem, const Eigen::VectorXd& x0,
                      const NewtonOptions& options, NewtonWorkspace::State& state) {
  const int n = problem.num_variables;
  NewtonResult result;
  result.x = x0;

  state.prepare(problem);
  const std::vector<int>& free_variables = state.free_variables;
  const int num_free = static_cast<int>(free_variables.size());
  auto restrict = [&](const Eigen::VectorXd& full) {
    Eigen::VectorXd r(num_free);
    for (int i = 0; i < num_free; ++i) r(i) = full(free_variables[i]);
    return r;
  };

  const auto call_start = Clock::now();
  Eigen::VectorXd gradient(n);
  Eigen::SparseMatrix<double> hessian(n, n);
  auto start = Clock::now();
  result.energy = problem.evaluate(result.x, &gradient, &hessian, false);
  result.assembly_seconds += seconds_since(start);
  if (!std::isfinite(result.energy) || !all_finite(gradient)) {
    result.status = NewtonStatus::kNonFinite;
    return result;
  }
  Eigen::VectorXd g = restrict(gradient);
  result.gradient_norm = g.norm();
  const double energy_floor =
      result.energy - options.divergence_factor * (std::abs(result.energy) + 1);
  const double max_move =
      options.divergence_factor * ((x0.size() ? x0.cwiseAbs().maxCoeff() : 0.0) + 1);
  if (num_free == 0) {
    result.status = NewtonStatus::kConverged;
    return result;
  }

  auto& solver = state.solver;
  auto factorize_hessian = [&](const Eigen::SparseMatrix<double>& full, double shift) {
    const auto t0 = Clock::now();
    if (!state.reduced || !state.reduced->matches(full)) {
      state.reduced = std::make_unique<ReducedHessian>(full, state.reduced_index, num_free);
      state.analyzed = false;
    }
    const Eigen::SparseMatrix<double>& h = state.reduced->update(full);
    if (!state.analyzed) {
      analyze_pattern(solver, h);
      state.analyzed = true;
    }
    solver.setShift(shift);
    factorize(solver, h);
    result.factorization_seconds += seconds_since(t0);
    return solver.info() == Eigen::Success;
  };

  result.status = NewtonStatus::kIterationLimit;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    if (seconds_since(call_start) > options.max_seconds) {
      result.status = NewtonStatus::kTimeLimit;
      break;
    }
    NewtonIteration record;
    record.energy = result.energy;
    bool ok = factorize_hessian(hessian, 0.0);
    if (!ok) {
      record.exact_hessian = false;
      start = Clock::now();
      const Eigen::SparseMatrix<double> exact = hessian;
      problem.evaluate(result.x, nullptr, &hessian, true);
      result.assembly_seconds += seconds_since(start);
      // First the exact Hessian with a tenth of the projected one mixed in (as the reference
      // implementation does): it keeps most of the true curvature, so a buckling or snapping
      // plate moves in a few steps where the projected Hessian alone crawls (the paper's hat on
      // its wrong side fell back in 36 of its first 40 steps without it, in 3 with it).
      if (exact.nonZeros() == hessian.nonZeros()) {  // the same pattern, as evaluate promises
        Eigen::SparseMatrix<double> blend = hessian;
        for (Eigen::Index k = 0; k < blend.nonZeros(); ++k) {
          blend.valuePtr()[k] = 0.9 * exact.valuePtr()[k] + 0.1 * hessian.valuePtr()[k];
        }
        ok = factorize_hessian(blend, 0.0);
      }
      if (!ok) ok = factorize_hessian(hessian, 0.0);
      // A sum of PSD element Hessians can still be singular (flat directions no element sees):
      // shift it by growing multiples of its largest diagonal entry until it factorizes.
      const double scale = state.reduced->update(hessian).diagonal().cwiseAbs().maxCoeff();
      for (double s = 1e-12; !ok && s <= 1e-2; s *= 100) ok = factorize_hessian(hessian, s * scale);
      if (!ok) {
        result.status = NewtonStatus::kFactorizationFailed;
        break;
      }
    }
    start = Clock::now();
    const Eigen::VectorXd d_free = solver.solve(-g);
    result.solve_seconds += seconds_since(start);
    if (!all_finite(d_free)) {
      result.status = NewtonStatus::kNonFinite;
      break;
    }
    const double slope = g.dot(d_free);
    record.decrement = -0.5 * slope;
    if (record.exact_hessian && record.decrement < options.tolerance) {
      result.status = NewtonStatus::kConverged;
      state.exact_at_result = true;
      result.history.push_back(record);
      break;
    }
    if (!(slope < 0)) {
      result.status = NewtonStatus::kLineSearchFailed;
      result.history.push_back(record);
      break;
    }
    Eigen::VectorXd direction = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < num_free; ++i) direction(free_variables[i]) = d_free(i);

    start = Clock::now();
    double step = 1.0;
    bool accepted = false;
    Eigen::VectorXd trial;
    double trial_energy = 0.0;
    for (int k = 0; k < options.max_line_search_steps; ++k, step *= options.backtracking_factor) {
      trial = result.x + step * direction;
      if (problem.is_feasible && !problem.is_feasible(trial)) continue;
      trial_energy = problem.evaluate(trial, nullptr, nullptr, false);
      if (std::isfinite(trial_energy) &&
          trial_energy <= result.energy + options.armijo_constant * step * slope) {
        accepted = true;
        break;
      }
    }
    // Away from a minimum the projected Hessian overestimates the curvature along directions where
    // the true one is negative (a buckling plate leaving a saddle), and full steps keep being
    // accepted while the energy falls faster than predicted. Doubling the step while the energy
    // keeps falling escapes such regions in a few cheap energy evaluations instead of many Newton
    // iterations.
    if (accepted && step == 1.0 && !record.exact_hessian) {
      for (int k = 0; k < options.max_line_search_steps; ++k) {
        const Eigen::VectorXd longer = result.x + 2 * step * direction;
        if (problem.is_feasible && !problem.is_feasible(longer)) break;
        const double longer_energy = problem.evaluate(longer, nullptr, nullptr, false);
        if (!(longer_energy < trial_energy)) break;
        step *= 2;
        trial = longer;
        trial_energy = longer_energy;
      }
    }
    result.line_search_seconds += seconds_since(start);
    if (!accepted) {
      result.status = NewtonStatus::kLineSearchFailed;
      result.history.push_back(record);
      break;
    }
    record.step = step;
    result.history.push_back(record);
    ++result.iterations;
    if (!record.exact_hessian) ++result.projected_iterations;

    start = Clock::now();
    Eigen::VectorXd trial_gradient(n);
    double energy = problem.evaluate(trial, &trial_gradient, &hessian, false);
    // A state whose energy is finite can still have a non-finite gradient (an element at a
    // degenerate configuration, e.g. a buckling sheet folding a face onto a line): back off along
    // the direction, keeping the Armijo decrease, before giving up.
    for (int k = 0; (!std::isfinite(energy) || !all_finite(trial_gradient)) &&
                    k < options.max_line_search_steps;
         ++k) {
      step *= options.backtracking_factor;
      trial = result.x + step * direction;
      if (problem.is_feasible && !problem.is_feasible(trial)) continue;
      energy = problem.evaluate(trial, &trial_gradient, &hessian, false);
      if (std::isfinite(energy) &&
          energy > result.energy + options.armijo_constant * step * slope) {
        energy = std::numeric_limits<double>::quiet_NaN();  // no decrease: keep backing off
      }
    }
    result.history.back().step = step;
    result.assembly_seconds += seconds_since(start);
    if (!std::isfinite(energy) || !all_finite(trial_gradient)) {
      result.status = NewtonStatus::kNonFinite;  // keep the last good state
      break;
    }
    if (energy < energy_floor || (trial - x0).cwiseAbs().maxCoeff() > max_move) {
      result.status = NewtonStatus::kDiverged;  // keep the last state before the explosion
      break;
    }
    result.x = std::move(trial);
    result.energy = energy;
    g = restrict(trial_gradient);
    result.gradient_norm = g.norm();
    if (problem.stop_at && problem.stop_at(result.x)) {
      result.status = NewtonStatus::kStopped;
      break;
    }
    // Every iteration so far left one record, the energy at its start.
    const size_t done = result.history.size();
    const size_t window = static_cast<size_t>(std::max(options.stall_iterations, 1));
    if (done >= window && result.history[done - window].energy - result.energy <
                              static_cast<double>(window) * options.tolerance) {
      result.status = NewtonStatus::kStalled;
      break;
    }
  }
  return result;
}

}  // namespace

NewtonResult newton_minimize(const NewtonProblem& problem, const Eigen::VectorXd& x0,
                             const NewtonOptions& options, NewtonWorkspace* workspace) {
  NewtonWorkspace local;
  NewtonResult result = minimize(problem, x0, options, *(workspace ? workspace : &local)->state_);
  result.warning = advice(result, options);
  return result;
}

}  // namespace flatmorph
