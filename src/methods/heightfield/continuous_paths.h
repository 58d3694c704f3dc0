// Continuous toolpaths of a flattened printing graph (SCF 2020 §6.3 "Tool path generation" and
// §6.4 "G-code generation"): every strip between two isolines (and every patch fan) is filled with
// rows parallel to its printing edges, an even number per face so that the rows pair up into
// closed loops and double-backs (the paper's edge doubling), and the resulting graph is traced by
// the paper's five rules into a few long traces, one per hill wherever the rules allow. Each
// segment prints at the layer height whose shrink, on the material's thickness curve, is the
// segment's σ, and the same traces are stacked `num_layers` times at nozzle heights z = k · h.
// Units: millimetres, mm/s; σ is a fraction (0.3 for 30 %).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "material/material.h"
#include "methods/heightfield/isoline_mesh.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

struct ContinuousPathOptions {
  // g: the extrusion width and the intended distance between neighbouring rows (mm). The authors
  // print 0.48 mm with a 0.5 mm nozzle.
  double path_width = 0.48;
  // Identical layers stacked (SCF 2020 §6.4); unset: the layers the thickness curve was calibrated
  // with (6 for pla-geodesy).
  std::optional<int> num_layers;
  // Feed rate of every extruding segment (mm/s); 0: the material's print speed.
  double feed_rate = 0;
};

struct ContinuousPaths {
  // Layer k (k = 1 on the bed) holds one polyline: the traces in print order, joined by travel
  // segments (SegmentStyle::travel). Each extruding segment has width g and the layer height h of
  // its σ; each point lies at z = k · h of the extruding segment that ends at it (the first point
  // of a trace: of the segment that starts there), as SCF 2020 §6.4 sets z_i = θ_i · k. The layer's
  // z and height are k · h_max and h_max (its top). Travels run across the plate only at the top:
  // the polyline starts above its first trace, and between two traces rises there, crosses, and
  // comes down (vertical travel segments). No two consecutive points coincide.
  Toolpath toolpath;
  // Per hill (a summit: a leaf of the loop tree, in the order of mesh.loops), how many traces print
  // in the strips and cap above the lowest loop that belongs to that summit alone. The design
  // gives 1 (one spiral per hill); more means the rules had to break a hill's trace.
  std::vector<int> paths_per_hill;
  std::vector<int> hill_loops;  // the summit loop (index into mesh.loops) of each hill
  int num_traces = 0;           // per layer
  int num_double_backs = 0;     // U-turns where a face has more rows than its neighbour, per layer
  int num_saddle_patches = 0;   // saddle fans (patch centres that are not summit caps)
  double min_layer_height = 0;  // over the extruding segments, mm
  double max_layer_height = 0;
  // Extruding segments (per layer) whose σ lies outside the curve's reachable range
  // (reachable_shrinkage): printed at the nearest end of the range.
  int clamped_segments = 0;
  double path_length = 0;    // extruded per layer, mm
  double travel_length = 0;  // travelled between traces per layer, in xy, mm
};

// The toolpath of the flat printing graph `mesh` laid out as `plate` (#V x 2 mm, as flatten_sheet
// gives it), printing the shrink `vertex_shrinkage` (#V, fractions: the flattening's spread by
// vertex_shrinkage() of shrinkage_field.h, or the optimized one of optimize_shrinkage.h) with
// `material`'s thickness curve. Deterministic; depends on the plate only through lengths and the
// mesh's combinatorics, so a rotated plate gives rotated paths.
//
// Rules, with the authors' quirks fixed (notes §5; each is commented in the .cpp):
// - a face of altitude h (base edge to apex, in the plate) gets n = 2⌊h / 2g⌋ rows at t = j/(n+1)
//   (raised to two where no rows would leave a gap wider than 1.5 g); half-counts are smoothed
//   along each strip so that neighbours differ by at most one, and runs shorter than 10 g take a
//   neighbour's count, both only where the spacing h / (n + 1) stays within [0.5 g, 1.5 g];
// - rows continue across shared bridge edges; the extra rows of the face with more pair up into
//   U-turns (double-backs) whose two ends coincide, in the middle of the edge's rows; the nodes on
//   each bridge edge are spaced evenly;
// - summit caps and saddle polygons are filled like strips, their rows parallel to the rim and
//   shrinking toward the patch centre (concentric, not the authors' per-triangle zig-zags);
// - tracing follows the paper's rules 1-5 on unprinted edges (every printing edge and row is
//   printed once, a double-back's bridge twice): counter-clockwise first (left-first) seen from
//   +z; rule 5 climbs at most to the next isoline; a new trace starts at the lowest unprinted
//   node. Loops, strips and caps are traced first, then saddle chains with their saddle polygons
//   (as the authors' code does), so that a trace closing a loop at a saddle climbs its own hill;
// - a segment's σ: an isoline edge's the mean of its ends' (as a face prints the mean of its
//   corners'); a row's interpolated between the lower and the upper level by the row's position
//   (the authors always took the lower one).
//
// Throws UserError(kOption) when the material has no thickness curve, path_width is not positive
// or num_layers < 1, feed_rate < 0; UserError(kGeometry) when the graph has nothing to print;
// std::invalid_argument when sizes differ, the plate is not
// finite, a printing edge's σ is not finite, or a face breaks the structure of isoline_mesh.h.
ContinuousPaths continuous_paths(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                 const Eigen::VectorXd& edge_shrinkage, const Material& material,
                                 const ContinuousPathOptions& options = {});

}  // namespace flatmorph
