// Beads rasterized onto a plate (src/gcode/deposited_plate.h): coverage, direction and thickness
// of what was deposited, per face and layer, against beads laid out by hand.
#include "gcode/deposited_plate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/error.h"
#include "plate/layer_stack.h"
#include "plate/plate_fixtures.h"

namespace flatmorph::deposited_plate_test {
namespace {

constexpr double kWidth = 0.4;

// Parallel beads along `angle` (rad) at the spacing of their width, covering the disk of radius
// `radius` around the origin (and more), in layer `layer` at nozzle height z, bed coordinates.
void add_hatch(GcodeDeposition& d, double angle, double radius, int layer, double z, double height,
               int tool = 0, double x_max = INFINITY, double feed_rate = 1800,
               double x_min = -INFINITY) {
  const Eigen::Vector2d along(std::cos(angle), std::sin(angle));
  const Eigen::Vector2d across(-along.y(), along.x());
  const int lines = static_cast<int>(std::ceil(radius / kWidth)) + 1;
  for (int i = -lines; i <= lines; ++i) {
    Eigen::Vector2d a = i * kWidth * across - radius * along;
    Eigen::Vector2d b = i * kWidth * across + radius * along;
    // Clip to x_min <= x <= x_max (hatches along y only in the tests that use it).
    if (a.x() > x_max || a.x() < x_min) continue;
    DepositedBead bead;
    bead.start = Eigen::Vector3d(a.x(), a.y(), z);
    bead.end = Eigen::Vector3d(b.x(), b.y(), z);
    bead.width = kWidth;
    bead.height = height;
    bead.feed_rate = feed_rate;
    bead.tool = tool;
    bead.layer = layer;
    d.beads.push_back(bead);
  }
  d.num_layers = std::max(d.num_layers, layer + 1);
}

// Faces whose every corner lies at least `margin` inside the rectangle's border.
std::vector<int> interior_faces(const testing::TestPlate& plate, double half_x, double half_y,
                                double margin) {
  std::vector<int> faces;
  for (Eigen::Index f = 0; f < plate.F.rows(); ++f) {
    bool inside = true;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector2d p = plate.V.row(plate.F(f, c));
      inside = inside && std::abs(p.x()) <= half_x - margin && std::abs(p.y()) <= half_y - margin;
    }
    if (inside) faces.push_back(static_cast<int>(f));
  }
  return faces;
}

double axial_difference(double a, double b) {
  return std::abs(std::remainder(a - b, std::numbers::pi));
}

TEST(RasterizeDeposition, HatchedLayersCoverEveryFaceAlongTheirLines) {
  const testing::TestPlate plate = testing::rectangle_plate(40, 20, 40, 20);
  for (const double angle : {0.0, std::numbers::pi / 6, -1.2}) {
    GcodeDeposition d;
    add_hatch(d, angle, 30, 0, 0.2, 0.2);
    add_hatch(d, angle + std::numbers::pi / 2, 30, 1, 0.35, 0.15);
    const std::vector<DepositedLayer> layers = rasterize_deposition(d, plate.V, plate.F);
    ASSERT_EQ(layers.size(), 2u);
    for (int f : interior_faces(plate, 20, 10, 0.0)) {
      EXPECT_NEAR(layers[0].coverage(f), 1, 1e-12) << f;
      EXPECT_NEAR(layers[0].thickness(f), 0.2, 1e-12) << f;
      EXPECT_LT(axial_difference(layers[0].theta(f), angle), 1e-9) << f;
      EXPECT_NEAR(layers[1].thickness(f), 0.15, 1e-12) << f;
      EXPECT_LT(axial_difference(layers[1].theta(f), angle + std::numbers::pi / 2), 1e-9) << f;
      EXPECT_EQ(layers[1].tool(f), 0);
      EXPECT_NEAR(layers[1].feed_rate(f), 1800, 1e-9);
    }
  }
}

// A layer printed over half the plate: the other half is not covered by it, and a thicker bead
// on the covered half counts from the top of the layer below.
TEST(DepositedPlate, PartialLayersLeaveTheirFacesUncovered) {
  const testing::TestPlate plate = testing::rectangle_plate(20, 10, 20, 10);
  GcodeDeposition d;
  add_hatch(d, std::numbers::pi / 2, 15, 0, 0.2, 0.2);
  // Lines along y at x = i * width: the left half only.
  add_hatch(d, std::numbers::pi / 2, 15, 1, 0.5, 0.3, 0, -0.5);
  const Material pla = load_material("pla-paper");
  const DepositedPlate p = deposited_plate(d, plate.V, plate.F, {pla}, "test");
  EXPECT_EQ(p.removed_faces, 0);
  ASSERT_EQ(p.design.stack.num_layers(), 2);
  const Layer& top = p.design.stack.layers[1];
  for (Eigen::Index f = 0; f < plate.F.rows(); ++f) {
    double x_max = -INFINITY, x_min = INFINITY;
    for (int c = 0; c < 3; ++c) {
      x_max = std::max(x_max, plate.V(plate.F(f, c), 0));
      x_min = std::min(x_min, plate.V(plate.F(f, c), 0));
    }
    if (x_max <= -1) {
      ASSERT_TRUE(top.covers(f)) << f;
      EXPECT_NEAR(top.printed_thickness(f), 0.3, 1e-12);
    }
    if (x_min >= 0) {
      EXPECT_FALSE(top.covers(f)) << f;
    }
  }
}

// A plate mesh of two pieces apart, both printed on: the larger is the plate, the smaller would
// float free and is left out, counted apart from faces the file does not print.
TEST(DepositedPlate, OfAPlateInPiecesTheLargestIsKeptAndTheRestCountedAsLoose) {
  const testing::TestPlate big = testing::rectangle_plate(20, 10, 20, 10);  // 400 faces
  const testing::TestPlate small = testing::rectangle_plate(4, 4, 4, 4);    // 32 faces
  testing::TestPlate plate;
  plate.V.resize(big.V.rows() + small.V.rows(), 2);
  plate.V << big.V, small.V.rowwise() + Eigen::RowVector2d(-20, 0);  // x in [-22, -18]
  plate.F.resize(big.F.rows() + small.F.rows(), 3);
  plate.F << big.F, small.F.array() + static_cast<int>(big.V.rows());
  GcodeDeposition d;
  add_hatch(d, std::numbers::pi / 2, 30, 0, 0.2, 0.2);
  const DepositedPlate p =
      deposited_plate(d, plate.V, plate.F, {load_material("pla-paper")}, "test");
  EXPECT_EQ(p.loose_faces, small.F.rows());
  EXPECT_EQ(p.removed_faces, small.F.rows());
  EXPECT_EQ(p.design.F.rows(), big.F.rows());
}

// A lattice: lines 0.4 mm wide every 2.5 mm, along y in layer 1 and along x in layer 2. Each face
// a line crosses gets a layer as thick as the line's bead (not its volume smeared over the face),
// covering the share of the face under it; the shares add up to the lines' area.
TEST(DepositedPlate, ALatticeKeepsItsLinesHeightAndCoversTheirShare) {
  const testing::TestPlate plate = testing::rectangle_plate(20, 10, 20, 10);
  GcodeDeposition d;
  d.num_layers = 2;
  for (int layer = 0; layer < 2; ++layer) {
    for (double u = -8.75; u < 10; u += 2.5) {
      DepositedBead bead;
      const double z = 0.2 * (layer + 1);
      bead.start = layer == 0 ? Eigen::Vector3d(u, -6, z) : Eigen::Vector3d(-11, u / 2, z);
      bead.end = layer == 0 ? Eigen::Vector3d(u, 6, z) : Eigen::Vector3d(11, u / 2, z);
      bead.width = kWidth;
      bead.height = 0.2;
      bead.feed_rate = 1500;
      bead.layer = layer;
      d.beads.push_back(bead);
    }
  }
  DepositedPlateOptions options;
  options.min_coverage = 0.01;
  const DepositedPlate p =
      deposited_plate(d, plate.V, plate.F, {load_material("pla-paper")}, "test", options);
  ASSERT_EQ(p.design.stack.num_layers(), 2);
  double covered_area[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const Layer& l = p.design.stack.layers[k];
    for (Eigen::Index i = 0; i < p.design.F.rows(); ++i) {
      if (!l.covers(i)) continue;
      const Eigen::Vector2d a = p.design.plate.row(p.design.F(i, 0)).transpose(),
                            b = p.design.plate.row(p.design.F(i, 1)).transpose(),
                            c = p.design.plate.row(p.design.F(i, 2)).transpose();
      // The second family keeps its height where it lies on the bed between the first's lines.
      EXPECT_NEAR(l.printed_thickness(i), 0.2, 1e-12) << i;
      EXPECT_GT(l.cover(i), 0.0);
      EXPECT_LE(l.cover(i), 1.0);
      covered_area[k] +=
          l.cover(i) * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x()) / 2;
    }
  }
  // Eight lines 10 mm long along y, eight 20 mm long along x (1.25 mm apart: twice as dense).
  EXPECT_NEAR(covered_area[0], 8 * kWidth * 10, 0.05 * 8 * kWidth * 10);
  EXPECT_NEAR(covered_area[1], 8 * kWidth * 20, 0.05 * 8 * kWidth * 20);
}

// Beads printed the way the Shrink & Morph stack builder describes (n layers of one height along
// theta1 + w_k theta2) give back that builder's stack: the same thickness, direction and shrink
// ratios (the bilayer gradient included) on every face they cover.
TEST(DepositedPlate, APrintedShrinkMorphStackReadsBackAsItsDesign) {
  const testing::TestPlate plate = testing::rectangle_plate(30, 30, 15, 15);
  const Material pla = load_material("pla-paper");
  const int n = 6;
  const double theta1 = 0.3, theta2 = 0.8;
  GcodeDeposition d;
  for (int k = 1; k <= n; ++k) {
    add_hatch(d, theta1 + shrink_morph_layer_weight(k, n) * theta2, 25, k - 1, k * pla.layer_height,
              pla.layer_height);
  }
  const DepositedPlate p = deposited_plate(d, plate.V, plate.F, {pla}, "test");
  const int nf = static_cast<int>(plate.F.rows());
  const LayerStack expected =
      shrink_morph_layer_stack(Eigen::VectorXd::Constant(nf, theta1),
                               Eigen::VectorXd::Constant(nf, theta2), pla, n, pla.layer_height);
  ASSERT_EQ(p.design.stack.num_layers(), n);
  ASSERT_EQ(p.design.F.rows(), nf);
  for (int k = 0; k < n; ++k) {
    const Layer& got = p.design.stack.layers[k];
    const Layer& want = expected.layers[k];
    for (int f = 0; f < nf; ++f) {
      EXPECT_NEAR(got.printed_thickness(f), want.printed_thickness(f), 1e-12);
      EXPECT_LT(axial_difference(got.theta(f), want.theta(f)), 1e-9);
      EXPECT_NEAR(got.lambda1(f), want.lambda1(f), 1e-12);
      EXPECT_NEAR(got.delta_lambda1(f), want.delta_lambda1(f), 1e-12);
      EXPECT_EQ(got.lambda2(f), want.lambda2(f));
      EXPECT_EQ(got.lambda3(f), want.lambda3(f));
    }
  }
}

// One layer printed at 20 mm/s on the left half and 60 mm/s on the right (feed rates 1200 and
// 3600 mm/min): with a speed curve the halves get the material's lambda1 scaled by the curve's
// ratio to its value at print_speed; without one they are the same.
TEST(DepositedPlate, ASpeedCurveGivesEachSpeedItsLambda1) {
  const testing::TestPlate plate = testing::rectangle_plate(20, 10, 20, 10);
  GcodeDeposition d;
  const double h = 0.2;
  add_hatch(d, std::numbers::pi / 2, 15, 0, h, h, 0, -0.2, 1200);
  add_hatch(d, std::numbers::pi / 2, 15, 0, h, h, 0, INFINITY, 3600, -0.2 + kWidth / 2);
  Material plain = load_material("pla-paper");  // lambda1 0.58 at print_speed 30 mm/s
  Material curved = plain;
  curved.speed_curve = SpeedCurve{{0.7, -0.002}, 20, 100, 0.08, 190};  // 0.64 at 30 mm/s
  const double slow = 0.58 * (0.7 - 0.002 * 20) / 0.64, fast = 0.58 * (0.7 - 0.002 * 60) / 0.64;
  for (const Material& m : {plain, curved}) {
    const DepositedPlate p = deposited_plate(d, plate.V, plate.F, {m}, "test");
    ASSERT_EQ(p.design.stack.num_layers(), 1);
    const Layer& layer = p.design.stack.layers[0];
    int left = 0, right = 0;
    for (Eigen::Index f = 0; f < p.design.F.rows(); ++f) {
      double x_min = INFINITY, x_max = -INFINITY;
      for (int c = 0; c < 3; ++c) {
        x_min = std::min(x_min, p.design.plate(p.design.F(f, c), 0));
        x_max = std::max(x_max, p.design.plate(p.design.F(f, c), 0));
      }
      // One layer: no bilayer offset, lambda1 is the bead's.
      if (x_max <= -1) {
        EXPECT_NEAR(layer.lambda1(f), m.speed_curve ? slow : 0.58, 1e-12) << f;
        ++left;
      } else if (x_min >= 1) {
        EXPECT_NEAR(layer.lambda1(f), m.speed_curve ? fast : 0.58, 1e-12) << f;
        ++right;
      }
    }
    EXPECT_GT(left, 20);
    EXPECT_GT(right, 20);
  }
}

TEST(DepositedPlate, ATwoToolPlateNeedsAMaterialPerTool) {
  const testing::TestPlate plate = testing::rectangle_plate(10, 10, 5, 5);
  GcodeDeposition d;
  add_hatch(d, 0, 10, 0, 0.2, 0.2, 0);
  add_hatch(d, 0, 10, 1, 0.4, 0.2, 1);
  const Material pla = load_material("pla-paper");
  EXPECT_THROW(deposited_plate(d, plate.V, plate.F, {pla}, "test"), UserError);
  const DepositedPlate p = deposited_plate(d, plate.V, plate.F, {pla, pla}, "test");
  EXPECT_EQ(p.design.stack.layers[1].material(0), 1);
}

// The footprint of the first layer, meshed on a lattice: a disk of beads gives a disk of cells.
TEST(FootprintPlate, MeshesTheCellsUnderTheFirstLayer) {
  GcodeDeposition d;
  // Concentric rings of radius 2..20 mm, 64 chords each.
  for (double r = 2; r <= 20 + 1e-9; r += kWidth) {
    for (int i = 0; i < 64; ++i) {
      const double a0 = 2 * std::numbers::pi * i / 64, a1 = 2 * std::numbers::pi * (i + 1) / 64;
      DepositedBead bead;
      bead.start = Eigen::Vector3d(r * std::cos(a0), r * std::sin(a0), 0.2);
      bead.end = Eigen::Vector3d(r * std::cos(a1), r * std::sin(a1), 0.2);
      bead.width = kWidth;
      bead.height = 0.2;
      d.beads.push_back(bead);
    }
  }
  d.num_layers = 1;
  const FootprintMesh mesh = footprint_plate(d, "rings");
  double area = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector2d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                          c = mesh.V.row(mesh.F(f, 2));
    const double signed_area = ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x()) / 2;
    EXPECT_GT(signed_area, 0) << "counter-clockwise faces";
    area += signed_area;
  }
  // The annulus 1.8 < r < 20.2 (the rings' outer edges), within the lattice's staircase.
  const double expected = std::numbers::pi * (20.2 * 20.2 - 1.8 * 1.8);
  EXPECT_NEAR(area, expected, 0.03 * expected);
  EXPECT_THROW(footprint_plate(GcodeDeposition{}, "empty"), UserError);
}

}  // namespace
}  // namespace flatmorph::deposited_plate_test
