// Refining a flat plate before tracing paths on it: the stripe pattern needs edges no longer than
// a small multiple of the path spacing (Shrink & Morph §3.2.3, notes §5.1). Unlike Loop
// subdivision, which rounds the plate's outline, the linear split used here (every edge cut into n
// equal parts, every face into n^2) keeps the plate's geometry exact, so paths clipped to the
// refined boundary lie on the plate's own boundary, and n is any integer, so the mean edge lands
// within a factor (n - 1)/n of the one asked for instead of a factor 2.
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
  int splits = 1;               // n: every coarse edge is cut into n equal parts
};

// The linear split into n: every edge cut into n equal parts (the new points numbered after the
// old vertices, edge by edge in edge_topology order, then the faces' interior points face by face),
// every face into n^2 faces of the same orientation, numbered n^2 f .. n^2 (f + 1) - 1.
RefinedPlate regular_subdivide(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int n);

// The split with the smallest n whose mean edge length is at most mean_edge_mm (mm); the longest
// edge keeps its ratio to the mean. V is #V x 2 or #V x 3 (z ignored). Throws
// UserError(kResource) when that would need more than max_faces faces, and UserError(kOption)
// when mean_edge_mm is not positive.
RefinedPlate refine_plate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double mean_edge_mm,
                          int max_faces = 20'000'000);

// Longest and mean edge length of a mesh (mm; the mean over face sides, so interior edges count
// twice).
double longest_edge(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
double mean_edge(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace flatmorph
