// Shrink & Morph §3.2.2: the through-thickness variation theta2 of the print direction whose
// simulated equilibrium comes closest to the target, with the plate and theta1 fixed.
//
// Objective (Eq. 13), normalized so that the weights do not depend on the part's size or the mesh
// resolution (docs/design.md):
//   E(θ2) = Σ_v m_v |x_v(θ2) − x_T,v|² / (A ℓ²) + w_M Σ_v m_v θ2_v² / A + w_L θ2ᵀ L θ2
// with m the lumped mass of the target (mm²), A its total area, ℓ = 0.3 % of the target's
// bounding-box diagonal (so the first term is the mean squared distance in units of 0.3 % of the
// diagonal), L the cotan Laplacian of the target (dimensionless) and x(θ2) the equilibrium of the
// plate energy of the exact laminate of the printed layers (θ^k from θ1 and the face-averaged θ2 by
// the stack builder, plate/layer_stack.h; not the first-order Eq. 7, 17, which is far off for
// |θ2| above about 1 rad), registered to the target by the 3-2-1 constraint of simulate.h. The
// gradient is the adjoint one (Eq. 14); steps are Gauss–Newton with exact sensitivities, S = dx/dθ2
// = −H⁻¹ H_xθ (H_xθ from the exact derivative of the laminate's ā, b̄ and stiffness with respect to
// each face's θ2), solved matrix-free by conjugate gradients on (Sᵀ 2D S + 2 w_M M + 2 w_L L) Δθ =
// −g reusing the Cholesky factor of H. The solver is the shared one of simulate/adjoint_design.h;
// this file holds what is θ2's: its layer stack and derivative, bounds and regularizer.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "material/material.h"
#include "methods/shrink_morph/flatten.h"
#include "simulate/simulate.h"

namespace flatmorph {

// The plate and what it should become.
struct Theta2Problem {
  Eigen::MatrixXd plate;   // #V x 2, mm, counter-clockwise faces
  Eigen::MatrixXi F;       // #F x 3
  Eigen::MatrixXd target;  // #V x 3, mm, same vertices as the plate
  Eigen::VectorXd theta1;  // per face, rad
  Material material;
  // Printed as shrink_morph_layer_stack(theta1, face-averaged theta2, material, num_layers,
  // material.layer_height): the exact laminate of these layers is what the objective simulates.
  int num_layers = 10;
  // Where the first equilibrium is searched from (#V x 3, mm); empty: the target. An equilibrium
  // already found (e.g. while choosing the printed side) makes the first solve nearly free.
  Eigen::MatrixXd start;
};

struct Theta2Iteration {
  int iteration = 0;
  double objective = 0;      // E at the start of the iteration
  double distance_term = 0;  // its first term
  double step = 0;           // accepted line-search step (0 when none)
  // −½ gᵀΔθ: the decrease of E the Gauss–Newton model predicts for the full step Δθ.
  double decrement = 0;
  int cg_iterations = 0;       // for the Gauss–Newton step
  int forward_iterations = 0;  // Newton iterations of all forward solves of the line search
  int line_search_trials = 0;
  bool shifted_hessian = false;  // H at the equilibrium needed a diagonal shift to factorize
  double elapsed_seconds = 0;    // since the optimization started
};

struct OptimizeTheta2Options {
  double w_M = 0.01;  // weight of the mass term (dimensionless)
  double w_L = 0.01;  // weight of the Laplacian term (dimensionless)
  int max_iterations = 100;
  // Stop when the Gauss–Newton model predicts that its full step lowers E by less than this (E's
  // distance term is the mean squared distance in units of (0.3 % of the diagonal)², so 0.02 is a
  // fiftieth of that unit), or when an iteration lowers E by less than relative_decrease × E.
  // Past this point the optimization only trades the maximum distance for the mean
  // (docs/design.md).
  double decrement_tolerance = 0.02;
  double relative_decrease = 1e-4;
  int max_cg_iterations = 200;
  double cg_tolerance = 1e-2;  // relative residual of the Gauss–Newton system
  double armijo_constant = 1e-4;
  int max_line_search_steps = 20;  // Armijo backtracking by halves
  // The line search starts with max |Δθ2| at most this, and the length accepted last grows up to
  // it (a trust radius): longer steps leave the range where the linear prediction warm-starts the
  // forward solve well.
  double max_step_rad = 0.5;
  // Backtracking gives up when max |Δθ2| falls below this (the optimization has stalled at a
  // fold of the equilibrium branch).
  double min_step_rad = 1e-3;
  // Newton iterations allowed to a line-search trial's forward solve (it starts at the linear
  // prediction, so a trial that needs more is a step too long, e.g. a snap-through): rejected.
  // Trials are solved to the tolerance of every equilibrium: with a looser one (1000x, as
  // before) the optimizer accepted states that were not equilibria, and on strongly curved caps
  // the equilibrium of the θ2 it returned was farther from the target than θ2 = 0 (docs/design.md).
  int max_trial_forward_iterations = 4;
  // Newton iterations all the line searches' forward solves may take together (a work budget
  // that does not depend on the machine's speed).
  int max_forward_iterations = std::numeric_limits<int>::max();
  // θ2 stays within ±max_abs_theta2 (rad); empty: kShrinkMorphTheta2Bound (π/2), past
  // which the layer directions alias (plate/layer_stack.h). Steps are
  // projected onto the bound, and a vertex held at it is left out of the Gauss–Newton system.
  std::optional<double> max_abs_theta2;
  // The paths traced for a layer depart from its direction field by small angles that change from
  // face to face (stripe patterns trade alignment for even spacing: 1.3-2.9° rms per face and
  // layer on the paper's hat and top, read back from their plate.gcode). A design at a fold of
  // its equilibria turns into another shape under such errors, so E's distance term is the mean
  // over the nominal stack and path_error_samples stacks whose layer directions carry seeded
  // Gaussian errors of path_error_rad rms (rad, per face and layer, correlated over neighbouring
  // faces by path_error_smoothing_passes passes; the same on every run). Errors of about 1° that
  // vary over a couple of rings of faces turn the paper's top and hat into the shapes their own
  // plate.gcode prints, and independent errors do not; the traced paths' own errors, averaged
  // over a ring of faces, are 1.3-1.8° rms. A design for the mean under 2° errors holds under
  // them (the top's plate.gcode lands 0.62 % / 3.7 % from the target, against 0.84 % / 6.2 % for
  // 1.5° and 1.62 % / 7.7 % for 1°). 0 samples: the nominal stack alone (docs/design.md).
  double path_error_rad = 2.0 * std::numbers::pi / 180;
  int path_error_smoothing_passes = 2;
  int path_error_samples = 2;
  SimulationOptions forward;  // the equilibrium solves
  // Called after every iteration, and with the record that stopped it (no line-search trial) when
  // the optimization converges (progress lines); may be empty.
  std::function<void(const Theta2Iteration&)> progress;
};

struct Theta2Result {
  Eigen::VectorXd theta2;     // per vertex, rad
  Eigen::MatrixXd V;          // #V x 3, mm: the equilibrium for theta2, registered to the target
  Eigen::MatrixXd initial_V;  // the equilibrium for the starting theta2
  double objective = 0;
  double initial_objective = 0;
  double distance_term = 0;
  int iterations = 0;
  bool converged = false;
  // Converged: what stopped it. Otherwise one sentence for the user: why, and what to change.
  std::string stop_reason;
  std::vector<Theta2Iteration> history;
  double seconds = 0;
  double initial_seconds = 0;  // the first equilibrium (setup included)
  double cg_seconds = 0;       // in the Gauss–Newton solves
  double forward_seconds = 0;
  // Diagnostics: whether the first equilibrium converged, and how many factorizations of H needed a
  // diagonal shift (H not positive definite: the equilibrium is not a stable minimum, and the
  // sensitivities are approximate).
  bool initial_forward_converged = false;
  std::string initial_forward_warning;  // why it did not, in one sentence (empty when it did)
  int shifted_factorizations = 0;
  double theta2_bound = 0;    // the bound θ2 was kept within, rad
  int vertices_at_bound = 0;  // of the result
};

// The problem of a flattened target (flatten.h) printed in num_layers layers of `material`.
Theta2Problem theta2_problem(const FlatPlate& flat, const Material& material, int num_layers);

// The layer stack printed for theta2 (per vertex, rad; each face takes the mean of its corners).
LayerStack theta2_layer_stack(const Theta2Problem& problem, const Eigen::VectorXd& theta2);

// The plate printed with theta2 (per vertex, rad; each face takes the mean of its corners, as the
// optimization does), for simulate().
PlateProblem theta2_plate_problem(const Theta2Problem& problem, const Eigen::VectorXd& theta2);

// Minimizes E from theta2_start (per vertex, rad; empty means zeros), the first equilibrium solved
// from the target. Throws UserError on inconsistent sizes or a bad plate.
Theta2Result optimize_theta2(const Theta2Problem& problem, const Eigen::VectorXd& theta2_start,
                             const OptimizeTheta2Options& options = {});

// Samples of the paths' errors: Gaussian angle errors per face and layer (seeded: sample i is the
// same on every run), correlated over neighbouring faces by `smoothing_passes` passes of
// face -> corner -> face averaging, rms_rad rms (rad). The optimization uses samples 0 to
// path_error_samples - 1.
struct PathErrorModel {
  double rms_rad = 0;
  int smoothing_passes = 0;
  int first_sample = 0;
  int samples = 0;
};

// The equilibria (#V x 3, mm) of theta2's stack printed with each sample of the model's errors,
// each solved from `start` (#V x 3, mm; empty: the target).
std::vector<Eigen::MatrixXd> theta2_equilibria_under_path_errors(
    const Theta2Problem& problem, const Eigen::VectorXd& theta2, const PathErrorModel& model,
    const SimulationOptions& forward = {}, const Eigen::MatrixXd& start = {});

// E at theta2 (per vertex, rad), the equilibrium solved from `start` (#V x 3, mm; e.g. the
// target), and with `with_gradient` its adjoint gradient (Eq. 14; one more factorization of H and
// a solve).
struct Theta2Evaluation {
  double objective = 0;
  Eigen::VectorXd gradient;  // empty without with_gradient or when H could not be factorized
  Eigen::MatrixXd V;         // the equilibrium, #V x 3, mm
  bool forward_converged = false;
};
Theta2Evaluation evaluate_theta2_objective(const Theta2Problem& problem,
                                           const Eigen::VectorXd& theta2,
                                           const Eigen::MatrixXd& start,
                                           const OptimizeTheta2Options& options = {},
                                           bool with_gradient = true);

}  // namespace flatmorph
