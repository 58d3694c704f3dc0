#include "mesh/subdivide.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>

#include "mesh/mesh_fixtures.h"
#include "mesh/topology.h"
#include "mesh/validate.h"

namespace flatmorph::subdivide_test {
namespace {

using testing::grid;
using testing::icosahedron;

// Unit disk in the z = 0 plane: a centre vertex and `rings` rings, ring j with 6 j vertices, the
// rings zipped together by angle. Counter-clockwise seen from +z.
Mesh disk(int rings) {
  std::vector<Eigen::RowVector3d> points{Eigen::RowVector3d::Zero()};
  std::vector<std::vector<int>> ring_vertices{{0}};
  for (int j = 1; j <= rings; ++j) {
    std::vector<int> ring;
    for (int i = 0; i < 6 * j; ++i) {
      const double t = 2.0 * std::numbers::pi * i / (6 * j);
      const double r = static_cast<double>(j) / rings;
      ring.push_back(static_cast<int>(points.size()));
      points.emplace_back(r * std::cos(t), r * std::sin(t), 0.0);
    }
    ring_vertices.push_back(ring);
  }
  std::vector<Eigen::RowVector3i> faces;
  for (int j = 1; j <= rings; ++j) {
    const std::vector<int>& in = ring_vertices[j - 1];
    const std::vector<int>& out = ring_vertices[j];
    const int n_in = static_cast<int>(in.size()), n_out = static_cast<int>(out.size());
    // Advance along whichever ring's next vertex comes first in angle (fraction of a turn).
    for (int a = 0, b = 0; a < n_in || b < n_out;) {
      const double next_in = static_cast<double>(a + 1) / n_in;
      const double next_out = static_cast<double>(b + 1) / n_out;
      if (a < n_in && (b == n_out || next_in < next_out) && n_in > 1) {
        faces.emplace_back(in[a], out[b % n_out], in[(a + 1) % n_in]);
        ++a;
      } else {
        faces.emplace_back(in[a % n_in], out[b], out[(b + 1) % n_out]);
        ++b;
        if (n_in == 1 && b == n_out) a = n_in;
      }
    }
  }
  Mesh m;
  m.V.resize(static_cast<int>(points.size()), 3);
  for (int v = 0; v < m.num_vertices(); ++v) m.V.row(v) = points[v];
  m.F.resize(static_cast<int>(faces.size()), 3);
  for (int f = 0; f < m.num_faces(); ++f) m.F.row(f) = faces[f];
  return m;
}

// Vertices on a boundary edge.
std::vector<bool> on_boundary(const Mesh& m) {
  std::vector<bool> result(m.num_vertices(), false);
  for (const auto& loop : boundary_loops(m.F)) {
    for (int v : loop) result[v] = true;
  }
  return result;
}

double max_row_sum_error(const Eigen::SparseMatrix<double>& S) {
  const Eigen::VectorXd sums = S * Eigen::VectorXd::Ones(S.cols());
  return (sums.array() - 1.0).abs().maxCoeff();
}

TEST(MeshSubdivide, CountsAndFaceLayout) {
  for (const Mesh& m : {grid(4, 3), icosahedron(), disk(3)}) {
    const EdgeTopology topo = edge_topology(m.F);
    const Subdivision s = loop_subdivide(m);
    ASSERT_EQ(s.mesh.num_faces(), 4 * m.num_faces());
    ASSERT_EQ(s.mesh.num_vertices(), m.num_vertices() + topo.num_edges());
    ASSERT_EQ(s.S.rows(), s.mesh.num_vertices());
    ASSERT_EQ(s.S.cols(), m.num_vertices());
    for (int f = 0; f < m.num_faces(); ++f) {
      for (int k = 0; k < 3; ++k) {
        // Corner face k keeps old corner k; its second corner is the new vertex of edge k.
        EXPECT_EQ(s.mesh.F(4 * f + k, 0), m.F(f, k));
        EXPECT_EQ(s.mesh.F(4 * f + k, 1), m.num_vertices() + topo.face_edges(f, k));
        EXPECT_EQ(s.mesh.F(4 * f + 3, k), s.mesh.F(4 * f + k, 1));
      }
    }
  }
}

TEST(MeshSubdivide, StencilWeights) {
  // 4 x 4 grid: vertex 12 = (2, 2) is interior with valence 6, vertex 2 = (2, 0) on the boundary.
  const Mesh m = grid(4, 4);
  const Subdivision s = loop_subdivide(m);
  const Eigen::MatrixXd S = s.S;
  EXPECT_DOUBLE_EQ(S(12, 12), 1.0 - 6 * 3.0 / 48.0);  // beta = 3 / (8 n) = 1/16
  for (int n : {7, 11, 13, 17, 6, 18}) EXPECT_DOUBLE_EQ(S(12, n), 1.0 / 16.0) << n;
  EXPECT_DOUBLE_EQ(S.row(12).sum(), 1.0);
  EXPECT_DOUBLE_EQ(S(2, 2), 0.75);
  EXPECT_DOUBLE_EQ(S(2, 1), 0.125);
  EXPECT_DOUBLE_EQ(S(2, 3), 0.125);
  EXPECT_EQ(S(2, 7), 0.0);  // interior neighbours do not pull on the boundary
  EXPECT_EQ(S(2, 8), 0.0);
  // Face 20 = (12, 13, 18); the face across (12, 13) is 13 = (7, 13, 12).
  const int mid = s.mesh.F(4 * 20, 1);
  EXPECT_DOUBLE_EQ(S(mid, 12), 0.375);
  EXPECT_DOUBLE_EQ(S(mid, 13), 0.375);
  EXPECT_DOUBLE_EQ(S(mid, 18), 0.125);
  EXPECT_DOUBLE_EQ(S(mid, 7), 0.125);
  EXPECT_EQ((S.row(mid).array() != 0.0).count(), 4);
  // Face 0 = (0, 1, 6): edge (0, 1) is on the boundary, its new vertex is the midpoint.
  const int boundary_mid = s.mesh.F(0, 1);
  EXPECT_DOUBLE_EQ(S(boundary_mid, 0), 0.5);
  EXPECT_DOUBLE_EQ(S(boundary_mid, 1), 0.5);
  EXPECT_EQ((S.row(boundary_mid).array() != 0.0).count(), 2);

  // Closed tetrahedron: valence 3 uses beta = 3/16.
  Mesh t;
  t.V = Eigen::MatrixXd::Identity(4, 3);
  t.F.resize(4, 3);
  t.F << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  const Eigen::MatrixXd St = loop_subdivide(t).S;
  EXPECT_DOUBLE_EQ(St(0, 0), 1.0 - 9.0 / 16.0);
  EXPECT_DOUBLE_EQ(St(0, 3), 3.0 / 16.0);
}

TEST(MeshSubdivide, RowsSumToOneAndSCarriesFields) {
  Mesh m = disk(4);
  std::mt19937 rng(3);
  std::normal_distribution<double> z(0.0, 0.1);
  for (int v = 0; v < m.num_vertices(); ++v) m.V(v, 2) = z(rng);
  const Subdivision s = loop_subdivide_to(m, 16 * m.num_faces());
  ASSERT_EQ(s.mesh.num_faces(), 16 * m.num_faces());
  EXPECT_LT(max_row_sum_error(s.S), 1e-14);
  for (int k = 0; k < s.S.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(s.S, k); it; ++it) {
      EXPECT_GE(it.value(), 0.0);  // Loop weights are convex for every valence
    }
  }
  // The composed matrix gives the positions the two steps gave.
  EXPECT_LT((s.S * m.V - s.mesh.V).cwiseAbs().maxCoeff(), 1e-14);
  // A linear field (a x + b y + c z + d) is carried along exactly, since rows sum to 1.
  const Eigen::VectorXd field =
      m.V * Eigen::Vector3d(0.3, -1.2, 2.0) + Eigen::VectorXd::Constant(m.num_vertices(), 5.0);
  const Eigen::VectorXd expected = s.mesh.V * Eigen::Vector3d(0.3, -1.2, 2.0) +
                                   Eigen::VectorXd::Constant(s.mesh.num_vertices(), 5.0);
  EXPECT_LT((s.S * field - expected).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(MeshSubdivide, PlanarMeshStaysInItsPlane) {
  // A disk with randomly moved interior vertices, put in a tilted plane far from the origin.
  Mesh m = disk(5);
  const std::vector<bool> boundary = on_boundary(m);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> shift(-0.03, 0.03);  // a fifth of the ring spacing
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (boundary[v]) continue;
    m.V(v, 0) += shift(rng);
    m.V(v, 1) += shift(rng);
  }
  const Eigen::Vector3d normal = Eigen::Vector3d(1.0, -2.0, 3.0).normalized();
  const Eigen::Vector3d e1 = normal.unitOrthogonal(), e2 = normal.cross(e1);
  const Eigen::Vector3d origin(40.0, -25.0, 10.0);
  const double size = 30.0;  // mm
  Mesh tilted = m;
  for (int v = 0; v < m.num_vertices(); ++v) {
    tilted.V.row(v) = (origin + size * (m.V(v, 0) * e1 + m.V(v, 1) * e2)).transpose();
  }
  const Subdivision s = loop_subdivide_to(tilted, 16 * m.num_faces());
  double off_plane = 0.0;
  for (int v = 0; v < s.mesh.num_vertices(); ++v) {
    off_plane = std::max(off_plane, std::abs(normal.dot(s.mesh.V.row(v).transpose() - origin)));
  }
  EXPECT_LT(off_plane, 1e-12 * size);
  const MeshDiagnosis d = diagnose_mesh(s.mesh);
  EXPECT_TRUE(d.is_disk());
  EXPECT_EQ(d.euler_characteristic, 1);
}

TEST(MeshSubdivide, BoundaryFollowsTheBoundaryCurveRule) {
  // Planar polygon: the boundary is refined on its own as a cubic B-spline, whatever the inside:
  // new edge points are midpoints (on the coarse polyline), old points (p- + 6 p + p+) / 8, so a
  // point between two collinear neighbours stays on the polyline and corners are cut.
  Mesh m = disk(3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> shift(-0.05, 0.05);
  for (int v = 0; v < m.num_vertices(); ++v) {
    m.V(v, 0) += shift(rng);
    m.V(v, 1) += shift(rng);
  }
  const Subdivision s = loop_subdivide(m);
  const std::vector<int> coarse = boundary_loops(m.F).at(0);
  const std::vector<int> fine = boundary_loops(s.mesh.F).at(0);
  ASSERT_EQ(fine.size(), 2 * coarse.size());
  // Loops start at their smallest vertex; old vertices keep their indices and come first.
  const int n = static_cast<int>(coarse.size());
  for (int i = 0; i < n; ++i) {
    const Eigen::RowVector3d prev = m.V.row(coarse[(i + n - 1) % n]), p = m.V.row(coarse[i]),
                             next = m.V.row(coarse[(i + 1) % n]);
    EXPECT_EQ(fine[2 * i], coarse[i]);
    EXPECT_LT((s.mesh.V.row(fine[2 * i]) - (prev + 6 * p + next) / 8).norm(), 1e-15);
    EXPECT_LT((s.mesh.V.row(fine[2 * i + 1]) - (p + next) / 2).norm(), 1e-15);
  }
  // Only coarse boundary vertices enter the rows of fine boundary vertices.
  const std::vector<bool> coarse_boundary = on_boundary(m);
  for (int v : fine) {
    for (int c = 0; c < m.num_vertices(); ++c) {
      if (!coarse_boundary[c]) {
        EXPECT_EQ(s.S.coeff(v, c), 0.0) << v << " " << c;
      }
    }
  }
  // On a straight side (the bottom of a grid) boundary points stay on the side; the corner
  // (0, 0) is cut to (1/8, 1/8).
  const Subdivision g = loop_subdivide(grid(3, 2));
  const std::vector<int> grid_boundary = boundary_loops(g.mesh.F).at(0);
  for (int v : grid_boundary) {
    const Eigen::RowVector3d x = g.mesh.V.row(v);
    const bool on_side = std::abs(x.y()) < 1e-15 || std::abs(x.y() - 2) < 1e-15 ||
                         std::abs(x.x()) < 1e-15 || std::abs(x.x() - 3) < 1e-15;
    EXPECT_TRUE(on_side || v == 0 || v == 3 || v == 8 || v == 11) << v << ": " << x;
  }
  EXPECT_LT((g.mesh.V.row(0) - Eigen::RowVector3d(0.125, 0.125, 0)).norm(), 1e-15);
}

TEST(MeshSubdivide, IcosahedronConvergesToARoundSurface) {
  // An icosahedron on the unit sphere. With Warren's weights (n beta = 3/8 for n > 3), a vertex p
  // whose 1-ring is symmetric and the mean q of that ring evolve by [[5/8, 3/8], [3/8, 5/8]]
  // (eigenvalues 1 and 1/4): p tends to (p + q)/2 and the rest decays by 4 per step. The ring
  // of an icosahedron vertex lies at height 1/sqrt(5), so the limit radius of the 12 original
  // vertices is (1 + 1/sqrt(5))/2 = 0.7236: the limit surface is smaller than the sphere, and
  // roundness is measured against the best centred sphere, radius (min + max)/2.
  const double r_limit = (1.0 + 1.0 / std::sqrt(5.0)) / 2.0;
  const double R = 40.0;  // mm
  Mesh m = icosahedron();
  m.V.rowwise().normalize();
  m.V *= R;
  std::vector<double> roundness;
  for (int step = 0; step <= 3; ++step) {
    // Exact radius of the original vertex 0 after `step` steps.
    EXPECT_NEAR(m.V.row(0).norm() / R, r_limit + (1.0 - r_limit) * std::pow(0.25, step), 1e-13);
    // The surface: its vertices and the centres of its faces, farthest from the sphere.
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (int v = 0; v < m.num_vertices(); ++v) {
      lo = std::min(lo, m.V.row(v).norm());
      hi = std::max(hi, m.V.row(v).norm());
    }
    for (int f = 0; f < m.num_faces(); ++f) {
      const double r =
          ((m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))) / 3.0).norm();
      lo = std::min(lo, r);
      hi = std::max(hi, r);
    }
    roundness.push_back((hi - lo) / (hi + lo));  // max | |x| - R_fit | / R_fit
    m = loop_subdivide(m).mesh;
  }
  // Measured: 0.1144 (the flat faces of the icosahedron), 0.0489, 0.0229, 0.0172; the limit
  // surface (7 steps) deviates 1.504 %, and the excess over it shrinks by ~4 per step (the chord
  // error of flat faces, quadratic in the edge length). After 3 steps: 1.504 % + 0.2 % = 1.7 %.
  for (int step = 1; step <= 3; ++step) EXPECT_LT(roundness[step], roundness[step - 1]) << step;
  // Before any step: vertices at the circumradius, face centres at the inradius.
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  const double in_over_circum = phi * phi / (std::sqrt(3.0) * std::sqrt(phi * phi + 1.0));
  EXPECT_NEAR(roundness[0], (1.0 - in_over_circum) / (1.0 + in_over_circum), 1e-12);
  EXPECT_LT(roundness[3], 0.0180);
  EXPECT_GT(roundness[3], 0.0150);  // no rounder than the limit surface
}

// A disk mapped onto a sphere of radius R (polar angle up to 60 degrees, geodesic rings).
Mesh spherical_cap(double R, int rings) {
  const double cap = std::numbers::pi / 3.0;
  Mesh m = disk(rings);
  for (int v = 0; v < m.num_vertices(); ++v) {
    const double rho = std::hypot(m.V(v, 0), m.V(v, 1));
    const double theta = rho * cap, phi = std::atan2(m.V(v, 1), m.V(v, 0));
    m.V.row(v) << R * std::sin(theta) * std::cos(phi), R * std::sin(theta) * std::sin(phi),
        R * std::cos(theta);
  }
  return m;
}

// max | |x| - R | / R over the vertices after each of `steps` subdivision steps.
std::vector<double> sphere_deviation(Mesh m, double R, int steps) {
  std::vector<double> result;
  for (int step = 1; step <= steps; ++step) {
    m = loop_subdivide(m).mesh;
    double deviation = 0.0;
    for (int v = 0; v < m.num_vertices(); ++v) {
      deviation = std::max(deviation, std::abs(m.V.row(v).norm() - R) / R);
    }
    result.push_back(deviation);
  }
  return result;
}

TEST(MeshSubdivide, SphericalCapStaysOnItsSphere) {
  const double R = 50.0;
  const Mesh m = spherical_cap(R, 6);
  // The largest angle a coarse edge subtends at the centre.
  double alpha = 0.0;
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = m.V.row(m.F(f, k)), b = m.V.row(m.F(f, (k + 1) % 3));
      alpha = std::max(alpha, std::acos(std::clamp(a.dot(b) / (R * R), -1.0, 1.0)));
    }
  }
  // A vertex tends to the mean of itself and its ring (see the icosahedron test), so a ring at
  // angle alpha puts it (1 - cos alpha)/2 inside the sphere (2.2 % here); a boundary vertex tends
  // to the B-spline limit (prev + 4 p + next)/6, which moves less. Measured: 1.00, 1.16, 1.19 %,
  // converging by a factor 4 per step to 1.2 %.
  const double bound = (1.0 - std::cos(alpha)) / 2.0;
  const std::vector<double> coarse = sphere_deviation(m, R, 3);
  for (int step = 0; step < 3; ++step) EXPECT_LT(coarse[step], bound) << "step " << step + 1;
  EXPECT_NEAR(coarse[2] - coarse[1], (coarse[1] - coarse[0]) / 4.0, 0.2 * (coarse[1] - coarse[0]));
  // The shrinkage is quadratic in the edge length: twice the rings, a quarter of the deviation.
  const std::vector<double> fine = sphere_deviation(spherical_cap(R, 12), R, 3);
  EXPECT_NEAR(fine[2] / coarse[2], 0.25, 0.03);
}

TEST(MeshSubdivide, ToReachesTheFaceCountInTheFewestSteps) {
  const Mesh ico = icosahedron();
  const std::vector<std::pair<int, int>> cases{{1, 20},    {20, 20},    {21, 80},
                                               {320, 320}, {321, 1280}, {1280, 1280}};
  for (const auto& [wanted, faces] : cases) {
    const Subdivision s = loop_subdivide_to(ico, wanted);
    EXPECT_EQ(s.mesh.num_faces(), faces) << wanted;
    EXPECT_EQ(s.S.cols(), 12);
    EXPECT_EQ(s.S.rows(), s.mesh.num_vertices());
  }
  const Subdivision none = loop_subdivide_to(ico, 20);
  EXPECT_EQ(none.mesh.V, ico.V);
  EXPECT_EQ(none.mesh.F, ico.F);
  EXPECT_EQ(Eigen::MatrixXd(none.S), Eigen::MatrixXd::Identity(12, 12));
  // The paper's hemisphere: 1072 faces subdivided twice to 17152.
  const Subdivision hemi = loop_subdivide_to(grid(8, 67), 17152);
  EXPECT_EQ(hemi.mesh.num_faces(), 17152);
  // No faces: nothing to refine, and no endless loop.
  Mesh empty;
  empty.V = Eigen::MatrixXd::Zero(2, 3);
  empty.F.resize(0, 3);
  EXPECT_EQ(loop_subdivide_to(empty, 100).mesh.num_faces(), 0);
}

}  // namespace
}  // namespace flatmorph::subdivide_test
