// The triangles of a disk meshed in rings around a centre vertex, shared by the built-in examples,
// the height-field examples and the validation family. Internal to src/examples/. Units: mm.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/mesh.h"

namespace flatmorph {

// Vertex 0 is the centre; ring i (i = 1, 2, ...) follows with ring_sizes[i - 1] vertices in order
// counter-clockwise seen from +z, every ring's vertex 0 on one ray from the centre and the vertices
// of each ring at the same fractions of the way around for every ring (j / size). The centre is
// fanned to ring 1 and consecutive rings are stitched into strips by those fractions, compared
// exactly in integers. Ring sizes must be at least 3 and not decrease.
Eigen::MatrixXi ring_mesh_faces(const std::vector<int>& ring_sizes);

// Flat disk (z = 0) of concentric rings: ring i (i >= 1) at radius radii[i] (mm) with 6 i vertices
// at angles 2 pi j / (6 i); radii[0] is the centre's and unused. Every interior vertex has valence
// 6 (a hexagonal lattice bent onto circles), so triangles stay near-equilateral. Faces are
// counter-clockwise seen from +z.
Mesh ring_disk(const std::vector<double>& radii);

}  // namespace flatmorph
