// Per-layer directions as line fields: doubled-angle averaging, the layer formula and its sign
// convention, singularity indices, interpolation.
#include "toolpath/line_field.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "toolpath/test_plates.h"

namespace flatmorph::line_field_test {
namespace {

TEST(LineField, AveragesDoubledAnglesNotNumbers) {
  // Two triangles of equal area sharing a vertex, printed at -89 and +89 degrees: the same line
  // up to 2 degrees, so the average is the vertical line, not 0 (horizontal) as plain numbers give.
  Eigen::MatrixXd V(4, 2);
  V << 0, 0, 1, 0, 0, 1, -1, 0;
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 0, 2, 3;
  Eigen::VectorXd theta(2);
  theta << -89 * kDegree, 89 * kDegree;
  const Eigen::VectorXd vertex = line_field_angle(face_to_vertex_line_field(V, F, theta));
  EXPECT_NEAR(line_angle_difference(vertex(0), kPi / 2), 0, 1e-12);
  EXPECT_NEAR(line_angle_difference(vertex(1), -89 * kDegree), 0, 1e-12);  // only the first face
  EXPECT_NEAR(line_angle_difference(vertex(3), 89 * kDegree), 0, 1e-12);
}

TEST(LineField, AreaWeighted) {
  // A vertex shared by a triangle of area 1/2 at 0 degrees and one of area 3/2 at 60 degrees:
  // arg(0.5 + 1.5 e^{2 i 60 deg}) / 2.
  Eigen::MatrixXd V(4, 2);
  V << 0, 0, 1, 0, 0, 1, -3, 0;
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 0, 2, 3;
  Eigen::VectorXd theta(2);
  theta << 0, 60 * kDegree;
  const Eigen::VectorXd vertex = line_field_angle(face_to_vertex_line_field(V, F, theta));
  const double expected = 0.5 * std::arg(0.5 + 1.5 * std::polar(1.0, 120 * kDegree));
  EXPECT_NEAR(vertex(0), expected, 1e-12);
}

TEST(LineField, DoubledIndexFindsSingularities) {
  const toolpath_testing::TestPlate plate = toolpath_testing::disk_plate(20, 2.0);
  const auto count = [&](const toolpath_testing::Field& field, int expected_value) {
    const Eigen::VectorXi index =
        line_field_doubled_index(plate.F, toolpath_testing::per_vertex(plate, field));
    int nonzero = 0, total = 0;
    for (int f = 0; f < index.size(); ++f) {
      if (index(f) != 0) {
        ++nonzero;
        total += index(f);
      }
    }
    EXPECT_GE(nonzero, 1);
    EXPECT_EQ(total, expected_value);
  };
  // Concentric circles and radial lines: index +1 (doubled: 2) around the centre.
  count([](double x, double y) { return std::atan2(y, x) + kPi / 2; }, 2);
  count([](double x, double y) { return std::atan2(y, x); }, 2);
  // A "comet" (+1/2) and a "tripod" (-1/2): half-turns, which a vector field cannot have.
  count([](double x, double y) { return 0.5 * std::atan2(y - 0.3, x - 0.2); }, 1);
  count([](double x, double y) { return -0.5 * std::atan2(y - 0.3, x - 0.2); }, -1);
  // A smooth field: none.
  const Eigen::VectorXi smooth = line_field_doubled_index(
      plate.F,
      toolpath_testing::per_vertex(plate, [](double x, double y) { return 0.05 * x + 0.03 * y; }));
  EXPECT_EQ(smooth.cwiseAbs().sum(), 0);
}

TEST(LineField, InterpolationAndAngleDifference) {
  // Halfway between 80 and -80 degrees (as lines 20 degrees apart across the vertical) is 90.
  const double mid = interpolate_line_field(80 * kDegree, -80 * kDegree, -80 * kDegree,
                                            Eigen::Vector3d(0.5, 0.25, 0.25));
  EXPECT_NEAR(line_angle_difference(mid, 90 * kDegree), 0, 1e-12);
  EXPECT_NEAR(line_angle_difference(10 * kDegree, 190 * kDegree), 0, 1e-12);
  EXPECT_NEAR(line_angle_difference(0, 100 * kDegree), 80 * kDegree, 1e-12);
  EXPECT_NEAR(line_angle_difference(0, 90 * kDegree), 90 * kDegree, 1e-12);
}

}  // namespace
}  // namespace flatmorph::line_field_test
