// Linear refinement of a plate (every edge cut into n): exact geometry, edges divided by n,
// interpolation matrix.
#include "toolpath/refine_plate.h"

#include <gtest/gtest.h>

#include "common/error.h"
#include "mesh/operators.h"
#include "mesh/topology.h"
#include "toolpath/test_plates.h"

namespace flatmorph::refine_plate_test {
namespace {

TEST(RefinePlate, KeepsTheOutlineAndAreaExactly) {
  const toolpath_testing::TestPlate plate = toolpath_testing::disk_plate(20, 3.0);
  const RefinedPlate r = refine_plate(plate.V, plate.F, 1.0);
  ASSERT_GE(r.splits, 3);  // not a power of two: the general lattice
  EXPECT_EQ(r.F.rows(), plate.F.rows() * r.splits * r.splits);
  const Eigen::VectorXd coarse_area = face_areas(plate.V, plate.F);
  const Eigen::VectorXd fine_area = face_areas(r.V, r.F);
  EXPECT_GT(fine_area.minCoeff(), 0);  // still counter-clockwise
  EXPECT_NEAR(fine_area.sum(), coarse_area.sum(), 1e-9);
  // Each coarse face is tiled by its children.
  Eigen::VectorXd by_parent = Eigen::VectorXd::Zero(plate.F.rows());
  for (int f = 0; f < r.F.rows(); ++f) by_parent(r.face_parent(f)) += fine_area(f);
  EXPECT_LT((by_parent - coarse_area).cwiseAbs().maxCoeff(), 1e-12);
  // Edges: divided by n exactly; the mean no longer than asked, and n the smallest that does it.
  EXPECT_LE(mean_edge(r.V, r.F), 1.0);
  EXPECT_GT(mean_edge(r.V, r.F) * r.splits / (r.splits - 1), 1.0);
  EXPECT_NEAR(mean_edge(r.V, r.F) * r.splits, mean_edge(plate.V, plate.F), 1e-12);
  EXPECT_NEAR(longest_edge(r.V, r.F) * r.splits, longest_edge(plate.V, plate.F), 1e-12);
  // A manifold disk: every interior edge has two faces, so no lattice point was made twice.
  const EdgeTopology fine_topology = edge_topology(r.F);
  EXPECT_EQ(r.V.rows() - fine_topology.num_edges() + r.F.rows(), 1);  // Euler characteristic
  Eigen::VectorXi used = Eigen::VectorXi::Zero(r.V.rows());
  for (int f = 0; f < r.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) used(r.F(f, k)) = 1;
  }
  EXPECT_EQ(used.sum(), r.V.rows());
  // The boundary is the same polygon: every fine boundary vertex lies on a coarse boundary edge.
  const auto coarse_loops = boundary_loops(plate.F);
  const auto fine_loops = boundary_loops(r.F);
  ASSERT_EQ(fine_loops.size(), 1u);
  for (int v : fine_loops[0]) {
    double best = 1e9;
    const auto& loop = coarse_loops[0];
    for (size_t k = 0; k < loop.size(); ++k) {
      const Eigen::Vector2d a = plate.V.row(loop[k]), b = plate.V.row(loop[(k + 1) % loop.size()]);
      const Eigen::Vector2d p = r.V.row(v);
      const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * (b - a) - p).norm());
    }
    EXPECT_LT(best, 1e-12);
  }
}

TEST(RefinePlate, InterpolationMatrixIsExactForLinearFields) {
  const toolpath_testing::TestPlate plate = toolpath_testing::rectangle_plate(10, 6, 2.0);
  const RefinedPlate r = refine_plate(plate.V, plate.F, 0.6);
  ASSERT_GE(r.splits, 4);
  EXPECT_LT((r.S * plate.V - r.V).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::VectorXd linear =
      3 * plate.V.col(0) - 2 * plate.V.col(1) + Eigen::VectorXd::Ones(plate.V.rows());
  const Eigen::VectorXd fine = r.S * linear;
  const Eigen::VectorXd expected =
      3 * r.V.col(0) - 2 * r.V.col(1) + Eigen::VectorXd::Ones(r.V.rows());
  EXPECT_LT((fine - expected).cwiseAbs().maxCoeff(), 1e-12);
  // Rows are partitions of unity.
  const Eigen::VectorXd ones = r.S * Eigen::VectorXd::Ones(plate.V.rows());
  EXPECT_LT((ones - Eigen::VectorXd::Ones(r.V.rows())).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RefinePlate, NoSplitWhenEdgesAreShortEnough) {
  const toolpath_testing::TestPlate plate = toolpath_testing::rectangle_plate(4, 4, 1.0);
  const RefinedPlate r = refine_plate(plate.V, plate.F, 2.0);
  EXPECT_EQ(r.splits, 1);
  EXPECT_EQ(r.F, plate.F);
}

TEST(RefinePlate, RejectsBadRequests) {
  const toolpath_testing::TestPlate plate = toolpath_testing::rectangle_plate(4, 4, 1.0);
  try {
    refine_plate(plate.V, plate.F, 0.0);
    FAIL() << "expected UserError";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
  }
  try {
    refine_plate(plate.V, plate.F, 1e-4, 1'000'000);
    FAIL() << "expected UserError";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kResource);
  }
}

}  // namespace
}  // namespace flatmorph::refine_plate_test
