// Rings of Geodesy tiles (note §4): inward offsets of the outline at the pitch, their containment
// tree and chains, and one continuous path through a chain. Checked against closed forms (discs,
// squares, holes), invariants (every vertex at its depth, rotation) and the path's geometry.
#include "methods/tiles/tile_rings.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "common/error.h"
#include "mesh/polygon.h"

namespace flatmorph::tile_rings_test {
namespace {

Eigen::MatrixX2d circle(double radius, int n, double cx = 0, double cy = 0) {
  Eigen::MatrixX2d points(n, 2);
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * kPi * i / n;
    points.row(i) << cx + radius * std::cos(angle), cy + radius * std::sin(angle);
  }
  return points;
}

Eigen::MatrixX2d polygon(std::initializer_list<std::pair<double, double>> xy) {
  Eigen::MatrixX2d points(static_cast<Eigen::Index>(xy.size()), 2);
  Eigen::Index i = 0;
  for (const auto& [x, y] : xy) points.row(i++) << x, y;
  return points;
}

TileOutline outline_of(Eigen::MatrixX2d boundary, std::string source = "test tile") {
  TileOutline outline;
  outline.boundary = std::move(boundary);
  outline.source = std::move(source);
  return outline;
}

// Sagitta of a 2000-gon of radius 15: 1.8e-5 mm, well inside the arc tolerance.
TileOutline disc(double radius) { return outline_of(circle(radius, 2000)); }

TileOutline square(double side) {
  const double h = side / 2;
  return outline_of(polygon({{-h, -h}, {h, -h}, {h, h}, {-h, h}}));
}

// Two 6 mm squares joined by a 1 mm wide, 4 mm long bar: the bar is gone at depth 0.6.
TileOutline dumbbell() {
  return outline_of(polygon({{0, 0},
                             {6, 0},
                             {6, 2.5},
                             {10, 2.5},
                             {10, 0},
                             {16, 0},
                             {16, 6},
                             {10, 6},
                             {10, 3.5},
                             {6, 3.5},
                             {6, 6},
                             {0, 6}}));
}

TileOutline l_shape() {
  return outline_of(polygon({{0, 0}, {12, 0}, {12, 5}, {5, 5}, {5, 12}, {0, 12}}));
}

double closed_length(const Eigen::MatrixX2d& loop) {
  double length = 0;
  for (Eigen::Index i = 0; i < loop.rows(); ++i) {
    length += (loop.row((i + 1) % loop.rows()) - loop.row(i)).norm();
  }
  return length;
}

double open_length(const Eigen::MatrixX2d& path) {
  double length = 0;
  for (Eigen::Index i = 0; i + 1 < path.rows(); ++i)
    length += (path.row(i + 1) - path.row(i)).norm();
  return length;
}

std::vector<int> level_sizes(const TileRings& rings) {
  std::vector<int> sizes;
  for (const Ring& ring : rings.rings) {
    if (ring.level >= static_cast<int>(sizes.size())) sizes.resize(ring.level + 1, 0);
    ++sizes[ring.level];
  }
  return sizes;
}

// Every vertex and every edge's midpoint of every ring lies at its depth from the outline, within
// the arc tolerance: half of it for simplifying the outline (either way), half for the chords of
// round joins (which only cut corners off the removed discs: less deep).
void expect_rings_at_their_depth(const TileOutline& outline, const TileRings& rings,
                                 double arc_tolerance) {
  const double slack = 2e-4;  // Clipper's integer grid and the simplification's own rounding
  for (size_t r = 0; r < rings.rings.size(); ++r) {
    const Ring& ring = rings.rings[r];
    for (Eigen::Index i = 0; i < ring.points.rows(); ++i) {
      const Eigen::Vector2d p = ring.points.row(i).transpose();
      const Eigen::Vector2d q = ring.points.row((i + 1) % ring.points.rows()).transpose();
      for (const Eigen::Vector2d& x : {p, Eigen::Vector2d((p + q) / 2)}) {
        const double depth = outline_depth(outline, x);
        ASSERT_GE(depth, ring.depth - arc_tolerance - slack) << "ring " << r << " edge " << i;
        ASSERT_LE(depth, ring.depth + arc_tolerance / 2 + slack) << "ring " << r << " edge " << i;
      }
    }
  }
}

TEST(TileRings, DiscRingsAreCirclesAtTheBeadCentres) {
  // Ring m exists iff its radius r_m = R − (m + ½)w reaches r_min = max(min_length/2π,
  // sqrt(min_area/π)): N = floor((R − w/2 − r_min)/w) + 1. R = 10 makes the two rules differ.
  const double radius = 10, w = 0.4;
  for (const bool defaults : {true, false}) {
    RingOptions options;
    options.pitch = w;
    if (!defaults) options.min_length = options.min_area = 0;
    const double r_min = defaults ? std::max(kPi * w / (2 * kPi), std::sqrt(w * w / kPi)) : 0.0;
    const int expected = static_cast<int>(std::floor((radius - w / 2 - r_min) / w)) + 1;
    EXPECT_EQ(expected, defaults ? 24 : 25);
    const TileRings rings = tile_rings(disc(radius), options);
    ASSERT_EQ(static_cast<int>(rings.rings.size()), expected) << "defaults " << defaults;
    for (int m = 0; m < expected; ++m) {
      const Ring& ring = rings.rings[m];
      EXPECT_EQ(ring.level, m);
      EXPECT_EQ(ring.parent, m - 1);
      EXPECT_NEAR(ring.depth, (m + 0.5) * w, 1e-12);
      EXPECT_GT(signed_area(ring.points), 0) << "ring " << m << " must be counter-clockwise";
      const double r = radius - (m + 0.5) * w;
      for (Eigen::Index i = 0; i < ring.points.rows(); ++i) {
        ASSERT_NEAR(ring.points.row(i).norm(), r, options.arc_tolerance) << "ring " << m;
      }
      // Starts at the smallest x.
      EXPECT_NEAR(ring.points(0, 0), -r, options.arc_tolerance);
      EXPECT_NEAR(ring.points(0, 1), 0, 0.05);
    }
    EXPECT_NEAR(rings.max_depth, radius * std::cos(kPi / 2000), 1e-5);
  }
}

TEST(TileRings, SquareRingsKeepSharpCorners) {
  // Inward offsets of a convex polygon keep its corners: ring m is a square of half side
  // 5.1 − (m + ½)w. Side 10.2 − (2m + 1)·0.4 ≥ w (area ≥ w²) gives m ≤ 11.
  const double w = 0.4;
  const TileOutline outline = square(10.2);
  const TileRings rings = tile_rings(outline);
  ASSERT_EQ(rings.rings.size(), 12u);
  for (int m = 0; m < 12; ++m) {
    const Ring& ring = rings.rings[m];
    const double h = 5.1 - (m + 0.5) * w;
    for (Eigen::Index i = 0; i < ring.points.rows(); ++i) {
      ASSERT_NEAR(ring.points.row(i).cwiseAbs().maxCoeff(), h, 1e-4) << "ring " << m;
    }
    for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
      double nearest = 1e9;
      for (Eigen::Index i = 0; i < ring.points.rows(); ++i) {
        nearest =
            std::min(nearest, (ring.points.row(i) - Eigen::RowVector2d(sx * h, sy * h)).norm());
      }
      EXPECT_LT(nearest, 1e-4) << "ring " << m << " lacks its corner (" << sx * h << ", " << sy * h
                               << ")";
    }
    EXPECT_NEAR(closed_length(ring.points), 8 * h, 1e-3);
  }
  EXPECT_NEAR(rings.max_depth, 5.1, 1e-3);
  EXPECT_EQ(ring_chains(rings).size(), 1u);
}

TEST(TileRings, LShapeRingsLieAtTheirDepthWithRoundReflexCorners) {
  const TileOutline outline = l_shape();
  const TileRings rings = tile_rings(outline);
  expect_rings_at_their_depth(outline, rings, 0.01);
  // Around the reflex corner (5, 5) each ring follows a quarter circle of radius depth: it passes
  // within the arc tolerance of the arc's middle on the diagonal.
  for (const Ring& ring : rings.rings) {
    const double d = ring.depth / std::sqrt(2.0);
    const Eigen::RowVector2d middle(5 - d, 5 - d);
    double nearest = 1e9;
    for (Eigen::Index i = 0; i < ring.points.rows(); ++i) {
      const Eigen::RowVector2d a = ring.points.row(i);
      const Eigen::RowVector2d ab = ring.points.row((i + 1) % ring.points.rows()) - a;
      const double t = std::clamp((middle - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (a + t * ab - middle).norm());
    }
    EXPECT_LT(nearest, 0.01 + 2e-4) << "ring at depth " << ring.depth;
  }
  // The widest inscribed circle touches x = 0, y = 0 and the reflex corner: centre (a, a) with
  // a = √2 (5 − a).
  EXPECT_NEAR(rings.max_depth, 5 * std::sqrt(2.0) / (1 + std::sqrt(2.0)), 1e-5);
}

TEST(TileRings, DumbbellSplitsIntoTwoChildrenOfOneRing) {
  const TileOutline outline = dumbbell();
  const TileRings rings = tile_rings(outline);
  expect_rings_at_their_depth(outline, rings, 0.01);
  const std::vector<int> sizes = level_sizes(rings);
  ASSERT_GE(sizes.size(), 3u);
  EXPECT_EQ(sizes[0], 1);
  EXPECT_EQ(sizes[1], 2);
  EXPECT_EQ(rings.rings[1].parent, 0);
  EXPECT_EQ(rings.rings[2].parent, 0);
  // Ordered by reference point: the left lobe first.
  EXPECT_LT(rings.rings[1].points(0, 0), 3);
  EXPECT_GT(rings.rings[2].points(0, 0), 9);
  // Each 6 mm lobe holds rings at depths 0.2 .. 2.6 (side 6 − 2·2.6 = 0.8 ≥ w).
  EXPECT_EQ(static_cast<int>(sizes.size()), 7);
  for (size_t level = 1; level < sizes.size(); ++level) EXPECT_EQ(sizes[level], 2);

  const std::vector<std::vector<int>> chains = ring_chains(rings);
  ASSERT_EQ(chains.size(), 3u);
  EXPECT_EQ(chains[0], std::vector<int>{0});
  ASSERT_EQ(chains[1].size(), 6u);
  ASSERT_EQ(chains[2].size(), 6u);
  EXPECT_EQ(chains[1][0], 1);
  EXPECT_EQ(chains[2][0], 2);
  std::vector<int> all;
  for (const std::vector<int>& chain : chains) {
    for (size_t k = 1; k < chain.size(); ++k) {
      EXPECT_EQ(rings.rings[chain[k]].parent, chain[k - 1]);
    }
    all.insert(all.end(), chain.begin(), chain.end());
  }
  std::sort(all.begin(), all.end());
  for (int i = 0; i < static_cast<int>(all.size()); ++i) EXPECT_EQ(all[i], i);
  // Siblings cannot follow each other in one path.
  EXPECT_THROW(join_rings(rings, {1, 2}), std::invalid_argument);
  // A chain can: it starts in the right lobe and stays there.
  const RingPath path = join_rings(rings, chains[2]);
  EXPECT_GT(path.points.col(0).minCoeff(), 10 - 1e-9);
}

TEST(TileRings, HoleRingsAreClockwiseAtTheirDistanceFromTheHole) {
  // A 20 mm square with a hole of radius 3 in its middle. Rings around the hole are circles of
  // radius 3 + depth until depth 3.5, where they meet the square's rings and the region splits
  // into four corners.
  TileOutline outline = square(20);
  outline.holes.push_back(circle(3, 400).colwise().reverse());
  const TileRings rings = tile_rings(outline);
  expect_rings_at_their_depth(outline, rings, 0.01);
  int around_holes = 0;
  for (size_t r = 0; r < rings.rings.size(); ++r) {
    const Ring& ring = rings.rings[r];
    if (signed_area(ring.points) > 0) continue;
    ++around_holes;
    EXPECT_LT(ring.depth, 3.5);
    for (Eigen::Index i = 0; i < ring.points.rows(); ++i) {
      ASSERT_NEAR(ring.points.row(i).norm(), 3 + ring.depth, 0.01);
    }
    if (ring.level > 0) {
      EXPECT_LT(signed_area(rings.rings[ring.parent].points), 0) << "ring " << r;
    }
  }
  EXPECT_EQ(around_holes, 9);  // depths 0.2 .. 3.4
  const std::vector<int> sizes = level_sizes(rings);
  for (int level = 0; level < 9; ++level) EXPECT_EQ(sizes[level], 2) << "level " << level;
  EXPECT_EQ(sizes[9], 4);  // the four corners
  // Chains: the outer rings down to level 8, then each corner; the hole's rings last.
  const std::vector<std::vector<int>> chains = ring_chains(rings);
  ASSERT_EQ(chains.size(), 6u);
  EXPECT_EQ(chains[0].size(), 9u);
  EXPECT_EQ(chains[5].size(), 9u);
  EXPECT_LT(signed_area(rings.rings[chains[5][0]].points), 0);
  // Around the hole the path still turns counter-clockwise, between the hole's rings.
  const RingPath path = join_rings(rings, chains[5]);
  for (Eigen::Index i = 0; i + 1 < path.points.rows(); ++i) {
    const Eigen::Vector2d a = path.points.row(i), b = path.points.row(i + 1);
    ASSERT_GT(a.x() * b.y() - a.y() * b.x(), 0) << "segment " << i;
    ASSERT_GE(a.norm(), 3.2 - 0.01);
    ASSERT_LE(a.norm(), 6.4 + 0.01);
  }
}

TEST(TileRings, RotatedOutlineGivesRotatedRings) {
  for (const TileOutline& outline : {dumbbell(), l_shape()}) {
    TileOutline turned = outline;
    const double angle = 0.7;
    Eigen::Matrix2d rotation;
    rotation << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    turned.boundary =
        (outline.boundary * rotation.transpose()).rowwise() + Eigen::RowVector2d(3.3, -1.7);
    const TileRings a = tile_rings(outline), b = tile_rings(turned);
    ASSERT_EQ(level_sizes(a), level_sizes(b));
    for (int level = 0; level < static_cast<int>(level_sizes(a).size()); ++level) {
      std::vector<double> la, lb;
      for (const Ring& ring : a.rings) {
        if (ring.level == level) la.push_back(closed_length(ring.points));
      }
      for (const Ring& ring : b.rings) {
        if (ring.level == level) lb.push_back(closed_length(ring.points));
      }
      std::sort(la.begin(), la.end());
      std::sort(lb.begin(), lb.end());
      for (size_t i = 0; i < la.size(); ++i) EXPECT_NEAR(la[i], lb[i], 1e-3) << "level " << level;
    }
    EXPECT_NEAR(a.max_depth, b.max_depth, 1e-3);
  }
}

TEST(TileRings, StoppingRuleDropsShortRings) {
  // min_length 3 mm on a disc of radius 5: rings need 2πr ≥ 3, r ≥ 0.477 (the area rule asks only
  // r ≥ 0.226): N = floor((5 − 0.2 − 3/2π)/0.4) + 1 = 11.
  RingOptions options;
  options.min_length = 3;
  const TileRings rings = tile_rings(disc(5), options);
  ASSERT_EQ(rings.rings.size(), 11u);
  for (const Ring& ring : rings.rings) EXPECT_GE(closed_length(ring.points), 3);
  // With the defaults (π·w, w²) no ring is shorter than π·w or smaller than w².
  for (const TileOutline& outline : {l_shape(), dumbbell(), disc(3.3), square(4.1)}) {
    for (const Ring& ring : tile_rings(outline).rings) {
      EXPECT_GE(closed_length(ring.points), kPi * 0.4);
      EXPECT_GE(signed_area(ring.points), 0.16);
    }
  }
}

TEST(TileRings, ChainsOfTheSquareWithAHoleAreDepthFirst) {
  TileOutline outline = square(20);
  outline.holes.push_back(circle(3, 400).colwise().reverse());
  const TileRings rings = tile_rings(outline);
  const std::vector<std::vector<int>> chains = ring_chains(rings);
  // Chain 0 ends at the split; its corner chains follow before the hole's chain.
  ASSERT_EQ(chains.size(), 6u);
  for (int c = 1; c < 5; ++c) EXPECT_EQ(rings.rings[chains[c][0]].parent, chains[0].back());
  EXPECT_EQ(rings.rings[chains[5][0]].parent, -1);
}

// Polar angle increases along every segment (the path winds counter-clockwise round the centre).
void expect_winding(const RingPath& path) {
  for (Eigen::Index i = 0; i + 1 < path.points.rows(); ++i) {
    const Eigen::Vector2d a = path.points.row(i), b = path.points.row(i + 1);
    ASSERT_GT(a.x() * b.y() - a.y() * b.x(), 0) << "segment " << i;
  }
}

// Points of a connector lie between the two rings' radii.
void expect_between_rings(const RingPath& path, double radius, double w, double tolerance) {
  for (Eigen::Index i = 0; i < path.points.rows(); ++i) {
    const double c = path.ring_coordinate(i);
    const double outer = radius - (std::floor(c) + 0.5) * w;
    const double inner = radius - (std::ceil(c) + 0.5) * w;
    ASSERT_LE(path.points.row(i).norm(), outer + tolerance) << "point " << i << " c " << c;
    ASSERT_GE(path.points.row(i).norm(), inner - tolerance) << "point " << i << " c " << c;
  }
}

TEST(JoinRings, DiscOutsideInIsOneBlendedPath) {
  const double radius = 10, w = 0.4;
  const TileRings rings = tile_rings(disc(radius));
  const int n = static_cast<int>(rings.rings.size());
  ASSERT_EQ(n, 24);
  std::vector<int> sequence(n);
  for (int i = 0; i < n; ++i) sequence[i] = i;
  EXPECT_EQ(ring_chains(rings), std::vector<std::vector<int>>{sequence});
  const RingPath path = join_rings(rings, sequence);
  ASSERT_EQ(path.points.rows(), path.ring_coordinate.size());
  EXPECT_EQ(path.ring_coordinate(0), 0);
  EXPECT_EQ(path.ring_coordinate(path.ring_coordinate.size() - 1), n - 1);
  for (Eigen::Index i = 0; i + 1 < path.ring_coordinate.size(); ++i) {
    ASSERT_LE(path.ring_coordinate(i), path.ring_coordinate(i + 1)) << "point " << i;
  }
  expect_between_rings(path, radius, w, 0.01);
  expect_winding(path);

  // Each blend is min(8w, L/4) long; a connector is only slightly longer than the arc it replaces.
  // The target on the next ring runs as far as the nozzle (blend), or, on small rings, at most w
  // (shorter / longer ring) ahead of the nozzle's projection, blend · r_{m+1} / r_m: the connector
  // advances at least the shorter of the two.
  double rings_length = 0, slack = 0;
  std::vector<double> blend(n), connector_run(n);
  for (int m = 0; m < n; ++m) {
    const double length = closed_length(rings.rings[m].points);
    rings_length += length;
    blend[m] = std::min(8 * w, length / 4);
    const double ratio = (radius - (m + 1.5) * w) / (radius - (m + 0.5) * w);
    connector_run[m] = std::min(blend[m], (blend[m] + w) * ratio);
    // A connector sweeps the angle blend / r_{m+1} at a mean radius between the rings.
    if (m + 1 < n)
      slack += std::hypot(blend[m], w) - blend[m] + blend[m] * w / (radius - (m + 1.5) * w);
  }
  const double length = open_length(path.points);
  EXPECT_GE(length, rings_length - 1e-3);
  EXPECT_LE(length, rings_length + slack);

  // Connectors run within atan(w / blend) of the rings' tangent; ring starts move along.
  std::vector<double> starts;
  for (Eigen::Index i = 0; i + 1 < path.points.rows(); ++i) {
    const double c0 = path.ring_coordinate(i), c1 = path.ring_coordinate(i + 1);
    if (c0 == c1) continue;
    const Eigen::Vector2d a = path.points.row(i), b = path.points.row(i + 1);
    const Eigen::Vector2d radial = ((a + b) / 2).normalized();
    const double angle = std::asin(std::abs((b - a).normalized().dot(radial)));
    const int m = static_cast<int>(std::floor(c0));
    // The bound holds against the rings' own chords, which turn by 2π/#P: allow half of that.
    const double chord_turn = kPi / static_cast<double>(rings.rings[m].points.rows());
    ASSERT_LE(angle, std::atan(w / connector_run[m]) + chord_turn + 0.005)
        << "segment " << i << " after ring " << m;
    if (c1 == std::floor(c1)) starts.push_back(std::atan2(b.y(), b.x()));
  }
  ASSERT_EQ(static_cast<int>(starts.size()), n - 1);
  for (size_t k = 1; k < starts.size(); ++k) {
    EXPECT_GT(std::abs(std::remainder(starts[k] - starts[k - 1], 2 * kPi)), 0.01) << k;
  }
  // The whole path winds round the centre once per ring, give or take the landings' advance.
  double winding = 0;
  for (Eigen::Index i = 0; i + 1 < path.points.rows(); ++i) {
    const Eigen::Vector2d a = path.points.row(i), b = path.points.row(i + 1);
    winding += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  }
  EXPECT_GT(winding, 2 * kPi * (n - 1));
  EXPECT_LT(winding, 2 * kPi * (n + 1));
}

TEST(JoinRings, SeamRotatesTheStart) {
  const TileRings rings = tile_rings(disc(5));
  const double r0 = 5 - 0.2;
  for (const double seam : {0.0, 0.25, 1.25, -0.75}) {
    JoinOptions options;
    options.seam = seam;
    const RingPath path = join_rings(rings, {0, 1, 2}, options);
    // From the reference point (−r0, 0), a quarter turn counter-clockwise is (0, −r0).
    const Eigen::RowVector2d expected =
        seam == 0 ? Eigen::RowVector2d(-r0, 0) : Eigen::RowVector2d(0, -r0);
    EXPECT_LT((path.points.row(0) - expected).norm(), 0.05) << "seam " << seam;
  }
}

TEST(JoinRings, DiscInsideOutWindsTheSameWay) {
  const double radius = 6, w = 0.4;
  const TileRings rings = tile_rings(disc(radius));
  const int n = static_cast<int>(rings.rings.size());
  std::vector<int> sequence(n);
  for (int i = 0; i < n; ++i) sequence[i] = n - 1 - i;
  const RingPath path = join_rings(rings, sequence);
  EXPECT_EQ(path.ring_coordinate(0), n - 1);
  EXPECT_EQ(path.ring_coordinate(path.ring_coordinate.size() - 1), 0);
  for (Eigen::Index i = 0; i + 1 < path.ring_coordinate.size(); ++i) {
    ASSERT_GE(path.ring_coordinate(i), path.ring_coordinate(i + 1)) << "point " << i;
  }
  expect_between_rings(path, radius, w, 0.01);
  expect_winding(path);
}

TEST(JoinRings, PaperModeJogsRadially) {
  const TileRings rings = tile_rings(disc(5));
  JoinOptions options;
  options.blend_length = 0;
  const RingPath path = join_rings(rings, {0, 1, 2, 3}, options);
  double rings_length = 0;
  for (int m = 0; m < 4; ++m) rings_length += closed_length(rings.rings[m].points);
  EXPECT_NEAR(open_length(path.points), rings_length + 3 * 0.4, 2e-3);
  // The jogs lie on the ray through the reference point (−r, 0).
  for (Eigen::Index i = 0; i + 1 < path.points.rows(); ++i) {
    if (path.ring_coordinate(i) == path.ring_coordinate(i + 1)) continue;
    EXPECT_NEAR(path.points(i, 1), 0, 0.05);
    EXPECT_NEAR(path.points(i + 1, 1), 0, 0.05);
    EXPECT_NEAR(path.points(i, 0) - path.points(i + 1, 0), -0.4, 1e-3);
  }
}

TEST(JoinRings, PointSpacingBoundsEverySegment) {
  const TileRings rings = tile_rings(square(10.2));
  JoinOptions options;
  options.point_spacing = 0.25;
  const RingPath coarse = join_rings(rings, {0, 1, 2, 3});
  const RingPath fine = join_rings(rings, {0, 1, 2, 3}, options);
  double longest = 0, longest_coarse = 0;
  for (Eigen::Index i = 0; i + 1 < fine.points.rows(); ++i) {
    longest = std::max(longest, (fine.points.row(i + 1) - fine.points.row(i)).norm());
  }
  for (Eigen::Index i = 0; i + 1 < coarse.points.rows(); ++i) {
    longest_coarse =
        std::max(longest_coarse, (coarse.points.row(i + 1) - coarse.points.row(i)).norm());
  }
  EXPECT_LE(longest, 0.25 + 1e-9);
  EXPECT_GT(longest_coarse, 5);  // the square's sides
  EXPECT_NEAR(open_length(fine.points), open_length(coarse.points), 1e-3);
}

TEST(JoinRings, RefusesSequencesThatAreNotNested) {
  const TileRings rings = tile_rings(disc(5));
  EXPECT_THROW(join_rings(rings, {}), std::invalid_argument);
  EXPECT_THROW(join_rings(rings, {0, 2}), std::invalid_argument);
  EXPECT_THROW(join_rings(rings, {1, 1}), std::invalid_argument);
  EXPECT_THROW(join_rings(rings, {0, 99}), std::invalid_argument);
  EXPECT_NO_THROW(join_rings(rings, {2, 1, 0}));
  JoinOptions bad;
  bad.seam = std::nan("");
  EXPECT_THROW(join_rings(rings, {0}, bad), UserError);
}

void expect_refused(const TileOutline& outline, const RingOptions& options, ErrorCategory category,
                    const std::vector<std::string>& fragments) {
  try {
    tile_rings(outline, options);
    ADD_FAILURE() << "accepted " << outline.source;
  } catch (const UserError& error) {
    EXPECT_EQ(error.category(), category) << error.what();
    for (const std::string& fragment : fragments) {
      EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos)
          << "'" << fragment << "' missing from: " << error.what();
    }
  }
}

TEST(TileRings, RefusesBadOutlinesNamingTheSourceAndAPoint) {
  // Radius 0.3 < first offset 0.2 + smallest ring radius 0.4/√π = 0.4257: diameter 0.851.
  expect_refused(outline_of(circle(0.3, 64), "tiny.dxf: CIRCLE at line 7"), {},
                 ErrorCategory::kGeometry,
                 {"tiny.dxf: CIRCLE at line 7", "at least 0.851 mm", "pitch 0.4 mm", "near ("});
  expect_refused(outline_of(polygon({{0, 0}, {10, 0}, {10, 10}, {0, 10}, {12, 5}}), "star.svg"), {},
                 ErrorCategory::kGeometry, {"star.svg", "crosses", "(10.000, 5.833)"});
  expect_refused(outline_of(polygon({{0, 0}, {10, 0}}), "two.dxf"), {}, ErrorCategory::kGeometry,
                 {"two.dxf", "2 distinct", "(0.000, 0.000)"});
  expect_refused(outline_of(polygon({{0, 0}, {5, 0}, {10, 0}, {7, 0}}), "line.dxf"), {},
                 ErrorCategory::kGeometry, {"line.dxf", "zero area"});
  TileOutline outside = square(10);
  outside.source = "layout.json: tile 3";
  outside.holes.push_back(circle(1, 32, 20, 0).colwise().reverse());
  expect_refused(outside, {}, ErrorCategory::kGeometry,
                 {"layout.json: tile 3", "hole 1", "outside the boundary"});
  TileOutline crossing = square(10);
  crossing.holes.push_back(circle(2, 32, 4.5, 0));
  expect_refused(crossing, {}, ErrorCategory::kGeometry, {"boundary and the hole 1", "(5.000"});
  RingOptions zero_pitch;
  zero_pitch.pitch = 0;
  expect_refused(square(10), zero_pitch, ErrorCategory::kOption, {"pitch 0 mm"});
}

TEST(TileRings, AcceptsRepeatedPointsAndEitherOrientation) {
  const TileRings a =
      tile_rings(outline_of(polygon({{0, 0}, {10, 0}, {10, 10}, {10, 10}, {0, 10}, {0, 0}})));
  const TileRings b = tile_rings(outline_of(polygon({{0, 10}, {10, 10}, {10, 0}, {0, 0}})));
  ASSERT_EQ(a.rings.size(), b.rings.size());
  for (size_t i = 0; i < a.rings.size(); ++i) EXPECT_TRUE(a.rings[i].points == b.rings[i].points);
}

TEST(TileRings, ThirtyMillimetreDiscAtPitch04) {
  // The size the note's checks use (D = 30 mm, w = 0.4): 37 rings, joined outside in.
  const TileRings rings = tile_rings(disc(15));
  ASSERT_EQ(rings.rings.size(), 37u);
  std::vector<int> sequence(37);
  for (int i = 0; i < 37; ++i) sequence[i] = i;
  const RingPath path = join_rings(rings, sequence);
  expect_between_rings(path, 15, 0.4, 0.01);
  expect_winding(path);
}

}  // namespace
}  // namespace flatmorph::tile_rings_test
