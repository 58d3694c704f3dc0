// Discrete differential operators on triangle meshes. Lengths in the mesh's units (mm), angles in
// radians, curvatures in 1/mm.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "mesh/mesh.h"
#include "mesh/topology.h"

namespace flatmorph {

// Triangle areas (#F). Works for 2-column (plate) or 3-column V; in 2D the area is signed,
// positive for counter-clockwise triangles.
Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Unit face normals (#F x 3) by the right-hand rule on the face order.
Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Cotan Laplacian as a positive semi-definite matrix: L_ij = -(cot a_ij + cot b_ij)/2 for each edge,
// L_ii = -sum_j L_ij, so that u^T L u is twice the Dirichlet energy of the piecewise-linear u and
// L u = 0 for linear u at interior vertices. V may have 2 or 3 columns.
Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Lumped (barycentric) mass: a third of the incident triangle areas per vertex.
Eigen::VectorXd lumped_mass(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Curvature sign convention (docs/conventions.md), the one of Shrink & Morph's b = -dn^T dphi:
// curvature is positive where the surface bends toward its normal, i.e. where the side the normals
// point to is concave. A sphere with inward normals has curvature +1/R, with outward normals -1/R.

// Signed dihedral angle per edge of `topology` (#E), 0 on boundary edges: the angle between the two
// face normals, positive where the surface bends toward its normals (concave on the normal side).
Eigen::VectorXd signed_dihedral_angles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const EdgeTopology& topology);

// Per-face discrete shape operator (Grinspun et al. 2006, triangle-averaged; Shrink & Morph Eq. 10
// with the 1/(2A) normalization of notes §3.4): S_f = sum over the face's interior edges of
// theta_e * l_e / (2 A_f) * t_e t_e^T, t_e the unit in-plane edge normal. 3x3 symmetric, in world
// coordinates; its tangent eigenvalues approximate the principal curvatures with the sign convention
// above (+1/R on a sphere of radius R with inward normals, -1/R with outward ones; 1/R and 0 on a
// cylinder seen from inside; 0 on a plane).
std::vector<Eigen::Matrix3d> shape_operators(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                             const EdgeTopology& topology);

// Mean and Gaussian curvature per face from shape_operators: the half trace and the product of the
// two tangent eigenvalues.
void face_curvatures(const std::vector<Eigen::Matrix3d>& shape_operators,
                     const Eigen::MatrixXd& normals, Eigen::VectorXd& mean,
                     Eigen::VectorXd& gaussian);

// Angle defect per vertex: 2 pi - sum of corner angles at interior vertices, pi - sum at boundary
// vertices (integrated Gaussian curvature plus boundary turning, so that Gauss-Bonnet reads
// sum(defect) = 2 pi chi).
Eigen::VectorXd angle_defects(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace flatmorph
