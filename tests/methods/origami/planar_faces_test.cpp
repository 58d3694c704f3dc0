// From a triangle mesh to a solid of at most N planar faces (issue 27, item 1; notes §6 Step 1):
// a finely triangulated cube gives back its six squares, a fine sphere simplifies within budget
// and keeps its volume, a turned mesh gives the turned solid, planar regions that would have a
// hole are split, an open mesh keeps its border, bad meshes are refused by name, and the bunny.
#include "methods/origami/planar_faces.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <set>

#include "common/error.h"
#include "examples/bunny.h"
#include "examples/origami_examples.h"
#include "methods/origami/unfold.h"

namespace flatmorph::planar_faces_test {
namespace {

Mesh from_lists(const std::vector<Eigen::Vector3d>& points,
                const std::vector<std::array<int, 3>>& triangles) {
  Mesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i) mesh.V.row(Eigen::Index(i)) = points[i].transpose();
  mesh.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) mesh.F(Eigen::Index(t), k) = triangles[t][k];
  }
  return mesh;
}

// The cube [−h, h]³, each side an n × n grid of squares, each square split along a diagonal
// chosen by a fixed pseudo-random sequence; outward.
Mesh fine_cube(int n, double h) {
  std::vector<Eigen::Vector3d> points;
  std::map<std::array<long long, 3>, int> index;  // welds the sides' shared grid points
  const auto point = [&](const Eigen::Vector3d& p) {
    const std::array<long long, 3> key{std::llround(p.x() * 1e6), std::llround(p.y() * 1e6),
                                       std::llround(p.z() * 1e6)};
    const auto [it, added] = index.emplace(key, int(points.size()));
    if (added) points.push_back(p);
    return it->second;
  };
  std::vector<std::array<int, 3>> triangles;
  unsigned state = 12345;
  for (int axis = 0; axis < 3; ++axis) {
    for (double side : {-1.0, 1.0}) {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero(), u = Eigen::Vector3d::Zero();
      normal(axis) = side;
      u((axis + 1) % 3) = 1;
      const Eigen::Vector3d v = normal.cross(u);  // u, v, normal right-handed: CCW outside
      const auto at = [&](int i, int j) {
        return point(h * (normal + (2.0 * i / n - 1) * u + (2.0 * j / n - 1) * v));
      };
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
          state = state * 1103515245u + 12345u;
          if ((state >> 16) & 1) {
            triangles.push_back({a, b, c});
            triangles.push_back({a, c, d});
          } else {
            triangles.push_back({a, b, d});
            triangles.push_back({b, c, d});
          }
        }
      }
    }
  }
  return from_lists(points, triangles);
}

// The icosahedron with each triangle split in four `levels` times, on the sphere of `radius`.
Mesh icosphere(int levels, double radius) {
  const double phi = std::numbers::phi;
  std::vector<Eigen::Vector3d> points;
  for (double s : {-1.0, 1.0}) {
    for (double t : {-phi, phi}) {
      points.emplace_back(0, s, t);
      points.emplace_back(s, t, 0);
      points.emplace_back(t, 0, s);
    }
  }
  std::vector<std::array<int, 3>> triangles;
  for (int a = 0; a < 12; ++a) {
    for (int b = a + 1; b < 12; ++b) {
      for (int c = b + 1; c < 12; ++c) {
        const auto edge = [&](int i, int j) {
          return std::abs((points[i] - points[j]).norm() - 2) < 1e-9;
        };
        if (!edge(a, b) || !edge(b, c) || !edge(a, c)) continue;
        const bool outward =
            (points[b] - points[a]).cross(points[c] - points[a]).dot(points[a]) > 0;
        triangles.push_back(outward ? std::array<int, 3>{a, b, c} : std::array<int, 3>{a, c, b});
      }
    }
  }
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> middle;
    const auto mid = [&](int a, int b) {
      const auto [it, added] = middle.emplace(std::minmax(a, b), int(points.size()));
      if (added) points.push_back(0.5 * (points[a] + points[b]));
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& [a, b, c] : triangles) {
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      finer.push_back({a, ab, ca});
      finer.push_back({b, bc, ab});
      finer.push_back({c, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    triangles = finer;
  }
  for (Eigen::Vector3d& p : points) p = radius * p.normalized();
  return from_lists(points, triangles);
}

// A lumpy egg without symmetries, so that no two edge collapses cost the same.
Mesh lumpy(int levels) {
  Mesh mesh = icosphere(levels, 1);
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    const Eigen::Vector3d p = mesh.V.row(v).transpose();
    const double r = 1 + 0.15 * std::sin(3 * p.x() + 1) * std::cos(2 * p.y()) + 0.1 * p.z() * p.z();
    mesh.V.row(v) = (r * Eigen::Vector3d(30, 22, 25).cwiseProduct(p)).transpose();
  }
  return mesh;
}

double diagonal(const Eigen::MatrixX3d& V) {
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

// By the divergence theorem over each face's fan of triangles.
double enclosed_volume(const Polyhedron& solid) {
  double volume = 0;
  for (const std::vector<int>& face : solid.faces) {
    const Eigen::Vector3d a = solid.V.row(face[0]).transpose();
    for (size_t i = 1; i + 1 < face.size(); ++i) {
      volume += a.dot(solid.V.row(face[i]).transpose().cross(solid.V.row(face[i + 1]).transpose()));
    }
  }
  return volume / 6;
}

// Every face planar within 0.5 % of its diameter, checked about the plane of its first corner
// and its Newell normal.
void expect_planar(const Polyhedron& solid) {
  for (size_t f = 0; f < solid.faces.size(); ++f) {
    const Eigen::Vector3d n = face_normal(solid, int(f));
    const Eigen::Vector3d p = solid.V.row(solid.faces[f][0]).transpose();
    double diameter = 0, off = 0;
    for (int v : solid.faces[f]) {
      off = std::max(off, std::abs(n.dot(solid.V.row(v).transpose() - p)));
      for (int u : solid.faces[f]) {
        diameter = std::max(diameter, (solid.V.row(u) - solid.V.row(v)).norm());
      }
    }
    EXPECT_LE(off, 0.01 * diameter) << solid.source << " face " << f;
  }
}

// Each face seen from outside turns counter-clockwise: its Newell normal points away from the
// solid's inside, tested on a convex solid against its centre.
void expect_outward(const Polyhedron& solid) {
  const Eigen::Vector3d centre = solid.V.colwise().mean().transpose();
  for (size_t f = 0; f < solid.faces.size(); ++f) {
    const Eigen::Vector3d p = solid.V.row(solid.faces[f][0]).transpose();
    EXPECT_GT(face_normal(solid, int(f)).dot(p - centre), 0) << solid.source << " face " << f;
  }
}

bool closed(const Polyhedron& solid) {
  for (const PolyhedronEdge& e : polyhedron_edges(solid)) {
    if (e.right < 0) return false;
  }
  return true;
}

TEST(PlanarFaces, AFinelyTriangulatedCubeGivesBackItsSixSquares) {
  const Mesh mesh = fine_cube(4, 10);
  ASSERT_EQ(mesh.num_faces(), 6 * 4 * 4 * 2);
  const Polyhedron solid = planar_faces(mesh, "cube");
  ASSERT_EQ(solid.faces.size(), 6u);
  ASSERT_EQ(solid.V.rows(), 8);
  for (Eigen::Index v = 0; v < 8; ++v) {
    EXPECT_NEAR(solid.V.row(v).cwiseAbs().minCoeff(), 10, 1e-12) << "a corner of the cube";
  }
  for (const std::vector<int>& face : solid.faces) EXPECT_EQ(face.size(), 4u);
  const std::vector<PolyhedronEdge> edges = polyhedron_edges(solid);
  ASSERT_EQ(edges.size(), 12u);
  for (const PolyhedronEdge& e : edges) {
    EXPECT_NEAR((solid.V.row(e.v0) - solid.V.row(e.v1)).norm(), 20, 1e-12);
    EXPECT_NEAR(fold_angle(solid, e), -kPi / 2, 1e-12);  // convex: a mountain (notes §3)
  }
  expect_outward(solid);
}

TEST(PlanarFaces, AnIcosphereSimplifiesToAtMost70FacesKeepingItsVolume) {
  const double radius = 30;
  const Mesh mesh = icosphere(3, radius);
  ASSERT_EQ(mesh.num_faces(), 1280);
  std::vector<std::string> notes;
  const Polyhedron solid = planar_faces(mesh, "sphere", {}, &notes);
  EXPECT_LE(solid.faces.size(), 70u);
  EXPECT_GE(solid.faces.size(), 60u) << "the budget is used, not thrown away";
  EXPECT_TRUE(closed(solid));
  const int num_edges = static_cast<int>(polyhedron_edges(solid).size());
  EXPECT_EQ(solid.V.rows() - num_edges + static_cast<int>(solid.faces.size()), 2) << "a sphere";
  expect_planar(solid);
  expect_outward(solid);
  // Garland–Heckbert places the vertices a little outside (the quadric's minimum over a cap of
  // the sphere), so 70 faces keep more of the volume than the 80 triangles of the geodesic sphere
  // with its vertices on the surface (87.4 %); measured 92.9 %.
  const double sphere = 4.0 / 3 * kPi * std::pow(radius, 3);
  const Mesh geodesic = icosphere(1, radius);
  ASSERT_EQ(geodesic.num_faces(), 80);
  Polyhedron inscribed;
  inscribed.V = geodesic.V;
  for (Eigen::Index t = 0; t < geodesic.F.rows(); ++t) {
    inscribed.faces.push_back({geodesic.F(t, 0), geodesic.F(t, 1), geodesic.F(t, 2)});
  }
  EXPECT_GT(enclosed_volume(solid), enclosed_volume(inscribed));
  EXPECT_NEAR(enclosed_volume(solid) / sphere, 1, 0.08);
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes[0].find("1280 triangles"), std::string::npos) << notes[0];
}

TEST(PlanarFaces, ATetrahedronStaysItself) {
  const Polyhedron tetra = polyhedron_example("tetrahedron", 25);
  Mesh mesh;
  mesh.V = tetra.V;
  mesh.F.resize(4, 3);
  for (int f = 0; f < 4; ++f) {
    for (int k = 0; k < 3; ++k) mesh.F(f, k) = tetra.faces[f][k];
  }
  const Polyhedron solid = planar_faces(mesh, "tetrahedron");
  EXPECT_TRUE(solid.V.isApprox(tetra.V, 0));
  ASSERT_EQ(solid.faces.size(), 4u);
  for (const PolyhedronEdge& e : polyhedron_edges(solid)) {
    EXPECT_NEAR(fold_angle(solid, e), -(kPi - std::acos(1.0 / 3)), 1e-12);
  }
}

TEST(PlanarFaces, ATurnedMeshGivesTheTurnedSolid) {
  const Mesh mesh = lumpy(3);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  Mesh turned = mesh;
  turned.V = mesh.V * R.transpose();
  PlanarFacesOptions options;
  options.max_faces = 40;
  const Polyhedron a = planar_faces(mesh, "lumpy", options);
  const Polyhedron b = planar_faces(turned, "lumpy turned", options);
  ASSERT_EQ(a.faces.size(), b.faces.size());
  ASSERT_EQ(a.V.rows(), b.V.rows());
  EXPECT_LE(a.faces.size(), 40u);
  EXPECT_LT((a.V * R.transpose() - b.V).cwiseAbs().maxCoeff(), 1e-9 * diagonal(a.V));
  EXPECT_EQ(a.faces, b.faces);
}

// A flat square plate whose middle square rises into a pyramid: the eight flat squares around it
// are coplanar but form a ring, which no simple polygon can be, so they are split.
TEST(PlanarFaces, ACoplanarRingIsSplitIntoSimplePolygons) {
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j <= 3; ++j) {
    for (int i = 0; i <= 3; ++i) points.emplace_back(10.0 * i, 10.0 * j, 0);
  }
  points.emplace_back(15, 15, 8);  // the apex, 16
  std::vector<std::array<int, 3>> triangles;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      const int a = 4 * j + i, b = a + 1, c = a + 5, d = a + 4;
      if (i == 1 && j == 1) {
        for (const auto& [p, q] : {std::pair{a, b}, {b, c}, {c, d}, {d, a}}) {
          triangles.push_back({p, q, 16});
        }
      } else {
        triangles.push_back({a, b, c});
        triangles.push_back({a, c, d});
      }
    }
  }
  const Polyhedron solid = planar_faces(from_lists(points, triangles), "ring");
  int flat = 0;
  for (size_t f = 0; f < solid.faces.size(); ++f) {
    const std::vector<int>& face = solid.faces[f];
    EXPECT_EQ(std::set<int>(face.begin(), face.end()).size(), face.size()) << "a corner twice";
    if (std::abs(face_normal(solid, int(f)).z()) > 1 - 1e-12) ++flat;
  }
  EXPECT_GE(flat, 2);
  EXPECT_EQ(solid.faces.size(), 4u + flat);
  double area = 0;  // the flat faces still cover the ring: 900 − 100 mm²
  for (size_t f = 0; f < solid.faces.size(); ++f) {
    if (std::abs(face_normal(solid, int(f)).z()) < 1 - 1e-12) continue;
    const std::vector<int>& face = solid.faces[f];
    for (size_t i = 0; i < face.size(); ++i) {
      const Eigen::Vector3d p = solid.V.row(face[i]).transpose();
      const Eigen::Vector3d q = solid.V.row(face[(i + 1) % face.size()]).transpose();
      area += 0.5 * p.cross(q).z();
    }
  }
  EXPECT_NEAR(area, 800, 1e-9);
  double outline = 0;  // the plate's, 4 × 30 mm
  for (const PolyhedronEdge& e : polyhedron_edges(solid)) {
    if (e.right < 0) outline += (solid.V.row(e.v0) - solid.V.row(e.v1)).norm();
  }
  EXPECT_NEAR(outline, 120, 1e-9);
}

// An open dome (the upper half of a fine sphere, cut along its edges): simplified, its border
// stays a cut through the mesh's own border vertices.
TEST(PlanarFaces, AnOpenMeshKeepsItsBorderAsCuts) {
  const Mesh sphere = icosphere(3, 20);
  std::vector<std::array<int, 3>> upper;
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index t = 0; t < sphere.F.rows(); ++t) {
    bool above = true;
    for (int k = 0; k < 3; ++k) above = above && sphere.V(sphere.F(t, k), 2) > -1e-9;
    if (!above) continue;
    upper.push_back({sphere.F(t, 0), sphere.F(t, 1), sphere.F(t, 2)});
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(sphere.F(t, k), sphere.F(t, (k + 1) % 3))];
  }
  std::vector<Eigen::Vector3d> rim;  // the dome's border vertices
  for (const auto& [edge, count] : uses) {
    if (count > 1) continue;
    rim.push_back(sphere.V.row(edge.first).transpose());
    rim.push_back(sphere.V.row(edge.second).transpose());
  }
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index v = 0; v < sphere.V.rows(); ++v) points.push_back(sphere.V.row(v).transpose());
  PlanarFacesOptions options;
  options.max_faces = 30;
  const Polyhedron solid = planar_faces(from_lists(points, upper), "dome", options);
  EXPECT_LE(solid.faces.size(), 30u);
  expect_planar(solid);
  int border = 0;
  for (const PolyhedronEdge& e : polyhedron_edges(solid)) {
    if (e.right >= 0) continue;
    ++border;
    double nearest = 1e9;
    for (const Eigen::Vector3d& p : rim) {
      nearest = std::min(nearest, (solid.V.row(e.v0).transpose() - p).norm());
    }
    EXPECT_EQ(nearest, 0) << "a border corner left the mesh's border";
  }
  EXPECT_GE(border, 3);
}

TEST(PlanarFaces, AnInwardClosedMeshIsTurnedOutward) {
  Mesh mesh = icosphere(1, 10);
  mesh.F.col(1).swap(mesh.F.col(2));
  std::vector<std::string> notes;
  const Polyhedron solid = planar_faces(mesh, "inside out", {}, &notes);
  EXPECT_GT(enclosed_volume(solid), 0);
  expect_outward(solid);
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes[0].find("inward"), std::string::npos) << notes[0];
}

// The message of the UserError `mesh` raises, checked for its category.
std::string refusal(const Mesh& mesh, ErrorCategory category, int max_faces = 70) {
  PlanarFacesOptions options;
  options.max_faces = max_faces;
  try {
    planar_faces(mesh, "bad.obj", options);
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), category) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no UserError";
  return "";
}

Mesh tetrahedron_mesh() {
  return from_lists({{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}},
                    {{{0, 2, 1}}, {{0, 1, 3}}, {{0, 3, 2}}, {{1, 2, 3}}});
}

TEST(PlanarFaces, BadMeshesAreRefusedNamingTheirTriangles) {
  Mesh fin = tetrahedron_mesh();  // a third triangle on edge 1-2
  fin.V.conservativeResize(5, 3);
  fin.V.row(4) << 10, 10, 10;
  fin.F.conservativeResize(5, 3);
  fin.F.row(4) << 1, 4, 2;
  EXPECT_NE(
      refusal(fin, ErrorCategory::kTopology).find("edge 1-2 is shared by triangles 0, 3 and 4"),
      std::string::npos);

  Mesh flipped = tetrahedron_mesh();
  flipped.F.row(3) << 1, 3, 2;
  const std::string orientation = refusal(flipped, ErrorCategory::kTopology);
  EXPECT_NE(orientation.find("triangles 0 and 3 run their shared edge 1-2 the same way"),
            std::string::npos)
      << orientation;

  Mesh sliver = tetrahedron_mesh();  // triangle 1's corners on one line
  sliver.V.row(3) << 5, 0, 0;
  EXPECT_NE(refusal(sliver, ErrorCategory::kGeometry).find("triangle 1 has zero area"),
            std::string::npos);

  Mesh pinched = tetrahedron_mesh();  // a second tetrahedron touching the first at vertex 3
  pinched.V.conservativeResize(7, 3);
  pinched.V.bottomRows(3) << 0, 0, 20, 10, 0, 20, 0, 10, 20;
  pinched.F.conservativeResize(8, 3);
  pinched.F.bottomRows(4) << 3, 5, 4, 3, 4, 6, 3, 6, 5, 4, 5, 6;
  EXPECT_NE(refusal(pinched, ErrorCategory::kTopology).find("vertex 3"), std::string::npos);

  EXPECT_NE(refusal(tetrahedron_mesh(), ErrorCategory::kOption, 3).find("at least 4"),
            std::string::npos);
}

// A ring torus, 12 × 8 quadrilaterals each split in two, outward.
Mesh torus() {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  const int nu = 12, nv = 8;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      points.emplace_back((20 + 8 * std::cos(v)) * std::cos(u),
                          (20 + 8 * std::cos(v)) * std::sin(u), 8 * std::sin(v));
      const auto at = [&](int a, int b) { return (a % nu) * nv + b % nv; };
      triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return from_lists(points, triangles);
}

// A torus cannot shrink to a tetrahedron: the message says how many faces it can have, and that
// many work.
TEST(PlanarFaces, ATooSmallBudgetForAHoledSolidSaysWhatIsPossible) {
  const std::string message = refusal(torus(), ErrorCategory::kInfeasible, 4);
  const auto at = message.find("allow at least ");
  ASSERT_NE(at, std::string::npos) << message;
  PlanarFacesOptions options;
  options.max_faces = std::stoi(message.substr(at + 15));
  EXPECT_GT(options.max_faces, 4);
  const Polyhedron solid = planar_faces(torus(), "torus", options);
  EXPECT_LE(static_cast<int>(solid.faces.size()), options.max_faces);
  const int num_edges = static_cast<int>(polyhedron_edges(solid).size());
  EXPECT_EQ(solid.V.rows() - num_edges + static_cast<int>(solid.faces.size()), 0) << "a torus";
}

// The number of separate loops in which the plane z = height cuts the solid: faces crossing it,
// joined through the edges that cross it.
int cross_sections(const Polyhedron& solid, double height) {
  std::vector<int> label(solid.faces.size());
  std::iota(label.begin(), label.end(), 0);
  const auto find = [&](int f) {
    while (label[f] != f) f = label[f] = label[label[f]];
    return f;
  };
  std::set<int> crossing;
  for (const PolyhedronEdge& e : polyhedron_edges(solid)) {
    if ((solid.V(e.v0, 2) - height) * (solid.V(e.v1, 2) - height) >= 0) continue;
    crossing.insert(e.left);
    crossing.insert(e.right);
    label[find(e.left)] = find(e.right);
  }
  std::set<int> loops;
  for (int f : crossing) loops.insert(find(f));
  return static_cast<int>(loops.size());
}

// The acceptance: a bunny of at most 70 faces, designed (here: made and unfolded) in
// under 10 s; it stands 80 mm tall on a flat base, and above its head the two ears stand apart.
TEST(Bunny, IsAClosedSolidOfAtMost70PlanarFacesWithTwoEarsThatUnfolds) {
  const auto start = std::chrono::steady_clock::now();
  const Mesh mesh = bunny_mesh();
  const Polyhedron bunny = low_poly_bunny_solid();
  const Unfolding nets = unfold(bunny);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("seconds", std::to_string(seconds));
  EXPECT_LT(seconds, 10);
  EXPECT_GT(mesh.num_faces(), 1000);
  EXPECT_LE(bunny.faces.size(), 70u);
  EXPECT_TRUE(closed(bunny));
  expect_planar(bunny);
  EXPECT_GT(enclosed_volume(bunny), 0);
  const double height = bunny.V.col(2).maxCoeff() - bunny.V.col(2).minCoeff();
  EXPECT_NEAR(height, 80, 2);
  bool base = false;
  for (size_t f = 0; f < bunny.faces.size(); ++f) {
    base = base || face_normal(bunny, int(f)).z() < -1 + 1e-6;
  }
  EXPECT_TRUE(base) << "a flat face to sit on";
  EXPECT_EQ(cross_sections(bunny, 0.3 * height), 1) << "the body";
  EXPECT_EQ(cross_sections(bunny, 0.85 * height), 2) << "the ears";
  int laid = 0;
  for (int n = 0; n < static_cast<int>(nets.nets.size()); ++n) {
    EXPECT_TRUE(net_overlaps(nets, n).empty()) << "net " << n;
    laid += static_cast<int>(nets.nets[n].faces.size());
  }
  EXPECT_EQ(laid, static_cast<int>(bunny.faces.size()));
}

// The issue asks for the whole bunny design in under 10 s; Step 1 on a 5120-triangle mesh is a
// small part of it.
TEST(PlanarFaces, FiveThousandTrianglesSimplifyInWellUnderASecond) {
  const Mesh mesh = lumpy(4);
  ASSERT_EQ(mesh.num_faces(), 5120);
  const auto start = std::chrono::steady_clock::now();
  const Polyhedron solid = planar_faces(mesh, "lumpy");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("seconds", std::to_string(seconds));
  EXPECT_LE(solid.faces.size(), 70u);
  EXPECT_LT(seconds, 1.0);
}

}  // namespace
}  // namespace flatmorph::planar_faces_test
