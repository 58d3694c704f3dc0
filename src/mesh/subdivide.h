// Loop subdivision with boundary rules, and the linear map that carries per-vertex fields along.
#pragma once

#include <Eigen/SparseCore>

#include "mesh/mesh.h"

namespace flatmorph {

// A refined mesh and the subdivision matrix S (#V_fine x #V_coarse): V_fine = S * V_coarse, and any
// per-vertex field (theta2, plate positions, ...) is carried along the same way.
struct Subdivision {
  Mesh mesh;
  Eigen::SparseMatrix<double> S;
};

// One Loop step (Loop 1987; boundary rules of Hoppe et al. 1994): every triangle splits into four;
// interior old vertex of valence n gets weight beta = 3/16 (n = 3) or 3/(8n) on each neighbour;
// boundary old vertex 3/4 itself and 1/8 on each boundary neighbour; interior edge vertex 3/8, 3/8,
// 1/8, 1/8; boundary edge vertex is the midpoint. New vertices follow the old ones, in edge order.
// Face k of the coarse mesh becomes faces 4k..4k+3, the first three at its corners, the last central.
Subdivision loop_subdivide(const Mesh& mesh);

// Repeats loop_subdivide until the mesh has at least `min_faces` faces (none if it already has).
// S is the product of the steps' matrices.
Subdivision loop_subdivide_to(const Mesh& mesh, int min_faces);

}  // namespace flatmorph
