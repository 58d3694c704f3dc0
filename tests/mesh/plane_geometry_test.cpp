#include "mesh/plane_geometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace flatmorph::plane_geometry_test {
namespace {

using P = Eigen::Vector2d;

TEST(PlaneGeometry, CrossAndTriangleAreaHaveTheTurnsSign) {
  EXPECT_EQ(cross2(P(1, 0), P(0, 1)), 1);
  EXPECT_EQ(cross2(P(0, 1), P(1, 0)), -1);
  EXPECT_EQ(cross2(P(2, 3), P(4, 6)), 0);  // parallel
  // A right triangle with legs 4 and 3 mm: 6 mm², negative when run clockwise.
  EXPECT_EQ(triangle_signed_area(P(1, 1), P(5, 1), P(1, 4)), 6);
  EXPECT_EQ(triangle_signed_area(P(1, 1), P(1, 4), P(5, 1)), -6);
  EXPECT_EQ(triangle_signed_area(P(0, 0), P(1, 1), P(2, 2)), 0);
}

// Segment (0, 0)–(4, 0): a point above its middle, points beyond either end (nearest the end), a
// point on it, and a segment of zero length (its point).
TEST(PlaneGeometry, SegmentDistanceAtKnownPoints) {
  const P a(0, 0), b(4, 0);
  double t = -1;
  EXPECT_EQ(segment_distance(P(1, 3), a, b, t), 3);
  EXPECT_EQ(t, 0.25);
  EXPECT_EQ(segment_distance(P(-3, 4), a, b, t), 5);
  EXPECT_EQ(t, 0);
  EXPECT_EQ(segment_distance(P(7, -4), a, b, t), 5);
  EXPECT_EQ(t, 1);
  EXPECT_EQ(segment_distance(P(2, 0), a, b), 0);
  EXPECT_EQ(segment_distance(P(3, 4), a, a, t), 5);
  EXPECT_EQ(t, 0);
  // Either direction of the segment.
  EXPECT_DOUBLE_EQ(segment_distance(P(1, 3), b, a), 3);
  EXPECT_FALSE(std::isnan(segment_distance(P(1, 1), P(2, 2), P(2, 2))));
}

TEST(PlaneGeometry, SideCrossesRayToTheRight) {
  const P p(0, 0);
  EXPECT_TRUE(side_crosses_ray(p, P(1, -1), P(1, 1)));
  EXPECT_TRUE(side_crosses_ray(p, P(1, 1), P(1, -1)));
  EXPECT_FALSE(side_crosses_ray(p, P(-1, -1), P(-1, 1)));  // to the left
  EXPECT_FALSE(side_crosses_ray(p, P(1, 1), P(2, 2)));     // above
  // A corner on the ray's height, between a side going down and one going up: one of them counts.
  EXPECT_TRUE(side_crosses_ray(p, P(1, 0), P(1, -1)) != side_crosses_ray(p, P(1, 0), P(1, 1)));
}

TEST(PlaneGeometry, SegmentIntersectionCrossingTouchingAndApart) {
  const auto x = segment_intersection(P(0, 0), P(2, 2), P(0, 2), P(2, 0));
  ASSERT_TRUE(x);
  EXPECT_EQ(*x, P(1, 1));
  // An end on the other segment (a T), and collinear overlap: an end of one.
  const auto t = segment_intersection(P(0, 0), P(4, 0), P(2, 0), P(2, 3));
  ASSERT_TRUE(t);
  EXPECT_EQ(*t, P(2, 0));
  const auto overlap = segment_intersection(P(0, 0), P(4, 0), P(3, 0), P(6, 0));
  ASSERT_TRUE(overlap);
  EXPECT_EQ(*overlap, P(3, 0));
  EXPECT_FALSE(segment_intersection(P(0, 0), P(1, 0), P(2, -1), P(2, 1)));  // short of it
  EXPECT_FALSE(segment_intersection(P(0, 0), P(4, 0), P(0, 1), P(4, 1)));   // parallel
  EXPECT_FALSE(segment_intersection(P(0, 0), P(1, 0), P(2, 0), P(3, 0)));   // collinear, apart
}

}  // namespace
}  // namespace flatmorph::plane_geometry_test
