// Inverse design by the adjoint method over the plate simulator: per-vertex design variables p
// set the printed layer stack, the plate's equilibrium x(p) is that stack's (plate_energy.h,
// Newton, the 3-2-1 frame of rigid_frame.h), and p minimizes
//   E(p) = D(x(p)) + w_M pᵀ M p / A + w_L pᵀ L p,
//   D(x) = Σ_v m_v |x_v − x_T,v|² / (A ℓ²)       (or min over rigid motions (R, t) of
//          Σ_v m_v |R x_v + t − x_T,v|² / (A ℓ²)),
// with m the lumped mass of the target (mm², M its diagonal), A its area, ℓ = 0.3 % of its
// bounding-box diagonal (D is the mean squared distance in units of ℓ, whatever the part's size and
// mesh) and L its cotan Laplacian. This is Shrink & Morph's θ2 optimization (§3.2.2, Eq. 13-14),
// which the height fields' shrink optimization reuses with σ as the variable; the methods supply
// only what is theirs: how the variables are printed, the bounds and the regularizer's weights
// (methods/shrink_morph/optimize_theta2.h, methods/heightfield/optimize_shrinkage.h).
//
// Each face prints the mean of its corners' variables. The gradient is the adjoint one:
//   dE/dp = −Jᵀ H⁻¹ ∂D/∂x + 2 (w_M M / A + w_L L) p,
// with H the energy's Hessian at the equilibrium and J = ∂²W/∂x∂p = rest_forms_mixed_derivative
// (from the exact derivative of each face's laminate) times the face averaging. Steps are
// projected Gauss–Newton with exact sensitivities S = dx/dp = −H⁻¹ J: conjugate gradients on
// (Sᵀ 2D S + 2 w_M M / A + 2 w_L L) Δp = −g, matrix-free, reusing the Cholesky factor of H, over
// the variables not held at a bound; then Armijo backtracking along the step projected onto the
// bounds, each trial's equilibrium warm-started at the linear prediction x + s S Δp, its first
// length limited by a trust radius.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "numerics/newton.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "simulate/simulate.h"

namespace flatmorph {

// Box bounds on every design variable (in the variables' own units). Steps are projected onto
// [lower, upper]. A variable at or below lower_reached (at or above upper_reached) counts as at its
// bound: it keeps its value while its descent points out of the box, and vertices_at_bound counts
// it. Each method sets how close to the bound counts as on it.
struct DesignBounds {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  double lower_reached = -std::numeric_limits<double>::infinity();
  double upper_reached = std::numeric_limits<double>::infinity();
};

// What only the method knows: the plate, its target, and how the variables are printed.
struct AdjointDesignProblem {
  Eigen::MatrixXd plate;   // #V x 2, mm, counter-clockwise faces
  Eigen::MatrixXi F;       // #F x 3
  Eigen::MatrixXd target;  // #V x 3, mm, one row per plate vertex
  // The stack printed for the variables (per vertex). Each face must print the mean of its
  // corners' (face_average_matrix or vertex_to_face_average): the sensitivities assume it.
  std::function<LayerStack(const Eigen::VectorXd& variables)> layer_stack;
  // The exact derivative of the laminate of `stack` (printed by layer_stack) with respect to each
  // face's variable: laminate(stack, rates, derivative) with the method's per-layer rates.
  std::function<LaminateDerivative(const LayerStack& stack)> laminate_derivative;
  // The variables whose stack builds the energy and sets Newton's tolerance (its unit strain
  // energy), whatever the variables solved for later.
  Eigen::VectorXd reference_variables;
  DesignBounds bounds;
  // Where the first equilibrium is searched from (#V x 3, mm); empty: the target.
  Eigen::MatrixXd start;
  // Printing errors the design must hold under (e.g. the paths' departures from the layer
  // directions): each changes the printed stack in place. With any, D is the mean of the
  // distances of the nominal stack's equilibrium and of each perturbed stack's, all solved from
  // the same start and followed along the optimization, so that a design does not rest where a
  // small printing error makes the plate snap to another shape (docs/design.md).
  std::vector<std::function<void(LayerStack& stack)>> perturbations;
};

// How the optimization ended. Converged: kStationary, kSmallDecrement, kSmallDecrease.
enum class AdjointStop {
  kNone,                  // (on a record: the optimization went on)
  kIterationLimit,        // max_iterations while still improving
  kNoInitialEquilibrium,  // require_initial_equilibrium, and the first solve failed
  kUnstable,              // H could not be factorized, even shifted
  kNotFinite,             // E or its gradient became NaN or infinite
  kStationary,            // no descent direction
  kSmallDecrement,        // the model's predicted decrease below decrement_tolerance
  kSmallDecrease,         // an accepted step's decrease below relative_decrease × E
  kStalled,               // every trial longer than min_step failed
  kNoDecrease,            // max_line_search_steps halvings without sufficient decrease
  kBudgetInLineSearch,    // max_forward_iterations ran out during a line search
  kBudgetAfterStep,       // ... with an accepted step
};

// A short English description of each stop (the methods word their own for their users).
std::string_view to_string(AdjointStop stop);

struct AdjointIteration {
  int iteration = 0;
  double objective = 0;      // E at the start of the iteration
  double distance_term = 0;  // its D
  double step = 0;           // accepted line-search step (0 when none)
  double decrement = 0;  // −½ gᵀΔp: the decrease of E the model predicts for the full step
  int cg_iterations = 0;
  int forward_iterations = 0;  // Newton iterations of the line search's forward solves
  int line_search_trials = 0;
  int vertices_at_bound = 0;     // after the iteration
  bool shifted_hessian = false;  // H at the equilibrium needed a diagonal shift to factorize
  double elapsed_seconds = 0;    // since the optimization started
  AdjointStop stop = AdjointStop::kNone;
};

struct AdjointDesignOptions {
  // The regularizer's weights (dimensionless in E): w_M pᵀ M p / A + w_L pᵀ L p. A mass term of
  // weight 0 is left out.
  double mass_weight = 0;
  double laplacian_weight = 0;
  // D after the best rigid motion of the equilibrium onto the target (weighted_rigid_fit, the
  // distance a prediction reports, independent of how the equilibrium is registered); otherwise as
  // registered by the 3-2-1 frame at the target's central face.
  bool best_rigid_motion = false;
  // True: the start may lie anywhere (it is taken in its own central-face frame). False: it is
  // registered to the target (e.g. an equilibrium of an earlier solve) and taken in the target's.
  bool start_anywhere = false;
  // Stop at once when the first equilibrium is not found (gradients and steps at a state that is
  // not an equilibrium mean nothing); otherwise go on from the state reached.
  bool require_initial_equilibrium = false;
  int max_iterations = 100;
  // Newton iterations all the line searches' forward solves may take together (a work budget, so
  // that the result does not depend on the machine's speed); the iteration that spends the last of
  // them is the final one.
  int max_forward_iterations = std::numeric_limits<int>::max();
  // Stop when the Gauss–Newton model predicts that its full step lowers E by less than this, or
  // when an accepted step lowers E by less than relative_decrease × E.
  double decrement_tolerance = 0.02;
  double relative_decrease = 1e-4;
  int max_cg_iterations = 200;
  double cg_tolerance = 1e-2;  // relative residual of the Gauss–Newton system
  double armijo_constant = 1e-4;
  int max_line_search_steps = 20;  // backtracking by halves
  // The first trial changes no variable by more than max_step, and the length accepted last grows
  // up to it (a trust radius): longer steps leave the range where the linear prediction
  // warm-starts the forward solve well. Backtracking gives up when the largest change falls below
  // min_step. Both in the variables' units.
  double max_step = 0.5;
  double min_step = 1e-3;
  // Newton iterations a line-search trial's forward solve may take from its linear prediction;
  // more means the step left the equilibrium branch (a snap): the trial is rejected.
  int max_trial_forward_iterations = 4;
  // The first and every evaluation's equilibrium solve (max_iterations) and the tolerance of all.
  SimulationOptions forward;
  // Called with every record of the history, the one that stopped the optimization included.
  std::function<void(const AdjointIteration&)> progress;
};

struct AdjointDesignResult {
  Eigen::VectorXd variables;  // per vertex, within the bounds
  // #V x 3, mm: the equilibrium for `variables` and for the starting ones, registered to the
  // target at its central face (not moved by the best rigid motion).
  Eigen::MatrixXd V, initial_V;
  double objective = 0, initial_objective = 0;
  double distance_term = 0, initial_distance_term = 0;
  int iterations = 0;  // accepted steps
  bool converged = false;
  AdjointStop stop = AdjointStop::kIterationLimit;
  std::vector<AdjointIteration> history;
  // The first equilibrium solve: whether it reached one, and Newton's status and warning.
  bool initial_forward_converged = false;
  NewtonStatus initial_forward_status = NewtonStatus::kIterationLimit;
  std::string initial_forward_warning;
  int forward_iterations = 0;      // Newton iterations of all the line searches
  int shifted_factorizations = 0;  // of H (not positive definite: an unstable equilibrium)
  int vertices_at_bound = 0;
  double seconds = 0;
  double initial_seconds = 0;  // the first equilibrium, setup included
  double cg_seconds = 0;       // in the Gauss–Newton solves
  double forward_seconds = 0;
};

// Minimizes E from `variables` (per vertex, projected onto the bounds), the first equilibrium
// solved from problem.start. Throws UserError (kGeometry) when the target's central face is
// degenerate; numerical trouble ends the optimization with the reason in `stop`.
AdjointDesignResult optimize_adjoint_design(const AdjointDesignProblem& problem,
                                            const Eigen::VectorXd& variables,
                                            const AdjointDesignOptions& options);

// E at `variables` (per vertex, not projected), the equilibrium solved from `start` (#V x 3, mm;
// empty: problem.start, else the target), and with `with_gradient` its adjoint gradient.
struct AdjointEvaluation {
  double objective = 0;
  double distance_term = 0;
  Eigen::VectorXd gradient;  // empty without with_gradient or when H could not be factorized
  Eigen::MatrixXd V;         // the equilibrium, #V x 3, mm, registered at the central face
  bool forward_converged = false;
};
AdjointEvaluation evaluate_adjoint_design(const AdjointDesignProblem& problem,
                                          const Eigen::VectorXd& variables,
                                          const Eigen::MatrixXd& start,
                                          const AdjointDesignOptions& options,
                                          bool with_gradient = true);

// The #F x #V matrix of face means (1/3 at each corner): how the variables reach the faces.
Eigen::SparseMatrix<double> face_average_matrix(const Eigen::MatrixXi& F, int num_vertices);

}  // namespace flatmorph
