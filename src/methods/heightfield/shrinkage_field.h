// The printing edges' shrink σ (SCF 2020 §6.2: σ = 1 − l_3D / l_flat, a fraction) spread over the
// vertices and faces of the printing graph, so that the layer stack (per face) and the toolpaths
// (per segment, between two levels) read one field.
#pragma once

#include <Eigen/Core>

#include "methods/heightfield/isoline_mesh.h"

namespace flatmorph {

// Per vertex: the mean σ of its printing and boundary edges weighted by their flat lengths
// (`plate`, #V x 2, mm). A vertex without such an edge (a patch centre, a lone bridge end) takes
// the length-weighted mean over the printing edges of its faces' rims, i.e. of the faces around it.
// `edge_shrinkage` has one value per edge of mesh.E; bridge entries are ignored (may be NaN).
// Throws std::invalid_argument on sizes that differ.
Eigen::VectorXd vertex_shrinkage(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                 const Eigen::VectorXd& edge_shrinkage);

// Per face: the mean of its three vertices' σ (vertex_shrinkage): a face spans the strip between
// two levels, and the shrink it prints lies between theirs.
Eigen::VectorXd face_shrinkage(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                               const Eigen::VectorXd& edge_shrinkage);

}  // namespace flatmorph
