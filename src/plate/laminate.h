// From what is printed to what the plate wants to be: per-face rest fundamental forms.
//
// After heating, each layer's rest metric in the plate's frame is C̄_k(z') = R(θ_k) diag(λ1_k(z')²,
// λ2_k²) R(θ_k)ᵀ (Shrink & Morph Eq. 6 and 15). Integrating it through the POST-heating thickness
// (layer k is λ3_k times its printed thickness; z' measured from the mid-plane toward the top of
// the print, z' in [-t/2, t/2]) and fitting C̄(z') ≈ ā − 2 z' b̄ (Eq. 1) in the least-squares sense
// gives ā = (1/t) ∫ C̄ dz' and b̄ = −(6/t³) ∫ z' C̄ dz'. The plate energy then compares these with the
// fundamental forms a, b of the deformed mid-surface (b = −dnᵀdφ, positive where the surface bends
// toward its normal, i.e. toward the top: docs/conventions.md).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "material/material.h"
#include "plate/layer_stack.h"

namespace flatmorph {

// Per face, in the plate's frame (pulled back to the flat plate).
struct RestForms {
  std::vector<Eigen::Matrix2d> rest_first_fundamental_form;   // ā, dimensionless
  std::vector<Eigen::Matrix2d> rest_second_fundamental_form;  // b̄, 1/mm
  Eigen::VectorXd thickness;                                  // t, mm, after heating
  Eigen::VectorXd material_angle;  // rad: the stiff direction (E1) of the face's material norm

  int num_faces() const { return static_cast<int>(thickness.size()); }
};

// The rest forms of every face of the stack, integrated exactly (λ1 linear within each layer).
// material_angle is the thickness-weighted axial mean of the covered layers' θ (the angle of
// Σ τ_k e^{2iθ_k}, halved), which is θ1 for the Shrink & Morph stack. Throws UserError when a face
// is covered by no layer or a layer's arrays do not have one value per face.
RestForms laminate(const LayerStack& stack);

// The closed forms of the Shrink & Morph continuous model (Eq. 7, 15-17), first order in θ2 and
// Δλ1 as the inverse design needs them, over the post-heating thickness t = λ3 h
// (h = printed_thickness, mm):
//   ā = R(θ1) diag(λ1², λ2²) R(θ1)ᵀ
//   b̄ = θ2 (λ2² − λ1²)/(2t) R(θ1) [[0,1],[1,0]] R(θ1)ᵀ − (Δλ1 λ1 / t) R(θ1) [[1,0],[0,0]] R(θ1)ᵀ
// theta1, theta2 per face (rad); material_angle = θ1.
RestForms shrink_morph_rest_forms(const Eigen::VectorXd& theta1, const Eigen::VectorXd& theta2,
                                  const Material& material, double printed_thickness);

// R(θ): the rotation of the plane by θ (radians, counter-clockwise).
Eigen::Matrix2d rotation(double theta);

}  // namespace flatmorph
