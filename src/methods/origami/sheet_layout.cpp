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

std::vector<Eigen::Vector2d> pack_in_rows(const std::vector<Eigen::AlignedBox2d>& boxes,
                                          const std::vector<std::string>& names,
                                          const Eigen::Vector2d& room, double gap) {
  std::vector<int> order(boxes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return boxes[a].sizes().y() > boxes[b].sizes().y(); });
  std::vector<Eigen::Vector2d> offsets(boxes.size());
  Eigen::Vector2d cursor(0, 0);
  double row_height = 0, used_width = 0;
  for (int i : order) {
    const Eigen::Vector2d size = boxes[i].sizes();
    if (cursor.x() > 0 && cursor.x() + size.x() > room.x()) {  // next row
      cursor = {0, cursor.y() + row_height + gap};
      row_height = 0;
    }
    offsets[i] = cursor;
    used_width = std::max(used_width, cursor.x() + size.x());
    row_height = std::max(row_height, size.y());
    cursor.x() += size.x() + gap;
  }
  const Eigen::Vector2d used(used_width, cursor.y() + row_height);
  if (used.x() > room.x() || used.y() > room.y()) {
    std::string list;
    for (size_t i = 0; i < boxes.size(); ++i) {
      list += fmt::format("{}{} {:.0f} x {:.0f} mm", i ? ", " : "", names[i], boxes[i].sizes().x(),
                          boxes[i].sizes().y());
    }
    throw UserError(ErrorCategory::kInfeasible,
                    fmt::format("the printed sheet{} ({}) need{} {:.0f} x {:.0f} mm but the bed "
                                "has {:.0f} x {:.0f} mm to print on: make the solid smaller "
                                "(--size) or choose a larger printer",
                                boxes.size() > 1 ? "s" : "", list, boxes.size() > 1 ? "" : "s",
                                used.x(), used.y(), room.x(), room.y()));
  }
  return offsets;
}

}  // namespace flatmorph
