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

// The rotation and translation x ↦ R x + t that best fit `shape` to `target` (#V x 3, mm, row for
// row) in the least-squares sense (Kabsch; a proper rotation, never a mirror).
struct RigidFit {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};
RigidFit best_rigid_fit(const Eigen::MatrixXd& shape, const Eigen::MatrixXd& target);

// The same fit weighted per vertex, minimizing Σ_v m_v |R x_v + t − y_v|² (mass: e.g. the lumped
// mass, mm²), for shapes as stacked coordinates x, y = (x0, y0, z0, x1, ...) in mm (the inverse
// design's distance after the best rigid motion).
RigidFit weighted_rigid_fit(const Eigen::VectorXd& x, const Eigen::VectorXd& y,
                            const Eigen::VectorXd& mass);

// `shape` moved by best_rigid_fit, for comparing shapes simulated from different starts.
Eigen::MatrixXd rigidly_aligned(const Eigen::MatrixXd& shape, const Eigen::MatrixXd& target);

}  // namespace flatmorph
