#include "mesh/operators.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <random>
#include <utility>

#include "mesh/topology.h"

namespace flatmorph::operators_test {
namespace {

Eigen::MatrixXi flipped(const Eigen::MatrixXi& F) {
  Eigen::MatrixXi G = F;
  G.col(1) = F.col(2);
  G.col(2) = F.col(1);
  return G;
}

// Icosahedron refined `levels` times by midpoint subdivision and projected onto the sphere:
// 20 * 4^levels faces, outward normals.
Mesh icosphere(double radius, int levels) {
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0},
                                    {0, -1, p}, {0, 1, p}, {0, -1, -p}, {0, 1, -p},
                                    {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& x : v) x.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return midpoint[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> refined;
    for (const auto& t : f) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      refined.insert(refined.end(), {{t[0], ab, ca}, {t[1], bc, ab}, {t[2], ca, bc}, {ab, bc, ca}});
    }
    f = std::move(refined);
  }
  Mesh mesh;
  mesh.V.resize(static_cast<int>(v.size()), 3);
  for (int i = 0; i < mesh.V.rows(); ++i) mesh.V.row(i) = radius * v[i].transpose();
  mesh.F.resize(static_cast<int>(f.size()), 3);
  for (int i = 0; i < mesh.F.rows(); ++i) mesh.F.row(i) = f[i].transpose();
  return mesh;
}

// Grid of (nu + 1) x (nv + 1) vertices indexed u-major, quads split along alternating diagonals,
// faces counter-clockwise in (u, v).
Eigen::MatrixXi grid_faces(int nu, int nv) {
  Eigen::MatrixXi F(2 * nu * nv, 3);
  auto id = [&](int i, int j) { return i * (nv + 1) + j; };
  int f = 0;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0) {
        F.row(f++) << a, b, c;
        F.row(f++) << a, c, d;
      } else {
        F.row(f++) << a, b, d;
        F.row(f++) << b, c, d;
      }
    }
  }
  return F;
}

// Square [0, size]^2 with its interior vertices moved by up to 0.3 of the spacing (2 columns).
Mesh jittered_square(int n, double size) {
  std::mt19937 rng(12345);
  auto jitter = [&] { return static_cast<double>(rng()) / 4294967296.0 - 0.5; };
  const double h = size / n;
  Mesh mesh;
  mesh.V.resize((n + 1) * (n + 1), 2);
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const bool interior = i > 0 && i < n && j > 0 && j < n;
      const double dx = interior ? 0.6 * h * jitter() : 0.0;
      const double dy = interior ? 0.6 * h * jitter() : 0.0;
      mesh.V.row(i * (n + 1) + j) << i * h + dx, j * h + dy;
    }
  }
  mesh.F = grid_faces(n, n);
  return mesh;
}

// Cylinder patch of radius r around the z axis: `segments` columns over the angle `span` and
// `rows` rows over the height; normals point outward.
Mesh cylinder_patch(double r, double span, int segments, double height, int rows) {
  Mesh mesh;
  mesh.V.resize((segments + 1) * (rows + 1), 3);
  for (int i = 0; i <= segments; ++i) {
    const double psi = span * i / segments;
    for (int j = 0; j <= rows; ++j) {
      mesh.V.row(i * (rows + 1) + j) << r * std::cos(psi), r * std::sin(psi), height * j / rows;
    }
  }
  mesh.F = grid_faces(segments, rows);
  return mesh;
}

// Vertices that lie on no boundary loop.
std::vector<bool> interior_vertices(const Eigen::MatrixXi& F, int num_vertices) {
  std::vector<bool> interior(num_vertices, true);
  for (const auto& loop : boundary_loops(F)) {
    for (int v : loop) interior[v] = false;
  }
  return interior;
}

// The two tangent eigenvalues (min, max) per face, from mean and Gaussian curvature.
std::vector<std::pair<double, double>> principal_curvatures(const Mesh& mesh) {
  const auto S = shape_operators(mesh.V, mesh.F, edge_topology(mesh.F));
  Eigen::VectorXd mean, gaussian;
  face_curvatures(S, face_normals(mesh.V, mesh.F), mean, gaussian);
  std::vector<std::pair<double, double>> k(mesh.F.rows());
  for (int f = 0; f < mesh.F.rows(); ++f) {
    const double d = std::sqrt(std::max(0.0, mean[f] * mean[f] - gaussian[f]));
    k[f] = {mean[f] - d, mean[f] + d};
  }
  return k;
}

TEST(MeshOperators, SignedAreasFlipWithOrientation) {
  Eigen::MatrixXd V2(3, 2);
  V2 << 0, 0, 2, 0, 0, 3;
  Eigen::MatrixXi F(1, 3);
  F << 0, 1, 2;
  EXPECT_DOUBLE_EQ(face_areas(V2, F)[0], 3.0);
  EXPECT_DOUBLE_EQ(face_areas(V2, flipped(F))[0], -3.0);
  // In 3D areas are unsigned; the orientation lives in the normal.
  Eigen::MatrixXd V3(3, 3);
  V3 << 0, 0, 1, 2, 0, 1, 0, 3, 1;
  EXPECT_DOUBLE_EQ(face_areas(V3, F)[0], 3.0);
  EXPECT_DOUBLE_EQ(face_areas(V3, flipped(F))[0], 3.0);
  EXPECT_TRUE(face_normals(V3, F).row(0).isApprox(Eigen::RowVector3d(0, 0, 1)));
  EXPECT_TRUE(face_normals(V3, flipped(F)).row(0).isApprox(Eigen::RowVector3d(0, 0, -1)));
  EXPECT_TRUE(face_normals(V2, flipped(F)).row(0).isApprox(Eigen::RowVector3d(0, 0, -1)));

  const Mesh square = jittered_square(12, 30.0);
  EXPECT_NEAR(face_areas(square.V, square.F).sum(), 900.0, 1e-10);
  EXPECT_NEAR(face_areas(square.V, flipped(square.F)).sum(), -900.0, 1e-10);
  EXPECT_GT(face_areas(square.V, square.F).minCoeff(), 0.0);  // the jitter folds no triangle
}

TEST(MeshOperators, LumpedMassSumsToArea) {
  const Mesh sphere = icosphere(50.0, 3);
  const Eigen::VectorXd mass = lumped_mass(sphere.V, sphere.F);
  EXPECT_NEAR(mass.sum(), face_areas(sphere.V, sphere.F).sum(), 1e-9);
  // Inscribed polyhedron: a little less than the sphere's 4 pi R^2.
  EXPECT_NEAR(mass.sum() / (4 * kPi * 2500.0), 1.0, 0.01);
  EXPECT_GT(mass.minCoeff(), 0.0);

  const Mesh square = jittered_square(10, 20.0);
  EXPECT_NEAR(lumped_mass(square.V, square.F).sum(), 400.0, 1e-10);
  EXPECT_NEAR(lumped_mass(square.V, flipped(square.F)).sum(), 400.0, 1e-10);
  // A single triangle of area 3 gives each corner 1.
  Eigen::MatrixXd V(3, 2);
  V << 0, 0, 3, 0, 0, 2;
  Eigen::MatrixXi F(1, 3);
  F << 0, 1, 2;
  EXPECT_TRUE(lumped_mass(V, F).isApprox(Eigen::Vector3d::Constant(1.0)));
}

// Checks symmetry, zero row sums, L u = 0 at interior vertices for linear u, and
// u^T L u = integral of |grad u|^2 = area * |grad u|^2 (twice the Dirichlet energy 1/2 int |grad
// u|^2).
void check_cotan_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                           const Eigen::VectorXd& gradient, double in_plane_gradient_squared) {
  const Eigen::SparseMatrix<double> L = cotan_laplacian(V, F);
  ASSERT_EQ(L.rows(), V.rows());
  const Eigen::MatrixXd dense = L.toDense();
  const double scale = dense.cwiseAbs().maxCoeff();
  EXPECT_LE((dense - dense.transpose()).cwiseAbs().maxCoeff(), 1e-14 * scale);
  EXPECT_LE(dense.rowwise().sum().cwiseAbs().maxCoeff(), 1e-13 * scale);
  // Off-diagonal weights may be negative on obtuse pairs, but the diagonal is positive.
  EXPECT_GT(dense.diagonal().minCoeff(), 0.0);

  const Eigen::VectorXd u = V * gradient + Eigen::VectorXd::Constant(V.rows(), 7.0);
  const Eigen::VectorXd Lu = L * u;
  const auto interior = interior_vertices(F, static_cast<int>(V.rows()));
  const double u_scale = u.cwiseAbs().maxCoeff();
  int checked = 0;
  for (int i = 0; i < V.rows(); ++i) {
    if (!interior[i]) continue;
    const double row_scale = dense.row(i).cwiseAbs().sum();
    EXPECT_LE(std::abs(Lu[i]), 1e-10 * row_scale * u_scale) << "vertex " << i;
    ++checked;
  }
  EXPECT_GT(checked, 0);
  const double area = face_areas(V, F).cwiseAbs().sum();
  EXPECT_NEAR(u.dot(Lu) / (area * in_plane_gradient_squared), 1.0, 1e-10);
  // The boundary rows do not vanish: otherwise the energy check above could not pass.
  EXPECT_GT(Lu.cwiseAbs().maxCoeff(), 1e-3 * u_scale);
}

TEST(MeshOperators, CotanLaplacianIrregularPlane) {
  const Mesh square = jittered_square(12, 30.0);
  check_cotan_laplacian(square.V, square.F, Eigen::Vector2d(0.7, -1.3), 0.7 * 0.7 + 1.3 * 1.3);
}

TEST(MeshOperators, CotanLaplacianTiltedPlane) {
  const Mesh square = jittered_square(12, 30.0);
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())).toRotationMatrix();
  // Plane spanned by the first two rotated axes; a 3D gradient g restricted to it has squared
  // in-plane norm |g|^2 - (g . normal)^2.
  const Eigen::MatrixXd V =
      (square.V * rotation.leftCols<2>().transpose()).rowwise() + Eigen::RowVector3d(5, -3, 11);
  const Eigen::Vector3d g(0.4, 1.1, -0.8);
  const double normal_part = g.dot(rotation.col(2));
  check_cotan_laplacian(V, square.F, g, g.squaredNorm() - normal_part * normal_part);
}

TEST(MeshOperators, GaussBonnet) {
  // Disk: a bumpy height field over an irregular grid.
  Mesh disk = jittered_square(14, 20.0);
  disk.V.conservativeResize(Eigen::NoChange, 3);
  for (int i = 0; i < disk.V.rows(); ++i) {
    disk.V(i, 2) = 4.0 * std::sin(0.3 * disk.V(i, 0)) * std::cos(0.2 * disk.V(i, 1));
  }
  ASSERT_EQ(euler_characteristic(disk.F), 1);
  EXPECT_NEAR(angle_defects(disk.V, disk.F).sum(), 2 * kPi, 1e-9);
  // The flat version must also satisfy it (all interior defects 0, boundary turning 2 pi).
  Eigen::VectorXd flat = angle_defects(jittered_square(14, 20.0).V, disk.F);
  EXPECT_NEAR(flat.sum(), 2 * kPi, 1e-9);

  // Closed sphere: chi = 2.
  const Mesh sphere = icosphere(50.0, 3);
  ASSERT_EQ(euler_characteristic(sphere.F), 2);
  const Eigen::VectorXd sphere_defects = angle_defects(sphere.V, sphere.F);
  EXPECT_NEAR(sphere_defects.sum(), 4 * kPi, 1e-9);
  EXPECT_GT(sphere_defects.minCoeff(), 0.0);

  // Annulus on a wavy surface: chi = 0. The grid wraps in the angle: column `segments` is column 0.
  const int segments = 40, rows = 6;
  Mesh annulus;
  annulus.V.resize(segments * (rows + 1), 3);
  for (int i = 0; i < segments; ++i) {
    const double psi = 2 * kPi * i / segments;
    for (int j = 0; j <= rows; ++j) {
      const double r = 10.0 + 2.0 * j;
      annulus.V.row(i * (rows + 1) + j) << r * std::cos(psi), r * std::sin(psi),
          3.0 * std::sin(2 * psi) + 0.02 * r * r;
    }
  }
  annulus.F = grid_faces(segments, rows);
  for (int f = 0; f < annulus.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) annulus.F(f, k) %= segments * (rows + 1);
  }
  ASSERT_EQ(euler_characteristic(annulus.F), 0);
  ASSERT_EQ(boundary_loops(annulus.F).size(), 2u);
  EXPECT_NEAR(angle_defects(annulus.V, annulus.F).sum(), 0.0, 1e-9);
}

TEST(MeshOperators, DihedralAngleOfAFold) {
  // f0 lies in z = 0 with normal +z; f1 shares the edge along x and rises (or sinks) by `alpha`.
  for (const double alpha : {0.3, 1.2, 2.5}) {
    for (const double side : {1.0, -1.0}) {
      Eigen::MatrixXd V(4, 3);
      V << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -std::cos(alpha), side * std::sin(alpha);
      Eigen::MatrixXi F(2, 3);
      F << 0, 1, 2, 1, 0, 3;
      const EdgeTopology topology = edge_topology(F);
      const Eigen::VectorXd theta = signed_dihedral_angles(V, F, topology);
      int interior = -1;
      for (int e = 0; e < topology.num_edges(); ++e) {
        if (!topology.is_boundary_edge(e)) {
          interior = e;
        } else {
          EXPECT_EQ(theta[e], 0.0);
        }
      }
      ASSERT_GE(interior, 0);
      // Rising toward the +z normals: concave on the normal side, positive.
      EXPECT_NEAR(theta[interior], side * alpha, 1e-12) << "alpha " << alpha;
      // Reversing the orientation flips the normals and therefore the sign.
      EXPECT_NEAR(signed_dihedral_angles(V, flipped(F), edge_topology(flipped(F)))[interior],
                  -side * alpha, 1e-12);
      // Shape operator of f0: theta l / (2 A) t t^T with l = 1, A = 1/2 and t = y.
      const auto S = shape_operators(V, F, topology);
      Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
      expected(1, 1) = side * alpha;
      EXPECT_LE((S[0] - expected).norm(), 1e-12);
    }
  }
}

TEST(MeshOperators, ShapeOperatorSphere) {
  const double radius = 50.0;
  const Mesh outward = icosphere(radius, 4);
  ASSERT_GE(outward.F.rows(), 5000);
  // Outward normals: the centroid-to-face direction and the normal agree.
  const Eigen::MatrixXd normals = face_normals(outward.V, outward.F);
  for (int f = 0; f < outward.F.rows(); ++f) {
    ASSERT_GT(normals.row(f).dot(outward.V.row(outward.F(f, 0))), 0.0);
  }
  for (const double sign : {1.0, -1.0}) {
    Mesh mesh = outward;
    if (sign > 0) mesh.F = flipped(outward.F);  // inward normals: bends toward them, +1/R
    const auto k = principal_curvatures(mesh);
    double mean_min = 0.0, mean_max = 0.0;
    for (const auto& [k_min, k_max] : k) {
      mean_min += k_min / static_cast<double>(k.size());
      mean_max += k_max / static_cast<double>(k.size());
    }
    EXPECT_NEAR(mean_min * radius, sign, 0.02);
    EXPECT_NEAR(mean_max * radius, sign, 0.02);
    // Measured 0.985 and 1.019 at 5120 faces: the spread is per-face anisotropy of the projected
    // icosahedron, which largely cancels in the mean curvature (measured 1.002).
    EXPECT_NEAR(0.5 * (mean_min + mean_max) * radius, sign, 0.005);
    // Every face, however distorted by the icosahedral projection, has the right sign.
    for (const auto& [k_min, k_max] : k) {
      ASSERT_GT(sign * k_min, 0.0);
      ASSERT_GT(sign * k_max, 0.0);
    }
  }
}

TEST(MeshOperators, ShapeOperatorCylinder) {
  // A cylinder patch meshed along its rulings: each triangle has exactly one axial edge, across
  // which the normal turns by the angular step d; every other edge joins coplanar faces. The
  // operator is then d / chord t t^T with chord = 2 R sin(d / 2): the inscribed polygon's
  // curvature, (1 + d^2 / 24 + ...) / R. With d = pi / 40 that is 1/R within 2.6e-4, so the test
  // asks for the exact discrete value to 1e-9 and 1/R to 1e-3.
  const double radius = 30.0, step = kPi / 40;
  const Mesh outward = cylinder_patch(radius, kPi, 40, 60.0, 20);
  const double discrete = step / (2 * radius * std::sin(step / 2)) * radius;  // times R
  for (const double sign : {1.0, -1.0}) {
    Mesh mesh = outward;
    if (sign > 0) mesh.F = flipped(outward.F);  // seen from inside: +1/R
    const auto S = shape_operators(mesh.V, mesh.F, edge_topology(mesh.F));
    const auto k = principal_curvatures(mesh);
    const auto interior = interior_vertices(mesh.F, static_cast<int>(mesh.V.rows()));
    int checked = 0;
    for (int f = 0; f < mesh.F.rows(); ++f) {
      if (!interior[mesh.F(f, 0)] || !interior[mesh.F(f, 1)] || !interior[mesh.F(f, 2)]) continue;
      const double along = sign > 0 ? k[f].second : k[f].first;
      const double across = sign > 0 ? k[f].first : k[f].second;
      EXPECT_NEAR(along * radius, sign * discrete, 1e-9);
      EXPECT_NEAR(along * radius, sign, 1e-3);
      EXPECT_NEAR(across * radius, 0.0, 1e-9);
      // The flat direction is the axis.
      EXPECT_LE((S[f] * Eigen::Vector3d::UnitZ()).norm() * radius, 1e-9);
      ++checked;
    }
    EXPECT_GT(checked, 1000);
  }
}

TEST(MeshOperators, ShapeOperatorPlane) {
  const Mesh square = jittered_square(12, 30.0);
  Eigen::MatrixXd V(square.V.rows(), 3);
  V << square.V, Eigen::VectorXd::Zero(square.V.rows());
  const EdgeTopology topology = edge_topology(square.F);
  EXPECT_EQ(signed_dihedral_angles(V, square.F, topology).cwiseAbs().maxCoeff(), 0.0);
  for (const auto& S : shape_operators(V, square.F, topology)) EXPECT_EQ(S.norm(), 0.0);
  // A 2-column plate is a plane too.
  for (const auto& S : shape_operators(square.V, square.F, topology)) EXPECT_EQ(S.norm(), 0.0);

  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(1.1, Eigen::Vector3d(-2, 1, 0.5).normalized())).toRotationMatrix();
  const Eigen::MatrixXd tilted = V * rotation.transpose();
  for (const auto& S : shape_operators(tilted, square.F, topology)) EXPECT_LE(S.norm(), 1e-12);
}

TEST(MeshOperators, FaceCurvaturesOfKnownOperator) {
  // A face with normal n and S = a u u^T + b v v^T in its tangent plane has H = (a + b) / 2, K = a
  // b.
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, 2) / 3.0;
  const Eigen::Vector3d u = Eigen::Vector3d(2, -1, 0).normalized();
  const Eigen::Vector3d v = n.cross(u);
  std::vector<Eigen::Matrix3d> S = {0.02 * u * u.transpose() - 0.05 * v * v.transpose()};
  Eigen::VectorXd mean, gaussian;
  face_curvatures(S, n.transpose(), mean, gaussian);
  EXPECT_NEAR(mean[0], -0.015, 1e-15);
  EXPECT_NEAR(gaussian[0], -0.001, 1e-15);
}

}  // namespace
}  // namespace flatmorph::operators_test
