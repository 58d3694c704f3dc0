// The convex hull of points in the plane. Millimetres.
#pragma once

#include <Eigen/Core>

namespace flatmorph {

// The hull's corners counter-clockwise, each once, no three on a line (Andrew's monotone chain);
// fewer than three rows when the points are fewer or all on a line.
Eigen::MatrixX2d convex_hull(const Eigen::MatrixX2d& points);

}  // namespace flatmorph
