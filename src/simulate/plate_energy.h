// The discrete non-Euclidean plate energy (Shrink & Morph Eq. 2, 8-10) with exact gradient and
// Hessian, over the 3D positions of the plate's vertices.
//
// Per face f of the flat plate (rest area Â_f, mm²):
//   W_f = Â_f √det ā [ (t/4) ‖a − ā‖²_M + (t³/12) ‖b − b̄‖²_M ]                      (Eq. 2, 8)
// with a = FᵀF, F = [x1−x0, x2−x0][p1−p0, p2−p0]⁻¹ (Eq. 9), b = FᵀΛF the pulled-back second
// fundamental form from the triangle-averaged shape operator Λ (Eq. 10, normalized θ_e ℓ_e/(2A) as
// in notes §3.4; b > 0 where the surface bends toward its normal, docs/conventions.md), and the
// orthotropic material norm ‖ε‖²_M = ε_Mᵀ C ε_M, ε_M = Voigt(Rᵀ ā⁻¹ ε R), Voigt(E) = (E00, E11,
// E01 + E10), R = R(material_angle_f) (Eq. 3-4).
//
// Evaluation is cheap because b is linear in three scalars per face (docs/simulation.md):
//   b = Σ_e φ_e K_e,  φ_e = θ_e 2A/ℓ_e  (θ_e the signed dihedral angle at edge e, A the current
//   area, ℓ_e the current edge length), K_e = m̂_e m̂_eᵀ ℓ̂_e²/(2Â)² constant (m̂_e the unit normal of
// the rest edge in the plate, ℓ̂_e its rest length). Boundary edges contribute nothing.
// Each face is one element over its 3 vertices and the (up to) 3 vertices across its edges.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "material/material.h"
#include "plate/laminate.h"

namespace flatmorph {

// Orthotropic stiffness of the material norm (Eq. 4). MPa, though only the ratios change the
// predicted shape.
struct Stiffness {
  double young_modulus_along = 10.0;  // E1, along the material angle
  double young_modulus_across = 1.0;  // E2
  double poisson_ratio = 0.4;         // ν
};

Stiffness stiffness_of(const Material& material);

// The 3x3 Voigt matrix C of Eq. 4 (Li and Barbič 2014):
// 1/(1−ν²) [[E1, ν√(E1E2), 0], [ν√(E1E2), E2, 0], [0, 0, (1−ν)/2 √(E1E2)]].
Eigen::Matrix3d orthotropic_elasticity_tensor(const Stiffness& stiffness);

// Everything about the plate that does not change while the 3D positions do: per-face constants
// and the sparsity pattern of the Hessian. Build it with make_plate_energy.
struct PlateEnergy {
  struct FaceConstants {
    Eigen::Matrix2d inverse_rest_edges;  // [p1−p0, p2−p0]⁻¹
    // ε_M of the membrane term = membrane_map · (|u|², |v|², u·v) − membrane_offset, where u, v
    // are the current edges x1−x0, x2−x0; likewise ε_M of the bending term = bending_map · φ −
    // bending_offset. The maps fold in Voigt(Rᵀ ā⁻¹ · R), the rest triangle and the K_e.
    Eigen::Matrix3d membrane_map;
    Eigen::Vector3d membrane_offset;
    Eigen::Matrix3d bending_map;
    Eigen::Vector3d bending_offset;
    // Voigt(Rᵀ ā⁻¹ · R) as a map of (B00, B11, B01) of a symmetric B: bending_offset =
    // rest_strain_map · (b̄00, b̄11, b̄01).
    Eigen::Matrix3d rest_strain_map;
    double membrane_weight;  // Â √det ā t/4 (mm³)
    double bending_weight;   // Â √det ā t³/12 (mm⁵)
  };

  int num_vertices = 0;
  Eigen::MatrixXi F;
  // The 6 vertices of each face's element: its own 3, then the vertex across edge k (from corner
  // k to corner k+1) for k = 0, 1, 2, or -1 on the boundary.
  Eigen::Matrix<int, Eigen::Dynamic, 6, Eigen::RowMajor> element_vertices;
  std::vector<FaceConstants> faces;
  Eigen::Matrix3d elasticity;  // C of Eq. 4

  // Assembly: the lower triangle of the 3V x 3V Hessian (compressed, column-major), and for each
  // of its nonzeros the element entries that sum into it, in increasing face order (fixed order:
  // the sum does not depend on thread scheduling).
  Eigen::SparseMatrix<double> hessian_pattern;
  std::vector<int> gather_offsets;  // size nonZeros + 1
  std::vector<int> gather_sources;  // face * 324 + local column * 18 + local row
};

// Precomputes the energy of the flat plate (#V x 2, mm, counter-clockwise faces) with per-face rest
// forms. Throws UserError when a face is clockwise or degenerate in the plate, the rest forms do
// not have one entry per face, ā is not positive definite or a thickness is not positive.
PlateEnergy make_plate_energy(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                              const RestForms& rest_forms, const Stiffness& stiffness);

// The energy (MPa·mm³ = mJ) at the 3D positions x = (x0, y0, z0, x1, ...) in mm. Optionally the
// gradient (size 3V) and the Hessian (lower triangle, the pattern of energy.hessian_pattern), with
// each face's 18x18 Hessian projected onto the PSD cone when `project` is true. Deterministic and
// parallel (TBB). Returns +inf when a face is degenerate (zero area) in x.
double evaluate_plate_energy(const PlateEnergy& energy, const Eigen::VectorXd& x,
                             Eigen::VectorXd* gradient, Eigen::SparseMatrix<double>* hessian,
                             bool project);

// E1 · Σ_f Â_f t_f (mJ): the energy of a unit strain, the scale Newton's stopping tolerance is
// relative to, so that the stopping point does not depend on the plate's size or units.
double unit_strain_energy(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                          const Eigen::VectorXd& thickness, const Stiffness& stiffness);

// The two terms of Eq. 8 separately (membrane, bending), for reports and tests.
Eigen::Vector2d plate_energy_terms(const PlateEnergy& energy, const Eigen::VectorXd& x);

// Replaces the rest second fundamental forms b̄ (1/mm, one per face) without rebuilding the rest:
// the inverse design moves b̄ at every iteration. Throws UserError when the count is wrong.
void set_rest_second_fundamental_forms(PlateEnergy& energy,
                                       const std::vector<Eigen::Matrix2d>& rest_second_forms);

// The mixed second derivative ∂²W/∂x∂s_f when each face's b̄_f moves along a direction:
// b̄_f(s) = b̄_f + s_f G_f. W is quadratic in b̄, so column f is −2 Â√det ā (t³/12) (∂ε_b/∂x)ᵀ C
// ε_M(G_f), with ε_b the bending strain in the material frame (notes §4.2). Returns the 3V x F
// sparse matrix at positions x (mm), in mJ per mm per unit of s.
Eigen::SparseMatrix<double> rest_curvature_mixed_derivative(
    const PlateEnergy& energy, const Eigen::VectorXd& x,
    const std::vector<Eigen::Matrix2d>& directions);

// φ_e = θ_e · 2A/ℓ_e for the hinge at edge (i → j) of the face (i, j, k), with l the vertex across
// the edge; θ_e > 0 when the hinge bends toward the face's normal (x_j − x_i) × (x_k − x_i).
// Exposed for tests.
double hinge_bending_measure(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                             const Eigen::Vector3d& xk, const Eigen::Vector3d& xl);

}  // namespace flatmorph
