// The printed sheets on the bed (notes §6 "Fit"): each net turned so that its smallest bounding
// rectangle lies along the axes, longer side along x, and the nets packed side by side in rows.
// Millimetres and radians, plate coordinates (the G-code writer centres the whole on the bed).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "methods/origami/crease_pattern.h"

namespace flatmorph {

// The turn (rad) after which the points' bounding box is the smallest of any direction (one of
// the convex hull's sides along an axis: rotating calipers) with its longer side along x.
double min_area_rectangle_angle(const Eigen::MatrixX2d& points);

// Every corner of the printed sheet: its faces' and its actuators'.
Eigen::MatrixX2d sheet_points(const ActuatedSheet& sheet);

// Moves a sheet and its crease pattern together: x ↦ R(angle) x + offset.
void place_sheet(double angle, const Eigen::Vector2d& offset, CreasePattern& pattern,
                 ActuatedSheet& sheet);

// Offsets (the new lower-left corners) that lay the boxes in rows, `gap` apart, within a room of
// `room` (x, y); the tallest first, each row left to right. Throws UserError (kInfeasible) naming
// the sheets (`names`) and the room they would need when they do not fit.
std::vector<Eigen::Vector2d> pack_in_rows(const std::vector<Eigen::AlignedBox2d>& boxes,
                                          const std::vector<std::string>& names,
                                          const Eigen::Vector2d& room, double gap);

}  // namespace flatmorph
