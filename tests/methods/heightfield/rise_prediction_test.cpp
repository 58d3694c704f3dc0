#include "methods/heightfield/rise_prediction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "common/error.h"
#include "material/material.h"
#include "methods/heightfield/cap_printing_graph.h"
#include "methods/heightfield/shrinkage_field.h"
#include "plate/layer_stack.h"
#include "test_support.h"

namespace flatmorph::rise_prediction_test {
namespace {

using testing::cap_material;
using testing::cap_printing_graph;
using testing::CapPrintingGraph;
using testing::kCapAngle;
using testing::kCapRadius;

CapPrintingGraph test_cap(double lambda2 = 0.85) {
  return cap_printing_graph(kCapRadius, kCapAngle, 8, 7.0, lambda2);
}

SimulationOptions tight() {
  SimulationOptions o;
  o.relative_tolerance = 1e-12;
  return o;
}

TEST(DepositionDirections, FollowTheIsolinesOfTheCap) {
  const CapPrintingGraph cap = test_cap();
  const Eigen::VectorXd direction = deposition_directions(cap.mesh, cap.plate);
  ASSERT_EQ(direction.size(), cap.mesh.F.rows());
  for (Eigen::Index f = 0; f < cap.mesh.F.rows(); ++f) {
    EXPECT_GE(direction(f), 0.0);
    EXPECT_LT(direction(f), std::numbers::pi);
    // The base edge is a chord of a ring: perpendicular to the radius through its midpoint, whose
    // azimuth is the mean of its ends' (the face's two corners on one ring, or the rim of the fan).
    int a = -1, b = -1;
    for (int k = 0; k < 3; ++k) {
      const int u = cap.mesh.F(f, k), v = cap.mesh.F(f, (k + 1) % 3);
      if (cap.mesh.vertex_level(u) == cap.mesh.vertex_level(v) && cap.mesh.vertex_level(u) >= 0) {
        a = u, b = v;
      }
    }
    ASSERT_GE(a, 0) << "face " << f;
    const Eigen::Vector2d mid = 0.5 * (cap.plate.row(a) + cap.plate.row(b)).transpose();
    const Eigen::Vector2d along(std::cos(direction(f)), std::sin(direction(f)));
    EXPECT_NEAR(along.dot(mid.normalized()), 0.0, 1e-12) << "face " << f;
  }
}

TEST(DepositionDirections, RefuseAFaceWithoutABaseEdge) {
  CapPrintingGraph cap = test_cap();
  // Move a ring vertex to another level: its faces no longer have two corners at one level.
  const int v = cap.mesh.loops[3].vertices[0];
  cap.mesh.vertex_level(v) = 5;
  EXPECT_THROW(deposition_directions(cap.mesh, cap.plate), std::invalid_argument);
}

TEST(HeightFieldPlate, PrintsEachFacesShrinkAtTheCurvesLayerHeight) {
  const CapPrintingGraph cap = test_cap();
  const Material material = cap_material();
  const HeightFieldPlate printed =
      heightfield_plate(cap.mesh, cap.plate, cap.edge_shrinkage, material);
  const ThicknessCurve& curve = *material.thickness_curve;
  const Eigen::VectorXd wanted = face_shrinkage(cap.mesh, cap.plate, cap.edge_shrinkage);
  ASSERT_EQ(printed.design.stack.num_layers(), curve.layers);
  EXPECT_EQ(printed.design.method, "heightfield");
  EXPECT_EQ(printed.num_clamped(), 0);
  EXPECT_TRUE(printed.wanted_shrinkage.isApprox(wanted));
  const Eigen::VectorXd* height = printed.design.design_fields.find_face("layer_height");
  const Eigen::VectorXd* shrinkage = printed.design.design_fields.find_face("shrinkage");
  ASSERT_TRUE(height && shrinkage);
  for (Eigen::Index f = 0; f < cap.mesh.F.rows(); ++f) {
    // σ(φ) of the cap lies between 15 % and 20 % (see cap_material).
    EXPECT_GT(wanted(f), 0.149);
    EXPECT_LT(wanted(f), 0.201);
    EXPECT_NEAR(1 - lambda1_at_layer_height(curve, (*height)(f)), wanted(f), 1e-12);
    EXPECT_NEAR((*shrinkage)(f), wanted(f), 1e-12);
    for (const Layer& layer : printed.design.stack.layers) {
      EXPECT_DOUBLE_EQ(layer.printed_thickness(f), (*height)(f));
      EXPECT_DOUBLE_EQ(layer.theta(f), printed.direction(f));
      EXPECT_NEAR(layer.lambda1(f), 1 - wanted(f), 1e-12);
      EXPECT_DOUBLE_EQ(layer.lambda2(f), 0.85);
    }
  }
  // It is written and read back as a plate design, the fields with it.
  const auto path = testing::scratch_dir() / "flat.ply";
  write_plate_design(path, printed.design);
  const PlateDesignFile back = read_plate_design(path, material, 6);
  EXPECT_TRUE(back.from_stack_file);
  EXPECT_EQ(back.design.method, "heightfield");
  const Eigen::VectorXd* read_shrinkage = back.design.design_fields.find_face("shrinkage");
  ASSERT_TRUE(read_shrinkage);
  EXPECT_LT((*read_shrinkage - *shrinkage).cwiseAbs().maxCoeff(), 1e-6);
}

// With pla-geodesy's own λ2 (1 or more: the paths do not narrow), the cap's rings would have to
// shrink by σ(φ) = 1 − λ2 sin φ / φ ≤ 1 − sin φ0 / φ0 = 5.9 %, less than the least the curve gives
// (7.9 % at its thickest layer): every face is raised to that least shrink, and flagged.
TEST(HeightFieldPlate, ClampsAndFlagsWhatTheCurveCannotReach) {
  const Material material = load_material("pla-geodesy");
  ASSERT_GE(material.lambda2, 1.0);
  const CapPrintingGraph cap = test_cap(material.lambda2);
  const HeightFieldPlate printed =
      heightfield_plate(cap.mesh, cap.plate, cap.edge_shrinkage, material);
  const auto [least, most] = reachable_shrinkage(*material.thickness_curve);
  ASSERT_GT(least, 0.06);
  EXPECT_LT(printed.wanted_shrinkage.maxCoeff(), 1 - std::sin(kCapAngle) / kCapAngle + 1e-3);
  EXPECT_EQ(printed.num_clamped(), cap.mesh.F.rows());
  EXPECT_TRUE((printed.clamped.array() == -1).all());
  EXPECT_NEAR(printed.shrinkage.minCoeff(), least, 1e-12);
  EXPECT_NEAR(printed.shrinkage.maxCoeff(), least, 1e-12);
  EXPECT_GT(most, least);
  const Eigen::VectorXd* flags = printed.design.design_fields.find_face("shrinkage_clamped");
  ASSERT_TRUE(flags);
  EXPECT_EQ(flags->minCoeff(), -1.0);
  EXPECT_EQ(flags->maxCoeff(), -1.0);
}

TEST(HeightFieldPlate, RefusesAMaterialWithoutAThicknessCurve) {
  const CapPrintingGraph cap = test_cap();
  Material material = cap_material();
  material.thickness_curve.reset();
  EXPECT_THROW(heightfield_plate(cap.mesh, cap.plate, cap.edge_shrinkage, material), UserError);
}

TEST(BiasedFlatStart, IsTheFlatPlateWithADomeTowardPlusZ) {
  const CapPrintingGraph cap = test_cap();
  const Eigen::MatrixXd start = biased_flat_start(cap.plate, 0.01);
  EXPECT_TRUE(start.leftCols(2).isApprox(cap.plate));
  const double diagonal = (cap.plate.colwise().maxCoeff() - cap.plate.colwise().minCoeff()).norm();
  EXPECT_NEAR(start.col(2).maxCoeff(), 0.01 * diagonal, 1e-3 * diagonal);
  EXPECT_GE(start.col(2).minCoeff(), -1e-12);
  EXPECT_GT(height_above_boundary_plane(start, cap.mesh.F), 0.0);
}

// The cap's plate rises to the cap, toward +z. Its metric is the cap's up to the discretization (a
// face's σ is the mean of its corners', about (σ_i − σ_i+1)/6 ~ 1e-3 off between rings), so the
// rest is the sheet's bending stiffness: b̄ = 0 wants it flat, and the 1.1 mm thick sheet (6
// layers of about 0.12 mm, times λ3) settles some 9 % lower than the cap (the pole lies 1.2 mm
// low, 0.7 % of the diagonal; a finer mesh does not change that). With a quarter of the thickness
// the pole comes up (to 0.38 % here, 0.19 % with twice the rings): the bound below is the
// stiffness's, and a thinner sheet must beat it.
TEST(PredictRise, TheCapsPlateRisesToTheCapTowardPlusZ) {
  const CapPrintingGraph cap = test_cap();
  const HeightFieldPlate printed =
      heightfield_plate(cap.mesh, cap.plate, cap.edge_shrinkage, cap_material());
  RisePredictionOptions options;
  options.simulation = tight();
  options.from_target = true;
  const RisePrediction rise = predict_rise(printed.design, cap.mesh.V, options);
  ASSERT_TRUE(rise.from_flat.converged) << rise.from_flat.warning;
  EXPECT_EQ(rise.side, 1);
  // The cap is 18.6 mm high: its mean vertex lies some mm above the rim's plane.
  EXPECT_GT(rise.rise_mm, 5.0);
  EXPECT_LT(rise.distance.mean_percent, 0.3);
  EXPECT_LT(rise.distance.max_percent, 1.0);
  EXPECT_NEAR(rise.distance.diagonal_mm,
              std::hypot(120.0, 120.0, kCapRadius * (1 - std::cos(kCapAngle))), 0.5);
  ASSERT_TRUE(rise.has_from_target);
  EXPECT_TRUE(rise.from_target.converged);
  EXPECT_TRUE(rise.starts_agree);
  EXPECT_LT(rise.starts_difference_percent, 0.1);

  PlateDesign thin = printed.design;
  for (Layer& layer : thin.stack.layers) layer.printed_thickness *= 0.25;
  options.from_target = false;
  const RisePrediction thin_rise = predict_rise(thin, cap.mesh.V, options);
  ASSERT_TRUE(thin_rise.from_flat.converged);
  EXPECT_EQ(thin_rise.side, 1);
  EXPECT_LT(thin_rise.distance.max_percent, 0.6 * rise.distance.max_percent);
  EXPECT_LT(thin_rise.distance.mean_percent, rise.distance.mean_percent);
}

// Without the bias's side the sheet rises the other way: the mirror image through the plate's plane
// (b̄ = 0: the sheet has no side of its own).
TEST(PredictRise, ANegativeBiasRisesToMinusZTheMirrorImage) {
  const CapPrintingGraph cap = test_cap();
  const HeightFieldPlate printed =
      heightfield_plate(cap.mesh, cap.plate, cap.edge_shrinkage, cap_material());
  RisePredictionOptions options;
  options.simulation = tight();
  options.from_target = false;
  const RisePrediction up = predict_rise(printed.design, cap.mesh.V, options);
  options.bias = -0.01;
  const RisePrediction down = predict_rise(printed.design, cap.mesh.V, options);
  ASSERT_TRUE(up.from_flat.converged && down.from_flat.converged);
  EXPECT_EQ(up.side, 1);
  EXPECT_EQ(down.side, -1);
  Eigen::MatrixXd mirrored = down.from_flat.V;
  mirrored.col(2) *= -1;
  const ShapeDistance d = shape_distance(rigidly_aligned(mirrored, up.from_flat.V), up.from_flat.V);
  EXPECT_LT(d.max_percent, 1e-4);
}

// x -> −x with the faces reversed (to stay counter-clockwise) and the directions mirrored (π − θ)
// gives the mirrored shape; turning the plate and its directions by α turns the shape.
TEST(PredictRise, MirroringOrTurningThePlateMirrorsOrTurnsTheShape) {
  const CapPrintingGraph cap = test_cap();
  const Material material = cap_material();
  const HeightFieldPlate printed =
      heightfield_plate(cap.mesh, cap.plate, cap.edge_shrinkage, material);
  RisePredictionOptions options;
  options.simulation = tight();
  options.from_target = false;
  const RisePrediction rise = predict_rise(printed.design, cap.mesh.V, options);
  ASSERT_TRUE(rise.from_flat.converged);

  Eigen::MatrixXd mirror_plate = cap.plate;
  mirror_plate.col(0) *= -1;
  Eigen::MatrixXi mirror_faces = cap.mesh.F;
  mirror_faces.col(1).swap(mirror_faces.col(2));
  Eigen::MatrixXd mirror_target = cap.mesh.V;
  mirror_target.col(0) *= -1;
  const HeightFieldPlate mirror = heightfield_plate(
      mirror_plate, mirror_faces, (std::numbers::pi - printed.direction.array()).matrix(),
      printed.wanted_shrinkage, material);
  const RisePrediction mirror_rise = predict_rise(mirror.design, mirror_target, options);
  ASSERT_TRUE(mirror_rise.from_flat.converged);
  EXPECT_EQ(mirror_rise.side, 1);
  Eigen::MatrixXd expected = rise.from_flat.V;
  expected.col(0) *= -1;
  EXPECT_LT(
      shape_distance(rigidly_aligned(mirror_rise.from_flat.V, expected), expected).max_percent,
      1e-4);
  EXPECT_NEAR(mirror_rise.distance.mean_percent, rise.distance.mean_percent, 1e-4);

  const double alpha = 0.9;
  Eigen::Matrix3d turn = Eigen::Matrix3d::Identity();
  turn.topLeftCorner<2, 2>() << std::cos(alpha), -std::sin(alpha), std::sin(alpha), std::cos(alpha);
  const Eigen::MatrixXd turned_plate = cap.plate * turn.topLeftCorner<2, 2>().transpose();
  const HeightFieldPlate turned =
      heightfield_plate(turned_plate, cap.mesh.F, (printed.direction.array() + alpha).matrix(),
                        printed.wanted_shrinkage, material);
  const RisePrediction turned_rise =
      predict_rise(turned.design, cap.mesh.V * turn.transpose(), options);
  ASSERT_TRUE(turned_rise.from_flat.converged);
  const Eigen::MatrixXd turned_expected = rise.from_flat.V * turn.transpose();
  EXPECT_LT(
      shape_distance(rigidly_aligned(turned_rise.from_flat.V, turned_expected), turned_expected)
          .max_percent,
      1e-4);
  // And the directions matter: printed across the rings (θ + π/2) the plate is far from the cap.
  const HeightFieldPlate across = heightfield_plate(
      cap.plate, cap.mesh.F, (printed.direction.array() + std::numbers::pi / 2).matrix(),
      printed.wanted_shrinkage, material);
  const RisePrediction across_rise = predict_rise(across.design, cap.mesh.V, options);
  EXPECT_GT(across_rise.distance.mean_percent, 5 * rise.distance.mean_percent + 1.0);
}

}  // namespace
}  // namespace flatmorph::rise_prediction_test
