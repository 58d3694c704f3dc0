#include "examples/validation_family.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <set>

#include "mesh/operators.h"
#include "mesh/topology.h"

namespace flatmorph::validation_family_test {
namespace {

// 2 pi minus the angles around vertex v (an interior vertex): the integral of the Gaussian
// curvature over its neighbourhood, positive on a cap, negative on a saddle.
double angle_defect(const Mesh& mesh, int v) {
  double sum = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.F(f, k) != v) continue;
      const Eigen::Vector3d p = mesh.V.row(v);
      const Eigen::Vector3d a = mesh.V.row(mesh.F(f, (k + 1) % 3)).transpose() - p;
      const Eigen::Vector3d b = mesh.V.row(mesh.F(f, (k + 2) % 3)).transpose() - p;
      sum += std::atan2(a.cross(b).norm(), a.dot(b));
    }
  }
  return 2 * std::numbers::pi - sum;
}

double smallest_angle(const Mesh& mesh) {
  double smallest = std::numbers::pi;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = mesh.V.row(mesh.F(f, k));
      const Eigen::Vector3d a = mesh.V.row(mesh.F(f, (k + 1) % 3)).transpose() - p;
      const Eigen::Vector3d b = mesh.V.row(mesh.F(f, (k + 2) % 3)).transpose() - p;
      smallest = std::min(smallest, std::atan2(a.cross(b).norm(), a.dot(b)));
    }
  }
  return smallest;
}

// The angle defects of the vertices within 8 mm of the centre over a third of the area of their
// triangles: the discrete Gaussian curvature there, 1/mm^2.
double central_curvature(const Mesh& mesh) {
  double defect = 0, area = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.V.row(v).head<2>().norm() > 8) continue;
    defect += angle_defect(mesh, v);
    for (int f = 0; f < mesh.num_faces(); ++f) {
      if ((mesh.F.row(f).array() == v).any()) {
        const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 1)) - mesh.V.row(mesh.F(f, 0));
        const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 2)) - mesh.V.row(mesh.F(f, 0));
        area += a.cross(b).norm() / 6;
      }
    }
  }
  return defect / area;
}

TEST(ValidationFamily, EveryTargetIsAnUpwardDiskOfTheIssuesSizes) {
  const std::vector<ValidationTarget> family = validation_family();
  EXPECT_GE(family.size(), 10u);
  std::set<std::string> names;
  for (const ValidationTarget& t : family) {
    SCOPED_TRACE(t.name);
    names.insert(t.name);
    EXPECT_NE(t.description.find("mm"), std::string::npos);
    const Mesh& mesh = t.mesh;
    EXPECT_GE(mesh.num_faces(), 3000);
    EXPECT_LE(mesh.num_faces(), 10000);
    EXPECT_GE(t.width_mm, 80);
    EXPECT_LE(t.width_mm, 150.0 + 1e-9);
    EXPECT_TRUE(mesh.V.allFinite());
    EXPECT_EQ(boundary_loops(mesh.F).size(), 1u);
    EXPECT_EQ(euler_characteristic(mesh.F), 1);
    Eigen::VectorXi component;
    EXPECT_EQ(face_components(mesh.F, component), 1);
    std::vector<bool> used(static_cast<size_t>(mesh.num_vertices()), false);
    for (int f = 0; f < mesh.num_faces(); ++f) {
      for (int k = 0; k < 3; ++k) used[static_cast<size_t>(mesh.F(f, k))] = true;
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
    // Height fields seen from above: every normal up.
    EXPECT_GT(face_normals(mesh.V, mesh.F).col(2).minCoeff(), 0.3);
    // Rings that follow an elongated outline squeeze the triangles across its short axis, and
    // stretch them into corners; within reason.
    EXPECT_GT(smallest_angle(mesh), 11.0 * std::numbers::pi / 180);
  }
  EXPECT_EQ(names.size(), family.size()) << "duplicate names";
}

// Gauss-Bonnet near the centre: the angle defects of the vertices within 8 mm of it over a third of
// the area of their triangles (the discrete Gaussian curvature, exact for the integral), against
// the formula's K = (z_xx z_yy - z_xy^2) / (1 + |grad z|^2)^2, which moves by less than 5 % there;
// the monkey saddle's, -36 r^2 / 12500^2, averaged over the disk of radius 8 mm.
TEST(ValidationFamily, GaussianCurvatureAtTheCentreIsTheFormulas) {
  const std::map<std::string, double> curvature = {
      {"elliptic-cap-1", 1.0 / (80 * 80)},     {"elliptic-cap-2", 1.0 / (90 * 60)},
      {"elliptic-cap-3", 1.0 / (120 * 50)},    {"rounded-triangle-cap", 1.0 / (70 * 70)},
      {"rounded-square-cap", 1.0 / (80 * 80)}, {"saddle", -1.0 / (70 * 70)},
      {"elliptic-saddle", -1.0 / (100 * 60)},  {"monkey-saddle", -36.0 * 32 / (12500.0 * 12500)},
      {"twisted-strip", -1.0 / (200 * 200)},   {"wave", 0.0}};
  int checked = 0;
  for (const ValidationTarget& t : validation_family()) {
    const auto it = curvature.find(t.name);
    if (it == curvature.end()) continue;  // the off-centre bump: no round number at the centre
    SCOPED_TRACE(t.name);
    const double k = central_curvature(t.mesh);
    EXPECT_NEAR(k, it->second, 0.1 * std::abs(it->second) + 1e-6) << "discrete " << k;
    ++checked;
  }
  EXPECT_EQ(checked, 10);
}

TEST(ValidationFamily, IsTheSameOnEveryCall) {
  const std::vector<ValidationTarget> a = validation_family(), b = validation_family();
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].mesh.F, b[i].mesh.F);
    EXPECT_EQ(a[i].mesh.V, b[i].mesh.V);
  }
}

// The formula's Gaussian curvature K(x, y) averaged over the same vertices and areas as
// central_curvature: the monkey saddles' grows as r^2, so the mean over the vertices' areas (which
// reach past 8 mm) is what the discrete figure is to match.
template <typename Curvature>
double central_formula_curvature(const Mesh& mesh, const Curvature& curvature) {
  double integral = 0, area = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.V.row(v).head<2>().norm() > 8) continue;
    double vertex_area = 0;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      if ((mesh.F.row(f).array() == v).any()) {
        const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 1)) - mesh.V.row(mesh.F(f, 0));
        const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 2)) - mesh.V.row(mesh.F(f, 0));
        vertex_area += a.cross(b).norm() / 6;
      }
    }
    integral += curvature(mesh.V(v, 0), mesh.V(v, 1)) * vertex_area;
    area += vertex_area;
  }
  return integral / area;
}

// The variants: disks with one boundary, normals up, and near the centre the Gaussian curvature
// of their formulas, K = (z_xx z_yy - z_xy^2) / (1 + |grad z|^2)^2.
TEST(ValidationFamily, TheVariantsAreUpwardDisksWithTheirFormulasCurvature) {
  using Curvature = std::function<double(double, double)>;
  const auto cap = [](double rx, double ry) -> Curvature {
    return [=](double x, double y) {
      const double g = 1 + x * x / (rx * rx) + y * y / (ry * ry);
      return 1 / (rx * ry * g * g);
    };
  };
  const auto monkey = [](double s) -> Curvature {
    return [=](double x, double y) {
      const double zx = 3 * (x * x - y * y) / s, zy = -6 * x * y / s;
      const double g = 1 + zx * zx + zy * zy;
      return -36 * (x * x + y * y) / (s * s * g * g);
    };
  };
  const std::map<std::string, Curvature> curvature = {
      {"monkey-saddle-10k", monkey(12500)},     {"monkey-saddle-80", monkey(8000)},
      {"monkey-saddle-shallow", monkey(20000)}, {"elliptic-cap-small", cap(60, 60)},
      {"elliptic-cap-deep", cap(60, 60)},       {"elliptic-cap-1.5", cap(100, 70)},
      {"elliptic-cap-2.5", cap(110, 55)}};
  const std::vector<ValidationTarget> variants = validation_family_variants();
  ASSERT_EQ(variants.size(), curvature.size());
  for (const ValidationTarget& t : variants) {
    SCOPED_TRACE(t.name);
    ASSERT_EQ(curvature.count(t.name), 1u);
    const Mesh& mesh = t.mesh;
    EXPECT_TRUE(mesh.V.allFinite());
    EXPECT_EQ(boundary_loops(mesh.F).size(), 1u);
    EXPECT_EQ(euler_characteristic(mesh.F), 1);
    EXPECT_GT(face_normals(mesh.V, mesh.F).col(2).minCoeff(), 0.3);
    EXPECT_GT(smallest_angle(mesh), 11.0 * std::numbers::pi / 180);
    const double expected = central_formula_curvature(mesh, curvature.at(t.name));
    EXPECT_NEAR(central_curvature(mesh), expected, 0.1 * std::abs(expected)) << expected;
  }
}

}  // namespace
}  // namespace flatmorph::validation_family_test
