// The discrete non-Euclidean plate energy (Shrink & Morph Eq. 2, 8-10) of a laminate with exact
// gradient and Hessian, over the 3D positions of the plate's vertices.
//
// Per face f of the flat plate (rest area Â_f, mm²), with the laminate's rest forms and stiffness
// (plate/laminate.h):
//   W_f = Â_f ¼ (s − s̄)ᵀ K (s − s̄),  s = (a00, a11, a01, b00, b11, b01)                 (Eq. 2, 8)
// with a = FᵀF, F = [x1−x0, x2−x0][p1−p0, p2−p0]⁻¹ (Eq. 9), and b = FᵀΛF the pulled-back second
// fundamental form from the triangle-averaged shape operator Λ (Eq. 10, normalized θ_e ℓ_e/(2A) as
// in notes §3.4; b > 0 where the surface bends toward its normal, docs/conventions.md). K couples
// membrane and bending where the laminate is not symmetric through the thickness.
//
// Evaluation is cheap because s is linear in six scalars per face, r = (|u|², |v|², u·v, φ_0, φ_1,
// φ_2) for the current edges u = x1−x0, v = x2−x0 and the hinges φ_e = θ_e 2A/ℓ_e (θ_e the signed
// dihedral angle at edge e, A the current area, ℓ_e the current edge length): a = Dᵀ G D with D the
// inverse rest edges, b = Σ_e φ_e m̂_e m̂_eᵀ ℓ̂_e²/(2Â)² (m̂_e the unit normal of the rest edge in the
// plate, ℓ̂_e its rest length; boundary edges contribute nothing): s = T r (docs/simulation.md).
// Each face is one element over its 3 vertices and the (up to) 3 vertices across its edges.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "material/material.h"
#include "plate/laminate.h"

namespace flatmorph {

// Everything about the plate that does not change while the 3D positions do: per-face constants
// and the sparsity pattern of the Hessian. Build it with make_plate_energy.
struct PlateEnergy {
  struct FaceConstants {
    Eigen::Matrix2d inverse_rest_edges;  // [p1−p0, p2−p0]⁻¹
    Matrix6d strain_map;                 // T: s = T r, block diagonal (membrane, bending)
    double rest_area = 0;                // Â, mm²
    // Set from the rest forms (set_rest_forms): s̄, the weighted stiffness K' = Â K / 2 (so that
    // W = ½ (T r − s̄)ᵀ K' (T r − s̄)), and Tᵀ K' T, the Hessian of W in r.
    Vector6d rest;
    Matrix6d weighted_stiffness;
    Matrix6d stiffness_in_r;
  };

  int num_vertices = 0;
  Eigen::MatrixXi F;
  // The 6 vertices of each face's element: its own 3, then the vertex across edge k (from corner
  // k to corner k+1) for k = 0, 1, 2, or -1 on the boundary.
  Eigen::Matrix<int, Eigen::Dynamic, 6, Eigen::RowMajor> element_vertices;
  std::vector<FaceConstants> faces;

  // Assembly: the lower triangle of the 3V x 3V Hessian (compressed, column-major), and for each
  // of its nonzeros the element entries that sum into it, in increasing face order (fixed order:
  // the sum does not depend on thread scheduling).
  Eigen::SparseMatrix<double> hessian_pattern;
  std::vector<int> gather_offsets;  // size nonZeros + 1
  std::vector<int> gather_sources;  // face * 324 + local column * 18 + local row
};

// Precomputes the energy of the flat plate (#V x 2, mm, counter-clockwise faces) with per-face rest
// forms and stiffness (plate/laminate.h). Throws UserError when a face is clockwise or degenerate
// in the plate, the rest forms do not have one entry per face, a stiffness is not positive definite
// or a thickness is not positive.
PlateEnergy make_plate_energy(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                              const RestForms& rest_forms);

// The energy (MPa·mm³ = mJ) at the 3D positions x = (x0, y0, z0, x1, ...) in mm. Optionally the
// gradient (size 3V) and the Hessian (lower triangle, the pattern of energy.hessian_pattern), with
// each face's 18x18 Hessian projected onto the PSD cone when `project` is true. Deterministic and
// parallel (TBB). Returns +inf when a face is degenerate (zero area) in x.
double evaluate_plate_energy(const PlateEnergy& energy, const Eigen::VectorXd& x,
                             Eigen::VectorXd* gradient, Eigen::SparseMatrix<double>* hessian,
                             bool project);

// Σ_f Â_f Σ_k τ_k E1_k (mJ): the energy of a unit strain, the scale Newton's stopping tolerance is
// relative to, so that the stopping point does not depend on the plate's size or units.
double unit_strain_energy(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                          const RestForms& rest_forms);

// The forms of every face at the positions x (mm), as the energy sees them: s = (a00, a11, a01,
// b00, b11, b01) with a the pulled-back metric (dimensionless) and b the pulled-back second
// fundamental form (1/mm). At these rest forms the shape x has zero energy (the simulator's
// staged stimulus starts from a start shape's own forms).
std::vector<Vector6d> plate_forms(const PlateEnergy& energy, const Eigen::VectorXd& x);

// How far the most compressed face is squeezed at x (mm), relative to its rest metric ā: the
// smallest, over faces and directions v of the plate, of the squared stretch (vᵀ a v)/(vᵀ ā v)
// (1 at rest, 0 for a face collapsed onto a line).
double smallest_metric_ratio(const PlateEnergy& energy, const Eigen::VectorXd& x);

// The energy split into membrane and bending terms (the membrane-bending coupling split evenly),
// for reports and tests.
Eigen::Vector2d plate_energy_terms(const PlateEnergy& energy, const Eigen::VectorXd& x);

// Replaces the rest forms and stiffness (same plate, same faces) without rebuilding the rest: the
// inverse design moves them at every iteration. Throws UserError when the count is wrong.
void set_rest_forms(PlateEnergy& energy, const RestForms& rest_forms);

// The mixed second derivative ∂²W/∂x∂p_f when each face's rest forms move with a parameter of its
// own: d K_f/dp_f and d s̄_f/dp_f (laminate.h's LaminateDerivative). Column f is
// Â_f/2 (∂s/∂x)ᵀ (dK (s − s̄) − K ds̄). Returns the 3V x F sparse matrix at positions x (mm), in mJ
// per mm per unit of p.
Eigen::SparseMatrix<double> rest_forms_mixed_derivative(const PlateEnergy& energy,
                                                        const Eigen::VectorXd& x,
                                                        const LaminateDerivative& derivative);

// φ_e = θ_e · 2A/ℓ_e for the hinge at edge (i → j) of the face (i, j, k), with l the vertex across
// the edge; θ_e > 0 when the hinge bends toward the face's normal (x_j − x_i) × (x_k − x_i).
// Exposed for tests.
double hinge_bending_measure(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                             const Eigen::Vector3d& xk, const Eigen::Vector3d& xl);

}  // namespace flatmorph
