// The whole height-field method on a dome: the risen shape against the target, the G-code read
// back by the tests' own reader (layer heights within the thickness curve's range, one trace per
// hill), and a checkerboard screen print carried through the risen shape.
#include "methods/heightfield/design_height_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "examples/height_field_examples.h"
#include "gcode/gcode_replay.h"
#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "methods/heightfield/texture.h"
#include "plate/layer_stack.h"
#include "simulate/distance.h"
#include "test_support.h"

namespace flatmorph::design_height_field_test {
namespace {

// One design shared by the tests below: a 100 mm hill, 22 mm high (the default's proportions).
const HeightFieldDesign& hill_design() {
  static const HeightFieldDesign design = [] {
    HeightFieldDesignOptions options;
    options.material = load_material("pla-geodesy");
    options.path_options.path_width = 0.4;
    return design_height_field(height_field_example("hill", {100.0, 22.0, 2.0}), "hill", options);
  }();
  return design;
}

TEST(DesignHeightField, TheHillRisesToItsTarget) {
  const HeightFieldDesign& d = hill_design();
  EXPECT_LE(d.sheet.invalid_edge_percent, 5.0);
  EXPECT_EQ(d.sheet.flipped_faces, 0);
  EXPECT_TRUE(d.prediction.from_flat.converged) << d.prediction.from_flat.warning;
  EXPECT_EQ(d.prediction.side, 1);
  // The bar: within 2 % of the diagonal on average.
  EXPECT_LT(d.prediction.distance.mean_percent, 2.0);
  // The judge is the printed stack: the design's plate prints vertex_shrinkage, face by face.
  ASSERT_EQ(d.plate.shrinkage.size(), d.mesh.F.rows());
  for (Eigen::Index f = 0; f < d.mesh.F.rows(); ++f) {
    const double mean = (d.vertex_shrinkage(d.mesh.F(f, 0)) + d.vertex_shrinkage(d.mesh.F(f, 1)) +
                         d.vertex_shrinkage(d.mesh.F(f, 2))) /
                        3;
    ASSERT_NEAR(d.plate.wanted_shrinkage(f), mean, 1e-12) << f;
  }
  // Never worse than printing the flattening's shrink as it is.
  EXPECT_LE(d.prediction.distance.mean_mm, d.flattened_prediction.distance.mean_mm);
}

// The G-code read back by the tests' own reader (tests/gcode/gcode_replay.h, no code shared with
// src/gcode): every extruding move's layer height, both as the file tags it and as its filament
// says (volume / (length x width)), within the thickness curve's calibrated range; one trace per
// layer on a single hill (one run of extrusions without a travel between).
TEST(DesignHeightField, TheGcodePrintsEachSegmentWithinTheCurvesRange) {
  const HeightFieldDesign& d = hill_design();
  const Material material = load_material("pla-geodesy");
  const PrinterProfile printer = load_printer("generic-marlin");
  const GcodeResult gcode = make_gcode(d.paths.toolpath, printer, {material});
  const testing::ReadGcode read = testing::read_gcode(gcode.text);
  const ThicknessCurve& curve = *material.thickness_curve;
  ASSERT_EQ(read.layers.size(), static_cast<size_t>(curve.layers));
  const double filament_area = M_PI / 4 * printer.filament_diameter * printer.filament_diameter;
  for (size_t k = 0; k < read.layers.size(); ++k) {
    const testing::ReadLayer& layer = read.layers[k];
    ASSERT_FALSE(layer.extrusions.empty());
    int runs = 0;
    for (size_t i = 0; i < layer.extrusions.size(); ++i) {
      const testing::ReadExtrusion& e = layer.extrusions[i];
      EXPECT_GE(e.height, curve.min_layer_height - 1e-6) << "layer " << k + 1 << " move " << i;
      EXPECT_LE(e.height, curve.max_layer_height + 1e-6) << "layer " << k + 1 << " move " << i;
      const bool continues = i > 0 && std::hypot(e.x0 - layer.extrusions[i - 1].x1,
                                                 e.y0 - layer.extrusions[i - 1].y1) < 1e-6;
      if (!continues) ++runs;
      // The writer's bead: filament volume = 3D length x width x height (the nozzle climbs along
      // a segment whose layer height changes).
      const double dz = continues ? e.z - layer.extrusions[i - 1].z : 0.0;
      const double length =
          std::sqrt(std::pow(e.x1 - e.x0, 2) + std::pow(e.y1 - e.y0, 2) + dz * dz);
      if (continues && length > 0.2) {  // the file's E has 5 decimals: short moves say little
        const double height = e.filament * filament_area / (length * e.width);
        EXPECT_NEAR(height, e.height, 0.01) << "layer " << k + 1 << " move " << i;
      }
      // The nozzle rides on the layers below: z = (k + 1) h (SCF 2020 §6.4), both written to
      // 3 decimals.
      EXPECT_NEAR(e.z, (k + 1) * e.height, 5e-4 * (k + 2) + 1e-9)
          << "layer " << k + 1 << " move " << i;
    }
    EXPECT_EQ(runs, 1) << "layer " << k + 1;
  }
  ASSERT_EQ(d.paths.paths_per_hill.size(), 1u);
  EXPECT_EQ(d.paths.paths_per_hill[0], 1);
}

// The layer count is a design option: the stack the prediction and the optimizer simulate
// (flat.stack.json) and the paths (plate.gcode) print the same number of layers, so the plate
// simulated is as thick as the plate printed. Before, only the paths took it and the stack kept the
// curve's 6 layers: twice the printed thickness at 3.
TEST(DesignHeightField, ItsLayerCountIsTheSimulatedStacksAndThePrintedPathsAlike) {
  const Material material = load_material("pla-geodesy");
  const int num_layers = 3;
  ASSERT_NE(material.thickness_curve->layers, num_layers);
  HeightFieldDesignOptions options;
  options.material = material;
  options.num_layers = num_layers;
  options.path_options.path_width = 0.4;
  const HeightFieldDesign d =
      design_height_field(height_field_example("hill", {60.0, 13.0, 2.0}), "hill", options);

  const LayerStack& stack = d.plate.design.stack;
  ASSERT_EQ(stack.num_layers(), num_layers);
  ASSERT_EQ(d.flattened_plate.design.stack.num_layers(), num_layers);
  ASSERT_EQ(d.paths.toolpath.layers.size(), static_cast<size_t>(num_layers));
  const GcodeResult gcode =
      make_gcode(d.paths.toolpath, load_printer("generic-marlin"), {material});
  const testing::ReadGcode read = testing::read_gcode(gcode.text);
  ASSERT_EQ(read.layers.size(), static_cast<size_t>(num_layers));

  // The plate simulated: per face, num_layers layers of the face's layer height.
  const Eigen::VectorXd* layer_height = d.plate.design.design_fields.find_face("layer_height");
  ASSERT_NE(layer_height, nullptr);
  for (Eigen::Index f = 0; f < stack.num_faces(); ++f) {
    double thickness = 0;
    for (const Layer& layer : stack.layers) thickness += layer.printed_thickness(f);
    ASSERT_NEAR(thickness, num_layers * (*layer_height)(f), 1e-12) << f;
  }
  // The plate printed: its top layer's beads reach z = num_layers · h. The paths' σ is sampled
  // along the segments and the faces' at their corners, so the thickest bead and the thickest face
  // differ a little; a stack of the curve's 6 layers would be twice as thick.
  double printed_top = 0;
  for (const testing::ReadExtrusion& e : read.layers.back().extrusions) {
    printed_top = std::max(printed_top, e.z);
  }
  const double simulated_top = printed_thickness_range(stack).second;
  EXPECT_NEAR(simulated_top, printed_top, 0.25 * printed_top / num_layers);

  // The optimizer simulates the same plate: its first equilibrium, from the prediction's shape and
  // with the prediction's σ, is the prediction's.
  ASSERT_TRUE(d.optimized);
  EXPECT_LT(shape_distance(d.optimization.initial_V, d.flattened_prediction.aligned).max_mm, 1e-3);
}

// The texture bar: a checkerboard of 10 mm squares in the target's xy, printed on the
// sheet and carried through the simulated risen shape, keeps each square's area on the target
// within 10 %.
TEST(DesignHeightField, ACheckerboardKeepsItsSquaresAreasThroughTheRise) {
  const HeightFieldDesign& d = hill_design();
  const double square = 20.0;
  Eigen::MatrixXd colors(d.mesh.V.rows(), 3);
  for (Eigen::Index v = 0; v < d.mesh.V.rows(); ++v) {
    const long long i = static_cast<long long>(std::floor(d.mesh.V(v, 0) / square));
    const long long j = static_cast<long long>(std::floor(d.mesh.V(v, 1) / square));
    colors.row(v).setConstant(((i + j) % 2 + 2) % 2 == 0 ? 0.1 : 0.9);
  }
  ScreenPrintOptions options;
  options.dpi = 100;
  const ScreenPrint print =
      render_screen_print(d.plate.design.plate, d.mesh.V, d.mesh.F, colors, options);
  const SquareLabels labels =
      checkerboard_labels(print.placement, d.plate.design.plate, d.mesh.V, d.mesh.F, square);
  const CheckerboardCheck check = check_checkerboard(labels, d.plate.design.plate, d.mesh.V,
                                                     d.prediction.aligned, d.mesh.F, square);
  EXPECT_GT(check.squares_compared, 15);
  EXPECT_LT(check.worst_relative_error, 0.10)
      << "square (" << check.worst_square.x() << ", " << check.worst_square.y()
      << "): " << check.worst_risen_mm2 << " mm2 risen, " << check.worst_target_mm2
      << " on the target";
}

}  // namespace
}  // namespace flatmorph::design_height_field_test
