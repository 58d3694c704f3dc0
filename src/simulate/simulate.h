// Predicting the shape a printed plate takes in hot water: the equilibrium of the plate energy
// (plate_energy.h) found by Newton's method (numerics/newton.h).
//
// Rigid motions are removed exactly by a 3-2-1 constraint on the plate's central face (the face
// whose rest centroid is nearest the mean of the plate's vertices): the start shape is moved so
// that this face's first vertex is at the origin, its first edge along +x and the face in the xy
// plane; then x, y, z of its first vertex, y, z of its second and z of its third are fixed, which
// removes the six rigid motions and nothing else (the face stays free to stretch and bend). The
// result is moved back, so it stays registered to the start shape at that face
// (docs/simulation.md).
//
// The stimulus is applied at once when it can be. When Newton's states keep a face collapsed
// (squeezed to under a tenth of its rest metric along some direction, far past where the membrane
// energy, quadratic in the metric, softens), the plate creases instead of bending and Newton
// crawls (a disk printed along its radii, from its first in-plane steps): that solve is abandoned,
// and the rest forms go from the start shape's own forms to the plate's in steps, each solved from
// the last equilibria, a step halved while a face stays collapsed in it, down to an eighth of the
// stimulus (docs/simulation.md).
#pragma once

#include <Eigen/Core>
#include <string>

#include "numerics/newton.h"
#include "plate/laminate.h"
#include "simulate/plate_energy.h"

namespace flatmorph {

// What to simulate: the flat plate and what it wants to become.
struct PlateProblem {
  Eigen::MatrixXd plate;  // #V x 2, mm, the printed plate
  Eigen::MatrixXi F;      // #F x 3, counter-clockwise in the plate
  RestForms rest_forms;   // per face ā, b̄ (1/mm), stiffness, thickness (mm): laminate(stack)
};

struct SimulationOptions {
  // Newton iterations in all, over every step of the stimulus.
  int max_iterations = 1000;
  // Newton stops when its decrement (predicted energy decrease) is below relative_tolerance times
  // the energy scale E1 · Σ_f Â_f t_f (the energy of a unit strain), so the stopping point does not
  // depend on the plate's size or units.
  double relative_tolerance = 1e-12;
  // Wall-clock seconds the whole call may take: a last resort against a solve that crawls. A run
  // that reaches it depends on the machine's speed (its result is not reproducible byte for byte),
  // so the default is far above what any plate flatmorph designs needs.
  double max_seconds = 300;
};

struct SimulationResult {
  Eigen::MatrixXd V;             // #V x 3, mm: the equilibrium (or the best state reached)
  double energy = 0.0;           // mJ (MPa·mm³)
  double membrane_energy = 0.0;  // the two terms of Eq. 8
  double bending_energy = 0.0;
  int iterations = 0;  // Newton iterations in all (abandoned solves included)
  int projected_iterations = 0;
  // The stimulus was applied in this many steps, each solved to an equilibrium (1: at once).
  int stimulus_steps = 1;
  bool converged = false;
  NewtonStatus status = NewtonStatus::kIterationLimit;
  // Empty when converged; else one sentence: why the solve stopped (iteration or time budget,
  // stalled, NaN...), that the best finite state reached is returned in V, and what to change.
  std::string warning;
  double seconds = 0.0;  // wall clock, whole call
  // From Newton: evaluation (energy, gradient, Hessian), factorization, solves, line search.
  double assembly_seconds = 0.0;
  double factorization_seconds = 0.0;
  double solve_seconds = 0.0;
  double line_search_seconds = 0.0;
};

// The equilibrium reached from `start` (#V x 3, mm; e.g. the target surface, as the inverse
// problem needs). Throws UserError on inconsistent sizes or a bad plate (see make_plate_energy);
// numerical trouble is reported in the result (converged = false, status, warning), not thrown,
// and V is always finite.
SimulationResult simulate(const PlateProblem& problem, const Eigen::MatrixXd& start,
                          const SimulationOptions& options = {});

// Why the solve ended, for run records (design.json's sim_stop_reason keys): "converged", or the
// one sentence of `warning`.
std::string stop_reason(const SimulationResult& result);

// The forward prediction's start: the flat plate at z = 0 plus a small bump that follows the sign
// of the rest curvature, z = ½ ε (p − c)ᵀ B (p − c), with B the area-weighted mean of b̄ over the
// plate, c the mean vertex and ε = 0.01, so that the plate leaves the flat (unstable) state on the
// side it is programmed to bend to. Flat where B = 0.
Eigen::MatrixXd flat_start(const PlateProblem& problem);

// Simulation from a given shape and from the flat plate, and whether they disagree (several stable
// shapes, paper §6): `multistable` when, after a rigid alignment, some vertex differs by more than
// `tolerance_percent` of the bounding-box diagonal of the first result.
struct ForwardComparison {
  SimulationResult from_start;
  SimulationResult from_flat;
  double max_difference_mm = 0.0;
  double max_difference_percent = 0.0;
  bool multistable = false;
};

ForwardComparison simulate_from_start_and_flat(const PlateProblem& problem,
                                               const Eigen::MatrixXd& start,
                                               const SimulationOptions& options = {},
                                               double tolerance_percent = 1.0);

}  // namespace flatmorph
