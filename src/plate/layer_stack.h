// What is printed in each layer of a flat plate: the shared output of every design method
// (DESIGN.md, "a plate is a stack of printed layers").
//
// Layers are numbered from the bed up: layers[0] is layer 1, the one printed on the bed. Per-face
// quantities are indexed like the plate's faces. Angles in radians in the plate's frame, measured
// from +x counter-clockwise; thicknesses in mm; shrink ratios are new length / printed length.
#pragma once

#include <Eigen/Core>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "material/material.h"

namespace flatmorph {

// Per face, what layer k prints there.
struct Layer {
  Eigen::VectorXd printed_thickness;  // mm, before heating
  // Index into LayerStack::materials (the material is the tool that prints it), or kNotCovered
  // where this layer prints nothing (holes between tiles, hinge-only faces). The layers that do
  // cover a face are stacked without gaps in that face's laminate.
  Eigen::VectorXi material;
  Eigen::VectorXd theta;  // deposition direction (rad)
  // Shrink ratios after heating. lambda1 is the mean over the layer's thickness; delta_lambda1 is
  // lambda1 at the layer's top minus lambda1 at its bottom (lambda1 varies linearly through the
  // layer: the bilayer effect of Shrink & Morph §4.2 seen from one layer).
  Eigen::VectorXd lambda1;
  Eigen::VectorXd delta_lambda1;
  Eigen::VectorXd lambda2;
  Eigen::VectorXd lambda3;
  // The share of the face's area under the layer's beads, in (0, 1]: 1 for a solid layer, w /
  // spacing for a lattice's lines. The layer is printed_thickness thick where its beads lie and
  // absent between them, so its stiffness scales with the share (it bends as E s h³, not as a
  // plate s h thick: (s h)³ would make a sixth-covered lattice 36 times too soft).
  Eigen::VectorXd cover;

  static constexpr int kNotCovered = -1;
  bool covers(Eigen::Index face) const { return material(face) != kNotCovered; }
};

struct LayerStack {
  std::vector<Material> materials;  // materials[i] is printed by tool i
  std::vector<Layer> layers;        // bottom (on the bed) first

  int num_layers() const { return static_cast<int>(layers.size()); }
  int num_faces() const { return layers.empty() ? 0 : static_cast<int>(layers[0].theta.size()); }
};

// A layer of `num_faces` faces covered everywhere by material index `material` of the stack,
// printed `printed_thickness` mm thick along theta = 0 with that material's shrink ratios
// (lambda1 uniform through the layer); callers then set theta and what varies.
Layer uniform_layer(int num_faces, int material, const Material& properties,
                    double printed_thickness);

// The least and the greatest printed thickness of a face (the sum over the layers covering it),
// mm; {0, 0} for an empty stack.
std::pair<double, double> printed_thickness_range(const LayerStack& stack);

// Throws UserError (kOption) unless every layer gives one value per face, every covering material
// index names a material of the stack, thicknesses of covered faces are positive, every value is
// finite and every face is covered by at least one layer.
void check_layer_stack(const LayerStack& stack);

// The Shrink & Morph printing rule (paper §3.2.3 and §4.2), the only place that knows it:
// num_layers layers of layer_height mm of `material`, layer k (k = 1 on the bed) printed along
// theta^k = theta1 + w_k theta2 with w_k = shrink_morph_layer_weight(k, n), and lambda1 varying
// linearly through the whole printed thickness h as lambda1(z) = lambda1 + (z/h) delta_lambda1
// with z from the mid-plane toward the top (Eq. 15). theta1 and theta2 are per face (rad).
// Throws UserError on sizes that differ, num_layers < 1 or layer_height <= 0.
LayerStack shrink_morph_layer_stack(const Eigen::VectorXd& theta1, const Eigen::VectorXd& theta2,
                                    const Material& material, int num_layers, double layer_height);

// w_k = (k-1)/(n-1) - 1/2: where layer k (1 on the bed) sits in the plate's thickness, from -1/2
// (bed) to +1/2 (top); 0 for a single layer. d theta^k / d theta2 of the stack above.
double shrink_morph_layer_weight(int k, int num_layers);

// The largest |theta2| (rad) the design prints: π/2. theta2 is the angle from the bed layer's
// direction to the top layer's; two printed lines have no sign, so they make an angle of at most
// π/2, reached at |theta2| = π/2. Past it the outer layers' lines come closer again (at π − t as
// at t), the layer directions alias, and the design buys no new pair of outer directions, only
// stronger turns between neighbouring layers. On strongly curved test caps a bound of π/2 or 1.9
// rad ended 2-3x closer to the target than π or none (docs/design.md).
inline constexpr double kShrinkMorphTheta2Bound = std::numbers::pi / 2;

// The thickness-controlled printing rule of SCF 2020 (§6 "Material characterization", §6.4) and
// Geodesy (CHI 2019 §3), the only place that knows it: every face prints num_layers identical
// layers (SCF 2020 §6.4 stacks 6 copies of one layer at nozzle heights z_k = k h) along
// `direction` (rad, per face), of the layer height h (mm) at which the material's thickness curve
// shrinks by the face's wanted `shrinkage` σ (a fraction, 1 − λ1: thinner layers shrink more), with
// λ1 the curve at that h, so that the printed height and the predicted shrink come from one curve.
// λ2, λ3 are the material's; its Δλ1 (0 for the papers' sheet, printed "symmetric along the
// thickness", SCF 2020 §8) varies λ1 through each face's whole thickness as Shrink & Morph Eq. 15
// does. num_layers defaults to the layers of the curve's calibration samples (6 for pla-geodesy):
// the shrink was measured on that many.
//
// A σ the curve cannot reach is clamped to the reachable range (reachable_shrinkage) and flagged,
// never refused: a design method reports such faces as invalid (SCF 2020 §8, Table 1 "Inv.") and
// prints the nearest shrink (printed_shrinkage, thickness_curve.h, the conversion the paths share).
// Throws UserError (kOption) when the material has no thickness curve or num_layers < 1;
// std::invalid_argument on sizes that differ or a non-finite σ (a caller's bug).
struct ThicknessControlledStack {
  LayerStack stack;
  Eigen::VectorXd shrinkage;  // per face, σ printed: the wanted one clamped to the reachable range
  // Per face: 0 where σ was reachable, -1 where it was below the least shrink the curve gives
  // (raised to it; σ < 0 asks the path to grow), +1 where above the greatest (lowered to it).
  Eigen::VectorXi clamped;

  int num_clamped() const { return static_cast<int>((clamped.array() != 0).count()); }
};

ThicknessControlledStack thickness_controlled_layer_stack(
    const Eigen::VectorXd& direction, const Eigen::VectorXd& shrinkage, const Material& material,
    std::optional<int> num_layers = std::nullopt);

// A per-vertex field averaged to faces (the plain mean of the three corners), as the paper does
// for theta2 (§3.2.2).
Eigen::VectorXd vertex_to_face_average(const Eigen::MatrixXi& F, const Eigen::VectorXd& values);

}  // namespace flatmorph
