#include "methods/origami/sheet_layout.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "common/error.h"
#include "mesh/convex_hull.h"

namespace flatmorph {
namespace {

Eigen::Matrix2d rotation(double angle) { return Eigen::Rotation2Dd(angle).toRotationMatrix(); }

}  // namespace

double min_area_rectangle_angle(const Eigen::MatrixX2d& points) {
  const Eigen::MatrixX2d hull = convex_hull(points);
  double best_angle = 0, best_area = INFINITY;
  for (Eigen::Index i = 0; i < hull.rows(); ++i) {
    const Eigen::Vector2d side = hull.row((i + 1) % hull.rows()) - hull.row(i);
    const double angle = -std::atan2(side.y(), side.x());  // lays this side along +x
    const Eigen::MatrixX2d turned = hull * rotation(angle).transpose();
    const Eigen::Vector2d size = turned.colwise().maxCoeff() - turned.colwise().minCoeff();
    // Ties (a rectangle's four sides) go to the first side met: the result does not depend on
    // rounding in the comparison of equal areas.
    if (size.prod() < best_area * (1 - 1e-9)) {
      best_area = size.prod();
      best_angle = size.x() >= size.y() ? angle : angle + std::numbers::pi / 2;
    }
  }
  return std::remainder(best_angle, 2 * std::numbers::pi);
}

namespace {

// The size of the points' bounding box once turned by `angle`.
Eigen::Vector2d turned_size(const Eigen::MatrixX2d& points, double angle) {
  const Eigen::MatrixX2d turned = points * rotation(angle).transpose();
  return turned.colwise().maxCoeff() - turned.colwise().minCoeff();
}

double overfill(const Eigen::Vector2d& size, const Eigen::Vector2d& room) {
  return std::max(size.x() / room.x(), size.y() / room.y());
}

}  // namespace

double turn_to_room(const Eigen::MatrixX2d& points, const Eigen::Vector2d& room) {
  const double angle = min_area_rectangle_angle(points);
  const Eigen::Vector2d size = turned_size(points, angle);
  return overfill(size, room) > 1 && overfill(size.reverse(), room) <= 1
             ? angle + std::numbers::pi / 2
             : angle;
}

double room_overfill(const Eigen::MatrixX2d& points, const Eigen::Vector2d& room) {
  return overfill(turned_size(points, turn_to_room(points, room)), room);
}

Eigen::MatrixX2d sheet_points(const ActuatedSheet& sheet) {
  Eigen::Index n = 4 * static_cast<Eigen::Index>(sheet.actuators.size());
  for (const Eigen::MatrixX2d& face : sheet.faces) n += face.rows();
  Eigen::MatrixX2d points(n, 2);
  Eigen::Index row = 0;
  for (const Eigen::MatrixX2d& face : sheet.faces) {
    points.middleRows(row, face.rows()) = face;
    row += face.rows();
  }
  for (const Actuator& actuator : sheet.actuators) {
    points.middleRows(row, 4) = actuator.quad;
    row += 4;
  }
  return points;
}

void place_sheet(double angle, const Eigen::Vector2d& offset, CreasePattern& pattern,
                 ActuatedSheet& sheet) {
  const Eigen::Matrix2d R = rotation(angle);
  auto move = [&](auto& points) {
    points = (points * R.transpose()).rowwise() + offset.transpose();
  };
  move(pattern.V);
  for (Eigen::MatrixX2d& face : sheet.faces) move(face);
  for (Actuator& actuator : sheet.actuators) {
    move(actuator.quad);
    actuator.across = R * actuator.across;
  }
}

BedPlacement pack_on_beds(const std::vector<Eigen::AlignedBox2d>& boxes,
                          const std::vector<std::string>& names, const Eigen::Vector2d& room,
                          double gap) {
  std::string too_large;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Eigen::Vector2d size = boxes[i].sizes();
    if (size.x() > room.x() || size.y() > room.y()) {
      too_large += fmt::format("{}{} {:.0f} x {:.0f} mm", too_large.empty() ? "" : ", ", names[i],
                               size.x(), size.y());
    }
  }
  if (!too_large.empty()) {
    throw UserError(ErrorCategory::kInfeasible,
                    fmt::format("the printed sheet ({}) does not fit the {:.0f} x {:.0f} mm the "
                                "bed has to print on: make the solid smaller (--size) or choose "
                                "a larger printer",
                                too_large, room.x(), room.y()));
  }
  std::vector<int> order(boxes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return boxes[a].sizes().y() > boxes[b].sizes().y(); });
  BedPlacement out;
  out.bed.resize(boxes.size());
  out.corner.resize(boxes.size());
  Eigen::Vector2d cursor(0, 0);
  double row_height = 0;
  int bed = 0;
  for (int i : order) {
    const Eigen::Vector2d size = boxes[i].sizes();
    if (cursor.x() > 0 && cursor.x() + size.x() > room.x()) {  // next row
      cursor = {0, cursor.y() + row_height + gap};
      row_height = 0;
    }
    if (cursor.y() > 0 && cursor.y() + size.y() > room.y()) {  // next bed
      cursor = {0, 0};
      ++bed;
    }
    out.bed[i] = bed;
    out.corner[i] = cursor;
    row_height = std::max(row_height, size.y());
    cursor.x() += size.x() + gap;
  }
  out.num_beds = boxes.empty() ? 0 : bed + 1;
  return out;
}

}  // namespace flatmorph
