// Shrink & Morph's print paths (§3.2.3): for every printed layer, equally spaced curves that
// follow that layer's print direction and cover the plate, in a travel-saving order. This is the
// toolpath stage's entry point; docs/toolpaths.md explains the steps and their choices.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "common/progress.h"
#include "plate/layer_stack.h"
#include "toolpath/order_paths.h"
#include "toolpath/stripe_patterns.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

struct LayerPathOptions {
  double spacing = 0.4;  // mm between neighbouring paths = the extrusion width
  // The plate is refined until its mean edge is at most this x spacing (the longest edges of a
  // flattened plate are then about twice as long). The stripe phase winds more than once along
  // such an edge, which the isoline extraction handles; the eigenvector costs about the number of
  // faces, so this sets the time (docs/toolpaths.md: 2 keeps every quality figure on the paper's
  // six models and makes the stripes 5 to 20 times faster than 1).
  double edge_ratio = 2.0;
  double min_path_length = 3.0;  // fragments shorter than this x spacing are dropped
  // Path ends are cut back until they are this many spacings from every other path (at stripe
  // forks the ending branch runs into its neighbour; beads closer than this overlap by more than
  // a fifth of their width). 0 keeps the ends.
  double min_end_gap = 0.8;
  double simplify_tolerance_mm = 0.01;  // Ramer–Douglas–Peucker tolerance
  double feed_rate = 0;                 // mm/s written on every segment; 0: the printer's default
  // Closed loops along the outline, printed first, one spacing apart (0: none, the default: a
  // loop along the boundary shrinks along it and works against the designed directions). The
  // other paths then stop min_end_gap spacings short of the innermost loop.
  int perimeters = 0;
  // Passes that re-aim each layer's field by how far its stripes turned from it
  // (docs/toolpaths.md).
  int field_corrections = 2;
  StripeOptions stripes;  // its spacing is overwritten by `spacing`
  OrderOptions order;
  ProgressCallback progress;  // stage "trajectories": the stripe patterns, then layer by layer
};

// One layer's figures.
struct LayerPathReport {
  int layer = 0;  // k, 1 on the bed
  double z = 0;   // mm
  int paths = 0;
  double extrusion_mm = 0;        // printed length
  double travel_mm = 0;           // travel between paths in the chosen order
  double travel_greedy_mm = 0;    // the same with greedy nearest neighbour, for comparison
  int field_singular_faces = 0;   // faces of the refined plate where theta^k is singular
  int stripe_singular_faces = 0;  // faces where the stripes fork (paths end or begin)
  int dropped_fragments = 0;      // curves shorter than min_path_length (after trimming)
  int power_iterations = 0;
  double eigen_residual = 0;                     // relative residual of the stripe eigenvector
  std::vector<Eigen::Vector2d> singular_points;  // centroids of the field-singular faces, mm
  std::vector<Eigen::Vector2d> fork_points;      // centroids of the stripe-singular faces, mm
};

// Wall time per stage, seconds (reported, never used to decide anything).
struct LayerPathTimings {
  double refinement = 0;
  double fields = 0;
  double eigenvector = 0;
  double extraction = 0;
  double ordering = 0;
};

struct LayerPaths {
  Toolpath toolpath;  // one ToolpathLayer per printed layer, bottom first
  std::vector<LayerPathReport> layers;
  LayerPathTimings timings;
  // Area-weighted mean over layers and plate faces of how far the stripes turned from theta^k
  // (degrees): before any correction, then after each correction tried (the last one tried may
  // have been worse, and not kept).
  std::vector<double> stripe_turn_deg;
  int field_corrections = 0;  // corrections kept
  int refined_faces = 0;
  double refined_mean_edge_mm = 0;
  double refined_max_edge_mm = 0;
};

// A layer's print direction per vertex of the plate (rad, from +x, CCW): its per-face theta
// averaged to the vertices as a line field (area-weighted doubled angles), what the stripes follow.
Eigen::VectorXd layer_direction_vertex(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                                       const Eigen::VectorXd& layer_theta_face);

// The paths of every layer of the stack (plate/layer_stack.h; the stack decides each layer's
// direction, bead height and tool) for a flat plate (plate #V x 2 or x 3 with z ignored, mm, faces
// counter-clockwise): refines the plate (every edge cut into n, refine_plate.h), carries each
// layer's direction field onto it as a line field, computes one stripe pattern per layer
// (warm-started), extracts and chains its isolines, drops short fragments, simplifies, and orders
// them (order_paths, starting layer 1 at the plate's lower-left bounding-box corner and each next
// layer where the previous one ended; perimeter loops, when asked for, come first, outermost first,
// each from its point nearest to where the head is). Layer k's paths lie at z = the sum of the
// printed thicknesses of layers 1..k, and every segment extrudes with width = spacing, the layer's
// thickness, feed_rate and the layer's material index as its tool. Deterministic. Throws
// UserError(kOption) for inconsistent sizes, out-of-range options, or a layer whose material or
// thickness varies over the plate or that leaves faces uncovered (the stripe patterns trace whole,
// uniform layers).
LayerPaths stack_layer_paths(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                             const LayerStack& stack, const LayerPathOptions& options);

}  // namespace flatmorph
