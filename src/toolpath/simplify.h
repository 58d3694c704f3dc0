// Polyline simplification before printing: fewer, longer segments with the same shape.
#pragma once

#include <Eigen/Core>

namespace flatmorph {

// Ramer–Douglas–Peucker: the subset of the points (first and last kept) such that every dropped
// point lies within tolerance_mm of the simplified polyline's segment that replaces it. Points
// are rows (2 or 3 columns, distances in the xy plane). Deterministic, iterative (no recursion).
Eigen::MatrixXd simplify_polyline(const Eigen::MatrixXd& points, double tolerance_mm);

}  // namespace flatmorph
