// The print-time estimate against trapezoidal profiles computed by hand.
#include "gcode/estimate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace flatmorph::estimate_test {
namespace {

MotionLimits limits(double accel, CorneringModel model = CorneringModel::kJunctionDeviation) {
  MotionLimits l;
  l.print_acceleration = accel;
  l.travel_acceleration = accel;
  l.cornering = model;
  l.junction_deviation = 0.013;
  l.jerk = 10;
  return l;
}

Motion move(double dx, double dy, double speed, double e = 0) {
  Motion m;
  m.delta = Eigen::Vector3d(dx, dy, 0);
  m.speed = speed;
  m.e = e;
  return m;
}

TEST(Estimate, OneMoveFromRestToRest) {
  // 100 mm at 50 mm/s, 1000 mm/s^2: 0.05 s and 1.25 mm to reach 50 mm/s, the same to stop, and
  // 97.5 mm of cruise at 50 mm/s: 0.05 + 1.95 + 0.05 = 2.05 s.
  const std::vector<Motion> m = {move(100, 0, 50)};
  EXPECT_NEAR(estimate_time(m, limits(1000)), 2.05, 1e-12);
}

TEST(Estimate, ShortMoveNeverReachesItsSpeed) {
  // 1 mm at 50 mm/s: the ramps meet at sqrt(a L) = 31.6 mm/s, after sqrt(L / a) each.
  const std::vector<Motion> m = {move(0, 1, 50)};
  EXPECT_NEAR(estimate_time(m, limits(1000)), 2 * std::sqrt(1.0 / 1000), 1e-12);
}

TEST(Estimate, StraightJunctionKeepsTheSpeed) {
  const std::vector<Motion> two = {move(30, 40, 50), move(30, 40, 50)};
  const std::vector<Motion> one = {move(60, 80, 50)};
  EXPECT_NEAR(estimate_time(two, limits(1000)), estimate_time(one, limits(1000)), 1e-12);
  EXPECT_NEAR(estimate_time(two, limits(1000)), 2.05, 1e-12);
}

TEST(Estimate, RightAngleWithJunctionDeviation) {
  // Two 50 mm moves at 50 mm/s meeting at 90 degrees: sin(theta/2) = sqrt(1/2), so the corner
  // speed is v^2 = a delta s / (1 - s) = 1000 x 0.013 x 2.4142 = 31.385 (5.602 mm/s).
  const double s = std::sqrt(0.5);
  const double vj = std::sqrt(1000 * 0.013 * s / (1 - s));
  EXPECT_NEAR(vj, 5.6023, 1e-4);
  // Each move: accelerate 0 -> 50 (0.05 s over 1.25 mm), decelerate 50 -> vj, cruise the rest.
  const double decel_time = (50 - vj) / 1000;
  const double decel_dist = (50 * 50 - vj * vj) / 2000;
  const double one = 0.05 + decel_time + (50 - 1.25 - decel_dist) / 50;
  const std::vector<Motion> m = {move(50, 0, 50), move(0, 50, 50)};
  EXPECT_NEAR(estimate_time(m, limits(1000)), 2 * one, 1e-12);
}

TEST(Estimate, RightAngleWithClassicJerk) {
  // With jerk 10 mm/s, turning from +x to +y changes each axis' speed by the corner speed: 10.
  const double vj = 10;
  const double one = 0.05 + (50 - vj) / 1000 + (50 - 1.25 - (2500 - vj * vj) / 2000) / 50;
  const std::vector<Motion> m = {move(50, 0, 50), move(0, 50, 50)};
  EXPECT_NEAR(estimate_time(m, limits(1000, CorneringModel::kJerk)), 2 * one, 1e-12);
}

TEST(Estimate, ReversalStops) {
  const std::vector<Motion> there_and_back = {move(10, 0, 50), move(-10, 0, 50)};
  const std::vector<Motion> there = {move(10, 0, 50)};
  EXPECT_NEAR(estimate_time(there_and_back, limits(1000)), 2 * estimate_time(there, limits(1000)),
              1e-12);
}

TEST(Estimate, SlowNextMoveLimitsTheJunction) {
  // 100 mm at 50 then 100 mm at 10, straight on: the junction is taken at 10 mm/s.
  const std::vector<Motion> m = {move(100, 0, 50), move(100, 0, 10)};
  const double first = 0.05 + (50 - 10) / 1000.0 + (100 - 1.25 - (2500 - 100) / 2000.0) / 50;
  const double second = 10 / 1000.0 + (100 - 0.05) / 10;
  EXPECT_NEAR(estimate_time(m, limits(1000)), first + second, 1e-12);
}

TEST(Estimate, ExtrusionUsesThePrintAcceleration) {
  MotionLimits l = limits(5000);
  l.print_acceleration = 500;
  // 10 mm at 50 mm/s: 2.5 mm ramps at 500 mm/s^2 (0.1 s each), 5 mm cruise (0.1 s).
  const std::vector<Motion> extrude = {move(10, 0, 50, 0.3)};
  EXPECT_NEAR(estimate_time(extrude, l), 0.3, 1e-12);
  // The same move as a travel: 0.25 mm ramps at 5000 (0.01 s each), 9.5 mm cruise (0.19 s).
  const std::vector<Motion> travel = {move(10, 0, 50)};
  EXPECT_NEAR(estimate_time(travel, l), 0.21, 1e-12);
}

TEST(Estimate, RetractionMovesTheFilamentAlone) {
  // 2 mm of filament at 40 mm/s, 1000 mm/s^2: 0.8 mm ramps (0.04 s each), 0.4 mm at 40 (0.01 s).
  Motion retract;
  retract.e = -2;
  retract.speed = 40;
  const std::vector<Motion> m = {move(10, 0, 50), retract, move(10, 0, 50)};
  const std::vector<Motion> travel = {move(10, 0, 50)};
  EXPECT_NEAR(estimate_time(m, limits(1000)), 2 * estimate_time(travel, limits(1000)) + 0.09,
              1e-12);
}

TEST(Estimate, TrapezoidTime) {
  EXPECT_NEAR(trapezoid_time(100, 0, 50, 0, 1000), 2.05, 1e-12);
  EXPECT_NEAR(trapezoid_time(100, 50, 50, 50, 1000), 2.0, 1e-12);
  EXPECT_EQ(trapezoid_time(0, 0, 50, 0, 1000), 0);
}

TEST(Estimate, DurationInPrusaSlicersForm) {
  EXPECT_EQ(format_duration(3723), "1h 2m 3s");
  EXPECT_EQ(format_duration(59.6), "1m 0s");
  EXPECT_EQ(format_duration(12), "12s");
  EXPECT_EQ(format_duration(7200), "2h 0m 0s");
  EXPECT_EQ(format_duration(90061), "1d 1h 1m 1s");
}

}  // namespace
}  // namespace flatmorph::estimate_test
