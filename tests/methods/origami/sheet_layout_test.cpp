// The sheets on the bed (issue 27, item 1: nets that fit the printer's bed): each turned to its
// smallest bounding rectangle, packed in rows, refused with the room they need.
#include "methods/origami/sheet_layout.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "mesh/convex_hull.h"

namespace flatmorph::sheet_layout_test {
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

// On a room narrower than the sheet is long, the sheet's long side goes along the room's.
TEST(SheetLayout, ASheetTurnsAQuarterMoreWhenOnlyThatFitsTheRoom) {
  Eigen::MatrixX2d rectangle(4, 2);
  rectangle << 0, 0, 30, 0, 30, 10, 0, 10;
  const Eigen::MatrixX2d points = turned(rectangle, 0.4);
  for (const Eigen::Vector2d& room : {Eigen::Vector2d(40, 15), Eigen::Vector2d(15, 40)}) {
    const Eigen::MatrixX2d on_room = turned(points, turn_to_room(points, room));
    const Eigen::Vector2d size = on_room.colwise().maxCoeff() - on_room.colwise().minCoeff();
    EXPECT_LE(size.x(), room.x() + 1e-9);
    EXPECT_LE(size.y(), room.y() + 1e-9);
    EXPECT_NEAR(room_overfill(points, room), std::max(30 / std::max(room.x(), room.y()), 10 / 15.0),
                1e-9);
  }
  EXPECT_NEAR(room_overfill(points, {20, 20}), 1.5, 1e-9);  // 30 mm on 20: shrink by 1.5
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

// Boxes go in rows within the room, overlapping nowhere on the same bed; those that no longer fit
// go on another bed; one too large for any bed is refused with its size and the room.
TEST(SheetLayout, BoxesGoInRowsOnAsManyBedsAsTheyNeed) {
  const std::vector<Eigen::AlignedBox2d> boxes = {
      {Eigen::Vector2d(0, 0), Eigen::Vector2d(100, 60)},
      {Eigen::Vector2d(-5, -5), Eigen::Vector2d(75, 75)},
      {Eigen::Vector2d(10, 10), Eigen::Vector2d(60, 40)}};
  const std::vector<std::string> names = {"net 1", "net 2", "net 3"};
  for (const auto& [room, beds] :
       {std::pair{Eigen::Vector2d(200, 200), 1}, std::pair{Eigen::Vector2d(120, 120), 2},
        std::pair{Eigen::Vector2d(100, 80), 3}}) {
    const BedPlacement at = pack_on_beds(boxes, names, room, 5);
    EXPECT_EQ(at.num_beds, beds) << room.transpose();
    for (size_t i = 0; i < boxes.size(); ++i) {
      const Eigen::AlignedBox2d a(at.corner[i], at.corner[i] + boxes[i].sizes());
      EXPECT_GE(a.min().minCoeff(), 0);
      EXPECT_LE(a.max().x(), room.x());
      EXPECT_LE(a.max().y(), room.y());
      EXPECT_LT(at.bed[i], beds);
      for (size_t j = 0; j < i; ++j) {
        if (at.bed[j] != at.bed[i]) continue;
        const Eigen::AlignedBox2d b(at.corner[j], at.corner[j] + boxes[j].sizes());
        EXPECT_TRUE(a.intersection(b).isEmpty() || a.intersection(b).volume() == 0) << i << j;
      }
    }
  }
  try {
    pack_on_beds(boxes, names, {90, 90}, 5);
    FAIL() << "a 100 mm sheet on a 90 mm bed";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
    EXPECT_NE(std::string(e.what()).find("net 1 100 x 60 mm"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("net 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("90 x 90 mm"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace flatmorph::sheet_layout_test
