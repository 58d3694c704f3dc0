#include "mesh/validate.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "mesh/mesh_fixtures.h"
#include "mesh/topology.h"

namespace flatmorph::validate_test {
namespace {

using testing::grid;
using testing::icosahedron;

// The mesh without the listed faces (vertices kept).
Mesh without_faces(const Mesh& m, std::vector<int> drop) {
  Mesh out;
  out.V = m.V;
  out.F.resize(m.num_faces() - static_cast<int>(drop.size()), 3);
  for (int f = 0, row = 0; f < m.num_faces(); ++f) {
    if (std::find(drop.begin(), drop.end(), f) == drop.end()) out.F.row(row++) = m.F.row(f);
  }
  return out;
}

// Ring of `segments` quads per ring between radii 1 and 2, `rings` rings; vertex (ring j,
// segment i) is j * segments + i, so the inner circle holds vertices 0 .. segments-1.
Mesh annulus(int segments, int rings) {
  Mesh m;
  m.V.resize(segments * (rings + 1), 3);
  for (int j = 0; j <= rings; ++j) {
    const double r = 1.0 + static_cast<double>(j) / rings;
    for (int i = 0; i < segments; ++i) {
      const double t = 2.0 * std::numbers::pi * i / segments;
      m.V.row(j * segments + i) << r * std::cos(t), r * std::sin(t), 0.0;
    }
  }
  m.F.resize(2 * segments * rings, 3);
  for (int j = 0; j < rings; ++j) {
    for (int i = 0; i < segments; ++i) {
      const int a = j * segments + i, b = j * segments + (i + 1) % segments;
      const int c = b + segments, d = a + segments;
      m.F.row(2 * (j * segments + i)) << a, b, c;
      m.F.row(2 * (j * segments + i) + 1) << a, c, d;
    }
  }
  return m;
}

Mesh octahedron() {
  Mesh m;
  m.V.resize(6, 3);
  m.V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  m.F.resize(8, 3);
  m.F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  return m;
}

// A Moebius strip of n quads: the strip's two edges swap after one turn.
Mesh moebius(int n) {
  Mesh m;
  m.V.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double u = 2.0 * std::numbers::pi * i / n;
    for (int side = 0; side < 2; ++side) {
      const double s = side == 0 ? 0.5 : -0.5;
      const double r = 2.0 + s * std::cos(u / 2);
      m.V.row(2 * i + side) << r * std::cos(u), r * std::sin(u), s * std::sin(u / 2);
    }
  }
  m.F.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const int t = 2 * i, b = 2 * i + 1;
    // After the last quad, top meets bottom.
    const int t1 = i + 1 < n ? t + 2 : 1, b1 = i + 1 < n ? b + 2 : 0;
    m.F.row(2 * i) << t, b, b1;
    m.F.row(2 * i + 1) << t, b1, t1;
  }
  return m;
}

// Every face gets its own three corners, as an STL file stores them.
Mesh soup(const Mesh& m) {
  Mesh s;
  s.V.resize(3 * m.num_faces(), 3);
  s.F.resize(m.num_faces(), 3);
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      s.V.row(3 * f + k) = m.V.row(m.F(f, k));
      s.F(f, k) = 3 * f + k;
    }
  }
  return s;
}

// z component of face f's (right-hand rule) normal.
double normal_z(const Mesh& m, int f) {
  const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
  return (b - a).cross(c - a).z();
}

const MeshProblem* find_problem(const MeshDiagnosis& d, const std::string& what_prefix) {
  for (const MeshProblem& p : d.problems) {
    if (p.what.rfind(what_prefix, 0) == 0) return &p;
  }
  return nullptr;
}

std::string problem_list(const MeshDiagnosis& d) {
  std::string s;
  for (const MeshProblem& p : d.problems) s += p.what + ": " + p.first + "\n";
  return s;
}

// --- repair ---------------------------------------------------------------------------------

TEST(MeshRepair, SoupWeldsToTheIndexedMesh) {
  const Mesh original = grid(4, 3);  // 20 vertices, 24 faces
  Mesh m = soup(original);
  const RepairReport r = repair_mesh(m);
  EXPECT_EQ(r.welded_vertices, 3 * 24 - 20);
  EXPECT_EQ(r.unreferenced_vertices, 0);
  EXPECT_EQ(r.degenerate_faces, 0);
  EXPECT_EQ(r.duplicate_faces, 0);
  EXPECT_EQ(r.flipped_faces, 0);
  ASSERT_EQ(m.num_vertices(), 20);
  ASSERT_EQ(m.num_faces(), 24);
  // Same triangles, same order, same corners.
  for (int f = 0; f < 24; ++f) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(m.V.row(m.F(f, k)), original.V.row(original.F(f, k))) << "face " << f;
    }
  }
  // Representatives are first occurrences, so vertices come in the order faces first use them.
  EXPECT_EQ(m.F.row(0), Eigen::RowVector3i(0, 1, 2));
  const MeshDiagnosis d = diagnose_mesh(m);
  EXPECT_TRUE(d.is_disk()) << problem_list(d);
  EXPECT_EQ(d.euler_characteristic, 1);
  EXPECT_EQ(d.num_boundary_loops, 1);
}

TEST(MeshRepair, WeldToleranceIsRelativeToTheDiagonal) {
  const Mesh original = grid(4, 3);
  const double diagonal = 5.0;  // the 4 x 3 grid
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto jittered = [&](double amplitude) {
    Mesh m = soup(original);
    for (int v = 0; v < m.num_vertices(); ++v) {
      Eigen::RowVector3d d(unit(rng), unit(rng), unit(rng));
      m.V.row(v) += amplitude * d.normalized();
    }
    return m;
  };
  // Corners moved by 1e-11 diag (half the default tolerance at most apart 2e-11 < 1e-9) weld.
  Mesh close = jittered(1e-11 * diagonal);
  repair_mesh(close);
  EXPECT_EQ(close.num_vertices(), 20);
  // Moved by 1e-6 diag they are distinct points for the default tolerance ...
  Mesh apart = jittered(1e-6 * diagonal);
  const RepairReport r = repair_mesh(apart);
  EXPECT_EQ(r.welded_vertices, 0);
  EXPECT_EQ(apart.num_vertices(), 72);
  // ... and weld with a tolerance above their spread (2e-6 diag at most apart).
  Mesh apart_loose = jittered(1e-6 * diagonal);
  repair_mesh(apart_loose, {.weld_tolerance = 1e-5});
  EXPECT_EQ(apart_loose.num_vertices(), 20);
}

TEST(MeshRepair, WeldKeepsTheLowestIndex) {
  // Vertices 1, 3 and 4 coincide; 3 and 4 must both map to 1, and its position is kept.
  Mesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 1e-12, 1, 0, -1e-12;
  m.F.resize(3, 3);
  m.F << 0, 1, 2, 0, 3, 2, 0, 4, 2;
  Mesh copy = m;
  const RepairReport r = repair_mesh(copy);
  EXPECT_EQ(r.welded_vertices, 2);
  EXPECT_EQ(r.duplicate_faces, 2);
  ASSERT_EQ(copy.num_vertices(), 3);
  EXPECT_EQ(copy.V.row(1), Eigen::RowVector3d(1, 0, 0));
  ASSERT_EQ(copy.num_faces(), 1);
  EXPECT_EQ(copy.F.row(0), Eigen::RowVector3i(0, 1, 2));
}

TEST(MeshRepair, UnreferencedVerticesAreRemovedInOrder) {
  const Mesh original = grid(3, 2);  // 12 vertices
  // Insert stray vertices at the front, the middle and the end.
  Mesh m;
  m.V.resize(15, 3);
  std::vector<int> old_to_new(12);
  for (int v = 0, row = 0; v < 12; ++v) {
    if (v == 0) m.V.row(row++) << 9, 9, 9;
    if (v == 6) m.V.row(row++) << -9, 9, 9;
    old_to_new[v] = row;
    m.V.row(row++) = original.V.row(v);
  }
  m.V.row(14) << 9, -9, 9;
  m.F = original.F;
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) m.F(f, k) = old_to_new[original.F(f, k)];
  }
  const RepairReport r = repair_mesh(m);
  EXPECT_EQ(r.unreferenced_vertices, 3);
  EXPECT_EQ(r.welded_vertices, 0);
  EXPECT_EQ(m.V, original.V);
  EXPECT_EQ(m.F, original.F);
}

TEST(MeshRepair, ZeroAreaAndDuplicateFacesAreRemoved) {
  const Mesh original = grid(3, 2);
  Mesh m = original;
  const int nf = original.num_faces();
  m.F.conservativeResize(nf + 4, 3);
  m.F.row(nf) << 0, 0, 5;                                                   // repeated index
  m.F.row(nf + 1) << 0, 1, 2;                                               // collinear (row y = 0)
  m.F.row(nf + 2) << original.F(3, 1), original.F(3, 2), original.F(3, 0);  // same, rotated
  m.F.row(nf + 3) << original.F(3, 2), original.F(3, 1), original.F(3, 0);  // same, reversed
  const RepairReport r = repair_mesh(m);
  EXPECT_EQ(r.degenerate_faces, 2);
  EXPECT_EQ(r.duplicate_faces, 2);
  EXPECT_EQ(r.flipped_faces, 0);
  EXPECT_EQ(m.F, original.F);
  EXPECT_EQ(m.V, original.V);
}

TEST(MeshRepair, NearlyCollinearFaceWithAreaIsKept) {
  // A sliver with area 1e-9 diag^2 is a real (if bad) triangle, not a zero-area one.
  Mesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0.5, 2e-9, 0;
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  EXPECT_EQ(repair_mesh(m).degenerate_faces, 0);
  EXPECT_EQ(m.num_faces(), 1);
  m.V(2, 1) = 1e-16;
  EXPECT_EQ(repair_mesh(m).degenerate_faces, 1);
  EXPECT_EQ(m.num_faces(), 0);
}

TEST(MeshRepair, OneFlippedFaceIsTurnedBack) {
  const Mesh original = grid(4, 4);
  Mesh m = original;
  std::swap(m.F(13, 1), m.F(13, 2));
  const MeshDiagnosis before = diagnose_mesh(m);
  const MeshProblem* p = find_problem(before, "faces oriented against");
  ASSERT_NE(p, nullptr) << problem_list(before);
  EXPECT_EQ(p->count, 1);
  EXPECT_EQ(p->first, "face 13");
  EXPECT_EQ(before.num_boundary_loops, 1);
  const RepairReport r = repair_mesh(m);
  EXPECT_EQ(r.flipped_faces, 1);
  EXPECT_EQ(m.F, original.F);
  EXPECT_TRUE(diagnose_mesh(m).is_disk());
}

TEST(MeshRepair, OrientationFollowsEachComponentsFirstFace) {
  // Two separate squares, the second given clockwise (normal -z) in both faces: consistent in
  // itself, so nothing is flipped; one of its faces flipped makes that face the one to turn.
  Mesh a = grid(1, 1);
  Mesh m;
  m.V.resize(8, 3);
  m.V << a.V, a.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
  m.F.resize(4, 3);
  m.F << a.F, a.F.rowwise().reverse().array() + 4;
  Mesh copy = m;
  EXPECT_EQ(repair_mesh(copy).flipped_faces, 0);
  EXPECT_EQ(copy.F, m.F);
  std::swap(m.F(3, 0), m.F(3, 1));
  EXPECT_EQ(repair_mesh(m).flipped_faces, 1);
  const Eigen::Vector3d normals_z(normal_z(m, 0), normal_z(m, 2), normal_z(m, 3));
  EXPECT_GT(normals_z(0), 0.0);
  EXPECT_LT(normals_z(1), 0.0);
  EXPECT_LT(normals_z(2), 0.0);
  EXPECT_EQ(diagnose_mesh(m).problems.size(), 2u);  // two pieces, two boundary loops
}

TEST(MeshRepair, OneSidedSurfaceIsLeftAsItIs) {
  Mesh m = moebius(12);
  const Mesh original = m;
  const RepairReport r = repair_mesh(m);
  EXPECT_EQ(r.flipped_faces, 0);
  EXPECT_EQ(m.F, original.F);
}

TEST(MeshRepair, NanCoordinatesDoNotCrashAndAreNotWelded) {
  Mesh m = soup(grid(2, 2));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.V.row(0) << nan, 0, 0;
  m.V.row(1) << nan, 0, 0;  // equal NaNs are still not the same point
  const RepairReport r = repair_mesh(m);
  EXPECT_EQ(m.num_faces(), 8);
  EXPECT_TRUE(std::isnan(m.V(0, 0)));
  EXPECT_TRUE(std::isnan(m.V(1, 0)));
  EXPECT_EQ(r.degenerate_faces, 0);
  const MeshDiagnosis d = diagnose_mesh(m);
  const MeshProblem* p = find_problem(d, "NaN");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->count, 2);
}

TEST(MeshRepair, IndicesOutOfRangeLeaveTheMeshAlone) {
  Mesh m = grid(2, 2);
  m.F(3, 1) = 42;
  const Mesh original = m;
  const RepairReport r = repair_mesh(m);
  EXPECT_EQ(r.welded_vertices + r.unreferenced_vertices + r.degenerate_faces + r.duplicate_faces +
                r.flipped_faces,
            0);
  EXPECT_EQ(m.F, original.F);
}

// --- diagnose -------------------------------------------------------------------------------

TEST(MeshValidate, ValidDiskPasses) {
  const Mesh m = grid(5, 4);
  const MeshDiagnosis d = diagnose_mesh(m);
  EXPECT_TRUE(d.is_disk()) << problem_list(d);
  EXPECT_EQ(d.num_vertices, 30);
  EXPECT_EQ(d.num_faces, 40);
  EXPECT_EQ(d.num_edges, 5 * 5 + 4 * 6 + 20);  // horizontal, vertical, diagonal
  EXPECT_EQ(d.euler_characteristic, 1);
  EXPECT_EQ(d.num_boundary_loops, 1);
  EXPECT_EQ(d.num_components, 1);
  EXPECT_NO_THROW(require_disk(m, "grid.obj"));
}

TEST(MeshValidate, EmptyMesh) {
  const MeshDiagnosis d = diagnose_mesh(Mesh{});
  ASSERT_EQ(d.problems.size(), 1u);
  EXPECT_EQ(d.problems[0].what, "empty mesh");
  EXPECT_EQ(d.problems[0].count, 0);
  EXPECT_FALSE(d.is_disk());
  // Faces without vertices: every face points nowhere.
  Mesh no_vertices;
  no_vertices.F = grid(1, 1).F;
  const MeshDiagnosis e = diagnose_mesh(no_vertices);
  ASSERT_EQ(e.problems.size(), 1u) << problem_list(e);
  EXPECT_EQ(e.problems[0].what, "faces use vertices that do not exist");
  EXPECT_EQ(e.problems[0].count, 2);
}

TEST(MeshValidate, NanCoordinate) {
  Mesh m = grid(4, 4);
  m.V.row(17) << std::numeric_limits<double>::quiet_NaN(), 0, 1;
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_FALSE(d.problems.empty());
  const MeshProblem& p = d.problems[0];
  EXPECT_EQ(p.category, ErrorCategory::kGeometry);
  EXPECT_EQ(p.count, 1);
  EXPECT_EQ(p.first, "vertex 17 (nan, 0, 1)");
  EXPECT_EQ(d.problems.size(), 1u) << problem_list(d);  // topology is still fine
}

TEST(MeshValidate, InfiniteAndAbsurdCoordinates) {
  Mesh m = grid(4, 4);
  m.V(9, 2) = -std::numeric_limits<double>::infinity();
  m.V(12, 0) = 3e12;
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_FALSE(d.problems.empty());
  EXPECT_EQ(d.problems[0].count, 2);
  EXPECT_EQ(d.problems[0].first, "vertex 9 (4, 1, -inf)");
  EXPECT_EQ(d.problems.size(), 1u) << problem_list(d);
}

TEST(MeshValidate, IndexOutOfRange) {
  Mesh m = grid(2, 2);  // 9 vertices
  m.F(5, 2) = 9;
  m.F(6, 0) = -1;
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_FALSE(d.problems.empty());
  const MeshProblem& p = d.problems[0];
  EXPECT_EQ(p.what, "faces use vertices that do not exist");
  EXPECT_EQ(p.count, 2);
  EXPECT_EQ(p.first, "face 5 (3, 7, 9); the mesh has 9 vertices");
}

TEST(MeshValidate, ZeroAreaFaces) {
  Mesh m = grid(3, 1);
  m.F.conservativeResize(m.num_faces() + 2, 3);
  m.F.row(6) << 1, 2, 3;  // corners on the line y = 0
  m.F.row(7) << 5, 5, 6;
  const MeshDiagnosis d = diagnose_mesh(m);
  const MeshProblem* p = find_problem(d, "zero-area faces");
  ASSERT_NE(p, nullptr) << problem_list(d);
  EXPECT_EQ(p->count, 2);
  EXPECT_EQ(p->first, "face 6 (1, 2, 3)");
  EXPECT_EQ(p->category, ErrorCategory::kGeometry);
}

TEST(MeshValidate, ThreeFacesOnOneEdge) {
  Mesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1;
  m.F.resize(3, 3);
  m.F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_FALSE(d.problems.empty());
  const MeshProblem& p = d.problems[0];
  EXPECT_EQ(p.category, ErrorCategory::kTopology);
  EXPECT_EQ(p.count, 1);
  EXPECT_EQ(p.first, "edge (0, 1) shared by 3 faces");
  EXPECT_EQ(p.fix, "delete the extra faces or re-export as a manifold surface");
}

TEST(MeshValidate, BowtieVertex) {
  // Two squares touching at one corner.
  Mesh a = grid(1, 1);  // vertices 0..3, corner 3 at (1, 1)
  Mesh m;
  m.V.resize(7, 3);
  m.V << a.V, 2, 1, 0, 2, 2, 0, 1, 2, 0;
  m.F.resize(4, 3);
  // Second square on vertices 3 (1,1), 4 (2,1), 5 (2,2), 6 (1,2).
  m.F << a.F, 3, 4, 5, 3, 5, 6;
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_FALSE(d.problems.empty());
  const MeshProblem& p = d.problems[0];
  EXPECT_EQ(p.what.rfind("non-manifold vertices", 0), 0u) << p.what;
  EXPECT_EQ(p.count, 1);
  EXPECT_EQ(p.first, "vertex 3 joins 2 separate fans of faces");
  EXPECT_NE(find_problem(d, "more than one connected piece"), nullptr);
}

TEST(MeshValidate, BowtieInsideOnePiece) {
  // A 3 x 3 grid without the squares below-left and above-right of an interior vertex: its faces
  // form two fans, while the piece stays connected through the rest of the grid.
  const Mesh g = grid(3, 3);  // interior vertex (1, 1) = 5 has squares (0,0), (1,0), (0,1), (1,1)
  const Mesh m = without_faces(g, {0, 1, 8, 9});  // squares (0, 0) and (1, 1)
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_FALSE(d.problems.empty()) << problem_list(d);
  EXPECT_EQ(d.problems[0].first, "vertex 5 joins 2 separate fans of faces");
  EXPECT_EQ(d.num_components, 1);
}

TEST(MeshValidate, MoebiusStripIsNonOrientable) {
  const Mesh m = moebius(12);
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_EQ(d.problems.size(), 1u) << problem_list(d);
  const MeshProblem& p = d.problems[0];
  EXPECT_EQ(p.what.rfind("non-orientable", 0), 0u);
  EXPECT_EQ(p.count, 1);
  EXPECT_EQ(p.category, ErrorCategory::kTopology);
  EXPECT_EQ(d.num_boundary_loops, 1);  // a Moebius strip has one edge, twice around
  EXPECT_EQ(d.euler_characteristic, 0);
  EXPECT_EQ(d.num_components, 1);
}

TEST(MeshValidate, TwoSeparateTriangles) {
  Mesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 3, 0, 0, 4, 0, 0, 3, 1, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 3, 4, 5;
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_FALSE(d.problems.empty());
  const MeshProblem& p = d.problems[0];
  EXPECT_EQ(p.what, "more than one connected piece");
  EXPECT_EQ(p.count, 2);
  EXPECT_EQ(p.first, "face 1 in the second component");
  EXPECT_EQ(p.fix, "keep one piece (e.g. MeshLab: Remove Isolated pieces)");
  EXPECT_EQ(d.num_components, 2);
}

TEST(MeshValidate, ClosedSurfaces) {
  for (const auto& [m, faces] : {std::pair{octahedron(), 8}, std::pair{icosahedron(), 20}}) {
    const MeshDiagnosis d = diagnose_mesh(m);
    ASSERT_EQ(d.problems.size(), 1u) << problem_list(d);
    const MeshProblem& p = d.problems[0];
    EXPECT_EQ(p.what, "closed surface (no boundary)");
    EXPECT_EQ(p.count, 1);
    EXPECT_EQ(p.first, "the piece with face 0, " + std::to_string(faces) + " faces");
    EXPECT_EQ(p.fix, "cut the closed surface open, e.g. delete a face or a cap");
    EXPECT_EQ(d.euler_characteristic, 2);
    EXPECT_EQ(d.num_boundary_loops, 0);
  }
}

TEST(MeshValidate, ClosedSurfaceCutOpenIsADisk) {
  const MeshDiagnosis d = diagnose_mesh(without_faces(icosahedron(), {7}));
  EXPECT_TRUE(d.is_disk()) << problem_list(d);
  EXPECT_EQ(d.euler_characteristic, 1);
}

TEST(MeshValidate, AnnulusHasOneHole) {
  const Mesh m = annulus(16, 3);
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_EQ(d.problems.size(), 1u) << problem_list(d);
  const MeshProblem& p = d.problems[0];
  EXPECT_EQ(p.count, 2);
  // Both rings have 16 edges; the hole is the shorter (inner) one.
  EXPECT_EQ(p.first, "hole along vertex 0, 16 edges");
  EXPECT_EQ(p.fix, "fill the holes (e.g. MeshLab: Close Holes) or keep only the outer part");
  EXPECT_EQ(d.num_boundary_loops, 2);
  EXPECT_EQ(d.euler_characteristic, 0);
}

TEST(MeshValidate, DiskWithTwoHoles) {
  // 5 x 5 grid without squares (1, 1) and (3, 3): holes around vertices 7, 8, 13, 14 and
  // 21, 22, 27, 28.
  const Mesh m = without_faces(grid(5, 5), {12, 13, 36, 37});
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_EQ(d.problems.size(), 1u) << problem_list(d);
  EXPECT_EQ(d.problems[0].count, 3);
  EXPECT_EQ(d.problems[0].first, "hole along vertex 7, 4 edges");
  EXPECT_EQ(d.num_boundary_loops, 3);
  EXPECT_EQ(d.euler_characteristic, -1);
}

TEST(MeshValidate, RequireDiskMessage) {
  const Mesh m = annulus(16, 3);
  try {
    require_disk(m, "ring.obj");
    FAIL() << "no error for an annulus";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kTopology);
    EXPECT_STREQ(e.what(),
                 "ring.obj: holes (boundary loops; a disk has one): 2 (first: hole along vertex "
                 "0, 16 edges); fill the holes (e.g. MeshLab: Close Holes) or keep only the outer "
                 "part");
  }
  Mesh nan = grid(2, 2);
  nan.V(4, 1) = std::numeric_limits<double>::quiet_NaN();
  try {
    require_disk(nan, "bad.stl");
    FAIL() << "no error for a NaN coordinate";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kGeometry);
    EXPECT_EQ(std::string(e.what()).rfind("bad.stl: NaN", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("(first: vertex 4 (1, nan, 0))"), std::string::npos);
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

TEST(MeshValidate, ChecksComeInTheirOrder) {
  // A closed octahedron with a NaN and two pieces: coordinates first, then pieces, then closed.
  Mesh m = octahedron();
  const Mesh o = octahedron();
  m.V.conservativeResize(12, 3);
  m.V.bottomRows(6) = o.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
  m.F.conservativeResize(16, 3);
  m.F.bottomRows(8) = o.F.array() + 6;
  m.V(8, 2) = std::numeric_limits<double>::infinity();
  const MeshDiagnosis d = diagnose_mesh(m);
  ASSERT_EQ(d.problems.size(), 3u) << problem_list(d);
  EXPECT_EQ(d.problems[0].category, ErrorCategory::kGeometry);
  EXPECT_EQ(d.problems[1].what, "more than one connected piece");
  EXPECT_EQ(d.problems[2].what, "closed surface (no boundary)");
  EXPECT_EQ(d.problems[2].count, 2);
}

TEST(MeshValidate, NeverThrowsOnGarbage) {
  std::mt19937 rng(2024);
  for (int trial = 0; trial < 200; ++trial) {
    const int nv = std::uniform_int_distribution<int>(0, 12)(rng);
    const int nf = std::uniform_int_distribution<int>(0, 20)(rng);
    Mesh m;
    m.V.resize(nv, 3);
    for (int v = 0; v < nv; ++v) {
      for (int c = 0; c < 3; ++c) {
        const int kind = std::uniform_int_distribution<int>(0, 9)(rng);
        m.V(v, c) = kind == 0   ? std::numeric_limits<double>::quiet_NaN()
                    : kind == 1 ? std::numeric_limits<double>::infinity()
                                : std::uniform_int_distribution<int>(-2, 2)(rng);
      }
    }
    m.F.resize(nf, 3);
    for (int f = 0; f < nf; ++f) {
      for (int k = 0; k < 3; ++k) m.F(f, k) = std::uniform_int_distribution<int>(-1, nv)(rng);
    }
    MeshDiagnosis d;
    EXPECT_NO_THROW(d = diagnose_mesh(m));
    if (nf == 0) {
      EXPECT_FALSE(d.is_disk());
    }
    EXPECT_NO_THROW(repair_mesh(m));
    EXPECT_NO_THROW(diagnose_mesh(m));
  }
}

}  // namespace
}  // namespace flatmorph::validate_test
