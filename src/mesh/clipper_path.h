// Plane polygons in Clipper's integer plane (libpolyclipping), for the stages that offset, clip
// and test polygons with it: millimetres times `scale`, rounded to the nearest unit.
#pragma once

#include <clipper.hpp>

#include <Eigen/Core>

namespace flatmorph {

ClipperLib::Path to_clipper_path(const Eigen::MatrixX2d& polygon, double scale);
Eigen::MatrixX2d from_clipper_path(const ClipperLib::Path& path, double scale);

// The pieces of the open polyline `line` that lie inside `area` (closed polygons, non-zero
// winding), both in Clipper's plane: what of a hatch line or infill line to print. Each piece has
// at least two points; a piece may run either way along the line, and pieces come in no particular
// order.
ClipperLib::Paths clip_open_path(const ClipperLib::Path& line, const ClipperLib::Paths& area);

}  // namespace flatmorph
