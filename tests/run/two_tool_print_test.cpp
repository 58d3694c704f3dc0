// A plate of two materials prints as one file for a two-tool printer: each layer's tool is its
// material's in the stack, the G-code passes the safety check against the stack's materials, and
// tools change exactly where the layers do (issue 20, item 4, end to end from a PlateDesign).
#include <gtest/gtest.h>

#include <string>

#include "gcode/gcode_check.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "plate/plate_fixtures.h"
#include "run/print_plan.h"

namespace flatmorph::two_tool_print_test {
namespace {

TEST(TwoToolPrint, EachLayerPrintsWithItsMaterialsTool) {
  const testing::TestPlate p = testing::rectangle_plate(30, 20, 12, 8);
  const int nf = static_cast<int>(p.F.rows());
  PlateDesign design;
  design.plate = p.V;
  design.F = p.F;
  const Material pla = load_material("pla-paper"), tpu = load_material("tpu-generic");
  design.stack = shrink_morph_layer_stack(Eigen::VectorXd::Zero(nf), Eigen::VectorXd::Zero(nf), pla,
                                          4, pla.layer_height);
  // A TPU layer on the bed and one in the middle: PLA actuators on a soft skin.
  design.stack.materials.push_back(tpu);
  for (int k : {0, 2}) design.stack.layers[k] = uniform_layer(nf, 1, tpu, 0.12);
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  const PrintPlan plan = plan_print(design, printer, {});
  EXPECT_TRUE(check_gcode(plan.gcode.text, printer, design.stack.materials).empty());
  // The wrong way round is unsafe: each tool is judged by its own material.
  EXPECT_FALSE(check_gcode(plan.gcode.text, printer, {tpu, pla}).empty());
  ASSERT_EQ(plan.paths.toolpath.layers.size(), 4u);
  const int tools[4] = {1, 0, 1, 0};
  for (int k = 0; k < 4; ++k) {
    for (const PathPolyline& path : plan.paths.toolpath.layers[k].paths) {
      for (const SegmentStyle& s : path.segments) EXPECT_EQ(s.tool, tools[k]) << "layer " << k;
    }
  }
  // T0 is active after the start G-code: T0 -> T1 -> T0 -> T1 -> T0.
  EXPECT_EQ(plan.gcode.tool_changes, 4);
  EXPECT_GT(plan.gcode.tool_filament_mass.at(0), 0);
  EXPECT_GT(plan.gcode.tool_filament_mass.at(1), 0);
  EXPECT_NEAR(plan.paths.toolpath.layers[3].z, 0.12 + 0.08 + 0.12 + 0.08, 1e-9);
}

}  // namespace
}  // namespace flatmorph::two_tool_print_test
