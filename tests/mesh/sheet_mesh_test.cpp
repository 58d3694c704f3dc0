// The sheet mesh against closed forms (a disc's area, a square's and a lattice's union), its
// invariants (quality, orientation, Euler characteristic, one piece across joined tiles, rotation),
// refusals; and the ring frame against a disc's and a square's distance.
#include "mesh/sheet_mesh.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <utility>
#include <vector>

#include "common/error.h"
#include "mesh/polygon.h"

namespace flatmorph::sheet_mesh_test {
namespace {

// Directions are lines: compare modulo pi.
double angle_difference(double a, double b) { return std::abs(std::remainder(a - b, kPi)); }

// Inside the regular polygon polygon(n, radius, phase).
bool inside_regular(const Eigen::Vector2d& p, int n, double radius, double phase) {
  for (int k = 0; k < n; ++k) {
    const double a = phase + 2 * kPi * (k + 0.5) / n;
    if (p.x() * std::cos(a) + p.y() * std::sin(a) > radius * std::cos(kPi / n)) return false;
  }
  return true;
}

PlaneRegion polygon(int n, double radius, double phase = 0, const char* source = "disc") {
  PlaneRegion t;
  t.boundary.resize(n, 2);
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2 * kPi * i / n;
    t.boundary.row(i) << radius * std::cos(a), radius * std::sin(a);
  }
  t.source = source;
  return t;
}

// Counter-clockwise rectangle [x0, x1] x [y0, y1].
Eigen::MatrixX2d rectangle(double x0, double y0, double x1, double y1) {
  Eigen::MatrixX2d m(4, 2);
  m << x0, y0, x1, y0, x1, y1, x0, y1;
  return m;
}

PlaneRegion square_tile(double x0, double y0, double x1, double y1, const char* source) {
  PlaneRegion t;
  t.boundary = rectangle(x0, y0, x1, y1);
  t.source = source;
  return t;
}

PlaneRegion rotated(const PlaneRegion& t, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  auto turn = [&](const Eigen::MatrixX2d& m) {
    Eigen::MatrixX2d r(m.rows(), 2);
    r.col(0) = c * m.col(0) - s * m.col(1);
    r.col(1) = s * m.col(0) + c * m.col(1);
    return r;
  };
  PlaneRegion out = t;
  out.boundary = turn(t.boundary);
  for (Eigen::MatrixX2d& h : out.holes) h = turn(h);
  return out;
}

double face_area(const SheetMesh& m, Eigen::Index f) {
  const Eigen::Vector2d a = m.V.row(m.F(f, 0)).transpose();
  const Eigen::Vector2d ab = m.V.row(m.F(f, 1)).transpose() - a;
  const Eigen::Vector2d ac = m.V.row(m.F(f, 2)).transpose() - a;
  return (ab.x() * ac.y() - ab.y() * ac.x()) / 2;
}

struct Stats {
  double area = 0;
  std::map<int, double> region_area;
  double min_face_area = 1e300;
  double min_angle_deg = 180;
  double max_edge = 0;
  int edges = 0;
  double boundary_length = 0;  // edges with one face
  int pieces = 0;              // face-connected components
  bool all_referenced = true;
};

Stats stats(const SheetMesh& m) {
  Stats s;
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const double a = face_area(m, f);
    s.area += a;
    s.region_area[m.face_region(f)] += a;
    s.min_face_area = std::min(s.min_face_area, a);
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector2d p = m.V.row(m.F(f, j)).transpose();
      const Eigen::Vector2d q = m.V.row(m.F(f, (j + 1) % 3)).transpose();
      const Eigen::Vector2d r = m.V.row(m.F(f, (j + 2) % 3)).transpose();
      s.max_edge = std::max(s.max_edge, (q - p).norm());
      const double angle =
          std::acos(std::clamp((q - p).normalized().dot((r - p).normalized()), -1.0, 1.0));
      s.min_angle_deg = std::min(s.min_angle_deg, angle * 180 / kPi);
      edge_faces[std::minmax(m.F(f, j), m.F(f, (j + 1) % 3))].push_back(static_cast<int>(f));
    }
  }
  s.edges = static_cast<int>(edge_faces.size());
  std::vector<int> parent(m.F.rows());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& [e, faces] : edge_faces) {
    if (faces.size() == 1) s.boundary_length += (m.V.row(e.first) - m.V.row(e.second)).norm();
    for (size_t k = 1; k < faces.size(); ++k) parent[find(faces[k])] = find(faces[0]);
  }
  for (size_t i = 0; i < parent.size(); ++i)
    s.pieces += find(static_cast<int>(i)) == static_cast<int>(i);
  std::vector<bool> used(m.V.rows(), false);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    for (int j = 0; j < 3; ++j) used[m.F(f, j)] = true;
  }
  s.all_referenced = std::all_of(used.begin(), used.end(), [](bool u) { return u; });
  return s;
}

int close_pairs(const Eigen::MatrixXd& V, double tolerance) {
  std::vector<int> order(V.rows());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return V(a, 0) < V(b, 0); });
  int pairs = 0;
  for (size_t i = 0; i < order.size(); ++i) {
    for (size_t k = i + 1; k < order.size() && V(order[k], 0) - V(order[i], 0) <= tolerance; ++k) {
      pairs += (V.row(order[i]) - V.row(order[k])).norm() <= tolerance;
    }
  }
  return pairs;
}

Eigen::Vector2d face_centroid(const SheetMesh& m, Eigen::Index f) {
  return (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))).transpose() / 3;
}

TEST(SheetMesh, DiscIsCoveredByQualityTrianglesOfBoundedSize) {
  const PlaneRegion disc = polygon(64, 15);
  const SheetMesh m = sheet_mesh({disc}, {});
  const Stats s = stats(m);
  EXPECT_NEAR(s.area, signed_area(disc.boundary), 1e-9 * signed_area(disc.boundary));
  EXPECT_GT(s.min_face_area, 0);  // all counter-clockwise
  EXPECT_GE(s.min_angle_deg, 20.0);
  EXPECT_LE(s.max_edge, 1.0 * (1 + 1e-9));
  EXPECT_EQ(m.V.rows() - s.edges + m.F.rows(), 1);  // a disc
  EXPECT_EQ(s.pieces, 1);
  EXPECT_TRUE(s.all_referenced);
  EXPECT_TRUE((m.face_region.array() == 0).all());
  // The outline's points come first, as given.
  for (int i = 0; i < 64; ++i) {
    EXPECT_EQ(m.V.row(i), disc.boundary.row(i)) << i;
  }
  EXPECT_EQ(close_pairs(m.V, 1e-9), 0);
  std::printf("disc R 15, max_edge 1: %d vertices, %d faces, min angle %.2f deg, max edge %.4f\n",
              static_cast<int>(m.V.rows()), static_cast<int>(m.F.rows()), s.min_angle_deg,
              s.max_edge);
}

TEST(SheetMesh, IsDeterministic) {
  const PlaneRegion disc = polygon(40, 6);
  const SheetMesh a = sheet_mesh({disc}, {});
  const SheetMesh b = sheet_mesh({disc}, {});
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.F, b.F);
  // Faces sorted by region, then centroid x.
  for (Eigen::Index f = 1; f < a.F.rows(); ++f) {
    EXPECT_LE(face_centroid(a, f - 1).x(), face_centroid(a, f).x());
  }
}

TEST(SheetMesh, TilesJoinedEdgeToEdgeGiveOnePiece) {
  // B has two extra points on the edge it shares with A; A has none there.
  PlaneRegion a = square_tile(0, 0, 1, 1, "tile A");
  PlaneRegion b;
  b.boundary.resize(6, 2);
  b.boundary << 1, 0, 2, 0, 2, 1, 1, 1, 1, 0.7, 1, 0.3;
  b.source = "tile B";
  SheetMeshOptions options;
  options.max_edge = 0.25;
  const SheetMesh m = sheet_mesh({a, b}, options);
  const Stats s = stats(m);
  EXPECT_EQ(s.pieces, 1);
  EXPECT_EQ(close_pairs(m.V, 1e-9), 0);
  // Only the union's outline is a boundary: the shared edge is inside the mesh.
  EXPECT_NEAR(s.boundary_length, 6.0, 1e-12);
  EXPECT_NEAR(s.region_area.at(0), 1.0, 1e-12);
  EXPECT_NEAR(s.region_area.at(1), 1.0, 1e-12);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    EXPECT_EQ(m.face_region(f), face_centroid(m, f).x() < 1 ? 0 : 1) << f;
  }
  // B's extra points are vertices of faces on both sides.
  for (double y : {0.3, 0.7}) {
    std::set<int> sides;
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      for (int j = 0; j < 3; ++j) {
        if ((m.V.row(m.F(f, j)) - Eigen::RowVector2d(1, y)).norm() < 1e-12) {
          sides.insert(m.face_region(f));
        }
      }
    }
    EXPECT_EQ(sides, (std::set<int>{0, 1})) << y;
  }
  EXPECT_EQ(m.V.rows() - s.edges + m.F.rows(), 1);
}

TEST(SheetMesh, TilesOverlappingAlongPartOfAnEdgeAreJoinedThere) {
  // B's lower edge overlaps A's upper edge only on [1, 2]: the union is one piece, outline 12.
  const PlaneRegion a = square_tile(0, 0, 2, 1, "tile A");
  const PlaneRegion b = square_tile(1, 1, 3, 3, "tile B");
  const SheetMesh m = sheet_mesh({a, b}, {});
  const Stats s = stats(m);
  EXPECT_EQ(s.pieces, 1);
  EXPECT_NEAR(s.boundary_length, 12.0, 1e-12);
  EXPECT_NEAR(s.area, 6.0, 1e-12);
}

TEST(SheetMesh, LatticeAroundATileCoversTheUnion) {
  PlaneRegion lattice = square_tile(-10, -10, 10, 10, "lattice");
  Eigen::MatrixX2d hole = polygon(8, 5, kPi / 8).boundary.colwise().reverse();  // clockwise
  lattice.holes.push_back(hole);
  PlaneRegion tile = polygon(8, 5, kPi / 8, "tile");
  const SheetMesh m = sheet_mesh({lattice, tile}, {});
  const Stats s = stats(m);
  const double tile_area = signed_area(tile.boundary);
  EXPECT_NEAR(s.area, 400.0, 1e-9 * 400);
  EXPECT_NEAR(s.region_area.at(1), tile_area, 1e-9 * tile_area);
  EXPECT_NEAR(s.boundary_length, 80.0, 1e-9);  // the hole's edges are all shared
  EXPECT_EQ(s.pieces, 1);
  EXPECT_EQ(close_pairs(m.V, 1e-9), 0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    EXPECT_EQ(m.face_region(f), inside_regular(face_centroid(m, f), 8, 5, kPi / 8) ? 1 : 0) << f;
  }
  // Without the tile the hole stays empty.
  const Stats empty = stats(sheet_mesh({lattice}, {}));
  EXPECT_NEAR(empty.area, 400.0 - tile_area, 1e-9 * 400);
  EXPECT_NEAR(empty.boundary_length, 80.0 + 8 * 2 * 5 * std::sin(kPi / 8), 1e-9);
  EXPECT_EQ(empty.pieces, 1);
}

TEST(SheetMesh, GridOfSquareTiles) {
  std::vector<PlaneRegion> tiles;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      tiles.push_back(square_tile(25 * i, 25 * j, 25 * i + 25, 25 * j + 25, "grid"));
  }
  const SheetMesh m = sheet_mesh(tiles, {});
  const Stats s = stats(m);
  EXPECT_NEAR(s.area, 75.0 * 75.0, 1e-9 * 75 * 75);
  for (int r = 0; r < 9; ++r) EXPECT_NEAR(s.region_area.at(r), 625.0, 1e-9 * 625) << r;
  EXPECT_NEAR(s.boundary_length, 300.0, 1e-9);
  EXPECT_EQ(s.pieces, 1);
  EXPECT_LE(s.max_edge, 1.0 * (1 + 1e-9));
  EXPECT_EQ(m.V.rows() - s.edges + m.F.rows(), 1);
  std::printf("3x3 grid of 25 mm squares, max_edge 1: %d vertices, %d faces, min angle %.2f deg\n",
              static_cast<int>(m.V.rows()), static_cast<int>(m.F.rows()), s.min_angle_deg);
}

TEST(SheetMesh, RotationKeepsAreaAndFaceCount) {
  PlaneRegion lattice = square_tile(-6, -4, 6, 4, "lattice");
  lattice.holes.push_back(rectangle(-2, -2, 2, 2).colwise().reverse());
  const PlaneRegion tile = square_tile(-2, -2, 2, 2, "tile");
  const SheetMesh m0 = sheet_mesh({lattice, tile}, {});
  const Stats s0 = stats(m0);
  // An exact quarter turn, (x, y) -> (-y, x): every predicate and construction turns with it.
  auto quarter = [](PlaneRegion t) {
    auto turn = [](const Eigen::MatrixX2d& m) {
      Eigen::MatrixX2d r(m.rows(), 2);
      r.col(0) = -m.col(1);
      r.col(1) = m.col(0);
      return r;
    };
    t.boundary = turn(t.boundary);
    for (Eigen::MatrixX2d& h : t.holes) h = turn(h);
    return t;
  };
  // Delaunay refinement is not rotation invariant in its details (CGAL breaks cocircular ties by
  // lexicographic order, and the Steiner points' order follows): the face count varies by a few
  // percent (476-514 here, 3443-3563 for the disc), the area not at all.
  std::vector<std::vector<PlaneRegion>> turned = {{quarter(lattice), quarter(tile)}};
  for (double angle : {0.37, 2.0})
    turned.push_back({rotated(lattice, angle), rotated(tile, angle)});
  for (const std::vector<PlaneRegion>& regions : turned) {
    const SheetMesh m = sheet_mesh(regions, {});
    const Stats s = stats(m);
    EXPECT_NEAR(s.area, s0.area, 1e-9 * s0.area) << regions[1].boundary;
    EXPECT_NEAR(s.region_area.at(1), 16.0, 1e-9 * 16);
    EXPECT_NEAR(m.F.rows(), m0.F.rows(), 0.1 * m0.F.rows());
  }
  const PlaneRegion disc = polygon(64, 15);
  const SheetMesh d0 = sheet_mesh({disc}, {});
  for (double angle : {0.1, 1.0}) {
    const SheetMesh d = sheet_mesh({rotated(disc, angle)}, {});
    EXPECT_NEAR(stats(d).area, stats(d0).area, 1e-9 * stats(d0).area) << angle;
    EXPECT_NEAR(d.F.rows(), d0.F.rows(), 0.05 * d0.F.rows()) << angle;
  }
}

TEST(SheetMesh, RefusesOverlappingRegions) {
  try {
    sheet_mesh({square_tile(0, 0, 2, 2, "tile A"), square_tile(1, 1, 3, 3, "tile B")}, {});
    FAIL() << "overlap accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kGeometry);
    const std::string what = e.what();
    EXPECT_NE(what.find("overlap"), std::string::npos) << what;
    EXPECT_NE(what.find("tile A"), std::string::npos) << what;
    EXPECT_NE(what.find("tile B"), std::string::npos) << what;
  }
  // A tile laid on a lattice that has no hole for it.
  EXPECT_THROW(
      sheet_mesh({square_tile(0, 0, 10, 10, "lattice"), square_tile(2, 2, 4, 4, "tile")}, {}),
      UserError);
}

TEST(SheetMesh, RefusesBadInputAndTooManyVertices) {
  PlaneRegion line;
  line.boundary.resize(2, 2);
  line.boundary << 0, 0, 1, 0;
  line.source = "drawing.dxf: LINE";
  try {
    sheet_mesh({line}, {});
    FAIL();
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kGeometry);
    EXPECT_NE(std::string(e.what()).find("drawing.dxf: LINE"), std::string::npos) << e.what();
  }
  SheetMeshOptions bad;
  bad.max_edge = 0;
  EXPECT_THROW(sheet_mesh({polygon(8, 1)}, bad), UserError);
  // Refused before meshing (the estimate), and during it (the estimate is a lower bound).
  for (int limit : {500, 1000}) {
    SheetMeshOptions few;
    few.max_vertices = limit;
    try {
      sheet_mesh({polygon(64, 15)}, few);
      FAIL() << limit;
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kResource);
      EXPECT_NE(std::string(e.what()).find("raise max_edge"), std::string::npos) << e.what();
    }
  }
}

TEST(RingFrame, DiscDepthAndTangent) {
  // On the normals of a polygon's chords the frame is exact: depth R cos(pi/N) - r.
  const int n = 256;
  const double radius = 15;
  const PlaneRegion disc = polygon(n, radius);
  Eigen::MatrixX2d points(0, 2);
  std::vector<double> polar, r_of;
  for (int k = 0; k < n; k += 7) {
    for (double r : {0.1, 3.0, 7.5, 12.0, 14.9}) {
      const double phi = 2 * kPi * (k + 0.5) / n;
      points.conservativeResize(points.rows() + 1, 2);
      points.row(points.rows() - 1) << r * std::cos(phi), r * std::sin(phi);
      polar.push_back(phi);
      r_of.push_back(r);
    }
  }
  const RingFrame f = ring_frame(disc, points);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    EXPECT_NEAR(f.depth(i), radius * std::cos(kPi / n) - r_of[i], 1e-12 * radius) << i;
    EXPECT_LT(angle_difference(f.direction(i), polar[i] + kPi / 2), 1e-12) << i;
    EXPECT_GE(f.direction(i), 0);
    EXPECT_LT(f.direction(i), kPi);
  }
  // Anywhere: a fine polygon is the circle to 1e-6 R; the tangent within half a chord's angle.
  const int fine = 4096;
  const PlaneRegion circle = polygon(fine, radius);
  Eigen::MatrixX2d anywhere(10'000, 2);
  for (Eigen::Index i = 0; i < anywhere.rows(); ++i) {
    const double r = radius * (0.05 + 0.95 * ((i * 37) % 100) / 100.0);
    const double phi = 0.001 * static_cast<double>(i * 613 % 6283);
    anywhere.row(i) << r * std::cos(phi), r * std::sin(phi);
  }
  const RingFrame g = ring_frame(circle, anywhere);  // 4096 segments x 10 000 points, brute force
  for (Eigen::Index i = 0; i < anywhere.rows(); ++i) {
    const double r = anywhere.row(i).norm();
    ASSERT_NEAR(g.depth(i), radius - r, 1e-6 * radius) << i;
    const double phi = std::atan2(anywhere(i, 1), anywhere(i, 0));
    ASSERT_LT(angle_difference(g.direction(i), phi + kPi / 2), kPi / fine + 1e-12) << i;
  }
}

TEST(RingFrame, SquareWithAHole) {
  PlaneRegion t = square_tile(-5, -5, 5, 5, "square");
  Eigen::MatrixX2d points(0, 2);
  for (double x = -4.9; x < 5; x += 0.7) {
    for (double y = -4.8; y < 5; y += 0.65) {
      if (std::abs(std::abs(x) - std::abs(y)) < 1e-6) continue;  // the diagonals: two sides tie
      points.conservativeResize(points.rows() + 1, 2);
      points.row(points.rows() - 1) << x, y;
    }
  }
  const RingFrame f = ring_frame(t, points);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const double x = points(i, 0), y = points(i, 1);
    EXPECT_NEAR(f.depth(i), 5 - std::max(std::abs(x), std::abs(y)), 1e-12) << i;
    // Nearest side horizontal (|y| > |x|): the rings run along x.
    EXPECT_LT(angle_difference(f.direction(i), std::abs(y) > std::abs(x) ? 0 : kPi / 2), 1e-12)
        << i;
  }
  // A hole of half-width 1 in the middle: the nearer of the two.
  t.holes.push_back(rectangle(-1, -1, 1, 1).colwise().reverse());
  Eigen::MatrixX2d q(3, 2);
  q << 2, 0.5, 4.5, 0.2, 0, -2.5;
  const RingFrame h = ring_frame(t, q);
  EXPECT_NEAR(h.depth(0), 1.0, 1e-12);
  EXPECT_LT(angle_difference(h.direction(0), kPi / 2), 1e-12);
  EXPECT_NEAR(h.depth(1), 0.5, 1e-12);
  EXPECT_NEAR(h.depth(2), 1.5, 1e-12);
  EXPECT_LT(angle_difference(h.direction(2), 0), 1e-12);
  // On the outline: the outline's own direction; at a hole's corner, distance to the corner.
  Eigen::MatrixX2d on(2, 2);
  on << 5, 2, 1.6, 1.8;
  const RingFrame o = ring_frame(t, on);
  EXPECT_EQ(o.depth(0), 0);
  EXPECT_LT(angle_difference(o.direction(0), kPi / 2), 1e-12);
  EXPECT_NEAR(o.depth(1), 1.0, 1e-12);
  EXPECT_LT(angle_difference(o.direction(1), std::atan2(0.8, 0.6) + kPi / 2), 1e-12);
}

TEST(RingFrame, IsRotationInvariant) {
  const PlaneRegion t = polygon(7, 10, 0.3, "heptagon");
  Eigen::MatrixX2d p(4, 2);
  p << 1, 2, -3, 0.5, 0.2, -6, 4, 4;
  const double angle = 0.9;
  const PlaneRegion tr = rotated(t, angle);
  Eigen::MatrixX2d pr(4, 2);
  pr.col(0) = std::cos(angle) * p.col(0) - std::sin(angle) * p.col(1);
  pr.col(1) = std::sin(angle) * p.col(0) + std::cos(angle) * p.col(1);
  const RingFrame a = ring_frame(t, p), b = ring_frame(tr, pr);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(a.depth(i), b.depth(i), 1e-12);
    EXPECT_LT(angle_difference(a.direction(i) + angle, b.direction(i)), 1e-12);
  }
}

}  // namespace
}  // namespace flatmorph::sheet_mesh_test
