// Ramer–Douglas–Peucker: keeps the ends, drops what lies within the tolerance, keeps the rest.
#include "toolpath/simplify.h"

#include <gtest/gtest.h>

#include <cmath>

namespace flatmorph::simplify_test {
namespace {

double distance_to_polyline(const Eigen::Vector2d& p, const Eigen::MatrixXd& P) {
  double best = 1e300;
  for (int i = 0; i + 1 < P.rows(); ++i) {
    const Eigen::Vector2d a = P.row(i).head<2>(), b = P.row(i + 1).head<2>();
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * (b - a) - p).norm());
  }
  return best;
}

TEST(Simplify, CollinearPointsCollapseToTheEnds) {
  Eigen::MatrixXd P(5, 3);
  P << 0, 0, 0.2, 1, 1, 0.2, 2, 2, 0.2, 3, 3, 0.2, 4, 4, 0.2;
  const Eigen::MatrixXd S = simplify_polyline(P, 0.01);
  ASSERT_EQ(S.rows(), 2);
  EXPECT_EQ(S.row(0), P.row(0));
  EXPECT_EQ(S.row(1), P.row(4));
}

TEST(Simplify, ArcWithinTolerance) {
  // A quarter circle of radius 10 mm sampled every 0.1 mm: RDP keeps far fewer points, every
  // original point stays within the tolerance, and a chord's sagitta l^2/(8R) bounds the count.
  const int n = 158;
  Eigen::MatrixXd P(n, 2);
  for (int i = 0; i < n; ++i) {
    const double a = 0.5 * M_PI * i / (n - 1);
    P.row(i) << 10 * std::cos(a), 10 * std::sin(a);
  }
  const double tolerance = 0.01;
  const Eigen::MatrixXd S = simplify_polyline(P, tolerance);
  for (int i = 0; i < n; ++i) EXPECT_LE(distance_to_polyline(P.row(i), S), tolerance + 1e-12);
  // Chords with sagitta 0.01 mm are about sqrt(8 R tol) = 0.89 mm long: about 18 for 15.7 mm.
  EXPECT_LT(S.rows(), 40);
  EXPECT_GT(S.rows(), 10);
}

TEST(Simplify, KeepsACorner) {
  Eigen::MatrixXd P(5, 2);
  P << 0, 0, 1, 0, 2, 0, 2, 1, 2, 2;
  const Eigen::MatrixXd S = simplify_polyline(P, 0.01);
  ASSERT_EQ(S.rows(), 3);
  EXPECT_EQ(S.row(1), P.row(2));
}

}  // namespace
}  // namespace flatmorph::simplify_test
