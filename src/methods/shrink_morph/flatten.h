// Shrink & Morph §3.2.1: the flat plate of a target surface and the plate's mean print directions
// theta1. The plate is the map psi: target -> plane whose differential has singular values as close
// as possible to (1/lambda1, 1/lambda2), so that printed paths shrinking by lambda1 along theta1
// and growing by lambda2 across it restore the target's metric (Eq. 11, optionally smoothed by Eq.
// 12). docs/flatten.md explains the steps, the conventions and the normalization of w_D.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/progress.h"
#include "material/material.h"
#include "mesh/mesh.h"

namespace flatmorph {

// How many initial stretch directions flatten() can start Eq. 11 from (FlattenOptions).
inline constexpr int kStretchCandidates = 4;

struct FlattenOptions {
  // Shrink ratios after heating (new length / printed length), dimensionless.
  double lambda1 = 0.58;  // along the print path
  double lambda2 = 1.08;  // across the path
  // The plate is scaled so that the largest extent of its bounding box is this many mm; the target
  // is scaled by the same factor.
  double width_mm = 100.0;
  // Weight of the direction-smoothness term of Eq. 12 (dimensionless, mesh- and scale-independent;
  // docs/flatten.md). 0 skips the smoothing step; the paper uses 0.1 on some models.
  double w_D = 0.0;
  // false: the side the target's face normals point to (right-hand rule) is the top of the plate,
  // away from the bed. true: that side is printed down (the face orientation is reversed first).
  bool flip = false;
  // Which direction of the ARAP plate gets the stretch 1/lambda1 that starts Eq. 11, and so which
  // local minimum the iterations reach (docs/flatten.md): candidate k in [0, kStretchCandidates)
  // is phi0 + k pi/4, phi0 the best single direction for the ARAP plate (phi0 - k pi/4 with `flip`,
  // so that candidate k of the flipped target is the mirror image of candidate k). -1 (default):
  // the candidate with the lowest Eq. 11 energy after a few iterations.
  int stretch_candidate = -1;
  // The anisotropic local/global iterations stop when the area-weighted RMS change of the
  // singular values between two iterations is below `tolerance` times their area-weighted RMS
  // distance to (1/lambda1, 1/lambda2) (so a target that can be met exactly is iterated until it
  // is), or after `max_iterations` (with a warning). The isotropic ARAP start uses the same rule.
  double tolerance = 1e-3;
  int max_iterations = 10000;
  // Eq. 12 Newton stops when the Newton decrement is below `newton_tolerance` (the energy is
  // dimensionless), or after `max_newton_iterations` (with a warning).
  double newton_tolerance = 1e-10;
  int max_newton_iterations = 200;
  // Stage "flatten": one report after each phase (Tutte, ARAP, anisotropic, smoothing).
  ProgressCallback progress;
};

// How far the plate's differential is from the one printing can make: per face the relative
// deviation max(|sigma1 lambda1 - 1|, |sigma2 lambda2 - 1|) of the singular values sigma1 >= sigma2
// of the target -> plate map from (1/lambda1, 1/lambda2). Dimensionless.
struct ShrinkFeasibility {
  double mean_deviation = 0;  // area-weighted over the target
  double max_deviation = 0;
  double infeasible_area_fraction = 0;  // target area whose deviation exceeds the tolerance (5 %)
};

// Iterations and wall time of one step of the flattening.
struct FlattenStep {
  std::string name;  // "tutte", "arap", "anisotropic", "smoothing"
  int iterations = 0;
  double seconds = 0;
  bool converged = true;
};

struct FlatPlate {
  // The target as the design uses it: scaled by the plate's factor (about its bounding-box centre)
  // and, with `flip`, with every face reversed. Same vertex and face order as `plate`. mm.
  Mesh target;
  // #V x 2 plate positions in mm, bounding box centred on the origin; every triangle is
  // counter-clockwise seen from +z (positive signed area).
  Eigen::MatrixXd plate;
  // Per face: the print direction, the plate direction of maximal shrink, in radians from +x,
  // counter-clockwise, in [-pi/2, pi/2).
  Eigen::VectorXd theta1;
  Eigen::MatrixXd singular_values;  // #F x 2, sigma1 >= sigma2 of target -> plate (aim 1/lambda)
  Eigen::VectorXd sv_deviation;     // #F, the relative deviation of ShrinkFeasibility
  ShrinkFeasibility feasibility;
  double direction_dirichlet = 0;  // direction_dirichlet_energy of theta1 (dimensionless)
  int stretch_candidate = 0;       // the initial stretch direction used (FlattenOptions)
  std::vector<FlattenStep> steps;
  std::vector<std::string> warnings;  // e.g. an iteration cap that was hit
};

// The defaults with the material's shrink ratios, a plate `width_mm` mm wide and the Eq. 12 weight
// w_D (dimensionless).
FlattenOptions flatten_options(const Material& material, double width_mm, double w_D = 0.0);

// Flattens a disk-like target (one component, one boundary loop; units arbitrary, the result is in
// mm through options.width_mm): Tutte embedding on a circle, isotropic ARAP, alignment and stretch
// by (1/lambda1, 1/lambda2), anisotropic local/global (Eq. 11), then, if w_D > 0, projected Newton
// on Eq. 12. Deterministic. Throws UserError(kOption) for out-of-range options and
// UserError(kTopology) when the target is not a disk.
FlatPlate flatten(const Mesh& target, const FlattenOptions& options);

// The quantities below work on any target/plate pair with the same faces (e.g. a flat.ply read
// back). `plate` is #V x 2 (or #V x 3 with z ignored), in the same units as `target_V`.

// Per face sigma1 >= sigma2 (signed: sigma2 < 0 on a flipped triangle) of the differential of the
// target -> plate map. #F x 2, dimensionless.
Eigen::MatrixXd plate_singular_values(const Eigen::MatrixXd& target_V, const Eigen::MatrixXi& F,
                                      const Eigen::MatrixXd& plate);

// Per face theta1: the minor eigenvector of the pulled-back metric I = D^T D, D the plate -> target
// deformation gradient, i.e. the plate direction that shrinks most. Radians from +x, CCW, in
// [-pi/2, pi/2).
Eigen::VectorXd theta1_per_face(const Eigen::MatrixXd& target_V, const Eigen::MatrixXi& F,
                                const Eigen::MatrixXd& plate);

// Per face relative deviation of `singular_values` (from plate_singular_values) from
// (1/lambda1, 1/lambda2).
Eigen::VectorXd shrink_deviation(const Eigen::MatrixXd& singular_values, double lambda1,
                                 double lambda2);

// Mean (weighted by `face_areas`), max, and the area fraction above `tolerance`.
ShrinkFeasibility shrink_feasibility(const Eigen::VectorXd& deviation,
                                     const Eigen::VectorXd& face_areas, double tolerance = 0.05);

// Dirichlet energy of the face-constant unit field u = e^{2 i theta1} on the target:
// sum over interior edges e = (f, g) of w_e |u_f - u_g|^2 = w_e 4 sin^2(theta1_f - theta1_g), with
// w_e = 3 l_e^2 / (2 (A_f + A_g)) (edge length over the distance between the face centroids across
// the edge). Dimensionless and independent of the mesh resolution; approximates int |grad u|^2 dA.
double direction_dirichlet_energy(const Eigen::MatrixXd& target_V, const Eigen::MatrixXi& F,
                                  const Eigen::VectorXd& theta1);

}  // namespace flatmorph
