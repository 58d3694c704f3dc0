// The path-quality evaluator against layouts whose answers are known.
#include "toolpath/path_quality.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "toolpath/test_plates.h"

namespace flatmorph::path_quality_test {
namespace {

// Straight lines across the 20 x 10 mm rectangle at angle `angle` (rad), `pitch` mm apart.
std::vector<PathPolyline> lines(double pitch, double angle = 0, double y_offset = 0.5) {
  std::vector<PathPolyline> out;
  for (double y = -5 + pitch * y_offset; y < 5; y += pitch) {
    PathPolyline p;
    // A line through (0, y) at `angle`, clipped to |x| <= 10 with |y| <= 5.
    const double dx = std::cos(angle), dy = std::sin(angle);
    double t0 = -10 / dx, t1 = 10 / dx;
    if (dy != 0) {
      const double ta = (-5 - y) / dy, tb = (5 - y) / dy;
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
    p.points.resize(2, 3);
    p.points.row(0) << t0 * dx, y + t0 * dy, 0.08;
    p.points.row(1) << t1 * dx, y + t1 * dy, 0.08;
    p.segments.resize(1);
    out.push_back(p);
  }
  return out;
}

TEST(PathQuality, PerfectLines) {
  const toolpath_testing::TestPlate plate = toolpath_testing::rectangle_plate(20, 10, 1.0);
  const Eigen::VectorXd theta = Eigen::VectorXd::Zero(plate.V.rows());
  PathQualityOptions options;
  const PathQuality q = evaluate_path_quality(plate.V, plate.F, theta, lines(0.4), {}, options);
  EXPECT_EQ(q.spacing_in_range, 1.0);
  EXPECT_NEAR(q.spacing_median, 1.0, 1e-9);
  EXPECT_GT(q.covered_area, 0.995);
  EXPECT_EQ(q.points_outside, 0);
  EXPECT_NEAR(q.angle_median_deg, 0, 1e-9);
  EXPECT_NEAR(q.angle_p95_deg, 0, 1e-9);
  // 25 lines of 20 mm sampled every 0.1 mm.
  EXPECT_NEAR(q.samples, 25 * 201, 25);
}

TEST(PathQuality, SparseLinesLeaveGaps) {
  // Lines 2 spacings apart (y = -4.6 + 0.8 k, k = 0..11): each covers a band 1.2 spacings =
  // 0.48 mm wide, 12 x 0.48 / 10 of the plate; the nearest other line is 2 spacings away, out of
  // the accepted band.
  const toolpath_testing::TestPlate plate = toolpath_testing::rectangle_plate(20, 10, 1.0);
  const Eigen::VectorXd theta = Eigen::VectorXd::Zero(plate.V.rows());
  const PathQuality q =
      evaluate_path_quality(plate.V, plate.F, theta, lines(0.8), {}, PathQualityOptions{});
  EXPECT_NEAR(q.covered_area, 0.576, 0.005);
  EXPECT_LT(q.spacing_in_range, 0.01);
}

TEST(PathQuality, MisalignedLinesAndSingularExclusion) {
  const toolpath_testing::TestPlate plate = toolpath_testing::rectangle_plate(20, 10, 1.0);
  const Eigen::VectorXd theta =
      Eigen::VectorXd::Constant(plate.V.rows(), 5 * std::numbers::pi / 180);
  const PathQuality q =
      evaluate_path_quality(plate.V, plate.F, theta, lines(0.4), {}, PathQualityOptions{});
  EXPECT_NEAR(q.angle_median_deg, 5, 1e-9);
  // Samples near a singular point are not judged.
  PathQualityOptions options;
  options.singular_exclusion_mm = 3;
  const PathQuality excluded =
      evaluate_path_quality(plate.V, plate.F, theta, lines(0.4), {Eigen::Vector2d(0, 0)}, options);
  EXPECT_LT(excluded.angle_samples, q.angle_samples);
  // A circle of radius 3 holds about pi 9 / (0.4 x 0.1) samples.
  EXPECT_NEAR(q.angle_samples - excluded.angle_samples, std::numbers::pi * 9 / 0.04, 30);
}

TEST(PathQuality, PointsOutsideThePlate) {
  const toolpath_testing::TestPlate plate = toolpath_testing::rectangle_plate(20, 10, 1.0);
  const Eigen::VectorXd theta = Eigen::VectorXd::Zero(plate.V.rows());
  std::vector<PathPolyline> paths = lines(0.4);
  paths[0].points(0, 0) -= 0.5;  // 0.5 mm beyond the left edge
  const PathQuality q = evaluate_path_quality(plate.V, plate.F, theta, paths, {}, {});
  EXPECT_EQ(q.points_outside, 1);
  EXPECT_NEAR(q.max_outside_mm, 0.5, 1e-9);
  paths[0].points(0, 0) += 0.5 - 1e-7;  // within the tolerance of the boundary
  EXPECT_EQ(evaluate_path_quality(plate.V, plate.F, theta, paths, {}, {}).points_outside, 0);
}

TEST(PathQuality, SpiralTurnsAreNeighbours) {
  // One Archimedean spiral with a pitch of one spacing: its own next turn is its neighbour.
  const toolpath_testing::TestPlate plate = toolpath_testing::disk_plate(20, 1.0);
  PathPolyline spiral;
  const int n = 20000;
  spiral.points.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * 20 * i / (n - 1);  // 20 turns
    const double r = 1.5 + 0.4 * a / (2 * std::numbers::pi);
    spiral.points.row(i) << r * std::cos(a), r * std::sin(a), 0;
  }
  spiral.segments.resize(n - 1);
  Eigen::VectorXd theta(plate.V.rows());
  for (int v = 0; v < plate.V.rows(); ++v) {
    theta(v) = std::atan2(plate.V(v, 1), plate.V(v, 0)) + std::numbers::pi / 2;
  }
  const PathQuality q = evaluate_path_quality(plate.V, plate.F, theta, {spiral}, {}, {});
  // The first and last turns have a neighbour on one side only, so all are in range.
  EXPECT_GT(q.spacing_in_range, 0.99);
  EXPECT_NEAR(q.spacing_median, 1.0, 0.01);
  EXPECT_LT(q.angle_median_deg, 2);
}

}  // namespace
}  // namespace flatmorph::path_quality_test
