// Issue 6 acceptance on real designs, with issue 21's bar: the flattened hat (the paper's Hat:
// hat.obj Loop-subdivided to 11008 faces, plate 100 mm wide, theta2 = 0) and every built-in
// example (plate ~100 mm). Per layer: (a) >= 99 % of path samples have their nearest neighbour
// path at 0.8 to 1.25 spacings, (b) >= 98.5 % of the plate within 0.6 spacings of a path, (c) no
// path point outside the plate, (d) path tangents within a median of 2 deg and a 95th percentile of
// 10 deg of theta^k (one spacing around singular points excluded); on the hat, travel >= 15 %
// shorter than greedy nearest neighbour.
#include <gtest/gtest.h>

#include <iostream>

#include "examples/examples.h"
#include "mesh/io.h"
#include "mesh/subdivide.h"
#include "methods/shrink_morph/design.h"
#include "methods/shrink_morph/flatten.h"
#include "test_support.h"
#include "toolpath/layer_paths.h"
#include "toolpath/path_quality.h"

namespace flatmorph::designs_test {
namespace {

struct DesignResult {
  double travel = 0;
  double travel_greedy = 0;
};

DesignResult check_design(const Mesh& target, const LayerPathOptions& options, int num_layers) {
  FlattenOptions flatten_options;
  flatten_options.width_mm = 100;
  const FlatPlate flat = flatten(target, flatten_options);
  const PlateDesign plate =
      shrink_morph_plate_design(flat, Eigen::VectorXd(), Material{}, num_layers);
  const LayerPaths result = stack_layer_paths(plate.plate, plate.F, plate.stack, options);
  PathQualityOptions quality_options;
  quality_options.spacing = options.spacing;
  quality_options.singular_exclusion_mm = 1.5 * options.spacing;
  DesignResult totals;
  EXPECT_EQ(static_cast<int>(result.toolpath.layers.size()), num_layers);
  for (int k = 1; k <= num_layers; ++k) {
    const LayerPathReport& report = result.layers[k - 1];
    const Eigen::VectorXd theta =
        layer_direction_vertex(plate.plate, plate.F, plate.stack.layers[k - 1].theta);
    const PathQuality q =
        evaluate_path_quality(flat.plate, flat.target.F, theta, result.toolpath.layers[k - 1].paths,
                              report.singular_points, quality_options);
    std::cout << "  layer " << k << ": " << report.paths << " paths, spacing in range "
              << q.spacing_in_range << ", covered " << q.covered_area << ", outside "
              << q.points_outside << ", angle median " << q.angle_median_deg << " p95 "
              << q.angle_p95_deg << ", travel " << report.travel_mm << " (greedy "
              << report.travel_greedy_mm << ")\n";
    EXPECT_GE(q.spacing_in_range, 0.99) << "layer " << k;
    EXPECT_GE(q.covered_area, 0.985) << "layer " << k;
    EXPECT_EQ(q.points_outside, 0) << "layer " << k;
    EXPECT_LT(q.angle_median_deg, 2.0) << "layer " << k;
    EXPECT_LT(q.angle_p95_deg, 10.0) << "layer " << k;
    totals.travel += report.travel_mm;
    totals.travel_greedy += report.travel_greedy_mm;
  }
  std::cout << "  refined faces " << result.refined_faces << "\n";
  return totals;
}

TEST(DesignPaths, Hat) {
  const Mesh hat = read_mesh(testing::shared_dir() / "meshes" / "hat.obj").mesh;
  const Mesh target = loop_subdivide_to(hat, 11008).mesh;
  ASSERT_EQ(target.num_faces(), 11008);
  LayerPathOptions options;  // 0.4 mm apart, the paper's 10 layers of 0.08 mm
  const DesignResult r = check_design(target, options, 10);
  // Per layer the test above printed both; over the ten layers the order saves at least 15 %.
  EXPECT_LT(r.travel, 0.85 * r.travel_greedy);
}

TEST(DesignPaths, BuiltInExamples) {
  LayerPathOptions options;
  for (const ExampleInfo& example : example_list()) {
    SCOPED_TRACE(example.name);
    std::cout << example.name << ":\n";
    // theta2 = 0: every layer follows theta1; two show the warm start.
    check_design(make_example(example.name), options, 2);
  }
}

}  // namespace
}  // namespace flatmorph::designs_test
