// The rigid fit of a shape onto a target surface by closest points (src/simulate/surface_fit.h)
// and the closest points it rests on (src/mesh/closest_point.h): a shape moved by a known rigid
// motion is fitted back, onto its own vertices or onto another mesh of the same surface.
#include "simulate/surface_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "common/error.h"
#include "mesh/closest_point.h"
#include "mesh/mesh_fixtures.h"

namespace flatmorph::surface_fit_test {
namespace {

// A patch of the saddle-like surface z = (x² − 2 y² + x y / 2) / 40 (no symmetry a fit could
// confuse) over [x0, x1] × [y0, y1] mm, n x m cells.
Mesh saddle(double x0, double x1, double y0, double y1, int n, int m) {
  return testing::grid_mesh(n, m, [&](double u, double v) {
    const double x = x0 + u * (x1 - x0), y = y0 + v * (y1 - y0);
    return Eigen::Vector3d(x, y, (x * x - 2 * y * y + x * y / 2) / 40);
  });
}

TEST(ClosestPointOnTriangle, FindsTheFaceTheEdgesAndTheCorners) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  auto near = [&](const Eigen::Vector3d& p) { return closest_point_on_triangle(p, a, b, c); };
  EXPECT_LT((near({0.5, 0.5, 3}) - Eigen::Vector3d(0.5, 0.5, 0)).norm(), 1e-15);  // face
  EXPECT_LT((near({1, -1, 1}) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15);         // edge ab
  EXPECT_LT((near({2, 2, 0}) - Eigen::Vector3d(1, 1, 0)).norm(), 1e-15);          // edge bc
  EXPECT_LT((near({-1, -1, 0}) - a).norm(), 1e-15);                               // corners
  EXPECT_LT((near({3, -1, 0}) - b).norm(), 1e-15);
  EXPECT_LT((near({-1, 3, 0}) - c).norm(), 1e-15);
  // Collinear corners: the nearest point of the segment they span.
  const Eigen::Vector3d q = closest_point_on_triangle({1, 1, 0}, a, b, Eigen::Vector3d(1, 0, 0));
  EXPECT_LT((q - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15);
}

TEST(TriangleTree, FindsTheNearestPointOfEveryFace) {
  const Mesh mesh = saddle(-10, 10, -8, 8, 12, 9);
  const TriangleTree tree = triangle_tree(mesh.V, mesh.F);
  // Against every face tried in turn, at points around and off the surface.
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d p(-14 + 0.14 * k, 11 * std::sin(0.7 * k), 4 * std::cos(1.3 * k));
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      const Eigen::Vector3d q = closest_point_on_triangle(
          p, mesh.V.row(mesh.F(f, 0)), mesh.V.row(mesh.F(f, 1)), mesh.V.row(mesh.F(f, 2)));
      best = std::min(best, (q - p).norm());
    }
    const SurfacePoint found = closest_surface_point(tree, p);
    EXPECT_NEAR(found.distance, best, 1e-12) << k;
    EXPECT_NEAR((found.point - p).norm(), found.distance, 1e-12);
  }
}

// A shape turned and moved far off (half a turn and more about a slanted axis): fitted back onto
// itself, on its own vertices or on a finer mesh of the same surface.
TEST(ClosestPointRigidFit, UndoesAKnownRigidMotion) {
  const Mesh target = saddle(-20, 20, -12, 12, 24, 15);
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d shift(40, -15, 70);
  const Eigen::MatrixXd moved = (target.V * turn.transpose()).rowwise() + shift.transpose();
  const SurfaceFit fit = closest_point_rigid_fit(moved, target.F, target.V, target.F);
  EXPECT_LT(fit.distance.max_mm, 1e-6);
  EXPECT_LT((fit.fit.rotation - turn.transpose()).norm(), 1e-6);
  EXPECT_LT((fit.aligned - target.V).cwiseAbs().maxCoeff(), 1e-6);

  // The same surface meshed about 2.5 times finer, sharing only the corners: what is left is the
  // fine mesh's chords between the coarse vertices and the surface (h² |z''| / 8 ≈ 0.005 mm).
  const Mesh fine = saddle(-20, 20, -12, 12, 61, 37);
  const SurfaceFit on_fine = closest_point_rigid_fit(moved, target.F, fine.V, fine.F);
  EXPECT_LT(on_fine.distance.max_mm, 0.01);
  EXPECT_LT(on_fine.distance.mean_percent, 0.01);
}

TEST(ClosestPointRigidFit, RefusesAMeshWithoutAreaOrWithNonFiniteCoordinates) {
  const Mesh good = saddle(-5, 5, -5, 5, 4, 4);
  EXPECT_THROW(closest_point_rigid_fit(good.V, good.F, good.V, Eigen::MatrixXi(0, 3)), UserError);
  Eigen::MatrixXd bad = good.V;
  bad(3, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(closest_point_rigid_fit(good.V, good.F, bad, good.F), UserError);
  EXPECT_THROW(
      closest_point_rigid_fit(good.V, good.F, Eigen::MatrixXd::Zero(good.V.rows(), 3), good.F),
      UserError);
}

}  // namespace
}  // namespace flatmorph::surface_fit_test
