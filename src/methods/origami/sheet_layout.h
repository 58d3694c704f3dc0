// The printed sheets on the bed (notes §6 "Fit"): each net turned so that its smallest bounding
// rectangle lies along the axes, longer side along x, and the nets packed side by side in rows,
// on as many beds (print jobs) as they need.
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

// The turn (rad) that lays the points on a room of `room` (x, y mm): min_area_rectangle_angle's,
// or a quarter turn more when the rectangle fits the room only with its longer side along y.
double turn_to_room(const Eigen::MatrixX2d& points, const Eigen::Vector2d& room);

// How many times larger than the room the points' smallest bounding rectangle is, turned as
// turn_to_room turns it: the factor by which they would have to shrink to fit (<= 1: they fit).
double room_overfill(const Eigen::MatrixX2d& points, const Eigen::Vector2d& room);

// Every corner of the printed sheet: its faces' and its actuators'.
Eigen::MatrixX2d sheet_points(const ActuatedSheet& sheet);

// Moves a sheet and its crease pattern together: x ↦ R(angle) x + offset.
void place_sheet(double angle, const Eigen::Vector2d& offset, CreasePattern& pattern,
                 ActuatedSheet& sheet);

// Where each box goes: on which bed (print job, from 0) and its new lower-left corner there.
struct BedPlacement {
  std::vector<int> bed;
  std::vector<Eigen::Vector2d> corner;
  int num_beds = 0;
};

// Lays the boxes in rows, `gap` apart, within a room of `room` (x, y) per bed; the tallest first,
// each row left to right, and a new bed when the next row would not fit the room. Throws
// UserError (kInfeasible) naming the boxes (`names`) that do not fit a bed on their own, with
// their size and the room.
BedPlacement pack_on_beds(const std::vector<Eigen::AlignedBox2d>& boxes,
                          const std::vector<std::string>& names, const Eigen::Vector2d& room,
                          double gap);

}  // namespace flatmorph
