// How far a predicted shape is from a target with the same vertices: the measure of Shrink & Morph
// Table 1 (per-vertex distance, average and maximum, in % of the target's bounding-box diagonal).
#pragma once

#include <Eigen/Core>

namespace flatmorph {

struct ShapeDistance {
  Eigen::VectorXd per_vertex_mm;  // |x_v − target_v|
  double mean_mm = 0.0;
  double max_mm = 0.0;
  double diagonal_mm = 0.0;   // of the target's axis-aligned bounding box
  double mean_percent = 0.0;  // of diagonal_mm
  double max_percent = 0.0;
};

// Per-vertex distances between two #V x 3 shapes in mm, as they are (no alignment: a simulation
// started from the target stays registered to it). Throws UserError when the sizes differ.
ShapeDistance shape_distance(const Eigen::MatrixXd& shape, const Eigen::MatrixXd& target);

// `shape` moved by the rotation and translation that best fit it to `target` in the least-squares
// sense (Kabsch), for comparing shapes simulated from different starts.
Eigen::MatrixXd rigidly_aligned(const Eigen::MatrixXd& shape, const Eigen::MatrixXd& target);

}  // namespace flatmorph
