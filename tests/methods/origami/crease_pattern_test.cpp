// A solid's net as a sheet (issue 27, item 1): hinges weld the corners their faces share, every
// other side is cut, the crease kinds follow the fold angles' signs and the tree folds the sheet.
#include "methods/origami/crease_pattern.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "examples/origami_examples.h"
#include "mesh/polygon.h"

namespace flatmorph::crease_pattern_test {
namespace {

TEST(CreasePattern, TheCubesNetHasFourteenCornersFiveMountainsAndItsArea) {
  const Polyhedron cube = polyhedron_example("cube", 20);
  const Unfolding unfolding = unfold(cube);
  ASSERT_EQ(unfolding.nets.size(), 1u);
  const CreasePattern sheet = crease_pattern_of_net(unfolding, 0, "net 1", 1e-3);
  EXPECT_EQ(sheet.num_faces(), 6);
  EXPECT_EQ(sheet.V.rows(), 14);         // 24 corners, two welded per hinge
  EXPECT_EQ(sheet.creases.size(), 19u);  // 24 sides, one shared per hinge
  int mountains = 0, borders = 0, hinges = 0;
  for (int c = 0; c < static_cast<int>(sheet.creases.size()); ++c) {
    const Crease& crease = sheet.creases[c];
    if (crease.kind == CreaseKind::kMountain) {
      ++mountains;
      EXPECT_NEAR(crease.fold_angle, -std::numbers::pi / 2, 1e-9);
      EXPECT_GE(crease.right, 0);
    }
    if (crease.kind == CreaseKind::kBorder) {
      ++borders;
      EXPECT_EQ(crease.right, -1);
      EXPECT_EQ(crease.fold_angle, 0);
    }
    hinges += sheet.is_hinge(c);
  }
  EXPECT_EQ(mountains, 5);
  EXPECT_EQ(hinges, 5);
  EXPECT_EQ(borders, 14);
  double area = 0;
  for (const auto& face : sheet.faces) {
    Eigen::MatrixX2d polygon(face.size(), 2);
    for (size_t k = 0; k < face.size(); ++k) polygon.row(k) = sheet.V.row(face[k]);
    EXPECT_GT(signed_area(polygon), 0);  // counter-clockwise from above
    area += signed_area(polygon);
  }
  EXPECT_NEAR(area, 6 * 400.0, 1e-9);
  // The tree: the root first, every other face after its parent.
  ASSERT_EQ(sheet.fold_order.size(), 6u);
  EXPECT_EQ(sheet.fold_order[0], sheet.root);
  EXPECT_EQ(sheet.parent_crease[sheet.root], -1);
  std::vector<bool> seen(6, false);
  for (int f : sheet.fold_order) {
    if (f != sheet.root) {
      EXPECT_TRUE(seen[sheet.other_face(sheet.parent_crease[f], f)]);
    }
    seen[f] = true;
  }
}

TEST(CreasePattern, AFoldBelowTheFlatAngleIsAFlatCreaseAndNoHinge) {
  Polyhedron roof;  // two squares meeting at 0.5° off flat
  const double a = 0.5 * std::numbers::pi / 180;
  roof.V.resize(6, 3);
  roof.V << 0, 0, 0, 10, 0, 0, 10, 10, 0, 0, 10, 0, 10 + 10 * std::cos(a), 0, -10 * std::sin(a),
      10 + 10 * std::cos(a), 10, -10 * std::sin(a);
  roof.faces = {{0, 1, 2, 3}, {1, 4, 5, 2}};
  roof.source = "roof";
  const CreasePattern sheet =
      crease_pattern_of_net(unfold(roof), 0, "net 1", 1.0 * std::numbers::pi / 180);
  int flats = 0;
  for (int c = 0; c < static_cast<int>(sheet.creases.size()); ++c) {
    if (sheet.creases[c].kind == CreaseKind::kFlat) {
      ++flats;
      EXPECT_FALSE(sheet.is_hinge(c));
    }
  }
  EXPECT_EQ(flats, 1);
}

}  // namespace
}  // namespace flatmorph::crease_pattern_test
