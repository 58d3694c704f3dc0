// Curved-crease actuators (issue 27, item 2; notes §4): the W, L, δ table, faces trimmed by the
// general corner rule (convex, non-convex, a hinge ending on a straight side), the shifts adding up
// along the tree, and the refusals with what would fix them.
#include "methods/origami/actuators.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/error.h"
#include "mesh/polygon.h"
#include "methods/origami/origami_fixtures.h"

namespace flatmorph::actuators_test {
namespace {

using testing::drawn_sheet;
using testing::example_sheet;
using testing::hinges_of;

// Rows of notes §4's table for r = 5 mm: |θ| in degrees, W, L, δ in mm (three decimals).
struct Row {
  double angle, width, cut, shift;
};
constexpr Row kTetrahedron{109.4712, 9.553, 14.142, 4.589};
constexpr Row kCube{90, 7.854, 10.000, 2.146};
constexpr Row kOctahedron{70.5288, 6.155, 7.071, 0.916};
constexpr Row kDodecahedron{63.4349, 5.536, 6.180, 0.645};
constexpr Row kIcosahedron{41.8103, 3.649, 3.820, 0.171};
constexpr Row kPyramidBase{125.2644, 10.931, 19.319, 8.387};

// The distance from the actuator's parent side (corners 0, 1) to each child corner (2, 3).
Eigen::Vector2d child_side_distances(const Actuator& actuator) {
  const Eigen::Vector2d base = actuator.quad.row(0).transpose();
  return {(actuator.quad.row(2).transpose() - base).dot(actuator.across),
          (actuator.quad.row(3).transpose() - base).dot(actuator.across)};
}

// Notes §4's table, on every hinge of every example's net, and each actuator W wide.
TEST(Actuators, EveryExamplesHingesMatchTheWLDeltaTableOfNotesSection4) {
  const std::vector<std::pair<const char*, std::vector<Row>>> solids = {
      {"tetrahedron", {kTetrahedron}}, {"cube", {kCube}},
      {"octahedron", {kOctahedron}},   {"dodecahedron", {kDodecahedron}},
      {"icosahedron", {kIcosahedron}}, {"pyramid", {kPyramidBase, kOctahedron}}};
  for (const auto& [name, rows] : solids) {
    const CreasePattern pattern = example_sheet(name, 60);
    const std::vector<HingeDesign> hinges = hinges_of(pattern, 5.0);
    ASSERT_EQ(static_cast<int>(hinges.size()), pattern.num_faces() - 1) << name;
    for (const HingeDesign& hinge : hinges) {
      const Row* row = nullptr;
      for (const Row& r : rows) {
        if (std::abs(std::abs(hinge.fold_angle) / kDegree - r.angle) < 1e-3) row = &r;
      }
      ASSERT_NE(row, nullptr) << name << ": a hinge of " << hinge.fold_angle / kDegree << "°";
      EXPECT_NEAR(hinge.width, row->width, 6e-4) << name;
      EXPECT_NEAR(hinge.cut, row->cut, 6e-4) << name;
      EXPECT_NEAR(hinge.shift, row->shift, 6e-4) << name;
      EXPECT_LT(hinge.fold_angle, 0) << name << ": convex, so mountains";
    }
    const ActuatedSheet sheet = actuate(pattern, hinges);
    ASSERT_EQ(sheet.actuators.size(), hinges.size()) << name;
    for (const Actuator& actuator : sheet.actuators) {
      const Eigen::Vector2d distance = child_side_distances(actuator);
      EXPECT_NEAR(distance(0), actuator.hinge.width, 1e-9) << name;
      EXPECT_NEAR(distance(1), actuator.hinge.width, 1e-9) << name;
      // A trapezoid W high, counter-clockwise.
      const double parallel_sides = (actuator.quad.row(1) - actuator.quad.row(0)).norm() +
                                    (actuator.quad.row(2) - actuator.quad.row(3)).norm();
      EXPECT_NEAR(signed_area(actuator.quad), actuator.hinge.width * parallel_sides / 2, 1e-9)
          << name;
    }
    EXPECT_TRUE(sheet_overlaps(sheet).empty()) << name;
  }
}

double interior_angle(const Eigen::MatrixX2d& polygon, Eigen::Index k) {
  const Eigen::Index n = polygon.rows();
  const Eigen::Vector2d a = (polygon.row((k + n - 1) % n) - polygon.row(k)).transpose();
  const Eigen::Vector2d b = (polygon.row((k + 1) % n) - polygon.row(k)).transpose();
  return std::acos(a.normalized().dot(b.normalized()));
}

// Two equilateral triangles joined by one hinge: each hinge side shortens by 2 (L/2) cot 60° =
// 0.5774 L (notes §4, not the paper's e₀ − L/2), each triangle keeps its angles, and the child
// moves δ toward the parent.
TEST(Actuators, AnEquilateralTrianglesHingeSideShortensBy0_5774L) {
  const double e = 40, h = e * std::sqrt(3.0) / 2;
  Eigen::MatrixX2d V(4, 2);
  V << 0, 0, e, 0, e / 2, h, e / 2, -h;
  const CreasePattern pattern = drawn_sheet(V, {{0, 1, 2}, {1, 0, 3}}, {{1, 0, kPi / 2}});
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 5.0));
  const double L = 10, delta = L - 5 * kPi / 2;
  ASSERT_EQ(sheet.actuators.size(), 1u);
  const Actuator& actuator = sheet.actuators[0];
  EXPECT_NEAR((actuator.quad.row(1) - actuator.quad.row(0)).norm(), e - 0.57735 * L, 1e-4);
  EXPECT_NEAR((actuator.quad.row(2) - actuator.quad.row(3)).norm(), e - 0.57735 * L, 1e-4);
  EXPECT_NEAR(actuator.across.x(), 0, 1e-12);
  EXPECT_NEAR(actuator.across.y(), -1, 1e-12);  // the child lies below
  for (int f = 0; f < 2; ++f) {
    ASSERT_EQ(sheet.faces[f].rows(), 3);
    for (Eigen::Index k = 0; k < 3; ++k) {
      EXPECT_NEAR(interior_angle(sheet.faces[f], k), kPi / 3, 1e-12) << f;
    }
  }
  // The parent's apex stays, the child's apex moves up by δ; each trimmed base lies L/2 off the
  // hinge.
  EXPECT_NEAR((sheet.faces[0].row(2) - V.row(2)).norm(), 0, 1e-12);
  EXPECT_NEAR((sheet.faces[1].row(2) - (V.row(3) + Eigen::RowVector2d(0, delta))).norm(), 0, 1e-12);
  EXPECT_NEAR(sheet.faces[0](0, 1), L / 2, 1e-12);
  EXPECT_NEAR(sheet.faces[1](0, 1), -L / 2 + delta, 1e-12);
}

// A square with a hinge on each side (paper's square case): e₁ = e₀ − L; each flap keeps its hinge
// side (corners of 90°) and loses L/2 from its two other sides there; the flaps move δ inward and
// the actuators are the trapezoids between.
TEST(Actuators, ASquareHingedOnEverySideShrinksByL) {
  const double e = 30, L = 10, W = 5 * kPi / 2, delta = L - W;
  Eigen::MatrixX2d V(12, 2);
  V << 0, 0, e, 0, e, e, 0, e,  // the middle square
      0, -e, e, -e,             // below
      2 * e, 0, 2 * e, e,       // right
      e, 2 * e, 0, 2 * e,       // above
      -e, e, -e, 0;             // left
  const CreasePattern pattern =
      drawn_sheet(V, {{0, 1, 2, 3}, {4, 5, 1, 0}, {1, 6, 7, 2}, {3, 2, 8, 9}, {11, 0, 3, 10}},
                  {{1, 0, -kPi / 2}, {2, 0, -kPi / 2}, {3, 0, -kPi / 2}, {4, 0, -kPi / 2}});
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 5.0));
  Eigen::MatrixX2d middle(4, 2);
  middle << L / 2, L / 2, e - L / 2, L / 2, e - L / 2, e - L / 2, L / 2, e - L / 2;
  EXPECT_LT((sheet.faces[0] - middle).cwiseAbs().maxCoeff(), 1e-12);
  Eigen::MatrixX2d above(4, 2);  // face 3: trimmed from below by L/2, moved down by δ
  above << 0, e + L / 2 - delta, e, e + L / 2 - delta, e, 2 * e - delta, 0, 2 * e - delta;
  EXPECT_LT((sheet.faces[3] - above).cwiseAbs().maxCoeff(), 1e-12);
  const Actuator& up = sheet.actuators[2];
  ASSERT_EQ(up.child_face, 3);
  Eigen::Matrix<double, 4, 2> quad;
  // Along the hinge the strip spans what both trimmed sides span: the middle square's.
  quad << L / 2, e - L / 2, e - L / 2, e - L / 2, e - L / 2, e + L / 2 - delta, L / 2,
      e + L / 2 - delta;
  EXPECT_LT((up.quad - quad).cwiseAbs().maxCoeff(), 1e-12);
}

// Shifts add up down the tree (Algorithm 1): in a strip of squares, face k moves back by k δ.
TEST(Actuators, ShiftsAddUpAlongTheTree) {
  const double e = 20;
  Eigen::MatrixX2d V(8, 2);
  for (int k = 0; k < 4; ++k) V.row(2 * k) << k * e, 0, V.row(2 * k + 1) << k * e, e;
  const CreasePattern pattern =
      drawn_sheet(V, {{0, 2, 3, 1}, {2, 4, 5, 3}, {4, 6, 7, 5}},
                  {{1, 0, -kPi / 2}, {2, 1, 2 * kPi / 3}});  // a mountain, then a valley
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 4.0));
  const HingeDesign first = hinge_design(0, kPi / 2, 4, true, 0);
  const HingeDesign second = hinge_design(0, 2 * kPi / 3, 4, true, 0);
  // The far border of the last face: at 3e, back by both shifts.
  EXPECT_NEAR(sheet.faces[2](1, 0), 3 * e - first.shift - second.shift, 1e-12);
  EXPECT_NEAR(sheet.faces[1](1, 0), 2 * e - second.cut / 2 - first.shift, 1e-12);
  EXPECT_NEAR(sheet.faces[1](0, 0), e + first.cut / 2 - first.shift, 1e-12);
  EXPECT_EQ(sheet.actuators[1].parent_face, 1);
  EXPECT_NEAR(child_side_distances(sheet.actuators[1])(0), second.width, 1e-12);
}

// A non-convex face: an L whose notch side is a hinge. The moved line meets the unmoved sides at
// both ends (a reflex corner keeps its 90° turn); the child, a trapezoid with a 56.3° corner,
// shortens its hinge side by (L/2) cot α there and not at its right angle.
TEST(Actuators, ANonConvexFaceIsTrimmedByTheSameCornerRule) {
  Eigen::MatrixX2d V(8, 2);
  V << 0, 0, 40, 0, 40, 20, 20, 20, 20, 40, 0, 40, 40, 35, 30, 35;
  const CreasePattern pattern =
      drawn_sheet(V, {{0, 1, 2, 3, 4, 5}, {3, 2, 6, 7}}, {{1, 0, -kPi / 2}});
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 5.0));
  const double half = 5, delta = 10 - 5 * kPi / 2;
  Eigen::MatrixX2d l_shape(6, 2);
  l_shape << 0, 0, 40, 0, 40, 20 - half, 20, 20 - half, 20, 40, 0, 40;
  EXPECT_LT((sheet.faces[0] - l_shape).cwiseAbs().maxCoeff(), 1e-12);
  const double cot = 10.0 / 15.0;  // the trapezoid's corner at (20, 20)
  Eigen::MatrixX2d child(4, 2);
  child << 20 + half * cot, 20 + half, 40, 20 + half, 40, 35, 30, 35;
  child.col(1).array() -= delta;
  EXPECT_LT((sheet.faces[1] - child).cwiseAbs().maxCoeff(), 1e-12);
}

// A hinge that ends on a straight side (a drawn flap on part of a border) leaves a step there: the
// border keeps its line, the hinge side moves in.
TEST(Actuators, AHingeEndingOnAStraightSideLeavesAStep) {
  Eigen::MatrixX2d V(7, 2);
  V << 0, 0, 10, 0, 30, 0, 30, 20, 0, 20, 30, -15, 10, -15;
  const CreasePattern pattern = drawn_sheet(V, {{0, 1, 2, 3, 4}, {1, 6, 5, 2}}, {{1, 0, kPi / 2}});
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 3.0));
  Eigen::MatrixX2d stepped(6, 2);
  stepped << 0, 0, 10, 0, 10, 3, 30, 3, 30, 20, 0, 20;
  EXPECT_LT((sheet.faces[0] - stepped).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR((sheet.actuators[0].quad.row(1) - sheet.actuators[0].quad.row(0)).norm(), 20, 1e-12);
}

// Faces too narrow for their trims: the cube with r = 15 mm (L/2 = 15) leaves the faces hinged on
// two opposite sides 30 − 2·15 = 0 wide. The message names such a face, the scale (30 + 0.8) / 30
// = 1.0267 → 1.03 and the radius (30 − 0.8) / 2 = 14.6 mm; at that scale the cube actuates.
TEST(Actuators, FacesTooNarrowForTheirTrimsAreRefusedWithTheScaleThatWorks) {
  const CreasePattern pattern = example_sheet("cube", 30);
  int expected = -1;  // the first face hinged on two opposite sides
  for (int f = 0; f < pattern.num_faces() && expected < 0; ++f) {
    std::vector<bool> hinged;
    for (size_t k = 0; k < 4; ++k) {
      const int a = pattern.faces[f][k], b = pattern.faces[f][(k + 1) % 4];
      bool hinge = false;
      for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
        const Crease& crease = pattern.creases[c];
        hinge |= pattern.is_hinge(c) &&
                 ((crease.v0 == a && crease.v1 == b) || (crease.v0 == b && crease.v1 == a));
      }
      hinged.push_back(hinge);
    }
    if ((hinged[0] && hinged[2]) || (hinged[1] && hinged[3])) expected = f;
  }
  ASSERT_GE(expected, 0) << "the cube's net has a row of three faces";
  try {
    actuate(pattern, hinges_of(pattern, 15.0));
    ADD_FAILURE() << "a cube whose faces vanish was actuated";
  } catch (const UserError& error) {
    const std::string message = error.what();
    EXPECT_EQ(error.category(), ErrorCategory::kInfeasible);
    // Messages number faces from 1, as net.svg shows them.
    EXPECT_NE(message.find("face " + std::to_string(expected + 1) + " is"), std::string::npos)
        << message;
    EXPECT_NE(message.find("by at least 1.03"), std::string::npos) << message;
    EXPECT_NE(message.find("14.60 mm"), std::string::npos) << message;
  }
  for (const double scale : {1.02, 1.03}) {
    const CreasePattern scaled = example_sheet("cube", 30 * scale);
    if (scale < 1.0267) {
      EXPECT_THROW(actuate(scaled, hinges_of(scaled, 15.0)), UserError);
    } else {
      EXPECT_NO_THROW(actuate(scaled, hinges_of(scaled, 15.0)));
    }
  }
  EXPECT_NO_THROW(actuate(pattern, hinges_of(pattern, 14.6)));
  ActuateOptions options;
  options.min_face_width = 12;  // the same faces at r = 10: 10 mm wide
  EXPECT_THROW(actuate(pattern, hinges_of(pattern, 10.0), options), UserError);
}

// Beyond 170° no finite actuator fits (L/2 = r tan 87.5° = 22.9 r): refused naming the hinge.
TEST(Actuators, AFoldOfMoreThan170DegreesIsRefusedNamingItsHinge) {
  Eigen::MatrixX2d V(6, 2);
  V << 0, 0, 20, 0, 20, 20, 0, 20, 40, 0, 40, 20;
  const CreasePattern pattern =
      drawn_sheet(V, {{0, 1, 2, 3}, {1, 4, 5, 2}}, {{1, 0, 175 * kDegree}});
  try {
    actuate(pattern, hinges_of(pattern, 0.1));
    ADD_FAILURE() << "a 175° hinge was actuated";
  } catch (const UserError& error) {
    const std::string message = error.what();
    EXPECT_EQ(error.category(), ErrorCategory::kInfeasible);
    EXPECT_NE(message.find("faces 1 and 2"), std::string::npos) << message;
    EXPECT_NE(message.find("175.0°"), std::string::npos) << message;
  }
  EXPECT_THROW(actuate(pattern, {}), std::invalid_argument);  // a hinge without a design
  EXPECT_THROW(hinge_design(0, 1.0, 0.0, true, 0), std::invalid_argument);
}

// Pieces moved onto each other are found; an actuator and its own faces touch but never overlap.
TEST(Actuators, SheetOverlapsFindsPiecesOnTopOfEachOther) {
  const CreasePattern pattern = example_sheet("cube", 30);
  ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 5.0));
  ASSERT_TRUE(sheet_overlaps(sheet).empty());
  const Actuator& actuator = sheet.actuators[0];
  int other = 0;
  while (other == actuator.parent_face || other == actuator.child_face) ++other;
  sheet.faces[other] = sheet.faces[actuator.child_face].array() + 1.0;
  const std::vector<std::pair<int, int>> overlaps = sheet_overlaps(sheet);
  ASSERT_FALSE(overlaps.empty());
  EXPECT_EQ(overlaps[0], std::make_pair(std::min(other, actuator.child_face),
                                        std::max(other, actuator.child_face)));
}

// The hole at a cube's corner where two hinges meet (notes §4): the face between them keeps a
// corner L/2 in from both hinges, the two others meet L/2 along their cut edge, L/2 √3 apart.
TEST(Actuators, TheHoleAtACubesCornerIsHalfLTimesRootThree) {
  const CreasePattern pattern = example_sheet("cube", 30);
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 5.0));
  EXPECT_NEAR(largest_corner_gap(pattern, sheet), 5 * std::sqrt(3.0), 1e-9);
}

}  // namespace
}  // namespace flatmorph::actuators_test
