// The tiles' acceptance checks of issue 24: circular tiles risen by the shared simulator against
// the profile their printed shrink gives geometrically, the side each rises to, their print
// replayed against the printed beads, and the network examples.
#include "methods/tiles/design_tiles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "examples/tile_examples.h"
#include "gcode/bead_collision.h"
#include "gcode/gcode_check.h"
#include "gcode/gcode_replay.h"
#include "gcode/gcode_writer.h"
#include "material/material.h"
#include "material/thickness_curve.h"

namespace flatmorph::design_tiles_test {
namespace {

TileLayout one_tile(const std::string& profile, double radius, double height, int side) {
  TileLayout layout;
  layout.source = "test";
  TileSpec tile;
  tile.outline.boundary = circle_polygon({0, 0}, radius, 0.002);
  tile.outline.source = "test tile";
  tile.profile = profile;
  tile.height_mm = height;
  tile.side = side;
  layout.tiles.push_back(tile);
  return layout;
}

TilesDesignOptions default_options() {
  TilesDesignOptions options;
  options.material = load_material("pla-geodesy");
  options.lattice_material = options.material;
  return options;
}

// The bar of the issue: rings within 0.1 mm of where the printed shrink puts them, the depth from
// 0.2 R to the rim within 3 %, on the side asked.
void expect_risen_as_printed(const TilesDesign& design, int side) {
  ASSERT_TRUE(design.simulated);
  EXPECT_TRUE(design.simulation.converged) << design.simulation.warning;
  const TileMeasure& m = design.tiles[0].measure;
  EXPECT_TRUE(design.tiles[0].circular);
  EXPECT_LT(m.ring_radius_error_mm, 0.1);
  EXPECT_LT(std::abs(m.depth_error_pct), 3.0) << m.depth_mm << " vs " << m.expected_depth_mm;
  EXPECT_EQ(m.side, side);
  EXPECT_GT(m.height_mm, 0.5 * m.expected_height_mm);
}

TEST(DesignTiles, AConeRisesAsItsUniformShrinkGives) {
  // Sh = 0.2 everywhere: a cone of slope acos(0.8), 9 mm high on a 15 mm flat radius.
  const TilesDesign design = design_tiles(one_tile("cone", 15, 9, +1), default_options());
  const TileLevels& levels = design.tiles[0].levels;
  for (const RingLevel& level : levels.levels) {
    EXPECT_NEAR(level.wanted, 0.2, 2e-3);
    EXPECT_EQ(level.clamped, 0);
  }
  EXPECT_FALSE(levels.printability.any_clamped);
  expect_risen_as_printed(design, +1);
}

TEST(DesignTiles, AParaboloidWithAClampedApexRisesAsTheClampedShrinkGives) {
  const TilesDesign design = design_tiles(one_tile("paraboloid", 15, 7, +1), default_options());
  const TileLevels& levels = design.tiles[0].levels;
  EXPECT_TRUE(levels.printability.any_clamped);
  EXPECT_EQ(levels.levels.back().clamped, -1);  // the innermost ring asks for less than the least
  EXPECT_EQ(levels.levels.front().clamped, 0);
  EXPECT_FALSE(design.warnings.empty());
  expect_risen_as_printed(design, +1);
}

TEST(DesignTiles, TheTileAskedToRiseDownRisesDownAsTheMirrorImage) {
  const TilesDesign up = design_tiles(one_tile("cone", 15, 9, +1), default_options());
  const TilesDesign down = design_tiles(one_tile("cone", 15, 9, -1), default_options());
  expect_risen_as_printed(down, -1);
  EXPECT_NEAR(down.tiles[0].measure.height_mm, up.tiles[0].measure.height_mm,
              0.03 * up.tiles[0].measure.height_mm);
  // The bilayer's halves swap: the bed side shrinks more to rise up, less to rise down.
  const RingLevel& a = up.tiles[0].levels.levels[5];
  const RingLevel& b = down.tiles[0].levels.levels[5];
  EXPECT_GT(a.bed_shrinkage, a.top_shrinkage);
  EXPECT_LT(b.bed_shrinkage, b.top_shrinkage);
  EXPECT_NEAR(a.bed_shrinkage, b.top_shrinkage, 1e-12);
}

// Every built-in layout: one continuous path per tile and pass, a G-code that passes the check,
// no bead the nozzle runs into when the file is replayed, layer heights within the curve's range.
TEST(DesignTiles, TheExamplesPrintOnePathPerTileAndPassWithoutRunningIntoTheirBeads) {
  TilesDesignOptions options = default_options();
  options.simulate = false;
  const PrinterProfile printer = load_printer("generic-marlin");
  const ThicknessCurve& curve = *options.material.thickness_curve;
  for (const std::string& name : tile_example_names()) {
    SCOPED_TRACE(name);
    const TilesDesign design = design_tiles(tile_layout_example(name), options);
    for (const std::vector<int>& passes : design.print.paths_per_pass) {
      for (int paths : passes) EXPECT_EQ(paths, 1);
    }
    const GcodeResult gcode =
        make_gcode(design.print.toolpath, printer, design.plate.design.stack.materials);
    EXPECT_TRUE(check_gcode(gcode.text, printer, design.plate.design.stack.materials).empty());
    const testing::ReadGcode read = testing::read_gcode(gcode.text);
    const std::vector<testing::BeadCollision> collisions =
        testing::replay_collisions(read, testing::CollisionOptions{});
    EXPECT_TRUE(collisions.empty()) << collisions.size() << " collisions, the first at ("
                                    << (collisions.empty() ? 0 : collisions[0].x) << ", "
                                    << (collisions.empty() ? 0 : collisions[0].y) << ")";
    for (const testing::ReadLayer& layer : read.layers) {
      for (const testing::ReadExtrusion& e : layer.extrusions) {
        if (e.type == "Solid infill") continue;  // the lattice prints its own layer height
        EXPECT_GE(e.height, curve.min_layer_height - 1e-3);
        EXPECT_LE(e.height, curve.max_layer_height + 1e-3);
      }
    }
  }
}

// A square of side 2 h with corners rounded to radius c, counter-clockwise.
Eigen::MatrixX2d rounded_square(double h, double c) {
  std::vector<Eigen::Vector2d> points;
  const double corner[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d centre(corner[k][0] * (h - c), corner[k][1] * (h - c));
    for (int i = 0; i <= 8; ++i) {
      const double a = (k + i / 8.0) * std::numbers::pi / 2;
      points.push_back(centre + c * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
  }
  Eigen::MatrixX2d out(points.size(), 2);
  for (size_t i = 0; i < points.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = points[i];
  return out;
}

// The bar of issue 24: at least 2x closer to the target than the circle's mapping Sh′ alone, as
// judged from the flat sheet again (about 12x: 0.49 -> 0.04 mm on this 6 mm cap).
TEST(DesignTiles, TheOptimizedShrinkBringsARoundedSquareTwiceCloserThanTheCirclesMapping) {
  TileLayout layout = one_tile("spherical-cap", 15, 6, +1);
  layout.tiles[0].outline.boundary = rounded_square(15, 4);
  const TilesDesign design = design_tiles(layout, default_options());
  const TileResult& tile = design.tiles[0];
  EXPECT_FALSE(tile.circular);
  ASSERT_TRUE(tile.optimized) << tile.mapped_profile_rms_mm << " mm with Sh' alone";
  EXPECT_LT(2 * tile.measure.profile_rms_mm, tile.mapped_profile_rms_mm)
      << tile.measure.profile_rms_mm << " vs " << tile.mapped_profile_rms_mm << " mm";
  // The optimized shrink stays printable.
  const auto [least, most] = reachable_shrinkage(*default_options().material.thickness_curve);
  for (const RingLevel& level : tile.levels.levels) {
    EXPECT_GE(level.shrinkage, least - 1e-12);
    EXPECT_LE(level.shrinkage, most + 1e-12);
  }
  EXPECT_TRUE(design.simulation.converged);
  EXPECT_EQ(tile.measure.side, +1);
}

}  // namespace
}  // namespace flatmorph::design_tiles_test
