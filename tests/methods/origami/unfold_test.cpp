// The solids a Thermorph origami folds into and their nets (issue 27, item 1): the examples'
// counts and dihedral angles in closed form, nets without overlap that fold back onto the solid,
// the same nets for a turned solid, a saddle vertex that needs two nets, and bad solids refused.
#include "methods/origami/unfold.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "common/error.h"
#include "examples/origami_examples.h"

namespace flatmorph::unfold_test {
namespace {

double diagonal(const Polyhedron& solid) {
  return (solid.V.colwise().maxCoeff() - solid.V.colwise().minCoeff()).norm();
}

struct Expected {
  const char* name;
  int vertices, faces, edges;
  double dihedral;  // between adjacent faces, rad (the pyramid: between two triangles)
};
const Expected kSolids[] = {
    {"tetrahedron", 4, 4, 6, std::acos(1.0 / 3)},
    {"cube", 8, 6, 12, kPi / 2},
    {"octahedron", 6, 8, 12, std::acos(-1.0 / 3)},
    {"dodecahedron", 20, 12, 30, std::acos(-1 / std::sqrt(5.0))},
    {"icosahedron", 12, 20, 30, std::acos(-std::sqrt(5.0) / 3)},
    {"pyramid", 5, 5, 8, std::acos(-1.0 / 3)},
};

TEST(Polyhedron, TheExamplesAreTheRegularSolidsWithTheirDihedralAngles) {
  for (const Expected& x : kSolids) {
    const Polyhedron solid = polyhedron_example(x.name, 30);
    const std::vector<PolyhedronEdge> edges = polyhedron_edges(solid);
    EXPECT_EQ(solid.V.rows(), x.vertices) << x.name;
    EXPECT_EQ(static_cast<int>(solid.faces.size()), x.faces) << x.name;
    ASSERT_EQ(static_cast<int>(edges.size()), x.edges) << x.name;
    const Eigen::RowVector3d centre = solid.V.colwise().mean();
    for (size_t f = 0; f < solid.faces.size(); ++f) {
      const Eigen::Vector3d n = face_normal(solid, static_cast<int>(f));
      const Eigen::Vector3d p = solid.V.row(solid.faces[f][0]).transpose();
      EXPECT_GT(n.dot(p - centre.transpose()), 0) << x.name << " face " << f << " points inward";
      for (int v : solid.faces[f]) {
        EXPECT_NEAR(n.dot(solid.V.row(v).transpose() - p), 0, 1e-9) << x.name << " not planar";
      }
    }
    for (const PolyhedronEdge& e : edges) {
      EXPECT_GE(e.right, 0) << x.name << ": closed";
      EXPECT_NEAR((solid.V.row(e.v0) - solid.V.row(e.v1)).norm(), 30, 1e-9) << x.name;
      // Convex everywhere: mountains, π − dihedral.
      const double theta = fold_angle(solid, e);
      const bool base = std::string(x.name) == "pyramid" && (e.left == 0 || e.right == 0);
      const double dihedral = base ? std::atan(std::numbers::sqrt2) : x.dihedral;
      EXPECT_NEAR(theta, -(kPi - dihedral), 1e-9) << x.name;
    }
  }
}

// Turned inside out (every face reversed), every fold is the same angle the other way: a valley.
TEST(Polyhedron, ASolidTurnedInsideOutFoldsTheOtherWay) {
  const Polyhedron cube = polyhedron_example("cube", 20);
  Polyhedron inside_out = cube;
  for (std::vector<int>& face : inside_out.faces) std::reverse(face.begin(), face.end());
  const std::vector<PolyhedronEdge> edges = polyhedron_edges(inside_out);
  for (const PolyhedronEdge& e : edges) EXPECT_NEAR(fold_angle(inside_out, e), kPi / 2, 1e-12);
}

// The acceptance of item 1: one net without overlap, F − 1 hinges, folded back by the nominal
// angles onto the solid within 0.1 % of its diagonal (here to rounding), and flat at progress 0.
TEST(Unfold, EveryExampleUnfoldsIntoOneNetThatFoldsBackOntoIt) {
  for (const Expected& x : kSolids) {
    const Polyhedron solid = polyhedron_example(x.name, 30);
    const Unfolding u = unfold(solid);
    ASSERT_EQ(u.nets.size(), 1u) << x.name;
    EXPECT_TRUE(net_overlaps(u, 0).empty()) << x.name;
    EXPECT_EQ(static_cast<int>(u.nets[0].faces.size()), x.faces);
    int hinges = 0;
    for (int e = 0; e < static_cast<int>(u.edges.size()); ++e) hinges += u.is_hinge(e);
    EXPECT_EQ(hinges, x.faces - 1) << x.name;

    const RigidMotion root = face_to_plane(solid, u.nets[0].root);
    const std::vector<Eigen::MatrixX3d> folded = fold_net(u, 0, 1.0);
    const std::vector<Eigen::MatrixX3d> flat = fold_net(u, 0, 0.0);
    double worst = 0;
    for (size_t f = 0; f < solid.faces.size(); ++f) {
      ASSERT_EQ(folded[f].rows(), static_cast<Eigen::Index>(solid.faces[f].size()));
      for (size_t i = 0; i < solid.faces[f].size(); ++i) {
        const Eigen::Vector3d expected =
            root.R * solid.V.row(solid.faces[f][i]).transpose() + root.t;
        worst = std::max(worst, (folded[f].row(i).transpose() - expected).norm());
        EXPECT_NEAR(flat[f](i, 2), 0, 1e-12);
        EXPECT_NEAR(flat[f](i, 0), u.flat[f](i, 0), 1e-12);
      }
    }
    EXPECT_LT(worst, 1e-9 * diagonal(solid)) << x.name;
  }
}

// A turned solid is laid out as the same net: the flat faces do not depend on where the solid is.
TEST(Unfold, ATurnedSolidGivesTheSameNet) {
  const Polyhedron solid = polyhedron_example("icosahedron", 25);
  Polyhedron turned = solid;
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  turned.V = (solid.V * R.transpose()).rowwise() + Eigen::RowVector3d(5, -3, 11);
  const Unfolding a = unfold(solid), b = unfold(turned);
  ASSERT_EQ(a.nets.size(), b.nets.size());
  EXPECT_EQ(a.parent_edge, b.parent_edge);
  for (size_t f = 0; f < a.flat.size(); ++f) {
    EXPECT_LT((a.flat[f] - b.flat[f]).cwiseAbs().maxCoeff(), 1e-9) << f;
  }
  for (Eigen::Index e = 0; e < a.fold_angle.size(); ++e) {
    EXPECT_NEAR(a.fold_angle(e), b.fold_angle(e), 1e-12);
  }
}

// Eight equilateral triangles around one vertex (480° of angle, a saddle): no tree lays them flat
// without overlap, so they split into nets, each without overlap, every face in one.
TEST(Unfold, ASaddleVertexSplitsIntoSeveralNets) {
  Polyhedron fan;
  fan.source = "saddle fan";
  const double h = std::sqrt((1 - 4 * std::pow(std::sin(kPi / 8), 2)) / 3);
  fan.V.resize(9, 3);
  fan.V.row(0) << 0, 0, 0;
  for (int k = 0; k < 8; ++k) {
    fan.V.row(k + 1) << std::cos(k * kPi / 4), std::sin(k * kPi / 4), k % 2 ? h : -h;
  }
  for (int k = 0; k < 8; ++k) fan.faces.push_back({0, k + 1, (k + 1) % 8 + 1});
  fan.V *= 20;
  const Unfolding u = unfold(fan);
  ASSERT_GE(u.nets.size(), 2u);
  int faces = 0;
  for (int net = 0; net < static_cast<int>(u.nets.size()); ++net) {
    EXPECT_TRUE(net_overlaps(u, net).empty()) << net;
    faces += static_cast<int>(u.nets[net].faces.size());
  }
  EXPECT_EQ(faces, 8);
}

TEST(Polyhedron, BadSolidsAreRefusedNamingTheFaces) {
  Polyhedron three;  // three triangles on one edge
  three.source = "three.obj";
  three.V.resize(5, 3);
  three.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1;
  three.faces = {{0, 1, 2}, {1, 0, 3}, {1, 0, 4}};
  try {
    polyhedron_edges(three);
    ADD_FAILURE() << "three faces on an edge accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("three.obj"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("three or more"), std::string::npos) << e.what();
  }
  Polyhedron flipped = polyhedron_example("cube", 10);
  std::reverse(flipped.faces[2].begin(), flipped.faces[2].end());
  EXPECT_THROW(polyhedron_edges(flipped), UserError);
  Polyhedron sliver = polyhedron_example("tetrahedron", 10);
  sliver.faces[1] = {0, 1};
  EXPECT_THROW(polyhedron_edges(sliver), UserError);
  sliver.faces[1] = {0, 1, 7};
  EXPECT_THROW(polyhedron_edges(sliver), UserError);
  EXPECT_THROW(polyhedron_example("rhombicuboctahedron", 10), UserError);
  EXPECT_THROW(polyhedron_example("cube", -1), UserError);
}

}  // namespace
}  // namespace flatmorph::unfold_test
