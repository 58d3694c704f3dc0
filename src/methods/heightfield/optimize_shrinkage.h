// Beyond SCF 2020: the shrink σ printed along the isolines whose simulated risen shape comes
// closest to the target, with the flat plate and the print directions fixed (the paper prints the
// flattening's σ as it is; its §8 then measures the risen shape's distance). The method is Shrink &
// Morph's θ2 optimization (§3.2.2, methods/shrink_morph/optimize_theta2.h) with σ as the design
// variable:
//
// Design variables: σ per vertex of the printing graph (fractions), each face printing the mean of
// its corners (as face_shrinkage spreads the flattening's σ, shrinkage_field.h, and as Shrink &
// Morph averages θ2): half as many variables as faces, and a face's σ cannot jump against its
// neighbours'. σ stays within the thickness curve's reachable range (reachable_shrinkage).
//
// Objective, normalized like optimize_theta2's Eq. 13 so that the weights do not depend on the
// part's size or the mesh resolution:
//   E(σ) = min_{R,t} Σ_v m_v |R x_v(σ) + t − x_T,v|² / (A ℓ²) + w_L (σ/Δ)ᵀ L (σ/Δ)
// with m the lumped mass of the target (mm²), A its area, ℓ = 0.3 % of its bounding-box diagonal,
// (R, t) the best rigid motion (weighted Kabsch: the distance the prediction reports, independent
// of how the equilibrium is registered), L the cotan Laplacian of the target, Δ the width of the
// reachable range (so σ/Δ is dimensionless and of order 1), and x(σ) the equilibrium of the plate
// energy of the exact laminate of the printed layers (thickness_controlled_layer_stack: each face
// prints its σ at the layer height h(σ) of the curve, λ1 = 1 − σ).
//
// Gradient: adjoint (Shrink & Morph Eq. 14). With H the energy's Hessian at the equilibrium,
//   dE/dσ = −(∂g/∂σ)ᵀ H⁻¹ ∂D/∂x + 2 w_L L σ / Δ²,
// ∂g/∂σ = rest_forms_mixed_derivative · (face average), from the exact derivative of each face's
// laminate (stiffness and rest forms) with respect to its σ (laminate.h, LayerShrinkRates):
// dλ1/dσ = −1 and dh/dσ = −1 / λ1'(h), the thickness curve's slope at the face's layer height. By
// the envelope theorem the rigid motion's own derivative drops out of ∂D/∂x. Steps: projected
// Gauss–Newton, (Sᵀ 2D S + 2 w_L L / Δ²) Δσ = −g with S = dx/dσ = −H⁻¹ ∂g/∂σ solved matrix-free by
// conjugate gradients reusing the factor of H, on the vertices not held at a bound; Armijo
// backtracking along the step projected onto the range, each trial's equilibrium warm-started at
// the linear prediction x + S Δσ. The solver is the shared one of simulate/adjoint_design.h; this
// file holds what is σ's: its layer stack and derivative, range and regularizer.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "material/material.h"
#include "methods/heightfield/isoline_mesh.h"
#include "simulate/simulate.h"

namespace flatmorph {

struct ShrinkageProblem {
  Eigen::MatrixXd plate;      // #V x 2, mm, counter-clockwise faces
  Eigen::MatrixXi F;          // #F x 3
  Eigen::MatrixXd target;     // #V x 3, mm, one row per plate vertex
  Eigen::VectorXd direction;  // per face, rad: the deposition direction (deposition_directions)
  Material material;          // with a thickness curve
  // Layers the plate prints (the design's --layers); none: the thickness curve's calibrated count.
  std::optional<int> num_layers;
  // Where the first equilibrium is searched from (#V x 3, mm, any rigid placement); empty: the
  // target. The risen shape predicted from the flat sheet (predict_rise's from_flat.V) makes the
  // optimization follow the equilibrium the sheet actually reaches.
  Eigen::MatrixXd start;
};

struct ShrinkageIteration {
  int iteration = 0;
  double objective = 0;      // E at the start of the iteration
  double distance_term = 0;  // its first term
  double step = 0;           // accepted line-search step (0 when none)
  double decrement = 0;      // −½ gᵀΔσ: the decrease the Gauss–Newton model predicts
  int cg_iterations = 0;
  int forward_iterations = 0;  // Newton iterations of the line search's forward solves
  int line_search_trials = 0;
  int vertices_at_bound = 0;   // after the iteration
  double elapsed_seconds = 0;  // since the optimization started
};

struct OptimizeShrinkageOptions {
  double w_L = 1e-2;  // weight of the smoothness term (dimensionless)
  // The optimization is bounded so that the whole design stays interactive (a few seconds): on the
  // built-in examples (2-3 thousand vertices) an iteration takes 0.2-0.4 s on two cores and the
  // first ten do most of the work (the distance term falls 5-7x on the saddle, docs in the report).
  int max_iterations = 10;
  // The line searches' forward solves may take this many Newton iterations in all (each ~35 ms on
  // 4k faces, two cores); the iteration that spends the last of them is the final one. A work
  // budget rather than a time limit, so the result does not depend on the machine's speed. Most
  // designs stop earlier; a sheet near a fold (the 146 mm saddle) spends 10-20 per step there and
  // gains little, and the budget keeps the whole design under 5 s.
  int max_forward_iterations = 45;
  // Stop when the Gauss–Newton model predicts a decrease of E below this (E's distance term is the
  // mean squared distance in units of (0.3 % of the diagonal)²) or an iteration lowers E by less
  // than relative_decrease × E.
  double decrement_tolerance = 0.02;
  double relative_decrease = 1e-3;
  // Conjugate-gradient iterations for a Gauss–Newton step (each costs two solves with H's factor);
  // 30 gave the same progress per iteration as 100 on the examples, at a third of the cost.
  int max_cg_iterations = 30;
  double cg_tolerance = 1e-2;
  double armijo_constant = 1e-4;
  int max_line_search_steps = 12;  // halvings
  // The first trial changes no σ by more than this (a fraction), and the length accepted last
  // grows up to it (a trust radius): longer steps leave the range where the linear prediction
  // warm-starts the forward solve well.
  double max_step = 0.05;
  // Backtracking gives up when the largest change of σ falls below this: 0.2 % of shrink is about
  // 1 µm of layer height (the curve's slope is ~2 per mm), below what a printer resolves, and each
  // further halving costs a forward solve.
  double min_step = 2e-3;
  // Newton iterations a trial's forward solve may take from its linear prediction; more means the
  // step left the equilibrium branch (a snap): rejected. Near the optimum the risen shape's
  // Hessian can be indefinite and Newton then needs a few projected steps more: with 6, rounding
  // alone (another CPU's BLAS kernels) stalled the cap's optimization at 1.3 % of its size instead
  // of 0.11 %.
  int max_trial_forward_iterations = 10;
  // The equilibrium solves; the first (from problem.start) may take up to max_iterations Newton
  // iterations (300, as the prediction's), the line search's max_trial_forward_iterations.
  SimulationOptions forward{.max_iterations = 300};
  // Called after every iteration (may be empty).
  std::function<void(const ShrinkageIteration&)> progress;
};

struct ShrinkageResult {
  Eigen::VectorXd vertex_shrinkage;  // σ per vertex (fractions), within the reachable range
  Eigen::VectorXd face_shrinkage;    // σ per face: the mean of its corners', what is printed
  Eigen::MatrixXd V;                 // #V x 3, mm: the equilibrium, moved by the best rigid motion
  Eigen::MatrixXd initial_V;         // the same for the starting σ
  double objective = 0;
  double initial_objective = 0;
  double distance_term = 0;
  double initial_distance_term = 0;
  int iterations = 0;  // accepted steps
  bool converged = false;
  std::string stop_reason;  // converged: what stopped it; otherwise why, and what to change
  std::vector<ShrinkageIteration> history;
  double seconds = 0;
  double initial_seconds = 0;  // the first equilibrium (setup included)
  double forward_seconds = 0;
  double cg_seconds = 0;
  bool initial_forward_converged = false;
  int shifted_factorizations = 0;  // of H (not positive definite: an unstable equilibrium)
  int vertices_at_bound = 0;
};

// The starting σ per vertex from the flattening: vertex_shrinkage (shrinkage_field.h) clamped to
// the material's reachable range. Throws UserError (kOption) without a thickness curve.
Eigen::VectorXd initial_vertex_shrinkage(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                         const Eigen::VectorXd& edge_shrinkage,
                                         const Material& material);

// Minimizes E from `vertex_shrinkage_start` (σ per vertex, projected onto the range). Throws
// UserError on a material without a thickness curve, a bad plate or negative weights;
// std::invalid_argument on sizes that differ.
ShrinkageResult optimize_shrinkage(const ShrinkageProblem& problem,
                                   const Eigen::VectorXd& vertex_shrinkage_start,
                                   const OptimizeShrinkageOptions& options = {});

// E at σ (per vertex, within the range), the equilibrium solved from `start` (#V x 3, mm; empty:
// problem.start, else the target), and with `with_gradient` its adjoint gradient (per vertex;
// empty when H could not be factorized).
struct ShrinkageEvaluation {
  double objective = 0;
  double distance_term = 0;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd V;  // the equilibrium, #V x 3, mm, registered to the target at its central face
  bool forward_converged = false;
};
ShrinkageEvaluation evaluate_shrinkage_objective(const ShrinkageProblem& problem,
                                                 const Eigen::VectorXd& vertex_shrinkage,
                                                 const Eigen::MatrixXd& start,
                                                 const OptimizeShrinkageOptions& options = {},
                                                 bool with_gradient = true);

}  // namespace flatmorph
