// The hinge curve of Thermorph's actuators (material/hinge_curve.h): evaluation on its range, the
// inverse (speed for a wanted curvature), the usability check, and the "hinge_curve" key of a
// material file.
#include "material/hinge_curve.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "material/material.h"
#include "test_support.h"

namespace flatmorph::hinge_curve_test {
namespace {

// κ_A(v) = 0.02 + 0.0004 v, κ_B(v) = 0.01 + 0.0002 v − 4e-7 v² (increasing up to 250 mm/s) on
// [50, 150] mm/s.
HingeCurve known_curve() {
  HingeCurve c;
  c.case_a_coefficients = {0.02, 0.0004};
  c.case_b_coefficients = {0.01, 0.0002, -4e-7};
  c.min_speed = 50;
  c.max_speed = 150;
  c.calibrated = true;
  c.nozzle_temperature = 210;
  return c;
}

// The UserError message of `f`, checking its category.
template <typename F>
std::string error_of(F f, ErrorCategory category) {
  try {
    f();
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), category) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no UserError";
  return "";
}

TEST(HingeCurve, EvaluatesEachCaseOnItsRange) {
  const HingeCurve c = known_curve();
  EXPECT_EQ(hinge_curve_problem(c), "");
  for (double v : {50.0, 83.3, 150.0}) {
    EXPECT_NEAR(hinge_curvature(c, v, true), 0.02 + 0.0004 * v, 1e-15);
    EXPECT_NEAR(hinge_curvature(c, v, false), 0.01 + 0.0002 * v - 4e-7 * v * v, 1e-15);
  }
  // The paper's reference sample, 20 mm at 5000 mm/min in case A: θ = κ W.
  EXPECT_NEAR(hinge_curvature(c, 5000.0 / 60, true) * 20, (0.02 + 0.0004 * 5000 / 60) * 20, 1e-14);
  const std::string message =
      error_of([&] { hinge_curvature(c, 200, true); }, ErrorCategory::kInfeasible);
  EXPECT_NE(message.find("200 mm/s (12000 mm/min)"), std::string::npos) << message;
  EXPECT_NE(message.find("50 to 150 mm/s (3000 to 9000 mm/min)"), std::string::npos) << message;
  EXPECT_NE(message.find("calibrate a wider one"), std::string::npos) << message;
}

TEST(HingeCurve, SpeedForCurvatureInvertsEachCase) {
  const HingeCurve c = known_curve();
  for (bool pla_on_bed : {true, false}) {
    for (double v : {50.0, 61.7, 100.0, 149.9, 150.0}) {
      EXPECT_NEAR(hinge_speed_for_curvature(c, hinge_curvature(c, v, pla_on_bed), pla_on_bed), v,
                  1e-9)
          << hinge_case_name(pla_on_bed);
    }
  }
  // A 90° fold over a 10 mm actuator needs κ = 0.157 /mm: more than case A reaches (0.08 /mm).
  const std::string message =
      error_of([&] { hinge_speed_for_curvature(c, 0.157, true); }, ErrorCategory::kInfeasible);
  EXPECT_NE(message.find("0.04 to 0.08 /mm (radius 12.5 to 25 mm)"), std::string::npos) << message;
  EXPECT_NE(message.find("case A"), std::string::npos) << message;
  EXPECT_NE(message.find("width"), std::string::npos) << message;
}

// A decreasing curve (slower printing folding more) is as invertible as an increasing one.
TEST(HingeCurve, ADecreasingCurveIsInvertedToo) {
  HingeCurve c = known_curve();
  c.case_a_coefficients = {0.1, -0.0004};
  EXPECT_EQ(hinge_curve_problem(c), "");
  EXPECT_NEAR(hinge_speed_for_curvature(c, 0.1 - 0.0004 * 70, true), 70, 1e-9);
}

TEST(HingeCurve, UnusableCurvesAreNamed) {
  auto problem = [](auto change) {
    HingeCurve c = known_curve();
    change(c);
    return hinge_curve_problem(c);
  };
  // 0.05 + 0.002 v − 1e-5 v² turns at 100 mm/s.
  EXPECT_NE(problem([](HingeCurve& c) {
              c.case_b_coefficients = {0.05, 0.002, -1e-5};
            }).find("case B (TPU on the bed)'s curvature is not strictly monotone"),
            std::string::npos);
  EXPECT_NE(problem([](HingeCurve& c) {
              c.case_a_coefficients = {-0.01, 0.0001};
            }).find("case A (PLA on the bed) gives a curvature of -0.005 /mm at 50 mm/s"),
            std::string::npos);
  EXPECT_NE(problem([](HingeCurve& c) { c.case_a_coefficients = {}; }).find("0 coefficients"),
            std::string::npos);
  EXPECT_NE(problem([](HingeCurve& c) {
              c.case_a_coefficients = {0.1, 0, 0, 0, 0, 1e-12};
            }).find("6 coefficients"),
            std::string::npos);
  EXPECT_NE(problem([](HingeCurve& c) {
              c.min_speed = 3000;
              c.max_speed = 9000;
            }).find("mm/min"),
            std::string::npos);
  EXPECT_NE(problem([](HingeCurve& c) { c.min_speed = 150; }).find("not an interval"),
            std::string::npos);
  EXPECT_NE(problem([](HingeCurve& c) { c.stack.pla_layers = 0; }).find("actuator stack"),
            std::string::npos);
  EXPECT_NE(problem([](HingeCurve& c) { c.stack.tpu_speed = 1500; }).find("not mm/min"),
            std::string::npos);
  EXPECT_NE(problem([](HingeCurve& c) { c.nozzle_temperature = 483; }).find("483 C"),
            std::string::npos);
}

std::filesystem::path write_file(const std::string& name, const std::string& text) {
  const std::filesystem::path path = testing::scratch_dir() / name;
  std::ofstream(path) << text;
  return path;
}

// Written into a material file and read back: the same curve, to the last bit, and the file's
// other keys untouched.
TEST(HingeCurve, RoundTripsThroughTheMaterialFile) {
  Material m = load_material("pla-generic");
  EXPECT_FALSE(m.hinge_curve);
  EXPECT_EQ(material_json(m).find("hinge_curve"), std::string::npos);
  m.hinge_curve = known_curve();
  m.hinge_curve->stack.layer_height = 0.25;
  m.hinge_curve->stack.pla_layers = 2;
  m.hinge_curve->stack.tpu_layers = 2;
  m.hinge_curve->stack.tpu_speed = 20;
  m.hinge_curve->stack.overlap = 1.5;
  const std::filesystem::path path = write_file("hinged.json", material_json(m));
  const Material back = load_material(path.string());
  ASSERT_TRUE(back.hinge_curve);
  const HingeCurve& c = *back.hinge_curve;
  EXPECT_EQ(c.case_a_coefficients, m.hinge_curve->case_a_coefficients);
  EXPECT_EQ(c.case_b_coefficients, m.hinge_curve->case_b_coefficients);
  EXPECT_EQ(c.min_speed, 50);
  EXPECT_EQ(c.max_speed, 150);
  EXPECT_TRUE(c.calibrated);
  EXPECT_EQ(c.stack.layer_height, 0.25);
  EXPECT_EQ(c.stack.pla_layers, 2);
  EXPECT_EQ(c.stack.tpu_layers, 2);
  EXPECT_EQ(c.stack.tpu_speed, 20);
  EXPECT_EQ(c.stack.overlap, 1.5);
  EXPECT_EQ(c.nozzle_temperature, 210);
  EXPECT_EQ(material_json(back), material_json(m));
  // The uncalibrated flag survives too.
  m.hinge_curve->calibrated = false;
  EXPECT_FALSE(parse_material_json(material_json(m), "text").hinge_curve->calibrated);
}

TEST(HingeCurve, MaterialFileErrorsNameTheKeyAndTheFile) {
  const std::string good =
      R"("case_a_curvature_coefficients": [0.02, 0.0004], )"
      R"("case_b_curvature_coefficients": [0.01, 0.0002], "min_print_speed": 50)";
  for (const auto& [curve, says] : std::vector<std::pair<std::string, std::string>>{
           {"{" + good + R"(, "max_print_speed": 150})", "needs \"calibrated\": true or false"},
           {"{" + good + R"(, "max_print_speed": 150, "calibrated": "yes"})",
            "needs \"calibrated\""},
           {"{" + good + R"(, "calibrated": true})", "lacks \"max_print_speed\""},
           {"{" + good + R"(, "max_print_speed": 9000, "calibrated": true})", "mm/min"},
           {"{" + good + R"(, "max_print_speed": 150, "calibrated": true, "pla_layers": 2.5})",
            "\"pla_layers\": 2.5, expected a whole number"},
           {"{" + good + R"(, "max_print_speed": 150, "calibrated": true, "case": "A"})",
            "unknown key \"case\""},
           {R"({"case_a_curvature_coefficients": [0.02, 0.0004], "min_print_speed": 50, )"
            R"("max_print_speed": 150, "calibrated": true})",
            "needs \"case_b_curvature_coefficients\""},
           {R"({"case_a_curvature_coefficients": [0.02, 0.0004], )"
            R"("case_b_curvature_coefficients": [0.02, -0.001], "min_print_speed": 50, )"
            R"("max_print_speed": 150, "calibrated": true})",
            "is unusable: case B (TPU on the bed) gives a curvature of -0.03 /mm at 50 mm/s"},
           {"[0.02, 0.0004]", "must be an object"},
       }) {
    const std::filesystem::path path =
        write_file("bad.json", R"({"lambda1": 0.6, "hinge_curve": )" + curve + "}");
    const std::string message =
        error_of([&] { load_material(path.string()); }, ErrorCategory::kProfile);
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("\"hinge_curve\""), std::string::npos) << message;
    EXPECT_NE(message.find(says), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace flatmorph::hinge_curve_test
