#include "examples/examples.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "common/error.h"
#include "mesh/operators.h"
#include "mesh/topology.h"

namespace flatmorph::examples_test {
namespace {

// The documented footprint diameter of each example (mm), from the descriptions.
double documented_diameter(const std::string& name) {
  if (name == "dome" || name == "saddle") return 80.0;
  if (name == "paraboloid") return 90.0;
  if (name == "bump") return 100.0;
  ADD_FAILURE() << "no documented size for example " << name;
  return 0.0;
}

// Area-weighted average of the per-face shape operators over faces whose centroid lies within
// `outer` (and beyond `inner`) of the z axis, in the horizontal tangent frame (x, y): near the
// centre the normal is close to +z, so this 2x2 block holds the principal curvatures there.
Eigen::Matrix2d average_shape_operator(const Mesh& mesh, double inner, double outer) {
  const auto S = shape_operators(mesh.V, mesh.F, edge_topology(mesh.F));
  const Eigen::VectorXd areas = face_areas(mesh.V, mesh.F);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  double total = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) centroid += mesh.V.row(mesh.F(f, k)).transpose() / 3.0;
    const double r = centroid.head<2>().norm();
    if (r < inner || r > outer) continue;
    sum += areas[f] * S[f];
    total += areas[f];
  }
  EXPECT_GT(total, 0.0);
  return sum.topLeftCorner<2, 2>() / total;
}

TEST(Examples, ListHasTheDocumentedSurfaces) {
  const auto list = example_list();
  std::set<std::string> names;
  for (const auto& info : list) {
    names.insert(info.name);
    EXPECT_NE(info.description.find("mm"), std::string::npos) << info.name << ": size missing";
    EXPECT_NE(info.description.find("curvature"), std::string::npos) << info.name;
  }
  EXPECT_EQ(names.size(), list.size()) << "duplicate names";
  for (const char* name : {"dome", "saddle", "paraboloid", "bump"}) {
    EXPECT_TRUE(names.count(name)) << name;
  }
}

TEST(Examples, EveryExampleIsAnEvenlyMeshedUpwardDisk) {
  for (const auto& info : example_list()) {
    SCOPED_TRACE(info.name);
    const Mesh mesh = make_example(info.name);
    ASSERT_EQ(mesh.V.cols(), 3);
    EXPECT_GE(mesh.num_faces(), 2000);
    EXPECT_LE(mesh.num_faces(), 4000);
    EXPECT_TRUE(mesh.V.allFinite());

    const auto loops = boundary_loops(mesh.F);
    ASSERT_EQ(loops.size(), 1u);
    EXPECT_EQ(euler_characteristic(mesh.F), 1);
    Eigen::VectorXi component;
    EXPECT_EQ(face_components(mesh.F, component), 1);
    // Every vertex is used (so chi counts them all).
    std::vector<bool> used(mesh.num_vertices(), false);
    for (int f = 0; f < mesh.num_faces(); ++f) {
      for (int k = 0; k < 3; ++k) used[mesh.F(f, k)] = true;
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);

    // Circular footprint centred on the origin: every boundary vertex at the documented radius.
    const double radius = documented_diameter(info.name) / 2.0;
    for (int v : loops[0]) {
      EXPECT_NEAR(mesh.V.row(v).head<2>().norm(), radius, 0.01 * radius) << "vertex " << v;
    }
    EXPECT_NEAR(mesh.V.col(0).maxCoeff() - mesh.V.col(0).minCoeff(), 2.0 * radius, 0.02 * radius);

    // Normals up: the +z side becomes the top of the plate.
    EXPECT_GT(face_normals(mesh.V, mesh.F).col(2).minCoeff(), 0.0);

    // Even edges. Measured max/min 3D edge length: dome 1.46, saddle 1.58, paraboloid 1.47,
    // bump 1.41. The ring lattice alone gives ~1.45 (a hexagonal lattice bent onto circles:
    // radial edges h, ring edges ~1.05 h, diagonals up to ~1.3 h); the saddle's direction-dependent
    // slope, which the radial spacing can only even out on average, adds the rest.
    const EdgeTopology topology = edge_topology(mesh.F);
    double shortest = std::numeric_limits<double>::infinity(), longest = 0.0;
    for (int e = 0; e < topology.num_edges(); ++e) {
      const double length =
          (mesh.V.row(topology.edges(e, 0)) - mesh.V.row(topology.edges(e, 1))).norm();
      shortest = std::min(shortest, length);
      longest = std::max(longest, length);
    }
    EXPECT_LT(longest / shortest, 1.7);
    // No sliver: the smallest angle stays well above zero.
    const Eigen::VectorXd areas = face_areas(mesh.V, mesh.F);
    EXPECT_GT(areas.minCoeff() / (longest * longest), 0.15);
  }
}

TEST(Examples, DomeCurvesAwayFromItsUpwardNormals) {
  const Mesh mesh = make_example("dome");
  // Radius of curvature 60 mm everywhere, bending down (away from the +z normals): both principal
  // curvatures -1/60 mm^-1, K = 1/3600 mm^-2 > 0.
  Eigen::VectorXd mean, gaussian;
  face_curvatures(shape_operators(mesh.V, mesh.F, edge_topology(mesh.F)),
                  face_normals(mesh.V, mesh.F), mean, gaussian);
  const auto interior = [&] {
    std::vector<bool> on_boundary(mesh.num_vertices(), false);
    const auto loops = boundary_loops(mesh.F);
    for (int v : loops[0]) on_boundary[v] = true;
    std::vector<int> faces;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      if (!on_boundary[mesh.F(f, 0)] && !on_boundary[mesh.F(f, 1)] && !on_boundary[mesh.F(f, 2)]) {
        faces.push_back(f);
      }
    }
    return faces;
  }();
  double mean_h = 0.0;
  for (int f : interior) {
    EXPECT_LT(mean[f], 0.0) << "face " << f;
    EXPECT_GT(gaussian[f], 0.0) << "face " << f;
    mean_h += mean[f] / interior.size();
  }
  EXPECT_NEAR(mean_h * 60.0, -1.0, 0.02);
  const Eigen::Matrix2d centre = average_shape_operator(mesh, 0.0, 10.0);
  EXPECT_NEAR(centre(0, 0) * 60.0, -1.0, 0.05);
  EXPECT_NEAR(centre(1, 1) * 60.0, -1.0, 0.05);
  EXPECT_GT(centre.determinant(), 0.0);
}

TEST(Examples, SaddleHasNegativeGaussianCurvature) {
  const Mesh mesh = make_example("saddle");
  // z = (x^2 - y^2) / 160: curvature +1/80 along x (bending up, toward the normal), -1/80 along y.
  const Eigen::Matrix2d centre = average_shape_operator(mesh, 0.0, 10.0);
  EXPECT_LT(centre.determinant(), 0.0);
  EXPECT_NEAR(centre(0, 0) * 80.0, 1.0, 0.05);
  EXPECT_NEAR(centre(1, 1) * 80.0, -1.0, 0.05);
  EXPECT_NEAR(centre(0, 1) * 80.0, 0.0, 0.05);
}

TEST(Examples, ParaboloidIsAnisotropic) {
  const Mesh mesh = make_example("paraboloid");
  // z = -(x^2 / 140 + y^2 / 220): curvatures -1/70 along x and -1/110 along y at the apex.
  const Eigen::Matrix2d centre = average_shape_operator(mesh, 0.0, 8.0);
  EXPECT_GT(centre.determinant(), 0.0);
  EXPECT_LT(centre.trace(), 0.0);
  EXPECT_NEAR(centre(0, 0) * 70.0, -1.0, 0.05);
  EXPECT_NEAR(centre(1, 1) * 110.0, -1.0, 0.05);
  EXPECT_NEAR(centre(0, 0) / centre(1, 1), 110.0 / 70.0, 0.05 * 110.0 / 70.0);
}

TEST(Examples, BumpIsPositiveOnTopAndNegativeOnTheFlank) {
  const Mesh mesh = make_example("bump");
  // z = 12 exp(-r^2 / 36^2): at the top both curvatures are -2 * 12 / 36^2 mm^-1 (bending away
  // from the upward normals, K > 0). Past the inflection radius 36 / sqrt(2) = 25.5 mm the radial
  // profile bends up while the rings still bend down: K < 0.
  const Eigen::Matrix2d top = average_shape_operator(mesh, 0.0, 6.0);
  EXPECT_GT(top.determinant(), 0.0);
  const double apex = -2.0 * 12.0 / (36.0 * 36.0);
  EXPECT_NEAR(top(0, 0) / apex, 1.0, 0.1);
  EXPECT_NEAR(top(1, 1) / apex, 1.0, 0.1);

  Eigen::VectorXd mean, gaussian;
  const Eigen::MatrixXd normals = face_normals(mesh.V, mesh.F);
  face_curvatures(shape_operators(mesh.V, mesh.F, edge_topology(mesh.F)), normals, mean, gaussian);
  int negative_on_flank = 0, flank = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) centroid += mesh.V.row(mesh.F(f, k)).transpose() / 3.0;
    const double r = centroid.head<2>().norm();
    if (r > 30.0 && r < 45.0) {
      ++flank;
      negative_on_flank += gaussian[f] < 0.0;
    }
  }
  ASSERT_GT(flank, 0);
  // Most flank faces, not just one: the sign is a property of the surface, not of mesh noise.
  EXPECT_GT(negative_on_flank, flank * 9 / 10);
}

TEST(Examples, Deterministic) {
  for (const auto& info : example_list()) {
    const Mesh a = make_example(info.name), b = make_example(info.name);
    EXPECT_TRUE(a.V == b.V) << info.name;
    EXPECT_TRUE(a.F == b.F) << info.name;
  }
}

TEST(Examples, UnknownNameListsTheValidOnes) {
  try {
    make_example("teapot");
    FAIL() << "no error for an unknown example";
  } catch (const UserError& error) {
    EXPECT_EQ(error.category(), ErrorCategory::kOption);
    const std::string message = error.what();
    EXPECT_NE(message.find("teapot"), std::string::npos) << message;
    for (const auto& info : example_list()) {
      EXPECT_NE(message.find(info.name), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace flatmorph::examples_test
