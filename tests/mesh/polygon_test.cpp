#include "mesh/polygon.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <vector>

namespace flatmorph::polygon_test {
namespace {

// A 3 x 2 rectangle: 6 mm² counter-clockwise, −6 clockwise, wherever it lies and however turned.
TEST(Polygon, SignedAreaIsTheEnclosedAreaWithTheLoopsSense) {
  Eigen::MatrixX2d rectangle(4, 2);
  rectangle << 0, 0, 3, 0, 3, 2, 0, 2;
  EXPECT_DOUBLE_EQ(signed_area(rectangle), 6);
  EXPECT_DOUBLE_EQ(signed_area(rectangle.colwise().reverse()), -6);
  const Eigen::Matrix2d turn = Eigen::Rotation2Dd(0.83).toRotationMatrix();
  const Eigen::MatrixX2d moved =
      (rectangle * turn.transpose()).rowwise() + Eigen::RowVector2d(7, -4);
  EXPECT_NEAR(signed_area(moved), 6, 1e-12);
  Eigen::MatrixX2d l_shape(6, 2);  // a 2 x 2 square less its 1 x 1 top-right quarter
  l_shape << 0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2;
  EXPECT_DOUBLE_EQ(signed_area(l_shape), 3);
  EXPECT_EQ(signed_area(Eigen::MatrixX2d(0, 2)), 0);
}

std::vector<Eigen::Vector2d> corners(const Eigen::MatrixX2d& polygon) {
  std::vector<Eigen::Vector2d> out;
  for (Eigen::Index i = 0; i < polygon.rows(); ++i) out.push_back(polygon.row(i).transpose());
  return out;
}

// The loop as a list of points gives the same bits as the loop as rows, in either sense.
TEST(Polygon, SignedAreaOfAListOfPointsIsTheSame) {
  Eigen::MatrixX2d l_shape(6, 2);
  l_shape << 0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2;
  EXPECT_DOUBLE_EQ(signed_area(corners(l_shape)), 3);
  EXPECT_DOUBLE_EQ(signed_area(corners(l_shape.colwise().reverse())), -3);
  const Eigen::Matrix2d turn = Eigen::Rotation2Dd(0.83).toRotationMatrix();
  const Eigen::MatrixX2d moved = (l_shape * turn.transpose()).rowwise() + Eigen::RowVector2d(7, -4);
  EXPECT_EQ(signed_area(corners(moved)), signed_area(moved));
  EXPECT_EQ(signed_area(std::vector<Eigen::Vector2d>{}), 0);
}

// The L shape's inside, its cut-away quarter and the outside; either sense, either form.
TEST(Polygon, PointInPolygonFollowsTheEvenOddRule) {
  Eigen::MatrixX2d l_shape(6, 2);
  l_shape << 0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2;
  const Eigen::MatrixX2d reversed = l_shape.colwise().reverse();
  for (const Eigen::MatrixX2d& polygon : {l_shape, reversed}) {
    EXPECT_TRUE(point_in_polygon(polygon, Eigen::Vector2d(0.5, 1.5)));
    EXPECT_TRUE(point_in_polygon(polygon, Eigen::Vector2d(1.5, 0.5)));
    EXPECT_FALSE(point_in_polygon(polygon, Eigen::Vector2d(1.5, 1.5)));  // the missing quarter
    EXPECT_FALSE(point_in_polygon(polygon, Eigen::Vector2d(-0.5, 0.5)));
    EXPECT_FALSE(point_in_polygon(polygon, Eigen::Vector2d(0.5, 2.5)));
    // A ray through a corner (y = 1) counts it once.
    EXPECT_TRUE(point_in_polygon(polygon, Eigen::Vector2d(0.5, 1)));
    EXPECT_TRUE(point_in_polygon(corners(polygon), Eigen::Vector2d(0.5, 1.5)));
    EXPECT_FALSE(point_in_polygon(corners(polygon), Eigen::Vector2d(1.5, 1.5)));
  }
  EXPECT_FALSE(point_in_polygon(Eigen::MatrixX2d(0, 2), Eigen::Vector2d(0, 0)));
}

Eigen::MatrixX2d square(double x, double y, double side) {
  Eigen::MatrixX2d out(4, 2);
  out << x, y, x + side, y, x + side, y + side, x, y + side;
  return out;
}

// Overlap is shared area, not contact: squares side by side or corner to corner do not overlap, a
// half-covered one does, and so does one inside the other.
TEST(Polygon, PolygonsOverlapWhenTheyShareAreaNotWhenTheyTouch) {
  const Eigen::MatrixX2d a = square(0, 0, 10);
  EXPECT_FALSE(polygons_overlap(a, square(10, 0, 10)));   // a shared side
  EXPECT_FALSE(polygons_overlap(a, square(10, 10, 10)));  // a shared corner
  EXPECT_FALSE(polygons_overlap(a, square(30, 0, 10)));
  EXPECT_TRUE(polygons_overlap(a, square(5, 0, 10)));
  EXPECT_TRUE(polygons_overlap(a, square(2, 2, 1)));
  EXPECT_TRUE(polygons_overlap(square(2, 2, 1), a));
  EXPECT_FALSE(polygons_overlap(a, square(10 - 1e-7, 0, 10)));  // a sliver from rounding
}

// Ear clipping: #P − 2 triangles of the polygon's sense whose areas add up to the polygon's; a
// partition, since none of them runs backwards. Checked on a comb (many reflex corners), its mirror
// image (clockwise) and a square with a corner on a straight side.
TEST(Polygon, TriangulatePolygonCutsASimplePolygonIntoTrianglesOfItsArea) {
  Eigen::MatrixX2d comb(12, 2);  // three teeth up from a 7 x 1 bar
  comb << 0, 0, 7, 0, 7, 3, 6, 3, 6, 1, 4, 1, 4, 3, 3, 3, 3, 1, 1, 1, 1, 3, 0, 3;
  Eigen::MatrixX2d mirrored = comb;
  mirrored.col(0) *= -1;
  Eigen::MatrixX2d straight(5, 2);
  straight << 0, 0, 1, 0, 2, 0, 2, 2, 0, 2;
  for (const Eigen::MatrixX2d& polygon : {comb, mirrored, straight, square(0, 0, 1)}) {
    const Eigen::MatrixX3i triangles = triangulate_polygon(polygon);
    ASSERT_EQ(triangles.rows(), polygon.rows() - 2);
    const double area = signed_area(polygon);
    double sum = 0;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
      Eigen::MatrixX2d triangle(3, 2);
      for (int k = 0; k < 3; ++k) triangle.row(k) = polygon.row(triangles(t, k));
      const double part = signed_area(triangle);
      EXPECT_GE(part * area, 0) << "triangle " << t << " runs backwards";
      sum += part;
    }
    EXPECT_NEAR(sum, area, 1e-12 * std::abs(area));
  }
  EXPECT_NEAR(signed_area(comb), 13, 1e-12);
  EXPECT_THROW(triangulate_polygon(Eigen::MatrixX2d(2, 2)), std::invalid_argument);
}

}  // namespace
}  // namespace flatmorph::polygon_test
