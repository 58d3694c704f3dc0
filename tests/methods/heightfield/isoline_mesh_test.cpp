// The printing graph of a height field (SCF 2020 §6.1): the structure every later stage relies on
// (isoline_mesh.h), checked on the built-in examples and an image, against what is known of each
// (its footprint, its peaks and saddles, its symmetry), not against the code's own output.
#include "methods/heightfield/isoline_mesh.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "common/error.h"
#include "examples/height_field_examples.h"
#include "mesh/topology.h"
#include "methods/heightfield/gray_image.h"

namespace flatmorph::isoline_mesh_test {
namespace {

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Eigen::Vector2d xy(const Eigen::MatrixXd& V, int v) { return Eigen::Vector2d(V(v, 0), V(v, 1)); }

double face_area_xy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const Eigen::Vector2d a = xy(V, F(f, 0));
  return 0.5 * cross2(xy(V, F(f, 1)) - a, xy(V, F(f, 2)) - a);
}

// The area the field covers seen from above (its faces may turn either way).
double footprint_area(const HeightField& field) {
  double sum = 0.0;
  for (int f = 0; f < field.F.rows(); ++f) sum += face_area_xy(field.V, field.F, f);
  return std::abs(sum);
}

// The height of the field at (x, y), found through a grid of buckets over the faces' boxes;
// NaN off the footprint.
class HeightLookup {
 public:
  explicit HeightLookup(const HeightField& field) : field_(field) {
    lo_ = field.V.leftCols(2).colwise().minCoeff().transpose();
    const Eigen::Vector2d hi = field.V.leftCols(2).colwise().maxCoeff().transpose();
    n_ = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(field.F.rows()) / 2.0)));
    cell_ = (hi - lo_) / n_ + Eigen::Vector2d::Constant(1e-9);
    buckets_.resize(n_ * n_);
    for (int f = 0; f < field.F.rows(); ++f) {
      Eigen::Vector2d a = xy(field.V, field.F(f, 0)), b = a;
      for (int k = 1; k < 3; ++k) {
        a = a.cwiseMin(xy(field.V, field.F(f, k)));
        b = b.cwiseMax(xy(field.V, field.F(f, k)));
      }
      const auto [i0, j0] = cell(a);
      const auto [i1, j1] = cell(b);
      for (int i = i0; i <= i1; ++i) {
        for (int j = j0; j <= j1; ++j) buckets_[i * n_ + j].push_back(f);
      }
    }
  }
  double operator()(double x, double y) const {
    const Eigen::Vector2d p(x, y);
    const auto [i, j] = cell(p);
    double best = -1.0, z = std::nan("");
    for (int f : buckets_[i * n_ + j]) {
      const Eigen::Vector2d a = xy(field_.V, field_.F(f, 0)), b = xy(field_.V, field_.F(f, 1)),
                            c = xy(field_.V, field_.F(f, 2));
      const double A = cross2(b - a, c - a);
      const double l0 = cross2(b - p, c - p) / A, l1 = cross2(c - p, a - p) / A;
      const double l2 = 1.0 - l0 - l1;
      const double worst = std::min({l0, l1, l2});
      if (worst > best) {
        best = worst;
        z = l0 * field_.V(field_.F(f, 0), 2) + l1 * field_.V(field_.F(f, 1), 2) +
            l2 * field_.V(field_.F(f, 2), 2);
      }
    }
    return best > -1e-9 ? z : std::nan("");
  }

 private:
  std::pair<int, int> cell(const Eigen::Vector2d& p) const {
    const Eigen::Vector2d u = (p - lo_).cwiseQuotient(cell_);
    return {std::clamp(static_cast<int>(u.x()), 0, n_ - 1),
            std::clamp(static_cast<int>(u.y()), 0, n_ - 1)};
  }
  const HeightField& field_;
  Eigen::Vector2d lo_, cell_;
  int n_ = 1;
  std::vector<std::vector<int>> buckets_;
};

bool same_level_edge(const IsolineMesh& m, int a, int b) {
  return m.vertex_level[a] >= 0 && m.vertex_level[a] == m.vertex_level[b];
}

// Everything isoline_mesh.h promises, plus the geometry: a disk covering the footprint exactly,
// no face flipped, every vertex on the field, printing edges no longer than l_u.
void expect_valid(const IsolineMesh& m, const HeightField& field, double l_u) {
  const int nv = static_cast<int>(m.V.rows());
  ASSERT_EQ(m.V.cols(), 3);
  ASSERT_EQ(m.vertex_level.size(), nv);
  ASSERT_EQ(m.vertex_loop.size(), nv);
  ASSERT_EQ(static_cast<Eigen::Index>(m.edge_kind.size()), m.E.rows());
  ASSERT_GE(m.levels.size(), 1);
  ASSERT_FALSE(m.loops.empty());
  for (int i = 1; i < m.levels.size(); ++i) EXPECT_LT(m.levels[i - 1], m.levels[i]);

  // E: exactly the unique edges of F, sorted, E(e, 0) < E(e, 1).
  const EdgeTopology topo = edge_topology(m.F);
  ASSERT_EQ(topo.edges.rows(), m.E.rows());
  EXPECT_TRUE(topo.edges == m.E);
  std::map<std::pair<int, int>, int> edge_index;
  for (int e = 0; e < m.E.rows(); ++e) {
    ASSERT_LT(m.E(e, 0), m.E(e, 1));
    edge_index[{m.E(e, 0), m.E(e, 1)}] = e;
  }
  const auto kind = [&](int a, int b) {
    return m.edge_kind[edge_index.at({std::min(a, b), std::max(a, b)})];
  };

  // Printing and boundary edges join vertices of one level.
  for (int e = 0; e < m.E.rows(); ++e) {
    if (m.edge_kind[e] != EdgeKind::kBridge) {
      EXPECT_TRUE(same_level_edge(m, m.E(e, 0), m.E(e, 1))) << "edge " << e;
    }
  }

  // Boundary edges = the mesh's boundary = loop 0; one boundary loop; a disk.
  EXPECT_EQ(euler_characteristic(m.F), 1);
  const std::vector<std::vector<int>> boundaries = boundary_loops(m.F);
  ASSERT_EQ(boundaries.size(), 1u);
  std::set<std::pair<int, int>> mesh_boundary, boundary_kind, loop0;
  for (size_t i = 0; i < boundaries[0].size(); ++i) {
    const int a = boundaries[0][i], b = boundaries[0][(i + 1) % boundaries[0].size()];
    mesh_boundary.insert({std::min(a, b), std::max(a, b)});
  }
  for (int e = 0; e < m.E.rows(); ++e) {
    if (m.edge_kind[e] == EdgeKind::kBoundary) boundary_kind.insert({m.E(e, 0), m.E(e, 1)});
  }
  const std::vector<int>& outer = m.loops[0].vertices;
  for (size_t i = 0; i < outer.size(); ++i) {
    const int a = outer[i], b = outer[(i + 1) % outer.size()];
    loop0.insert({std::min(a, b), std::max(a, b)});
  }
  EXPECT_TRUE(mesh_boundary == boundary_kind);
  EXPECT_TRUE(loop0 == boundary_kind);

  // Faces: a base on one level and an apex one level away, or a fan around a patch centre whose
  // spokes are bridges and whose rim is printed.
  int patch_faces = 0;
  for (int f = 0; f < m.F.rows(); ++f) {
    const int v[3] = {m.F(f, 0), m.F(f, 1), m.F(f, 2)};
    int centres = 0, centre = -1;
    for (int k = 0; k < 3; ++k) {
      if (m.vertex_level[v[k]] == -1) ++centres, centre = k;
    }
    ASSERT_LE(centres, 1) << "face " << f;
    if (centres == 1) {
      ++patch_faces;
      const int a = v[(centre + 1) % 3], b = v[(centre + 2) % 3];
      EXPECT_EQ(kind(v[centre], a), EdgeKind::kBridge);
      EXPECT_EQ(kind(v[centre], b), EdgeKind::kBridge);
      EXPECT_NE(kind(a, b), EdgeKind::kBridge) << "patch rim at face " << f;
      continue;
    }
    int bases = 0;
    for (int k = 0; k < 3; ++k) {
      const int a = v[k], b = v[(k + 1) % 3], apex = v[(k + 2) % 3];
      if (!same_level_edge(m, a, b)) continue;
      ++bases;
      EXPECT_NE(kind(a, b), EdgeKind::kBridge) << "face " << f;
      EXPECT_EQ(std::abs(m.vertex_level[apex] - m.vertex_level[a]), 1) << "face " << f;
    }
    EXPECT_EQ(bases, 1) << "face " << f;
  }
  EXPECT_GT(patch_faces, 0);

  // Seen from above: every face counter-clockwise, and together they cover the footprint.
  double area = 0.0, smallest = std::numeric_limits<double>::infinity();
  for (int f = 0; f < m.F.rows(); ++f) {
    const double a = face_area_xy(m.V, m.F, f);
    smallest = std::min(smallest, a);
    area += a;
  }
  EXPECT_GT(smallest, 0.0);
  const double footprint = footprint_area(field);
  EXPECT_NEAR(area, footprint, 1e-6 * footprint);

  // On the field; loop vertices exactly at their level.
  const HeightLookup height(field);
  const double scale = field.V.col(2).cwiseAbs().maxCoeff() + 1.0;
  for (int v = 0; v < nv; ++v) {
    EXPECT_NEAR(m.V(v, 2), height(m.V(v, 0), m.V(v, 1)), 1e-9 * scale) << "vertex " << v;
    if (m.vertex_loop[v] >= 0) {
      EXPECT_NEAR(m.V(v, 2), m.levels[m.vertex_level[v]], 1e-9 * scale) << "vertex " << v;
    }
  }

  // Loops: closed by printing edges, counter-clockwise, in a tree one level apart.
  for (size_t id = 0; id < m.loops.size(); ++id) {
    const IsolineLoop& loop = m.loops[id];
    ASSERT_GE(loop.vertices.size(), 3u) << "loop " << id;
    EXPECT_EQ(loop.parent < 0, id == 0) << "loop " << id;
    if (id > 0) {
      ASSERT_LT(loop.parent, static_cast<int>(m.loops.size()));
      EXPECT_EQ(m.loops[loop.parent].level, loop.level - 1) << "loop " << id;
    } else {
      EXPECT_EQ(loop.level, 0);
    }
    double area2 = 0.0;
    for (size_t i = 0; i < loop.vertices.size(); ++i) {
      const int a = loop.vertices[i], b = loop.vertices[(i + 1) % loop.vertices.size()];
      EXPECT_EQ(m.vertex_loop[a], static_cast<int>(id));
      EXPECT_EQ(m.vertex_level[a], loop.level);
      EXPECT_NE(kind(a, b), EdgeKind::kBridge) << "loop " << id << " is not closed";
      area2 += cross2(xy(m.V, a), xy(m.V, b));
    }
    EXPECT_GT(area2, 0.0) << "loop " << id << " is not counter-clockwise";
  }
  // Printing edges no longer than l_u.
  for (int e = 0; e < m.E.rows(); ++e) {
    if (m.edge_kind[e] == EdgeKind::kBridge) continue;
    EXPECT_LE((m.V.row(m.E(e, 0)) - m.V.row(m.E(e, 1))).norm(), l_u + 1e-9) << "edge " << e;
  }
}

std::vector<int> children_count(const IsolineMesh& m) {
  std::vector<int> count(m.loops.size(), 0);
  for (size_t id = 1; id < m.loops.size(); ++id) ++count[m.loops[id].parent];
  return count;
}

double printing_length(const IsolineMesh& m) {
  double sum = 0.0;
  for (int e = 0; e < m.E.rows(); ++e) {
    if (m.edge_kind[e] != EdgeKind::kBridge) {
      sum += (m.V.row(m.E(e, 0)) - m.V.row(m.E(e, 1))).norm();
    }
  }
  return sum;
}

// A Gaussian bump over a black border (the image's outer ring of pixels and the corners are 0).
GrayImage bump_image() {
  const int n = 41;
  GrayImage image{n, n, 8, std::vector<uint16_t>(n * n, 0)};
  const double c = 0.5 * (n - 1), sigma = 7.0;
  const double edge = std::exp(-(c * c) / (2.0 * sigma * sigma));
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const double r2 = (x - c) * (x - c) + (y - c) * (y - c);
      const double g = (std::exp(-r2 / (2.0 * sigma * sigma)) - edge) / (1.0 - edge);
      image.samples[y * n + x] = static_cast<uint16_t>(std::lround(255.0 * std::max(0.0, g)));
    }
  }
  return image;
}

class Examples : public ::testing::TestWithParam<std::string> {};

TEST_P(Examples, MeetsTheContract) {
  const HeightField field = height_field_example(GetParam());
  const IsolineMeshOptions options;
  const IsolineMesh m = isoline_mesh(field, options, GetParam());
  expect_valid(m, field, options.upsample_length_mm);
  // The boundary is level at z = 0 and the summit is kept: the highest vertex is the field's top.
  EXPECT_EQ(m.levels[0], 0.0);
  EXPECT_NEAR(m.V.col(2).maxCoeff(), field.V.col(2).maxCoeff(), 1e-12);
  // Automatic spacing: a twelfth of the height, give or take the saddle and summit levels.
  EXPECT_GE(m.levels.size(), 12);
  EXPECT_LE(m.levels.size(), 12 + 6);
}

TEST_P(Examples, RotatingTheFieldRotatesTheMesh) {
  const HeightField field = height_field_example(GetParam());
  HeightField turned = field;
  turned.V.col(0) = -field.V.col(1);
  turned.V.col(1) = field.V.col(0);
  const IsolineMesh a = isoline_mesh(field, {}, "a");
  const IsolineMesh b = isoline_mesh(turned, {}, "b");
  EXPECT_EQ(a.levels.size(), b.levels.size());
  EXPECT_EQ(a.loops.size(), b.loops.size());
  EXPECT_NEAR(printing_length(a), printing_length(b), 0.01 * printing_length(a));
  EXPECT_EQ(children_count(a), children_count(b));
}

// No needle bases: consecutive vertices along a loop are at least l_u / 4 apart along the
// isoline (a sixteenth of a loop shorter than 4 l_u), so a chord is at least l_u / 5 (its polygon
// at least 1/20 of its perimeter) unless the isoline bends by more than ~70 degrees within l_u / 4;
// the examples' input boundary vertices are about 2 mm apart. The saddle chains' printing edges
// (not bound by construction: a chain joins two anchors of different children) are checked against
// l_u / 5 as well.
TEST_P(Examples, PrintingEdgesAreNotNeedles) {
  const HeightField field = height_field_example(GetParam());
  const IsolineMeshOptions options;
  const double l_u = options.upsample_length_mm;
  const IsolineMesh m = isoline_mesh(field, options, GetParam());
  for (size_t id = 0; id < m.loops.size(); ++id) {
    const std::vector<int>& loop = m.loops[id].vertices;
    const int n = static_cast<int>(loop.size());
    double perimeter = 0.0;
    for (int i = 0; i < n; ++i) perimeter += (m.V.row(loop[i]) - m.V.row(loop[(i + 1) % n])).norm();
    const double least = std::min(l_u / 5.0, perimeter / 20.0);
    for (int i = 0; i < n; ++i) {
      const double length = (m.V.row(loop[i]) - m.V.row(loop[(i + 1) % n])).norm();
      EXPECT_GE(length, least) << "loop " << id << " at " << m.V.row(loop[i]);
    }
  }
  for (int e = 0; e < m.E.rows(); ++e) {
    const bool chain = m.vertex_loop[m.E(e, 0)] < 0 || m.vertex_loop[m.E(e, 1)] < 0;
    if (m.edge_kind[e] == EdgeKind::kBridge || !chain) continue;
    EXPECT_GE((m.V.row(m.E(e, 0)) - m.V.row(m.E(e, 1))).norm(), l_u / 5.0)
        << "edge at " << m.V.row(m.E(e, 0));
  }
}

INSTANTIATE_TEST_SUITE_P(IsolineMesh, Examples,
                         ::testing::Values("hill", "saddle", "island", "ridge"));

TEST(IsolineMesh, HillIsAChainOfLoops) {
  const IsolineMesh m = isoline_mesh(height_field_example("hill"), {}, "hill");
  EXPECT_EQ(m.loops.size(), static_cast<size_t>(m.levels.size()));
  for (int count : children_count(m)) EXPECT_LE(count, 1);
  // Equidistant levels 35/12 apart up to 11/12 of the height, then the summit level half-way
  // from there to the 35 mm summit.
  const double spacing = 35.0 / 12.0;
  ASSERT_EQ(m.levels.size(), 13);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(m.levels[i], i * spacing, 1e-4);
  EXPECT_NEAR(m.levels[12], 0.5 * (11.0 * spacing + 35.0), 1e-4);
  // One peak: one cap, at the summit (the centre).
  int centres = 0;
  for (int v = 0; v < m.V.rows(); ++v) {
    if (m.vertex_level[v] != -1) continue;
    ++centres;
    EXPECT_NEAR(m.V(v, 0), 0.0, 1e-9);
    EXPECT_NEAR(m.V(v, 1), 0.0, 1e-9);
  }
  EXPECT_EQ(centres, 1);
}

TEST(IsolineMesh, SaddleSplitsOneLoopInTwo) {
  const HeightField field = height_field_example("saddle");
  const IsolineMesh m = isoline_mesh(field, {}, "saddle");
  const std::vector<int> count = children_count(m);
  EXPECT_EQ(std::count(count.begin(), count.end(), 2), 1);
  EXPECT_EQ(*std::max_element(count.begin(), count.end()), 2);
  EXPECT_EQ(std::count(count.begin(), count.end(), 0), 2);  // two summits
  // The saddle polygon is fanned from the saddle itself: by symmetry at the origin, at the
  // field's height there (the lowest point of the crest between the peaks).
  const HeightLookup height(field);
  bool found = false;
  for (int v = 0; v < m.V.rows(); ++v) {
    if (m.vertex_level[v] == -1 && std::hypot(m.V(v, 0), m.V(v, 1)) < 1e-9) {
      found = true;
      EXPECT_NEAR(m.V(v, 2), height(0.0, 0.0), 1e-9);
    }
  }
  EXPECT_TRUE(found);
  // The saddle band: one level a quarter spacing below the saddle, one a quarter above.
  const double spacing = field.V.col(2).maxCoeff() / 12.0;
  const double saddle = height(0.0, 0.0);
  int band = 0;
  for (int i = 0; i < m.levels.size(); ++i) {
    if (std::abs(m.levels[i] - (saddle - 0.25 * spacing)) < 1e-4) ++band;
    if (std::abs(m.levels[i] - (saddle + 0.25 * spacing)) < 1e-4) ++band;
  }
  EXPECT_EQ(band, 2);
  // The loop with two children is the one just below the saddle.
  for (size_t id = 0; id < m.loops.size(); ++id) {
    if (count[id] == 2) {
      EXPECT_NEAR(m.levels[m.loops[id].level], saddle - 0.25 * spacing, 1e-4);
    }
  }
}

TEST(IsolineMesh, IslandHasThreeSummits) {
  const HeightField field = height_field_example("island");
  const IsolineMesh m = isoline_mesh(field, {}, "island");
  const std::vector<int> count = children_count(m);
  EXPECT_EQ(std::count(count.begin(), count.end(), 0), 3);
  // Each cap's centre is the highest point inside its top loop: a local maximum of the field.
  const HeightLookup height(field);
  for (size_t id = 0; id < m.loops.size(); ++id) {
    if (count[id] != 0) continue;
    const int any = m.loops[id].vertices[0];
    int centre = -1;
    for (int f = 0; f < m.F.rows() && centre < 0; ++f) {
      for (int k = 0; k < 3; ++k) {
        if (m.F(f, k) == any && m.vertex_level[m.F(f, (k + 1) % 3)] == -1) {
          centre = m.F(f, (k + 1) % 3);
        }
        if (m.F(f, k) == any && m.vertex_level[m.F(f, (k + 2) % 3)] == -1) {
          centre = m.F(f, (k + 2) % 3);
        }
      }
    }
    ASSERT_GE(centre, 0);
    const double z = m.V(centre, 2);
    EXPECT_GT(z, m.levels[m.loops[id].level]);
    for (double angle = 0.0; angle < 6.2; angle += 0.5) {
      EXPECT_LE(
          height(m.V(centre, 0) + 3.0 * std::cos(angle), m.V(centre, 1) + 3.0 * std::sin(angle)),
          z + 1e-9);
    }
  }
}

TEST(IsolineMesh, RidgeIsCappedAtItsTop) {
  const HeightField field = height_field_example("ridge");
  const IsolineMesh m = isoline_mesh(field, {}, "ridge");
  const std::vector<int> count = children_count(m);
  EXPECT_EQ(std::count(count.begin(), count.end(), 0), 1);
  EXPECT_NEAR(m.V.col(2).maxCoeff(), field.V.col(2).maxCoeff(), 1e-12);
}

TEST(IsolineMesh, ImageBumpOverABlackBorder) {
  const HeightField field = height_field_from_image(bump_image(), 60.0, 60.0, 10.0, 1.5, "b.png");
  IsolineMeshOptions options;
  options.upsample_length_mm = 1.0;
  const IsolineMesh m = isoline_mesh(field, options, "bump.png");
  expect_valid(m, field, options.upsample_length_mm);
  EXPECT_EQ(m.levels[0], 0.0);
  for (int count : children_count(m)) EXPECT_LE(count, 1);
}

TEST(IsolineMesh, OptionsChangeTheGraph) {
  const HeightField field = height_field_example("saddle");
  IsolineMeshOptions options;
  options.level_spacing_mm = 5.0;
  options.upsample_length_mm = 3.0;
  options.gradient_spacing_mm = 8.0;
  options.summit_levels = false;
  options.saddle_levels = false;
  const IsolineMesh m = isoline_mesh(field, options, "saddle");
  expect_valid(m, field, 3.0);
  // Only the equidistant levels: 0, 5, ..., 30 below the 35 mm top.
  ASSERT_EQ(m.levels.size(), 7);
  for (int i = 0; i < m.levels.size(); ++i) EXPECT_NEAR(m.levels[i], 5.0 * i, 1e-5);
}

TEST(IsolineMesh, TheInputFacesMayTurnEitherWay) {
  const HeightField field = height_field_example("saddle");
  HeightField clockwise = field;
  clockwise.F.col(1).swap(clockwise.F.col(2));
  const IsolineMesh a = isoline_mesh(field, {}, "a");
  const IsolineMesh b = isoline_mesh(clockwise, {}, "b");
  expect_valid(b, clockwise, IsolineMeshOptions{}.upsample_length_mm);
  EXPECT_EQ(a.V.rows(), b.V.rows());
  EXPECT_EQ(a.loops.size(), b.loops.size());
  EXPECT_NEAR(printing_length(a), printing_length(b), 1e-6 * printing_length(a));
}

TEST(IsolineMesh, IsDeterministic) {
  const HeightField field = height_field_example("island");
  const IsolineMesh a = isoline_mesh(field, {}, "island");
  const IsolineMesh b = isoline_mesh(field, {}, "island");
  EXPECT_TRUE(a.V == b.V);
  EXPECT_TRUE(a.F == b.F);
}

TEST(IsolineMesh, RefusesABoundaryThatIsNotLevel) {
  HeightField field = height_field_example("hill");
  const std::vector<int> boundary = boundary_loops(field.F)[0];
  const int raised = boundary[boundary.size() / 3];
  field.V(raised, 2) = 1.5;
  try {
    isoline_mesh(field, {}, "tilted.obj");
    ADD_FAILURE() << "accepted";
  } catch (const UserError& e) {
    const std::string message = e.what();
    EXPECT_EQ(e.category(), ErrorCategory::kGeometry);
    EXPECT_EQ(message.rfind("tilted.obj: ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find("not level"), std::string::npos) << message;
    EXPECT_NE(message.find("from 0.000 to 1.500 mm"), std::string::npos) << message;
    const std::string where =
        fmt::format("({:.1f}, {:.1f}) mm", field.V(raised, 0), field.V(raised, 1));
    EXPECT_NE(message.find(where), std::string::npos) << message;
    EXPECT_NE(message.find("black"), std::string::npos) << message;
  }
  // Within the tolerance (1e-3 of the 35 mm height) the boundary counts as level.
  field.V(raised, 2) = 0.02;
  const IsolineMesh m = isoline_mesh(field, {}, "tilted.obj");
  EXPECT_NEAR(m.levels[0], 0.02 / boundary.size(), 1e-12);
}

TEST(IsolineMesh, RefusesAFlatSurface) {
  HeightField field = height_field_example("hill");
  field.V.col(2).setZero();
  try {
    isoline_mesh(field, {}, "flat.obj");
    ADD_FAILURE() << "accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kGeometry);
    EXPECT_NE(std::string(e.what()).find("flat.obj: the surface is flat"), std::string::npos);
  }
}

TEST(IsolineMesh, RefusesBadOptions) {
  const HeightField field = height_field_example("hill");
  for (const auto& set : std::vector<void (*)(IsolineMeshOptions&)>{
           [](IsolineMeshOptions& o) { o.upsample_length_mm = 0.0; },
           [](IsolineMeshOptions& o) { o.level_spacing_mm = -1.0; },
           [](IsolineMeshOptions& o) { o.gradient_spacing_mm = std::nan(""); }}) {
    IsolineMeshOptions options;
    set(options);
    try {
      isoline_mesh(field, options, "hill");
      ADD_FAILURE() << "accepted";
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kOption);
    }
  }
}

}  // namespace
}  // namespace flatmorph::isoline_mesh_test
