// Stripe Patterns (Knöppel, Crane, Pinkall, Schröder 2015) on a flat plate, as Shrink & Morph
// §3.2.3 uses them: a complex value psi per vertex whose phase, the stripe phase, grows by 2 pi
// every `spacing` mm across the print direction, so that its 0 mod 2 pi isolines are equally
// spaced curves that follow the line field theta.
//
// On a flat plate one global frame with identity transport replaces the per-vertex tangent bases
// (notes §5.3). The line field enters as z_v = -e^{2 i theta_v}; its square root X_v, a unit vector
// at theta_v + pi/2 defined up to sign, is the direction in which the phase grows. Where the signs
// of X at the two ends of an edge disagree (dot product < 0) the edge "crosses sheets" and couples
// psi_j to the conjugate of psi_i.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/topology.h"

namespace flatmorph {

struct StripeOptions {
  double spacing = 0.4;  // mm between isolines (the frequency is nu = 2 pi / spacing, 1/mm)
  // Inverse power iteration stops when the residual |E psi - lambda M psi|_{M^-1} falls below
  // tolerance * nu^2 |psi|_M (a scale-free test: nu^2 is the stripe energy density), or after
  // max_iterations; both are counts, so results do not depend on the machine's speed. Iterating
  // to a tighter tolerance lowers the energy but lets the stripes drift from the field (the
  // energy trades alignment for fewer forks): 1e-4 (two or three iterations from these starts)
  // keeps them within a few degrees.
  double tolerance = 1e-4;
  int max_iterations = 50;
};

// The stripe pattern of one line field on a plate mesh.
struct StripePattern {
  Eigen::VectorXcd psi;  // per vertex, M-normalized (sum of m_v |psi_v|^2 = 1)
  // Per vertex the stripe phase arg(psi) in (-pi, pi], nudged 1e-9 rad away from 0 so that no
  // vertex lies exactly on an isoline (crossings are then the same seen from either face).
  Eigen::VectorXd vertex_phase;
  // Per edge e = (i, j) = topology.edges.row(e): the phase increment from i to j, in the sign of
  // X_i (alpha_j - alpha_i with alpha_i = vertex_phase(i)); edge_sign is -1 where the edge
  // crosses sheets (X_i . X_j < 0), +1 otherwise.
  Eigen::VectorXd edge_phase;
  Eigen::VectorXi edge_sign;
  // Per face: the stripe phase at the three corners in a sign consistent inside the face, each
  // corner's the previous one's plus the edge's increment; the phase is linear on the face, so
  // each level 2 pi k between the corner values is one straight piece of isoline. Around a fork the
  // last edge brings the phase back to corner 0 2 pi stripe_index higher. Meaningful only where
  // usable(f).
  Eigen::MatrixXd corner_phase;
  Eigen::VectorXi doubled_index;  // line-field singularity (line_field_doubled_index), != 0: skip
  Eigen::VectorXi stripe_index;   // phase winding around the face over 2 pi; != 0: a stripe fork
  // Faces the isolines cross: no field singularity, at most a simple fork (|stripe_index| <= 1),
  // and each edge's crossings the ones the face's corner phases give.
  std::vector<bool> usable;
  double eigenvalue = 0;  // Rayleigh quotient psi^T E psi / psi^T M psi, 1/mm^2
  double residual = 0;    // relative residual when the iteration stopped
  int iterations = 0;
};

// Number of isoline levels 2 pi k strictly between the phases a and b (rad): the crossings of a
// stretch of boundary whose phase runs from a to b. The extraction and the check of which faces it
// may trace count them the same way.
int count_phase_levels(double a, double b);

// Per face the direction of the pattern's isolines (rad, in (-pi/2, pi/2], from +x, CCW): the
// normal of the gradient of the face's linear phase. NaN where the face is not usable or the
// stripes fork in it (no single direction). V is #V x 2 (mm).
Eigen::VectorXd stripe_direction(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const StripePattern& pattern);

// Stripe patterns of a sequence of line fields on the same plate (one per printed layer): theta
// per vertex (rad, from +x, CCW). Each pattern is the smallest eigenvector of the connection
// Laplacian E of its field (Knöppel et al. 2015 §5: cotan weights, faces with a field singularity
// left out, negative weights of non-Delaunay edges clamped to 0) against the lumped mass M, by
// inverse power iteration on E + 1e-6 nu^2 M, from a start that is already a good stripe
// pattern, so that the iteration mostly heals defects:
// - the first field starts from its 1-form nu <X, dx> integrated along a breadth-first spanning
//   tree (stripes aligned everywhere, mismatched only across the tree's cuts);
// - each next field starts from the previous pattern advanced by the integrated change of the
//   1-form (warm start: stripes turn with the field and keep their offsets and forks);
// - a field equal to the previous one reuses its pattern.
// The sparsity pattern is analysed once. Deterministic. V is #V x 2 (mm).
std::vector<StripePattern> stripe_patterns(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                           const EdgeTopology& topology,
                                           const std::vector<Eigen::VectorXd>& theta_vertex,
                                           const StripeOptions& options);

// The patterns of fields close to earlier ones (theta_vertex[k] near previous_theta[k], whose
// pattern is previous[k]): each starts from its own earlier pattern advanced by the integrated
// change of the 1-form, so it keeps its forks and offsets, and the fields are solved side by side
// (TBB; each its own factorization). The same inverse power iteration and stopping rule as
// stripe_patterns. Deterministic.
std::vector<StripePattern> restripe_patterns(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                             const EdgeTopology& topology,
                                             const std::vector<Eigen::VectorXd>& theta_vertex,
                                             const std::vector<Eigen::VectorXd>& previous_theta,
                                             const std::vector<StripePattern>& previous,
                                             const StripeOptions& options);

}  // namespace flatmorph
