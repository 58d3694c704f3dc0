// Plane polygons as the methods draw them: a closed loop of #P x 2 corners, mm, the last joined
// back to the first.
#pragma once

#include <Eigen/Core>

namespace flatmorph {

// The shoelace area, mm²: positive for a counter-clockwise loop, negative for a clockwise one.
double signed_area(const Eigen::MatrixX2d& polygon);

}  // namespace flatmorph
