// Removing rigid motions from a plate simulation by a 3-2-1 constraint (docs/simulation.md).
//
// The shape is expressed in the frame of the plate's central face (the face whose rest centroid
// is nearest the mean plate vertex): its first vertex at the origin, its first edge along +x and
// the face in the xy plane. Then x, y, z of the first vertex, y, z of the second and z of the
// third are exactly zero and are held fixed, which removes the six rigid motions and nothing else.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace flatmorph {

struct RigidFrame {
  int face = 0;                      // the central face
  Eigen::Vector3d origin;            // its first vertex in the shape, mm
  Eigen::Matrix3d rotation;          // rows: first edge, in-plane normal to it, face normal
  std::vector<int> fixed_variables;  // indices into the stacked 3V coordinates
};

// The frame of `shape` (#V x 3, mm) at the central face of `plate` (#V x 2, mm). Throws UserError
// (kGeometry) when that face is degenerate in `shape`; `what` names the shape in the message.
RigidFrame central_face_frame(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                              const Eigen::MatrixXd& shape, const char* what);

// V (#V x 3, mm) as stacked coordinates in the frame, the fixed ones set to exactly 0.
Eigen::VectorXd to_frame(const RigidFrame& frame, const Eigen::MatrixXd& V);

// Stacked coordinates in the frame back to #V x 3 positions, mm.
Eigen::MatrixXd from_frame(const RigidFrame& frame, const Eigen::VectorXd& x);

}  // namespace flatmorph
