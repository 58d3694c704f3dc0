// The triangles of a disk meshed in rings around a centre vertex, shared by the built-in examples
// and the validation family. Internal to src/examples/.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace flatmorph {

// Vertex 0 is the centre; ring i (i = 1, 2, ...) follows with ring_sizes[i - 1] vertices in order
// counter-clockwise seen from +z, every ring's vertex 0 on one ray from the centre and the vertices
// of each ring at the same fractions of the way around for every ring (j / size). The centre is
// fanned to ring 1 and consecutive rings are stitched into strips by those fractions, compared
// exactly in integers. Ring sizes must be at least 3 and not decrease.
Eigen::MatrixXi ring_mesh_faces(const std::vector<int>& ring_sizes);

}  // namespace flatmorph
