// Refining a flat plate before tracing paths on it: the stripe pattern needs edges no longer than
// about the path spacing (Shrink & Morph §3.2.3, notes §5.1). Unlike Loop subdivision, which rounds
// the plate's outline, the linear 1-to-4 split used here keeps the plate's geometry exact, so paths
// clipped to the refined boundary lie on the plate's own boundary.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace flatmorph {

// A refined plate and the maps that carry coarse data onto it.
struct RefinedPlate {
  Eigen::MatrixXd V;  // #V x 2 positions, mm
  Eigen::MatrixXi F;  // #F x 3, same orientation as the coarse faces
  // #V_fine x #V_coarse linear interpolation: fine per-vertex values = S * coarse values (every
  // fine vertex is a barycentric combination of the corners of the coarse face it lies in).
  Eigen::SparseMatrix<double> S;
  Eigen::VectorXi face_parent;  // #F_fine: the coarse face each fine face lies in
  int levels = 0;               // number of 1-to-4 splits applied
};

// One linear 1-to-4 split: a new vertex at every edge midpoint (numbered after the old vertices,
// in edge_topology order); face k becomes faces 4k..4k+3, the first three at its corners, the last
// central. All edges are halved exactly.
RefinedPlate midpoint_subdivide(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Splits until the mean edge length is at most mean_edge_mm (mm); the longest edge keeps its ratio
// to the mean (every split halves every edge). V is #V x 2 or #V x 3 (z ignored). Throws
// UserError(kResource) when that would need more than max_faces faces, and UserError(kOption)
// when mean_edge_mm is not positive.
RefinedPlate refine_plate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double mean_edge_mm,
                          int max_faces = 20'000'000);

// Longest and mean edge length of a mesh (mm; the mean over face sides, so interior edges count
// twice).
double longest_edge(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
double mean_edge(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace flatmorph
