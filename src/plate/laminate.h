// From what is printed to what the plate wants to be and how stiff it is: per face, the rest
// fundamental forms (ā, b̄) and the laminate stiffness, by classical lamination theory.
//
// After heating, layer k's rest metric in the plate's frame is C̄_k(z) = R(θ_k) diag(λ1_k(z)²,
// λ2_k²) R(θ_k)ᵀ (Shrink & Morph Eq. 6 and 15), with z the height above the mid-plane of the face's
// POST-heating thickness (layer k is λ3_k times its printed thickness thick; z points to the top of
// the print). A deformed mid-surface with fundamental forms a, b has the metric a − 2 z b at height
// z (Kirchhoff), so the face stores the elastic energy (per unit rest area)
//   W = ¼ Σ_k ∫_k ‖a − 2 z b − C̄_k(z)‖²_{P_k} dz,                                        (Eq. 2-4)
// with P_k the orthotropic norm of layer k's material turned to θ_k and measured relative to its
// own rest metric (material_norm below). W is quadratic in s = (a00, a11, a01, b00, b11, b01):
//   W = ¼ (s − s̄)ᵀ K (s − s̄) + const,  K = [[A, −2B], [−2B, 4D]],
// A = Σ ∫ P_k, B = Σ ∫ z P_k, D = Σ ∫ z² P_k the membrane, coupling and bending stiffness, and s̄ =
// (ā, b̄) the stiffness-weighted least-squares fit C̄(z) ≈ ā − 2 z b̄ (Eq. 1). For layers of one
// material and one direction, B = 0, ā = (1/t) ∫ C̄, b̄ = −(6/t³) ∫ z C̄ and W is the orthotropic
// energy of Eq. 8 (t/4 ‖a − ā‖² + t³/12 ‖b − b̄‖²); a PLA layer on a soft TPU layer bends as
// Timoshenko's bilayer does. The simulator compares these with the forms a, b of the deformed
// mid-surface (b = −dnᵀdφ, positive where the surface bends toward its normal, i.e. toward the top:
// docs/conventions.md).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "material/material.h"
#include "plate/layer_stack.h"

namespace flatmorph {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// Orthotropic stiffness of one material (Eq. 4). MPa, though only ratios change a predicted shape.
struct Stiffness {
  double young_modulus_along = 10.0;  // E1, along the deposition direction
  double young_modulus_across = 1.0;  // E2
  double poisson_ratio = 0.4;         // ν
};

Stiffness stiffness_of(const Material& material);

// The 3x3 Voigt matrix C of Eq. 4 (Li and Barbič 2014):
// 1/(1−ν²) [[E1, ν√(E1E2), 0], [ν√(E1E2), E2, 0], [0, 0, (1−ν)/2 √(E1E2)]].
Eigen::Matrix3d orthotropic_elasticity_tensor(const Stiffness& stiffness);

// The norm P of a layer whose rest metric is `rest_metric` (plate frame) and whose stiff direction
// is at `material_angle` (rad), over the components (X00, X11, X01) of a symmetric tensor X in the
// plate's frame: Xᵀ P X = √det c̄ ‖Voigt(R(θ)ᵀ c̄⁻¹ X R(θ))‖²_C, Voigt(E) = (E00, E11, E01 + E10)
// (Eq. 3-4, the rest area factor √det c̄ of Eq. 2 folded in).
Eigen::Matrix3d material_norm(const Eigen::Matrix2d& rest_metric, double material_angle,
                              const Stiffness& stiffness);

// Per face, in the plate's frame (pulled back to the flat plate).
struct RestForms {
  std::vector<Eigen::Matrix2d> rest_first_fundamental_form;   // ā, dimensionless
  std::vector<Eigen::Matrix2d> rest_second_fundamental_form;  // b̄, 1/mm
  // K of W = ¼ (s − s̄)ᵀ K (s − s̄); blocks in MPa·mm (membrane), MPa·mm² (coupling), MPa·mm³.
  std::vector<Matrix6d> stiffness;
  Eigen::VectorXd thickness;  // t, mm, after heating
  // Σ_k τ_k E1_k (MPa·mm): the energy per unit area of a unit strain, the scale stopping
  // tolerances are relative to.
  Eigen::VectorXd energy_scale;

  int num_faces() const { return static_cast<int>(thickness.size()); }
};

// (ā, b̄) as the 6-vector s̄ = (ā00, ā11, ā01, b̄00, b̄11, b̄01) and back.
Vector6d rest_vector(const Eigen::Matrix2d& a_bar, const Eigen::Matrix2d& b_bar);

// The rest forms and stiffness of every face of the stack, integrated exactly (λ1 linear within
// each layer). Throws UserError (check_layer_stack) for an inconsistent stack.
RestForms laminate(const LayerStack& stack);

// How the rest forms move when every layer's direction turns: d/dp of K and s̄ per face when layer
// k's θ_k grows by angle_rates[k] per unit of p (e.g. Shrink & Morph's θ2: rates w_k; θ1: all 1).
struct LaminateDerivative {
  std::vector<Matrix6d> stiffness;
  std::vector<Vector6d> rest;
};

// laminate(stack), and its exact derivative along angle_rates (one per layer, rad per unit of p).
RestForms laminate(const LayerStack& stack, const std::vector<double>& angle_rates,
                   LaminateDerivative& derivative);

// The rest forms of faces of one material printed along one direction each: K = [[t P, 0],
// [0, (t³/3) P]] with P = material_norm(ā, material_angle, stiffness), the laminate of any stack
// of such layers. Per face ā (SPD), b̄ (1/mm), thickness (mm), material angle (rad).
RestForms single_material_rest_forms(const std::vector<Eigen::Matrix2d>& a_bar,
                                     const std::vector<Eigen::Matrix2d>& b_bar,
                                     const Eigen::VectorXd& thickness,
                                     const Eigen::VectorXd& material_angle,
                                     const Stiffness& stiffness);

// R(θ): the rotation of the plane by θ (radians, counter-clockwise).
Eigen::Matrix2d rotation(double theta);

// How the rest forms move when each face's layers change their shrink along the path and their
// printed thickness with a parameter of the face's own, p_f (the thickness-controlled methods'
// shrinkage σ, SCF 2020 §6: a face's σ sets both λ1 and the layer height h through the thickness
// curve). Per layer k and face f: lambda1[k](f) = dλ1_k(f)/dp_f (the layer's mean λ1; its Δλ1
// stays) and printed_thickness[k](f) = d printed_thickness_k(f)/dp_f (mm per unit of p); the
// layer's post-heating thickness λ3 h and every layer's height in the face follow.
struct LayerShrinkRates {
  std::vector<Eigen::VectorXd> lambda1;
  std::vector<Eigen::VectorXd> printed_thickness;
};

// laminate(stack), and per face its exact derivative dK_f/dp_f, ds̄_f/dp_f along `rates` (one
// entry per layer, each with one value per face; a face a layer does not cover ignores it).
// Throws std::invalid_argument when the rates do not match the stack's layers and faces.
RestForms laminate(const LayerStack& stack, const LayerShrinkRates& rates,
                   LaminateDerivative& derivative);

}  // namespace flatmorph
