#include "mesh/polygon.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace flatmorph {
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

}  // namespace
}  // namespace flatmorph
