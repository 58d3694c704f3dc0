// The printed sheet of a height field and the shape it rises to (SCF 2020 §6.2.4 "Forward
// Simulation", §6.4, §8): per face of the printing graph, the layers printed along its isoline at
// the layer height that shrinks by the face's σ, and the equilibrium of that plate found by the
// shared simulator (simulate/simulate.h) from the flat sheet with a small bias toward +z (notes
// §4), then measured against the target (Shrink & Morph Table 1's distance after the best rigid
// alignment). Millimetres and radians everywhere.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "material/material.h"
#include "methods/heightfield/isoline_mesh.h"
#include "plate/plate_design.h"
#include "simulate/distance.h"
#include "simulate/simulate.h"

namespace flatmorph {

// A printed height-field sheet: the plate design (method "heightfield") and the per-face
// quantities it was made from.
struct HeightFieldPlate {
  // plate (#V x 2, mm), F, the thickness-controlled layer stack, and design_fields per face:
  // "shrinkage" (σ printed, a fraction), "wanted_shrinkage" (σ asked, before clamping),
  // "layer_height" (mm), "direction" (rad), "shrinkage_clamped" (−1, 0, +1).
  PlateDesign design;
  Eigen::VectorXd direction;         // per face, rad: the deposition direction
  Eigen::VectorXd wanted_shrinkage;  // per face σ asked
  Eigen::VectorXd shrinkage;         // per face σ printed (clamped to the curve's range)
  Eigen::VectorXi clamped;           // per face: −1 raised to the least σ, +1 lowered, 0 reached

  int num_clamped() const { return static_cast<int>((clamped.array() != 0).count()); }
};

// Per face of `mesh`, the deposition direction (rad, from +x counter-clockwise, in [0, π)): the
// direction in the flat `plate` (#V x 2, mm) of the face's base edge, the edge whose two ends lie
// at one level (SCF 2020 §6.3: the paths run along the isolines); for a patch face, the rim edge
// (the one not touching the patch centre). Throws std::invalid_argument on sizes that differ or a
// face without such an edge (a broken printing-graph contract).
Eigen::VectorXd deposition_directions(const IsolineMesh& mesh, const Eigen::MatrixXd& plate);

// The sheet printed with per-face `direction` (rad) and shrink `face_shrinkage` (fractions; σ the
// curve cannot reach is clamped and flagged) by thickness_controlled_layer_stack, in `num_layers`
// identical layers (unset: the layers of the curve's calibration; the paths must print as many,
// ContinuousPathOptions::num_layers). Throws UserError (kOption) when `material` has no thickness
// curve or num_layers < 1; std::invalid_argument on sizes that differ or a non-finite σ.
HeightFieldPlate heightfield_plate(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                                   const Eigen::VectorXd& direction,
                                   const Eigen::VectorXd& face_shrinkage, const Material& material,
                                   std::optional<int> num_layers = std::nullopt);

// The same from the flattening: `plate` (#V x 2, mm) and the per-edge shrink of mesh.E
// (`edge_shrinkage`, NaN on bridges), spread over the faces by face_shrinkage (shrinkage_field.h),
// directions from deposition_directions.
HeightFieldPlate heightfield_plate(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                   const Eigen::VectorXd& edge_shrinkage, const Material& material,
                                   std::optional<int> num_layers = std::nullopt);

// The flat sheet with a small dome toward +z, z = bias · (1 − r²/R²) · D, r the distance to the
// plate's mean vertex, R the largest such distance, D the plate's bounding-box diagonal (mm). The
// sheet is symmetric through its thickness (b̄ = 0, SCF 2020 §8), so the flat state is an
// equilibrium (unstable) and flat_start stays flat; the bias picks the side it rises to, +z, the
// side the target rises to (in hot water the water's push does, notes §4).
Eigen::MatrixXd biased_flat_start(const Eigen::MatrixXd& plate, double bias = 0.01);

struct RisePredictionOptions {
  double bias = 0.01;  // of the start dome (biased_flat_start)
  // Also simulate from the target as the start and compare (several stable shapes, paper §6). Off
  // by default: a diagnostic that costs as much as the prediction or far more (a target far from
  // any equilibrium of the sheet takes hundreds of Newton iterations: 300 in 35 s on the ridge),
  // and the design must stay within a few seconds.
  bool from_target = false;
  int from_target_max_iterations = 100;  // Newton iterations for that check
  // The two starts agree when, after the best rigid alignment, no vertex differs by more than this
  // (% of the target's bounding-box diagonal).
  double agreement_percent = 1.0;
  // At most 300 Newton iterations per simulation: the examples settle from the flat sheet in 10-90;
  // one that has not settled by then is reported unconverged (SimulationResult::warning) rather
  // than kept running for minutes (a printing graph with needle triangles can creep for 1000).
  SimulationOptions simulation{.max_iterations = 300};
};

struct RisePrediction {
  SimulationResult from_flat;  // V: registered to the biased flat start (plate frame, +z up)
  Eigen::MatrixXd aligned;     // from_flat.V moved by the best rigid motion onto the target
  ShapeDistance distance;      // of `aligned` to the target
  // +1 when the sheet rises toward +z (its interior lies above the plane fitted to its boundary,
  // seen in the plate's frame, z toward the top of the print), −1 toward −z, 0 flat.
  int side = 0;
  double rise_mm = 0;  // the mean signed height of the vertices above that plane
  // From the target as the start (when options.from_target): the equilibrium, its distance to the
  // target after the best rigid alignment, and the largest vertex difference (mm and % of the
  // target's diagonal) between it and `aligned` after aligning them; the starts agree when that
  // is at most options.agreement_percent and both simulations converged.
  bool has_from_target = false;
  SimulationResult from_target;
  ShapeDistance from_target_distance;
  double starts_difference_mm = 0;
  double starts_difference_percent = 0;
  bool starts_agree = true;
  double seconds = 0;  // wall clock, whole call
};

// The shape `design` rises to and how far it is from `target` (#V x 3, mm, one row per plate
// vertex: the isoline mesh's V). Throws UserError on inconsistent sizes or a bad plate (simulate);
// numerical trouble is reported in the simulation results (converged = false), not thrown.
RisePrediction predict_rise(const PlateDesign& design, const Eigen::MatrixXd& target,
                            const RisePredictionOptions& options = {});

// The side of a shape (#V x 3, mm) relative to its boundary (vertices on the boundary loops of F):
// the mean signed height of all vertices above the least-squares plane of the boundary vertices,
// whose normal is taken with a positive z. Returns the height in mm (its sign is the side).
double height_above_boundary_plane(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace flatmorph
