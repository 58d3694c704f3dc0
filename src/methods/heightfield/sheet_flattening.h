// The flat sheet of a printing graph (SCF 2020 §6.2, "Mesh flattening"): the 3D target mesh is
// pressed into the plane while its bridge edges keep their length (grown by λ2 when heated) and its
// printing edges may lengthen by 1/(1 − σ) for σ in the printable range, so that each printing
// edge's flat length tells how much its path must shrink. Local/global projective steps (ShapeOp
// style, notes §3.3) alternate with the paper's vertex relocations (§6.2.2) until the sheet is
// flat; then the plane sheet is relaxed by Anderson-accelerated local/global steps. Units:
// millimetres for positions and lengths; every weight and rate below is dimensionless, so the
// result does not depend on the sheet's size (scaling the target by s scales the plate by s and
// keeps σ).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>

#include "methods/heightfield/isoline_mesh.h"

namespace flatmorph {

// An edge whose σ lies outside [min_shrinkage, max_shrinkage] by less than this counts as valid:
// edges held at a bound of the range by the projection land on it up to rounding, and a 0.1 %
// strain is far below what a printed layer thickness resolves.
inline constexpr double kShrinkageRangeTolerance = 1e-3;

struct SheetFlatteningOptions {
  // Constraint weights (§6.2.1; notes §3.2 and §3.5: the authors' code uses these times 400). Each
  // term is a squared residual made dimensionless by rest lengths: an edge term is
  // |Δx − p|² / (l_3D l̄), l̄ the mean 3D edge length, i.e. its strain squared weighted by its
  // length; bending is 3 |K x|² / (A0 + A1), dimensionless by itself.
  double printing = 1.0;   // printing and boundary edges: stretch l / l_3D in the printable range
  double bridge = 1.0;     // bridge edges: flat length l_3D / bridge_growth
  double bending = 0.025;  // every interior hinge toward planarity (Bergou cotangent weights)
  // The paper's w_shear = 0.25 is, in the authors' code, an isoline straightness term (notes
  // §3.2): each path vertex and its two path neighbours pulled onto their best-fitting line. We
  // keep straightness: per-corner shear (the paper's text) holds every corner at its 3D angle,
  // which cells whose ring edges stretch and whose bridges do not cannot keep (test
  // ShearBiasesTheFannedConeStraightnessDoesNot: on a cone with fans, σ off 1 − cos β by > 0.03 and
  // no convergence; on the built-in examples 10-28 % invalid edges and folds). Its weight is
  // lowered from 0.25 to 0.05: at 0.25 it straightens the tight ends of the built-in ridge's loops
  // below σ = 0 (1.8 % invalid edges against 0.5 %) for no visible gain in path smoothness. Shear
  // stays available for comparison.
  double straightness = 0.05;
  double shear = 0.0;
  // Even shrinkage along a path (not in the paper): at each path vertex, its two path edges pulled
  // to a common stretch l / l_3D. Where a gradient-line vertex fans to many vertices of the next
  // isoline, the bridges leave each fanned edge's length free within the range, and σ comes out
  // noisy from one edge to the next (the test EvenShrinkageSmoothsTheFans); exact rings are left
  // as they are. Where the target cannot be met, it also keeps the misfit from scattering over
  // single printing edges (built-in saddle: 13 % invalid edges without it, 2 % with it; the
  // relative length error of the rise, all edges, goes from 0.84 % to 1.2 % RMS).
  double smoothness = 1.0;
  // Proximal term toward the positions after the relocations (the code's closeness, 1/400 of its
  // bridge weight): damps the step and fixes the free translation. Must be > 0.
  double closeness = 0.01;

  // Relocations (§6.2.2), applied before each constraint solve while the sheet is not flat; 0
  // turns one off. Flattening: the heights above the mean height shrink by this fraction per step
  // (the paper's formula is not dimensionless; the code decays the Bear by ~12 % a step, notes
  // §3.4); in [0, 1).
  double flattening = 0.3;
  // Stretching: each boundary vertex moves by stretching · (|e0| + |e1|) / 2 · N_xy, N the
  // area-weighted normal of its faces, e0 and e1 its boundary edges (the paper's 1.0; absent from
  // the authors' code). It changes little (the fold guards keep its pushes from turning slivers
  // over) and fades as the sheet flattens (N_xy -> 0).
  double stretching = 1.0;
  // Spreading: each vertex opposite an interior edge in a face f moves by
  // spreading · (|e0| + |e1|) / 2 · N_xy(f), e0 and e1 its edges in f. The paper uses 0.5; off by
  // default, as in the authors' code (notes §3.4): it pushes every vertex downhill by about its
  // edge length a step whatever its neighbours do, and the sheet does not fully recover (test
  // PaperSpreadingSpoilsTheRidge: 7.7 % invalid edges on the built-in ridge against 0.5 %, and
  // the step limit reached on three of the four built-in examples).
  double spreading = 0.0;

  // Printing and boundary edges may lengthen by 1/(1 − σ) for σ in [min_shrinkage, max_shrinkage]
  // (fractions; the paper's range is 0–34.3 % for PLA). 0 <= min < max < 1.
  double min_shrinkage = 0.0;
  double max_shrinkage = 0.343;
  // λ2, the growth across the paths when heated: a bridge's flat length is l_3D / bridge_growth
  // (the paper: 1, inextensible; flatmorph's PLA grows 1.08 across the paths).
  double bridge_growth = 1.0;

  // Stopping rule (notes §10 item 6): the heights decay until the largest is below 1e-3 of the mean
  // edge length, then z is dropped and the plane sheet is relaxed until one plain local/global step
  // changes the edge lengths by less than `tolerance` on average (relative); at most `max_steps`
  // steps in all, the last few always spent in the plane, so that the plate is planar even when
  // the budget runs out.
  int max_steps = 500;
  double tolerance = 1e-6;
  // After each step: its number (from 1), the mean relative edge change, the largest height above
  // the mean height (mm; 0 once planar). May be empty.
  std::function<void(int step, double change, double max_height)> progress;
};

struct FlatSheet {
  // #V x 2, mm: the flat sheet, vertex centroid at the origin, turned so that it best matches the
  // target's footprint (x, y) in the least-squares sense; faces counter-clockwise.
  Eigen::MatrixXd plate;
  // Per edge of mesh.E: σ = 1 − l_3D / l_flat for printing and boundary edges (a fraction; the
  // path shrinks by σ when heated); NaN for bridges.
  Eigen::VectorXd edge_shrinkage;
  // Table 1 "Inv.": the printing and boundary edges whose σ lies outside
  // [min_shrinkage, max_shrinkage] by more than kShrinkageRangeTolerance, in % of their number
  // (counted, not length-weighted, as the paper counts them).
  double invalid_edge_percent = 0;
  // Faces turned over or collapsed in the plate (signed area below 1e-9 l̄², l̄ the mean 3D edge
  // length); 0 for a valid sheet. When not 0, stop_reason says so and converged is false.
  int flipped_faces = 0;
  int steps = 0;
  bool converged = false;  // the tolerance was met, the sheet was flat in time, nothing folded
  std::string stop_reason;
  double seconds = 0;  // wall clock
};

// The flat sheet of `mesh` (its V the 3D target in mm, edge_kind telling printing, bridge and
// boundary edges). Deterministic. Throws UserError(kOption) for out-of-range options (a weight or
// rate below 0 or not finite, closeness 0, flattening >= 1, a printing or bridge weight of 0, a
// shrinkage range not 0 <= min < max < 1, bridge_growth <= 0, max_steps < 1, tolerance <= 0) and
// std::invalid_argument for a malformed mesh (sizes that disagree, indices out of range, E not the
// edges of F, faces not consistently oriented, non-finite coordinates, a zero-length edge).
FlatSheet flatten_sheet(const IsolineMesh& mesh, const SheetFlatteningOptions& options = {});

// σ per edge of mesh.E for a flat plate (#V x 2, or #V x 3 with z ignored; mm): 1 − l_3D / l_flat
// on printing and boundary edges, NaN on bridges. Throws std::invalid_argument on sizes that
// differ.
Eigen::VectorXd sheet_edge_shrinkage(const IsolineMesh& mesh, const Eigen::MatrixXd& plate);

}  // namespace flatmorph
