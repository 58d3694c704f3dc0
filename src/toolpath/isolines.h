// The print paths of one layer: the 0 mod 2 pi isolines of a stripe pattern (Shrink & Morph
// §3.2.3, notes §5.4), chained into polylines.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/topology.h"
#include "toolpath/stripe_patterns.h"

namespace flatmorph {

// A polyline in the plate's plane (mm); a closed one repeats its first point at the end.
struct Polyline2 {
  Eigen::MatrixX2d points;
  bool closed = false;
};

// The isolines of `pattern` on the plate (V #V x 2, mm; the mesh the pattern was computed on).
// Inside a face the stripe phase is linear, so each level 2 pi k between its corner values is one
// straight segment between two edges: the matching is non-crossing by construction. In a face
// where the stripes fork, the curves that pass the fork are joined across the face the same way
// and the one branch that stops there ends on the face's edge. Crossing points are computed once
// per edge, so the pieces of neighbouring faces join exactly; faces that are not `usable` (field
// singularities) are skipped, so curves stop cleanly there, and curves end exactly on the plate's
// boundary edges. Polylines shorter than min_length_mm are dropped. Deterministic order:
// by the smallest crossing of each curve.
std::vector<Polyline2> stripe_isolines(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const EdgeTopology& topology, const StripePattern& pattern,
                                       double min_length_mm);

// Cuts every open polyline back from each end until its end is at least min_gap_mm from every
// other polyline. At a fork of the stripes (a stripe singularity) the branch that ends runs into
// its neighbour; printing the converging part would lay two beads on top of each other. Cuts at
// the first point (from the end) far enough, or between points by bisection on the segment.
// Polylines left with fewer than two points are removed. Deterministic: all cuts are measured
// against the uncut polylines.
void trim_converging_ends(std::vector<Polyline2>& polylines, double min_gap_mm);

// Removes polylines shorter than min_length_mm; returns how many were removed and adds their
// total length to *removed_length (when given).
int drop_short_polylines(std::vector<Polyline2>& polylines, double min_length_mm,
                         double* removed_length = nullptr);

// Length of a polyline (mm).
double polyline_length(const Eigen::MatrixX2d& points);

}  // namespace flatmorph
