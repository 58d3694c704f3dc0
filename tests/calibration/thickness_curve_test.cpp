// The thickness curve (SCF 2020 §6): fitted back from samples of a known polynomial, inverted, kept
// in material files, and refused outside its calibrated range.
#include "material/thickness_curve.h"

#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "calibration/fit.h"
#include "common/error.h"
#include "material/material.h"
#include "test_support.h"

namespace flatmorph::thickness_curve_test {
namespace {

// A monotone quartic over [0.08, 0.28] mm, lambda1 from 0.58 to 0.80 (thin layers shrink more).
const std::vector<double> kTrue = {0.5, 0.9, 2.0, -8.0, 10.0};

double truth(double h) {
  double v = 0;
  for (size_t i = kTrue.size(); i-- > 0;) v = v * h + kTrue[i];
  return v;
}

std::vector<double> ramp_heights() {
  std::vector<double> h;
  for (int i = 0; i <= 10; ++i) {
    for (int r = 0; r < 3; ++r) h.push_back(0.08 + 0.02 * i);  // 11 heights x 3, as SCF 2020
  }
  return h;
}

TEST(ThicknessCurve, ExactSamplesGiveBackTheQuartic) {
  const std::vector<double> h = ramp_heights();
  std::vector<double> l1;
  for (double x : h) l1.push_back(truth(x));
  const ThicknessCurve c = fit_thickness_curve(h, l1, 6, 200);
  ASSERT_EQ(c.lambda1_coefficients.size(), 5u);
  for (size_t i = 0; i < 5; ++i) EXPECT_NEAR(c.lambda1_coefficients[i], kTrue[i], 1e-6) << i;
  EXPECT_DOUBLE_EQ(c.min_layer_height, 0.08);
  EXPECT_DOUBLE_EQ(c.max_layer_height, 0.28);
  EXPECT_EQ(c.layers, 6);
  EXPECT_EQ(c.nozzle_temperature, 200);
  for (double x = 0.08; x <= 0.28; x += 0.005) {
    EXPECT_NEAR(lambda1_at_layer_height(c, x), truth(x), 1e-9);
  }
}

TEST(ThicknessCurve, NoisySamplesStayCloseToTheTruth) {
  const std::vector<double> h = ramp_heights();
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.003);
  std::vector<double> l1;
  for (double x : h) l1.push_back(truth(x) + noise(rng));
  const ThicknessCurve c = fit_thickness_curve(h, l1, 6, 200);
  EXPECT_TRUE(thickness_curve_problem(c).empty());
  for (double x = 0.08; x <= 0.28; x += 0.005) {
    EXPECT_NEAR(lambda1_at_layer_height(c, x), truth(x), 0.004) << x;
  }
}

TEST(ThicknessCurve, InverseRoundTrips) {
  const std::vector<double> h = ramp_heights();
  std::vector<double> l1;
  for (double x : h) l1.push_back(truth(x));
  const ThicknessCurve c = fit_thickness_curve(h, l1, 6, 200);
  for (double x = 0.08; x <= 0.28 + 1e-12; x += 0.01) {
    const double wanted = lambda1_at_layer_height(c, x);
    EXPECT_NEAR(layer_height_for_lambda1(c, wanted), x, 1e-9) << x;
    EXPECT_NEAR(layer_height_for_shrinkage(c, 1 - wanted), x, 1e-9) << x;
  }
  // And the other way: a wanted ratio gives a height where the true curve has that ratio.
  EXPECT_NEAR(truth(layer_height_for_lambda1(c, 0.7)), 0.7, 1e-9);
}

TEST(ThicknessCurve, RefusesValuesOutsideTheCalibratedRange) {
  const std::vector<double> h = ramp_heights();
  std::vector<double> l1;
  for (double x : h) l1.push_back(truth(x));
  const ThicknessCurve c = fit_thickness_curve(h, l1, 6, 200);
  for (double lambda1 : {truth(0.08) - 0.01, truth(0.28) + 0.01, 0.3, 1.2}) {
    try {
      layer_height_for_lambda1(c, lambda1);
      ADD_FAILURE() << lambda1 << " was accepted";
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
      EXPECT_NE(std::string(e.what()).find("0.08 to 0.28 mm"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(lambda1_at_layer_height(c, 0.05), UserError);
  EXPECT_THROW(lambda1_at_layer_height(c, 0.3), UserError);
  EXPECT_THROW(layer_height_for_shrinkage(c, 0.1), UserError);  // lambda1 0.9: beyond 0.80
}

TEST(ThicknessCurve, FallsBackToALowerDegreeWhenTheFitIsNotMonotone) {
  // A straight line with one outlier in the middle: a quartic through it would turn.
  std::vector<double> h = {0.1, 0.15, 0.2, 0.25, 0.3}, l1 = {0.60, 0.66, 0.60, 0.72, 0.75};
  const ThicknessCurve c = fit_thickness_curve(h, l1, 6, 200);
  EXPECT_LT(c.lambda1_coefficients.size(), 5u);
  EXPECT_TRUE(thickness_curve_problem(c).empty());
}

TEST(ThicknessCurve, NeedsTwoLayerHeights) {
  EXPECT_THROW(fit_thickness_curve({0.1, 0.1, 0.1}, {0.6, 0.61, 0.6}, 6, 200), UserError);
}

TEST(ThicknessCurve, MaterialFilesKeepIt) {
  const std::vector<double> h = ramp_heights();
  std::vector<double> l1;
  for (double x : h) l1.push_back(truth(x));
  Material m = load_material("pla-paper");
  m.name = "ramp";
  m.thickness_curve = fit_thickness_curve(h, l1, 6, 200);
  const auto path = testing::scratch_dir() / "ramp.json";
  write_material(path, m);
  const Material back = load_material(path.string());
  ASSERT_TRUE(back.thickness_curve.has_value());
  EXPECT_EQ(back.thickness_curve->lambda1_coefficients, m.thickness_curve->lambda1_coefficients);
  EXPECT_EQ(back.thickness_curve->min_layer_height, 0.08);
  EXPECT_EQ(back.thickness_curve->max_layer_height, 0.28);
  EXPECT_EQ(back.thickness_curve->layers, 6);
  EXPECT_EQ(back.lambda1, m.lambda1);
  EXPECT_EQ(back.delta_lambda1, m.delta_lambda1);
  EXPECT_EQ(material_json(back), material_json(m));
  EXPECT_NEAR(layer_height_for_lambda1(*back.thickness_curve, 0.7),
              layer_height_for_lambda1(*m.thickness_curve, 0.7), 1e-12);
  // The presets have none.
  EXPECT_FALSE(load_material("pla-paper").thickness_curve.has_value());
}

TEST(ThicknessCurve, MaterialFilesRefuseABadCurve) {
  const auto dir = testing::scratch_dir();
  for (const std::string& curve :
       {std::string(R"({"lambda1_coefficients": [0.6, 1, -5], "min_layer_height": 0.05, )"
                    R"("max_layer_height": 0.3})"),  // turns at 0.1 mm
        std::string(R"({"lambda1_coefficients": [], "min_layer_height": 0.1, )"
                    R"("max_layer_height": 0.3})"),
        std::string(R"({"lambda1_coefficients": [0.5, 1], "min_layer_height": 0.3, )"
                    R"("max_layer_height": 0.1})"),
        std::string(R"({"lambda1_coefficients": [0.5, 1], "max_layer_height": 0.3})"),
        std::string(R"({"lambda1_coefficients": [0.5, 1], "min_layer_height": 0.1, )"
                    R"("max_layer_height": 0.3, "colour": 1})")}) {
    const auto path = dir / "bad.json";
    std::ofstream(path) << R"({"lambda1": 0.6, "thickness_curve": )" << curve << "}";
    try {
      load_material(path.string());
      ADD_FAILURE() << curve << " was accepted";
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kProfile);
      EXPECT_NE(std::string(e.what()).find("thickness_curve"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace flatmorph::thickness_curve_test
