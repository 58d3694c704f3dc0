// One Gauss–Newton step of the theta2 optimization (optimize_theta2.h) by either of two equivalent
// linear systems, for the test and the benchmark that compare them (docs/design.md). With D the
// distance term's diagonal (m_v / (A ℓ²) per free coordinate, so 2D = ∂²E/∂x²),
// R = 2 w_M M/A + 2 w_L L, H = ∂²W/∂x² and J = ∂²W/∂x∂θ2 at the equilibrium (fixed coordinates
// decoupled), S = −H⁻¹J:
//   reduced: (Sᵀ 2D S + R) Δθ = −g, g = Sᵀ ∂E/∂x + R θ2 (Eq. 14), by conjugate gradients, each
//            product two solves with the Cholesky factor of H (what optimize_theta2 uses);
//   KKT:     the SGN system of Zehnder et al. 2021 in (Δx, Δθ, λ), the stationarity conditions of
//            the same quadratic model under the linearized equilibrium H Δx + J Δθ = 0:
//              [ 2D 0  H ] [Δx]   [ −∂E/∂x ]
//              [ 0  R  Jᵀ] [Δθ] = [ −R θ2  ]
//              [ H  J  0 ] [λ ]   [  0     ]
//            by one sparse direct factorization; eliminating Δx and λ gives the reduced system.
#pragma once

#include <Eigen/Core>

#include "methods/shrink_morph/optimize_theta2.h"

namespace flatmorph {

enum class GaussNewtonSystem { kReducedCG, kKKT };

// The direct solver of the (symmetric indefinite) KKT matrix. The LDLᵀ ones do not pivot: they
// fail on an exact zero pivot (λ's diagonal is zero until the elimination of a neighbouring x fills
// it) and lose accuracy on small ones. Measured on the paper's saddle and hat in docs/design.md.
enum class KktSolver {
  kSparseLU,        // Eigen::SparseLU, COLAMD ordering, partial pivoting
  kSimplicialLDLT,  // Eigen::SimplicialLDLT, AMD on the scalar matrix
  kCholmodLDLT,     // CHOLMOD simplicial LDLᵀ, its own ordering (AMD or METIS)
  // The same two LDLᵀ, with AMD on the vertex graph and each vertex's unknowns in the order x, θ,
  // λ: x_v's pivots (2D > 0) fill λ_v's before it is eliminated.
  kSimplicialLDLTByVertex,
  kCholmodLDLTByVertex,
};

struct GaussNewtonStep {
  Eigen::VectorXd direction;  // Δθ2 per vertex, rad
  // S Δθ2 (3 per vertex, mm), in the frame of the target's central face (simulate/rigid_frame.h).
  Eigen::VectorXd dx;
  Eigen::VectorXd gradient;  // g (Eq. 14) at theta2, per vertex, in E's units per rad
  bool forward_converged = false;
  bool solved = false;    // false: H or the KKT matrix could not be factorized
  int cg_iterations = 0;  // reduced system only
  // ‖(Sᵀ 2D S + R) Δθ + g‖ / ‖g‖, measured after the step (not timed) for both systems.
  double reduced_residual = 0;
  // Wall-clock seconds of the step only: the forward solve and what optimize_theta2 needs with
  // either system (g for the line search, so H's factorization, reused from the forward solve)
  // are not counted. Reduced: CG and S Δθ. KKT: assembly (H and the matrix) + analysis (ordering,
  // symbolic; could be done once per optimization, the pattern does not change) + factorization +
  // solve.
  double seconds = 0;
  double assembly_seconds = 0, analysis_seconds = 0, factorization_seconds = 0, solve_seconds = 0;
  int kkt_rows = 0;          // 7 #V (Δx, Δθ, λ)
  long kkt_nonzeros = 0;     // both triangles
  long factor_nonzeros = 0;  // L (and U for SparseLU)
};

// Solves the equilibrium for theta2 (per vertex, rad) from problem.start (the target when empty),
// linearizes there and computes the Gauss–Newton step with `system` (options.cg_tolerance and
// max_cg_iterations for the reduced one, `kkt_solver` for the KKT one; the default is the fastest
// that never hit a zero pivot). Throws UserError on inconsistent sizes.
GaussNewtonStep theta2_gauss_newton_step(const Theta2Problem& problem,
                                         const Eigen::VectorXd& theta2, GaussNewtonSystem system,
                                         const OptimizeTheta2Options& options = {},
                                         KktSolver kkt_solver = KktSolver::kSimplicialLDLTByVertex);

}  // namespace flatmorph
