// Newton's method for smooth unconstrained minimization over many variables with a sparse Hessian
// (the plate simulation, the flattening's smoothing step).
//
// Each iteration tries the exact Hessian first (fast, quadratic convergence near a minimum); when
// its Cholesky factorization fails (the Hessian is not positive definite, e.g. while a flat plate
// buckles) it falls back to 0.9 times the exact Hessian plus 0.1 times the one assembled from
// per-element Hessians projected onto the PSD cone, and when that fails too, to the projected one
// alone, which always gives a descent direction. Steps are chosen by Armijo backtracking. The
// sparsity pattern is fixed, so CHOLMOD's symbolic analysis (fill-reducing ordering) is done once.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace flatmorph {

struct NewtonProblem {
  int num_variables = 0;
  // Returns the objective at x. When `gradient` is not null, writes the gradient (size
  // num_variables). When `hessian` is not null, writes the Hessian's LOWER triangle (row >= column)
  // as a compressed num_variables^2 sparse matrix whose sparsity pattern is the same at every call
  // (whatever x and `project` are; store explicit zeros if needed). With `project` true, each
  // element's Hessian is projected onto the PSD cone before it is summed.
  std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                       Eigen::SparseMatrix<double>* hessian, bool project)>
      evaluate;
  // Variables kept at their starting values (e.g. to remove rigid motions). Sorted or not.
  std::vector<int> fixed_variables;
  // Optional: line-search trial points for which this returns false are rejected as if their
  // energy were infinite (the flattening rejects steps that flip a triangle).
  std::function<bool(const Eigen::VectorXd& x)> is_feasible;
  // Optional: called with every state Newton moves to; when it returns true, Newton stops there
  // (kStopped) and returns that state (the plate simulator abandons a solve whose states keep a
  // face collapsed, and applies the stimulus in steps instead).
  std::function<bool(const Eigen::VectorXd& x)> stop_at;
};

struct NewtonOptions {
  int max_iterations = 1000;
  // Wall-clock seconds one call may take, a last resort against a solve that crawls: a run that
  // reaches it depends on the machine's speed (its result is not reproducible), so normal runs
  // must stay far below it. Checked once per iteration.
  double max_seconds = 300;
  // Stop (kStalled) when this many iterations in a row lowered the energy by less than
  // `tolerance` each on average: Newton is crawling (along a fold of the state, or off a saddle
  // with the projected Hessian) and more iterations would only spend the budgets.
  int stall_iterations = 50;
  // Stop when the Newton decrement -g.d/2 (the predicted energy decrease, in the objective's
  // units) of an exact-Hessian step is below this.
  double tolerance = 1e-6;
  double armijo_constant = 1e-4;  // sufficient decrease: E(x + s d) <= E(x) + c s g.d
  double backtracking_factor = 0.5;
  int max_line_search_steps = 60;
  // Stop (kDiverged) when the energy falls below E0 - divergence_factor * (|E0| + 1) or a free
  // variable moves farther than divergence_factor * (max |x0| + 1) from its start: the problem is
  // unbounded below, and going on only produces garbage.
  double divergence_factor = 1e8;
};

enum class NewtonStatus {
  kConverged,            // Newton decrement below tolerance with the exact Hessian
  kIterationLimit,       // max_iterations reached
  kLineSearchFailed,     // no step along the Newton direction decreased the energy enough
  kNonFinite,            // the energy, the gradient or the step became NaN or infinite
  kFactorizationFailed,  // even the projected (and shifted) Hessian could not be factorized
  kDiverged,             // the energy or the state exploded (see NewtonOptions::divergence_factor)
  kTimeLimit,            // max_seconds reached
  kStalled,              // stall_iterations iterations lowered the energy by < tolerance each
  kStopped               // NewtonProblem::stop_at asked to stop
};

std::string_view to_string(NewtonStatus status);

struct NewtonIteration {
  double energy = 0.0;     // at the start of the iteration
  double decrement = 0.0;  // -g.d/2 for the direction taken
  double step = 0.0;       // accepted line-search step (0 when none)
  bool exact_hessian = true;
};

struct NewtonResult {
  Eigen::VectorXd x;  // the best (lowest-energy) state reached
  double energy = 0.0;
  double gradient_norm = 0.0;    // of the free variables, at x
  int iterations = 0;            // Newton steps taken
  int projected_iterations = 0;  // of which used the projected Hessian
  NewtonStatus status = NewtonStatus::kIterationLimit;
  std::vector<NewtonIteration> history;
  // Wall-clock seconds spent in: energy+gradient+Hessian evaluations, numeric Cholesky
  // factorizations (symbolic analysis included), triangular solves, line-search energy evaluations.
  double assembly_seconds = 0.0;
  double factorization_seconds = 0.0;
  double solve_seconds = 0.0;
  double line_search_seconds = 0.0;

  // Empty when converged; otherwise one sentence for the user: why Newton stopped, that the best
  // state found is returned, and what to change (finer mesh, smaller plate, other shrink ratios,
  // more iterations or time). Callers print it as a warning, prefixed with what was being solved.
  std::string warning;

  bool converged() const { return status == NewtonStatus::kConverged; }
};

// What newton_minimize keeps between calls on problems with the same variables, fixed variables
// and Hessian pattern (the theta2 optimization solves hundreds of equilibria of one plate): the
// restriction to the free variables and CHOLMOD's symbolic analysis are built once, and after a
// converged call the factorization of the exact Hessian at the returned x stays available for
// solves with that Hessian (the adjoint and sensitivity solves need exactly it).
class NewtonWorkspace {
 public:
  NewtonWorkspace();
  ~NewtonWorkspace();
  NewtonWorkspace(const NewtonWorkspace&) = delete;
  NewtonWorkspace& operator=(const NewtonWorkspace&) = delete;

  // True when the last newton_minimize call with this workspace converged (so the factorization
  // it holds is of the exact, unshifted Hessian at the x it returned).
  bool holds_exact_factorization() const;
  // H^-1 b over all variables, H the factorized Hessian restricted to the free variables: the
  // entries of b at fixed variables are ignored and the result is zero there.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

  struct State;

 private:
  friend NewtonResult newton_minimize(const NewtonProblem&, const Eigen::VectorXd&,
                                      const NewtonOptions&, NewtonWorkspace*);
  std::unique_ptr<State> state_;
};

// Minimizes problem.evaluate starting from x0 (size num_variables). Never throws on numerical
// trouble (non-convergence, NaN or infinite energy, gradient or step, exploding energy or state):
// it stops and returns the best finite state reached, with the reason in `status` and `warning`.
// With a workspace, the symbolic work of earlier calls is reused (see NewtonWorkspace).
NewtonResult newton_minimize(const NewtonProblem& problem, const Eigen::VectorXd& x0,
                             const NewtonOptions& options = {},
                             NewtonWorkspace* workspace = nullptr);

}  // namespace flatmorph
