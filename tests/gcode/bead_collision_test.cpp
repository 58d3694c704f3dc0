// The collision replay on hand-written G-code: concentric square rings printed in the unsafe and
// the safe order (note geodesy-tiles.md §4.6), rings out of the tip's reach, paths rising and
// descending along themselves, stacked layers, and the tolerance and tip width at their edges.
#include "gcode/bead_collision.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "gcode/gcode_replay.h"

namespace flatmorph::testing {
namespace {

// A layer's annotations, as PrusaSlicer writes them and gcode_replay expects them.
std::string layer(double z, double height) {
  return fmt::format(";LAYER_CHANGE\n;Z:{:.3f}\n;HEIGHT:{:.3f}\n;TYPE:Perimeter\n;WIDTH:0.4\n", z,
                     height);
}

// A square ring of half-side `half` around the origin, counter-clockwise from (-half, -half), its
// height going linearly from z_start to z_end along it, reached by a travel; beads `height` high.
std::string ring(double half, double z_start, double z_end, double height) {
  const double corners[5][2] = {
      {-half, -half}, {half, -half}, {half, half}, {-half, half}, {-half, -half}};
  std::string g = fmt::format(";HEIGHT:{:.3f}\nG1 X{:.4f} Y{:.4f} Z{:.4f} F9000\n", height,
                              corners[0][0], corners[0][1], z_start);
  for (int k = 1; k <= 4; ++k) {
    const double z = z_start + (z_end - z_start) * k / 4;
    g += fmt::format("G1 X{:.4f} Y{:.4f} Z{:.4f} E0.1 F1200\n", corners[k][0], corners[k][1], z);
  }
  return g;
}

std::vector<BeadCollision> replay(const std::string& body, CollisionOptions options = {}) {
  const ReadGcode read = read_gcode("M83\nG90\n" + body);
  EXPECT_TRUE(read.annotation_errors.empty()) << read.annotation_errors.front();
  return replay_collisions(read, options);
}

TEST(BeadCollision, ReaderGivesTheStartHeight) {
  const ReadGcode read = read_gcode("M83\nG90\n" + layer(0.3, 0.1) + ring(5, 0.1, 0.3, 0.1));
  ASSERT_EQ(read.layers.size(), 1u);
  ASSERT_EQ(read.layers[0].extrusions.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(read.layers[0].extrusions[k].z0, 0.1 + 0.05 * k, 1e-12) << k;
    EXPECT_NEAR(read.layers[0].extrusions[k].z, 0.15 + 0.05 * k, 1e-12) << k;
  }
}

TEST(BeadCollision, LowRingBesideATallerOneIsHit) {
  // Outer ring 0.3 mm high first, then the inner ring at 0.1 mm, 0.4 mm inside it: the tip
  // (radius 0.5) reaches the outer bead (edge 0.2 mm from the inner axis).
  const std::vector<BeadCollision> c =
      replay(layer(0.3, 0.3) + ring(5, 0.3, 0.3, 0.3) + ring(4.6, 0.1, 0.1, 0.1));
  ASSERT_EQ(c.size(), 4u);  // every side of the inner ring
  for (size_t k = 0; k < c.size(); ++k) {
    EXPECT_EQ(c[k].layer, 0);
    EXPECT_EQ(c[k].extrusion, 4 + k);
    EXPECT_NEAR(c[k].nozzle_z, 0.1, 1e-12);
    EXPECT_NEAR(c[k].bead_top, 0.3, 1e-12);
    EXPECT_NEAR(std::max(std::abs(c[k].x), std::abs(c[k].y)), 4.6, 1e-9);  // on the inner axis
  }
}

TEST(BeadCollision, AscendingOrderIsSafe) {
  // Note §4.6 rule 1: the low ring first, then the taller one over it.
  EXPECT_TRUE(replay(layer(0.3, 0.3) + ring(4.6, 0.1, 0.1, 0.1) + ring(5, 0.3, 0.3, 0.3)).empty());
}

TEST(BeadCollision, RingsOutOfReachNeverCollide) {
  EXPECT_TRUE(replay(layer(0.3, 0.3) + ring(5, 0.3, 0.3, 0.3) + ring(2, 0.1, 0.1, 0.1)).empty());
}

TEST(BeadCollision, PathRisingAlongItselfIsSafeDescendingIsNot) {
  EXPECT_TRUE(replay(layer(0.3, 0.2) + ring(5, 0.1, 0.3, 0.2)).empty());
  // Rim to centre, rising, one ring after the other (a dome's pass).
  EXPECT_TRUE(replay(layer(0.3, 0.2) + ring(5, 0.1, 0.2, 0.2) + ring(4.6, 0.2, 0.3, 0.2)).empty());
  // Descending, the last side runs at 0.1 over the ring's start at 0.3.
  const std::vector<BeadCollision> c = replay(layer(0.3, 0.2) + ring(5, 0.3, 0.1, 0.2));
  ASSERT_FALSE(c.empty());
  EXPECT_EQ(c.back().extrusion, 3u);
  EXPECT_GT(c.back().bead_top - c.back().nozzle_z, 0.1);
}

TEST(BeadCollision, StackedLayers) {
  EXPECT_TRUE(
      replay(layer(0.2, 0.2) + ring(5, 0.2, 0.2, 0.2) + layer(0.4, 0.2) + ring(5, 0.4, 0.4, 0.2))
          .empty());
  // A second layer below the first one's top.
  const std::vector<BeadCollision> c = replay(layer(0.2, 0.2) + ring(5, 0.2, 0.2, 0.2) +
                                              layer(0.15, 0.2) + ring(5, 0.15, 0.15, 0.2));
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0].layer, 1);
  EXPECT_EQ(c[0].extrusion, 0u);
}

TEST(BeadCollision, ToleranceAndTipWidth) {
  // Default tolerance for 0.1 mm beads: min(0.025, 0.02) = 0.02 mm.
  EXPECT_TRUE(
      replay(layer(0.2, 0.1) + ring(5, 0.115, 0.115, 0.1) + ring(4.6, 0.1, 0.1, 0.1)).empty());
  const std::string step = layer(0.2, 0.1) + ring(5, 0.13, 0.13, 0.1) + ring(4.6, 0.1, 0.1, 0.1);
  EXPECT_EQ(replay(step).size(), 4u);
  CollisionOptions loose;
  loose.tolerance = 0.05;
  EXPECT_TRUE(replay(step, loose).empty());
  // 0.9 mm apart: the outer bead's edge is 0.7 mm from the inner axis.
  const std::string apart = layer(0.3, 0.3) + ring(5, 0.3, 0.3, 0.3) + ring(4.1, 0.1, 0.1, 0.1);
  EXPECT_TRUE(replay(apart).empty());
  CollisionOptions wide;
  wide.tip_diameter = 2.0;
  EXPECT_EQ(replay(apart, wide).size(), 4u);
}

}  // namespace
}  // namespace flatmorph::testing
