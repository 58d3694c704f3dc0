// Plane polygons in Clipper's integer plane (libpolyclipping), for the stages that offset, clip
// and test polygons with it: millimetres times `scale`, rounded to the nearest unit.
#pragma once

#include <clipper.hpp>

#include <Eigen/Core>

namespace flatmorph {

ClipperLib::Path to_clipper_path(const Eigen::MatrixX2d& polygon, double scale);
Eigen::MatrixX2d from_clipper_path(const ClipperLib::Path& path, double scale);

}  // namespace flatmorph
