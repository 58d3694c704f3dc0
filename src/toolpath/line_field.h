// Per-layer print directions as line fields (Shrink & Morph §3.2.3). A print direction theta and
// theta + pi are the same line, so directions are averaged and interpolated through the doubled
// angle, u = e^{2 i theta} (the 2-RoSy field the paper feeds to the stripe patterns), never as
// plain numbers: -89 deg and +89 deg average to 90 deg, not 0. Angles in radians from +x,
// counter-clockwise, in the plate's frame.
#pragma once

#include <Eigen/Core>

namespace flatmorph {

// Per vertex e^{2 i theta} averaged over the incident faces, weighted by face area (not
// normalized: its modulus drops where the faces disagree). V is #V x 2 (or x 3, z ignored).
Eigen::VectorXcd face_to_vertex_line_field(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                           const Eigen::VectorXd& theta_face);

// The line direction of doubled-angle values: arg(u) / 2, in (-pi/2, pi/2].
Eigen::VectorXd line_field_angle(const Eigen::VectorXcd& u);

// Doubled index per face: the winding number of e^{2 i theta} around the face (the sum of the three
// wrapped doubled-angle differences over 2 pi). A line field's index is this over 2 (+1 around
// concentric circles or radial lines: 2; a +1/2 "comet": 1). Faces with a non-zero value hold a
// singularity.
Eigen::VectorXi line_field_doubled_index(const Eigen::MatrixXi& F,
                                         const Eigen::VectorXd& theta_vertex);

// Barycentric interpolation of a per-vertex line field inside one triangle (weights sum to 1):
// the angle of the interpolated doubled-angle value, in (-pi/2, pi/2].
double interpolate_line_field(double theta_a, double theta_b, double theta_c,
                              const Eigen::Vector3d& barycentric);

// The angle between two lines, in [0, pi/2].
double line_angle_difference(double theta_a, double theta_b);

}  // namespace flatmorph
