#include "mesh/prepare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/error.h"

namespace flatmorph::prepare_test {
namespace {

// A tetrahedron inside the box [10, 14] x [-3, -1] x [7, 8] (extents 4, 2, 1), touching every face.
Mesh offset_tetrahedron() {
  Mesh m;
  m.V.resize(4, 3);
  m.V << 10, -3, 7.5, 14, -2, 7, 12, -1, 8, 11, -2.5, 7.25;
  m.F.resize(4, 3);
  m.F << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  return m;
}

TEST(MeshPrepare, BoundingBox) {
  const BoundingBox box = bounding_box(offset_tetrahedron().V);
  EXPECT_EQ(box.min, Eigen::Vector3d(10, -3, 7));
  EXPECT_EQ(box.max, Eigen::Vector3d(14, -1, 8));
  EXPECT_EQ(box.extent(), Eigen::Vector3d(4, 2, 1));
  EXPECT_DOUBLE_EQ(box.diagonal(), std::sqrt(21.0));
}

TEST(MeshPrepare, ScaleToSizeSetsTheLargestExtent) {
  const Mesh original = offset_tetrahedron();
  Mesh m = original;
  const double scale = scale_to_size(m, 150.0);
  EXPECT_DOUBLE_EQ(scale, 37.5);
  const BoundingBox box = bounding_box(m.V);
  EXPECT_NEAR(box.extent().x(), 150.0, 1e-12);
  // Shape kept: extents keep their ratios 4 : 2 : 1, and so does every distance.
  EXPECT_NEAR(box.extent().y(), 75.0, 1e-12);
  EXPECT_NEAR(box.extent().z(), 37.5, 1e-12);
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) {
      EXPECT_NEAR((m.V.row(a) - m.V.row(b)).norm(),
                  37.5 * (original.V.row(a) - original.V.row(b)).norm(), 1e-12);
    }
  }
  // The centre stays put.
  const BoundingBox before = bounding_box(original.V);
  EXPECT_LT((0.5 * (box.min + box.max) - 0.5 * (before.min + before.max)).norm(), 1e-12);
  // Already the right size: nothing changes.
  EXPECT_NEAR(scale_to_size(m, 150.0), 1.0, 1e-15);
}

TEST(MeshPrepare, ScaleToSizeUsesTheLargestAxisWhicheverItIs) {
  Mesh m = offset_tetrahedron();
  m.V.col(2) *= 10.0;  // z extent 10 now beats x's 4
  const double scale = scale_to_size(m, 20.0);
  EXPECT_DOUBLE_EQ(scale, 2.0);
  EXPECT_NEAR(bounding_box(m.V).extent().maxCoeff(), 20.0, 1e-12);
  EXPECT_NEAR(bounding_box(m.V).extent().x(), 8.0, 1e-12);
}

TEST(MeshPrepare, ScaleToSizeRejectsBadSizesAndFlatPoints) {
  Mesh m = offset_tetrahedron();
  for (double size : {0.0, -5.0, std::numeric_limits<double>::quiet_NaN(),
                      std::numeric_limits<double>::infinity()}) {
    try {
      scale_to_size(m, size);
      FAIL() << "accepted size " << size;
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kOption);
    }
  }
  EXPECT_EQ(m.V, offset_tetrahedron().V);
  Mesh point;
  point.V = Eigen::MatrixXd::Ones(3, 3);
  point.F.resize(1, 3);
  point.F << 0, 1, 2;
  try {
    scale_to_size(point, 100.0);
    FAIL() << "scaled a mesh of zero size";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kGeometry);
  }
  Mesh empty;
  EXPECT_THROW(scale_to_size(empty, 100.0), UserError);
}

}  // namespace
}  // namespace flatmorph::prepare_test
