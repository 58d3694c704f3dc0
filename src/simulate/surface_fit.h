// How far a shape is from a target surface that shares no vertices with it: the rigid motion that
// brings the shape closest to the surface (iterative closest points) and the distance of each of
// its vertices to that surface afterwards. For a plate whose mesh is not the target's: a slicer's
// G-code simulated on its own footprint. Lengths in mm.
#pragma once

#include <Eigen/Core>

#include "simulate/distance.h"

namespace flatmorph {

struct SurfaceFit {
  RigidFit fit;             // shape ↦ R x + t
  Eigen::MatrixXd aligned;  // the shape moved by it, #V x 3
  // Per vertex of the shape, its distance to the nearest point of the target's surface; mean,
  // maximum and their % of the target's bounding-box diagonal, as shape_distance.
  ShapeDistance distance;
  int iterations = 0;  // closest-point steps taken from the best start
};

// The rigid motion (a proper rotation and a translation) minimizing Σ_v m_v d(R x_v + t)², x_v
// the shape's vertices (#V x 3, mm; faces shape_F, whose lumped areas are the weights m_v) and d
// the distance to the target's surface (target_V #T x 3, target_F). It alternates closest points
// (point to triangle) with the weighted rigid fit to them, from several starts: the shape as it
// is, and its centroid and principal axes put on the target's in each of the 24 ways that keep a
// proper rotation (axes in any order and sign); the best start after a few steps is carried to
// convergence. No vertex correspondence is needed: each of the shape's vertices is measured to
// wherever on the target is nearest. The starts assume the two cover about the same surface (a
// strip on a larger cylinder slides along it at no cost; a small part of a surface curved
// unevenly may stop at a fit that is only locally best). Throws UserError
// (kGeometry) when either mesh has no face of positive area or a coordinate is not finite.
SurfaceFit closest_point_rigid_fit(const Eigen::MatrixXd& shape, const Eigen::MatrixXi& shape_F,
                                   const Eigen::MatrixXd& target_V,
                                   const Eigen::MatrixXi& target_F);

}  // namespace flatmorph
