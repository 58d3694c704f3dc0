// The sheet folding (issue 27, item 6; notes §7): sharp folds that give back the solid, curved
// folds that put every trimmed face on its solid's plane (notes §4's exact test), the fold's sign,
// partial bends, invariance under turning and mirroring the sheet, loops that cannot close, the
// folded mesh, and collisions from exact triangle tests.
#include "methods/origami/fold_simulation.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "examples/origami_examples.h"
#include "mesh/polygon.h"
#include "methods/origami/actuators.h"
#include "methods/origami/origami_fixtures.h"

namespace flatmorph::fold_simulation_test {
namespace {

using testing::drawn_sheet;
using testing::example_sheet;
using testing::hinges_of;

const char* const kSolids[] = {"tetrahedron",  "cube",        "octahedron",
                               "dodecahedron", "icosahedron", "pyramid"};

double diagonal(const Polyhedron& solid) {
  return (solid.V.colwise().maxCoeff() - solid.V.colwise().minCoeff()).norm();
}

// The solid in the sheet's frame: its net's root face laid as unfold lays it.
Eigen::MatrixX3d solid_in_sheet_frame(const Polyhedron& solid, const CreasePattern& pattern) {
  const RigidMotion m = face_to_plane(solid, pattern.solid_face[pattern.root]);
  return (solid.V * m.R.transpose()).rowwise() + m.t.transpose();
}

// Acceptance (notes §11): the sharp fold of every example's net is the solid within 0.1 % of its
// diagonal, and flat at progress 0; a net has no loop to close.
TEST(FoldSimulation, TheSharpFoldOfEveryExampleNetIsTheSolid) {
  for (const char* name : kSolids) {
    const Polyhedron solid = polyhedron_example(name, 30);
    const CreasePattern pattern = example_sheet(name, 30);
    const Eigen::MatrixX3d V = solid_in_sheet_frame(solid, pattern);
    const std::vector<Eigen::MatrixX3d> folded = fold_sharp(pattern, 1.0);
    const std::vector<Eigen::MatrixX3d> flat = fold_sharp(pattern, 0.0);
    double worst = 0;
    for (int f = 0; f < pattern.num_faces(); ++f) {
      const std::vector<int>& face = solid.faces[pattern.solid_face[f]];
      for (size_t k = 0; k < face.size(); ++k) {
        const Eigen::Index i = static_cast<Eigen::Index>(k);
        worst = std::max(worst, (folded[f].row(i) - V.row(face[k])).norm());
        EXPECT_NEAR(flat[f](i, 2), 0, 1e-12);
        EXPECT_NEAR((flat[f].row(i).head<2>() - pattern.V.row(pattern.faces[f][k])).norm(), 0,
                    1e-12);
      }
    }
    EXPECT_LT(worst, 1e-3 * diagonal(solid)) << name;
    EXPECT_EQ(loop_closure_error(pattern), 0) << name;
  }
}

// Notes §4's exact test of the curved model: folded, every trimmed face lies in its solid face's
// plane, its cut sides on the solid's edges and its hinge sides L/2 in from them (1e-6 of the
// diagonal); this checks the trims, the δ shifts (a wrong one slides a face off its edges) and the
// sign. Each actuator strip starts on its parent's folded side and ends on its child's.
TEST(FoldSimulation, TheCurvedFoldLaysEveryTrimmedFaceOnItsSolidsPlane) {
  for (const char* name : kSolids) {
    const Polyhedron solid = polyhedron_example(name, 60);
    const CreasePattern pattern = example_sheet(name, 60);
    const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 5.0));
    const FoldedSheet folded = fold_curved(pattern, sheet, 1.0, 8);
    const Eigen::MatrixX3d V = solid_in_sheet_frame(solid, pattern);
    const double tolerance = 1e-6 * diagonal(solid);
    for (int f = 0; f < pattern.num_faces(); ++f) {
      const std::vector<int>& face = solid.faces[pattern.solid_face[f]];
      const Eigen::Index n = static_cast<Eigen::Index>(face.size());
      ASSERT_EQ(folded.faces[f].rows(), n) << name;
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      for (Eigen::Index k = 0; k < n; ++k) {
        normal += V.row(face[k]).cross(V.row(face[(k + 1) % n])).transpose();
      }
      normal.normalize();
      // Per side: how far in it was trimmed (L/2 of its actuator, or 0 for a cut).
      std::vector<double> inset(n, 0.0);
      for (const Actuator& actuator : sheet.actuators) {
        const Crease& crease = pattern.creases[actuator.hinge.crease];
        for (Eigen::Index k = 0; k < n; ++k) {
          const int a = pattern.faces[f][k], b = pattern.faces[f][(k + 1) % n];
          if ((crease.v0 == a && crease.v1 == b) || (crease.v0 == b && crease.v1 == a)) {
            inset[k] = actuator.hinge.cut / 2;
          }
        }
      }
      const auto distance_to_side = [&](const Eigen::Vector3d& p, Eigen::Index k) {
        const Eigen::Vector3d a = V.row(face[k]).transpose();
        const Eigen::Vector3d b = V.row(face[(k + 1) % n]).transpose();
        return (p - a).cross((b - a).normalized()).norm();
      };
      for (Eigen::Index k = 0; k < n; ++k) {
        const Eigen::Vector3d p = folded.faces[f].row(k).transpose();
        EXPECT_NEAR(normal.dot(p - V.row(face[0]).transpose()), 0, tolerance) << name << " " << f;
        EXPECT_NEAR(distance_to_side(p, k), inset[k], tolerance) << name << " " << f;
        EXPECT_NEAR(distance_to_side(p, (k + n - 1) % n), inset[(k + n - 1) % n], tolerance)
            << name << " " << f;
      }
    }
    for (size_t a = 0; a < sheet.actuators.size(); ++a) {
      const Actuator& actuator = sheet.actuators[a];
      const ActuatorStrip& strip = folded.actuators[a];
      // Distance to the nearest side of the folded face: the strip ends on the trimmed side.
      const auto on = [&](const Eigen::RowVector3d& p, int f) {
        double nearest = std::numeric_limits<double>::infinity();
        const Eigen::MatrixX3d& corners = folded.faces[f];
        for (Eigen::Index k = 0; k < corners.rows(); ++k) {
          const Eigen::RowVector3d a = corners.row(k), b = corners.row((k + 1) % corners.rows());
          const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
          nearest = std::min(nearest, (a + t * (b - a) - p).norm());
        }
        return nearest;
      };
      EXPECT_LT(on(strip.side0.row(0), actuator.parent_face), tolerance) << name;
      EXPECT_LT(on(strip.side1.row(0), actuator.parent_face), tolerance) << name;
      EXPECT_LT(on(strip.side0.row(8), actuator.child_face), tolerance) << name;
      EXPECT_LT(on(strip.side1.row(8), actuator.child_face), tolerance) << name;
    }
  }
}

// Two 20 mm squares side by side, the right one the child.
CreasePattern two_squares(double fold_angle) {
  Eigen::MatrixX2d V(6, 2);
  V << 0, 0, 20, 0, 20, 20, 0, 20, 40, 0, 40, 20;
  return drawn_sheet(V, {{0, 1, 2, 3}, {1, 4, 5, 2}}, {{1, 0, fold_angle}});
}

// FOLD's sign (notes §3): a valley lifts the child toward +z, a mountain lowers it; at 90° with
// r = 5 (L/2 = 5) the curved child ends where the sharp one does, its trimmed side 5 mm off the
// parent's plane.
TEST(FoldSimulation, AValleyLiftsTheChildAndAMountainLowersIt) {
  for (const double sign : {1.0, -1.0}) {
    const CreasePattern pattern = two_squares(sign * kPi / 2);
    const Eigen::MatrixX3d sharp = fold_sharp(pattern, 1.0)[1];
    EXPECT_LT((sharp.row(1) - Eigen::RowVector3d(20, 0, sign * 20)).norm(), 1e-12);
    const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 5.0));
    const Eigen::MatrixX3d curved = fold_curved(pattern, sheet, 1.0, 4).faces[1];
    EXPECT_LT((curved.row(0) - Eigen::RowVector3d(20, 0, sign * 5)).norm(), 1e-12);
    EXPECT_LT((curved.row(1) - Eigen::RowVector3d(20, 0, sign * 20)).norm(), 1e-12);
    EXPECT_LT((curved.row(2) - Eigen::RowVector3d(20, 20, sign * 20)).norm(), 1e-12);
  }
}

// At progress t a hinge bends to t θ over its unchanged width W (notes §7): the child face turns
// by t θ, the strip's ends lie on a circle of radius W / (t |θ|) tangent to the parent, evenly
// spaced; at t = 0 the fold is the flat sheet.
TEST(FoldSimulation, AtProgressTEveryHingeBendsToTThetaOverItsWidth) {
  const double theta = 120 * kDegree, t = 0.5, r = 5;
  const CreasePattern pattern = two_squares(theta);
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, r));
  const double width = r * theta, radius = width / (t * theta);  // 10.47, 10 mm
  const int steps = 6;
  const FoldedSheet half = fold_curved(pattern, sheet, t, steps);
  const Eigen::MatrixX3d& child = half.faces[1];
  const Eigen::Vector3d normal =
      (child.row(1) - child.row(0)).cross(child.row(2) - child.row(0)).normalized().transpose();
  EXPECT_NEAR(std::acos(normal.z()), t * theta, 1e-12);
  EXPECT_LT(normal.x(), 0);  // a valley: the child rises toward the parent's side
  const double edge = sheet.actuators[0].quad(0, 0);  // the parent's trimmed side, x = 20 − L/2
  const Eigen::Vector2d centre(edge, radius);
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector3d p = half.actuators[0].side0.row(i).transpose();
    EXPECT_NEAR((Eigen::Vector2d(p.x(), p.z()) - centre).norm(), radius, 1e-12) << i;
    EXPECT_NEAR(p.y(), 20, 1e-12);  // corner 0: the parent side's end
    if (i > 0) {
      const double chord =
          (half.actuators[0].side0.row(i) - half.actuators[0].side0.row(i - 1)).norm();
      EXPECT_NEAR(chord, 2 * radius * std::sin(t * theta / steps / 2), 1e-12);
    }
  }
  const FoldedSheet flat = fold_curved(pattern, sheet, 0.0, steps);
  for (int f = 0; f < 2; ++f) {
    EXPECT_LT(flat.faces[f].col(2).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_LT((flat.faces[f].leftCols<2>() - sheet.faces[f]).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// Turning the sheet in its plane turns the folded sheet about z; mirroring it (faces reversed to
// stay counter-clockwise) mirrors the folded sheet: the fold has no preferred direction or hand.
TEST(FoldSimulation, ATurnedOrMirroredSheetFoldsIntoTheTurnedOrMirroredShape) {
  const CreasePattern pattern = example_sheet("pyramid", 50);
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 4.0));
  const FoldedSheet folded = fold_curved(pattern, sheet, 0.8, 5);

  CreasePattern turned = pattern;
  const Eigen::Matrix2d Q = Eigen::Rotation2Dd(0.6).toRotationMatrix();
  turned.V = (pattern.V * Q.transpose()).rowwise() + Eigen::RowVector2d(7, -3);
  const FoldedSheet folded_turned =
      fold_curved(turned, actuate(turned, hinges_of(turned, 4.0)), 0.8, 5);
  Eigen::Matrix3d Q3 = Eigen::Matrix3d::Identity();
  Q3.topLeftCorner<2, 2>() = Q;
  const Eigen::RowVector3d shift(7, -3, 0);
  for (int f = 0; f < pattern.num_faces(); ++f) {
    const Eigen::MatrixX3d expected = (folded.faces[f] * Q3.transpose()).rowwise() + shift;
    EXPECT_LT((folded_turned.faces[f] - expected).cwiseAbs().maxCoeff(), 1e-9) << f;
  }
  for (size_t a = 0; a < folded.actuators.size(); ++a) {
    const Eigen::MatrixX3d expected =
        (folded.actuators[a].side1 * Q3.transpose()).rowwise() + shift;
    EXPECT_LT((folded_turned.actuators[a].side1 - expected).cwiseAbs().maxCoeff(), 1e-9) << a;
  }

  CreasePattern mirrored = pattern;
  mirrored.V.col(0) *= -1;
  for (std::vector<int>& face : mirrored.faces) std::reverse(face.begin(), face.end());
  for (Crease& crease : mirrored.creases) std::swap(crease.v0, crease.v1);
  const FoldedSheet folded_mirrored =
      fold_curved(mirrored, actuate(mirrored, hinges_of(mirrored, 4.0)), 0.8, 5);
  for (int f = 0; f < pattern.num_faces(); ++f) {
    const Eigen::Index n = folded.faces[f].rows();
    for (Eigen::Index k = 0; k < n; ++k) {
      Eigen::RowVector3d expected = folded.faces[f].row(n - 1 - k);
      expected.x() *= -1;
      EXPECT_LT((folded_mirrored.faces[f].row(k) - expected).norm(), 1e-9) << f;
    }
  }
}

// Four squares around a vertex, folded along the line x = 20 through it: both halves of that line
// folding 90° close the loop; folding the upper one 60° leaves the outer corner of the crease off
// the tree 2 · 20 · sin 15° apart.
TEST(FoldSimulation, LoopClosureErrorMeasuresWhetherALoopFoldsRigidly) {
  Eigen::MatrixX2d V(9, 2);
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) V.row(3 * j + i) << 20 * i, 20 * j;
  }
  const std::vector<std::vector<int>> faces = {
      {0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}};
  for (const double upper : {90.0, 60.0}) {
    const CreasePattern pattern =
        drawn_sheet(V, faces, {{1, 0, kPi / 2}, {2, 0, 0.0}, {3, 2, upper * kDegree}});
    const double expected = 40 * std::sin((90 - upper) / 2 * kDegree);
    EXPECT_NEAR(loop_closure_error(pattern), expected, 1e-12) << upper;
  }
}

// folded.ply: every face ear-clipped, every strip step two triangles, all facing out of the cube;
// the strips keep their flat area up to the chords' sin(φ/2)/(φ/2).
TEST(FoldSimulation, TheFoldedMeshHoldsEveryPieceFacingOut) {
  const CreasePattern pattern = example_sheet("cube", 40);
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 5.0));
  const int steps = 4;
  const FoldedSheet folded = fold_curved(pattern, sheet, 1.0, steps);
  const Mesh mesh = folded_mesh(folded);
  ASSERT_EQ(mesh.num_faces(), 6 * 2 + 5 * 2 * steps);
  Eigen::RowVector3d low = folded.faces[0].colwise().minCoeff(), high = low;
  for (const Eigen::MatrixX3d& face : folded.faces) {
    low = low.cwiseMin(face.colwise().minCoeff());
    high = high.cwiseMax(face.colwise().maxCoeff());
  }
  const Eigen::RowVector3d centre = (low + high) / 2;
  EXPECT_NEAR((high - low).maxCoeff(), 40, 1e-9);
  double area = 0, expected = 0;
  for (int t = 0; t < mesh.num_faces(); ++t) {
    const Eigen::RowVector3d a = mesh.V.row(mesh.F(t, 0)), b = mesh.V.row(mesh.F(t, 1)),
                             c = mesh.V.row(mesh.F(t, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a);
    EXPECT_GT(n.dot((a + b + c) / 3 - centre), 0) << "triangle " << t << " faces in";
    area += n.norm() / 2;
  }
  for (const Eigen::MatrixX2d& face : sheet.faces) expected += std::abs(signed_area(face));
  const double half_step = kPi / 2 / steps / 2;
  for (const Actuator& actuator : sheet.actuators) {
    expected += signed_area(actuator.quad) * std::sin(half_step) / half_step;
  }
  EXPECT_NEAR(area, expected, 1e-9 * expected);
}

Eigen::Matrix3d triangle(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b,
                         const Eigen::RowVector3d& c) {
  Eigen::Matrix3d out;
  out << a, b, c;
  return out;
}

// The exact triangle–triangle test: crossing and piercing count, touching (along a side, at a
// corner, a side lying on the other) does not once a tolerance is given, coplanar triangles count
// when they share area, and disjoint ones never do.
TEST(FoldSimulation, TrianglesIntersectWhenTheyCrossNotWhenTheyTouch) {
  const Eigen::Matrix3d floor = triangle({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const double tol = 1e-9;
  // Crossing: a vertical triangle through the floor's inside.
  EXPECT_TRUE(
      triangles_intersect(floor, triangle({0.5, 0.5, -1}, {0.5, 0.5, 1}, {0.5, -1, 0}), tol));
  // Piercing with one corner 0.1 deep, and only 1e-12 deep (within tolerance).
  EXPECT_TRUE(
      triangles_intersect(floor, triangle({0.5, 0.5, -0.1}, {0.5, 3, 1}, {3, 0.5, 1}), tol));
  EXPECT_FALSE(
      triangles_intersect(floor, triangle({0.5, 0.5, -1e-12}, {0.5, 3, 1}, {3, 0.5, 1}), tol));
  // Touching: along a shared side at a fold, at a corner, a side lying inside the floor.
  const Eigen::Matrix3d wall = triangle({0, 0, 0}, {2, 0, 0}, {0, 0, 2});
  EXPECT_FALSE(triangles_intersect(floor, wall, tol));
  EXPECT_TRUE(triangles_intersect(floor, wall, 0));  // closed triangles do share that side
  EXPECT_FALSE(triangles_intersect(floor, triangle({2, 0, 0}, {3, 0, 1}, {3, 1, -1}), tol));
  EXPECT_FALSE(
      triangles_intersect(floor, triangle({0.2, 0.2, 0}, {0.8, 0.2, 0}, {0.5, 0.2, 1}), tol));
  // Coplanar: sharing area, sharing a side only, apart.
  EXPECT_TRUE(triangles_intersect(floor, triangle({0.5, 0.5, 0}, {3, 0.5, 0}, {0.5, 3, 0}), tol));
  EXPECT_TRUE(
      triangles_intersect(floor, triangle({0.1, 0.1, 0}, {0.5, 0.1, 0}, {0.1, 0.5, 0}), tol));
  EXPECT_FALSE(triangles_intersect(floor, triangle({2, 0, 0}, {2, 2, 0}, {0, 2, 0}), tol));
  EXPECT_FALSE(triangles_intersect(floor, triangle({3, 3, 0}, {4, 3, 0}, {3, 4, 0}), tol));
  // Disjoint: a parallel plane, and one beside the floor's plane crossing its line.
  EXPECT_FALSE(triangles_intersect(floor, triangle({0, 0, 1}, {2, 0, 1}, {0, 2, 1}), tol));
  EXPECT_FALSE(triangles_intersect(floor, triangle({3, 3, -1}, {3, 3, 1}, {4, 2, 0}), tol));
  // Symmetric in its arguments.
  EXPECT_TRUE(
      triangles_intersect(triangle({0.5, 0.5, -1}, {0.5, 0.5, 1}, {0.5, -1, 0}), floor, tol));
}

// The cube's net folds into the cube without any piece crossing another, all together or hinge by
// hinge.
TEST(FoldSimulation, TheCubesNetFoldsWithoutCollision) {
  const CreasePattern pattern = example_sheet("cube", 40);
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 5.0));
  EXPECT_FALSE(first_collision(pattern, sheet).has_value());
  EXPECT_FALSE(first_collision(pattern, sheet, 20, true).has_value());
}

// Two flaps as long as the base is wide, on opposite sides, both folding 160° over it: sharply they
// would meet tip to tip at 120° (t = 0.75); folded one after the other, the second runs into the
// first.
TEST(FoldSimulation, TwoFlapsFoldingOntoTheSameFaceCollide) {
  Eigen::MatrixX2d V(8, 2);
  V << 0, 0, 20, 0, 20, 20, 0, 20, -20, 0, -20, 20, 40, 0, 40, 20;
  const CreasePattern pattern = drawn_sheet(V, {{0, 1, 2, 3}, {4, 0, 3, 5}, {1, 6, 7, 2}},
                                            {{1, 0, 160 * kDegree}, {2, 0, 160 * kDegree}});
  const ActuatedSheet sheet = actuate(pattern, hinges_of(pattern, 0.5));
  const std::optional<FoldCollision> together = first_collision(pattern, sheet);
  ASSERT_TRUE(together.has_value());
  EXPECT_EQ(together->piece_a, 1);
  EXPECT_EQ(together->piece_b, 2);
  EXPECT_GT(together->progress, 0.6);
  EXPECT_LT(together->progress, 0.9);
  EXPECT_EQ(together->folding_actuator, -1);
  EXPECT_EQ(piece_name(sheet, 4), "actuator 2 (faces 1–3)");  // numbered from 1, as net.svg
  const std::optional<FoldCollision> in_order = first_collision(pattern, sheet, 50, true);
  ASSERT_TRUE(in_order.has_value());
  EXPECT_EQ(in_order->folding_actuator, 1);
  EXPECT_EQ(in_order->piece_a, 1);
  EXPECT_GT(in_order->progress, 0.5);
}

}  // namespace
}  // namespace flatmorph::fold_simulation_test
