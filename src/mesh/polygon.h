// Plane polygons as the methods draw them: a closed loop of #P x 2 corners, mm, the last joined
// back to the first.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace flatmorph {

// The shoelace area, mm²: positive for a counter-clockwise loop, negative for a clockwise one; the
// same bits for the same loop in either form.
double signed_area(const Eigen::MatrixX2d& polygon);
double signed_area(const std::vector<Eigen::Vector2d>& polygon);

// Whether p lies inside the polygon (either sense) by the even-odd rule; a point on a side may fall
// either way. The same answer for the same loop in either form.
bool point_in_polygon(const Eigen::MatrixX2d& polygon, const Eigen::Vector2d& p);
bool point_in_polygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p);

// Whether two simple polygons overlap by more than a sliver: a common area (Clipper) over 1e-4 of
// the smaller one's. Polygons that only touch along a side or at a corner do not overlap.
bool polygons_overlap(const Eigen::MatrixX2d& a, const Eigen::MatrixX2d& b);

// A simple polygon (either sense, convex or not) cut into #P − 2 triangles by ear clipping: corner
// indices, each triangle running the polygon's sense. Corners on a straight side are kept (as
// corners of thin triangles). Throws std::invalid_argument for fewer than three corners.
Eigen::MatrixX3i triangulate_polygon(const Eigen::MatrixX2d& polygon);

}  // namespace flatmorph
