// The sheets on the bed (issue 27, item 1: nets that fit the printer's bed): each turned to its
// smallest bounding rectangle, packed in rows, refused with the room they need.
#include "methods/origami/sheet_layout.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "mesh/convex_hull.h"

namespace flatmorph {
namespace {

Eigen::MatrixX2d turned(const Eigen::MatrixX2d& points, double angle) {
  return points * Eigen::Rotation2Dd(angle).toRotationMatrix().transpose();
}

TEST(SheetLayout, ATurnedRectangleIsTurnedBackLongSideAlongX) {
  Eigen::MatrixX2d rectangle(4, 2);
  rectangle << 0, 0, 10, 0, 10, 30, 0, 30;  // long side along y
  for (double angle : {0.0, 0.3, -1.2, 2.9}) {
    const Eigen::MatrixX2d points = turned(rectangle, angle);
    const Eigen::MatrixX2d back = turned(points, min_area_rectangle_angle(points));
    const Eigen::Vector2d size = back.colwise().maxCoeff() - back.colwise().minCoeff();
    EXPECT_NEAR(size.x(), 30, 1e-9) << angle;
    EXPECT_NEAR(size.y(), 10, 1e-9) << angle;
  }
}

TEST(SheetLayout, AnLShapeGetsNoLargerBoxThanAnyOtherTurn) {
  Eigen::MatrixX2d l_shape(6, 2);
  l_shape << 0, 0, 40, 0, 40, 10, 10, 10, 10, 25, 0, 25;
  const Eigen::MatrixX2d points = turned(l_shape, 0.7);
  const Eigen::MatrixX2d best = turned(points, min_area_rectangle_angle(points));
  const double best_area = (best.colwise().maxCoeff() - best.colwise().minCoeff()).prod();
  for (int k = 0; k < 360; ++k) {
    const Eigen::MatrixX2d other = turned(points, k * M_PI / 180);
    EXPECT_LE(best_area, (other.colwise().maxCoeff() - other.colwise().minCoeff()).prod() + 1e-9);
  }
}

TEST(SheetLayout, ConvexHullIsCounterClockwiseWithoutInnerOrCollinearPoints) {
  Eigen::MatrixX2d points(7, 2);
  points << 0, 0, 2, 0, 4, 0, 4, 4, 1, 1, 0, 4, 2, 2;
  const Eigen::MatrixX2d hull = convex_hull(points);
  ASSERT_EQ(hull.rows(), 4);
  double twice_area = 0;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d a = hull.row(i), b = hull.row((i + 1) % 4);
    twice_area += a.x() * b.y() - a.y() * b.x();
  }
  EXPECT_NEAR(twice_area, 32, 1e-12);
}

TEST(SheetLayout, BoxesGoInRowsWithoutOverlapAndTooManyAreRefusedWithTheRoomNeeded) {
  const std::vector<Eigen::AlignedBox2d> boxes = {
      {Eigen::Vector2d(0, 0), Eigen::Vector2d(100, 60)},
      {Eigen::Vector2d(-5, -5), Eigen::Vector2d(75, 75)},
      {Eigen::Vector2d(10, 10), Eigen::Vector2d(60, 40)}};
  const std::vector<std::string> names = {"net 1", "net 2", "net 3"};
  const std::vector<Eigen::Vector2d> at = pack_in_rows(boxes, names, {200, 200}, 5);
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Eigen::AlignedBox2d a(at[i], at[i] + boxes[i].sizes());
    EXPECT_GE(a.min().minCoeff(), 0);
    EXPECT_LE(a.max().x(), 200);
    EXPECT_LE(a.max().y(), 200);
    for (size_t j = 0; j < i; ++j) {
      const Eigen::AlignedBox2d b(at[j], at[j] + boxes[j].sizes());
      EXPECT_TRUE(a.intersection(b).isEmpty() || a.intersection(b).volume() == 0) << i << j;
    }
  }
  try {
    pack_in_rows(boxes, names, {120, 120}, 5);
    FAIL() << "three sheets on a 120 mm bed";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
    EXPECT_NE(std::string(e.what()).find("net 2 80 x 80 mm"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("120 x 120 mm"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace flatmorph
