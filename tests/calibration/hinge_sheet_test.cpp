// The hinge calibration sheet of Thermorph (notes §5): the strips and their codes, the toolpaths
// and the two-tool G-code read back by the independent reader of tests/gcode/ (active PLA across
// each hinge at its speed, TPU only on the actuators, the case's layer order), the measurement
// sheet and the fit of κ(v) = θ / W from synthetic angles of a known curve.
#include "calibration/hinge_sheet.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/angles.h"
#include "common/error.h"
#include "gcode/gcode_replay.h"
#include "gcode/gcode_writer.h"

namespace flatmorph::hinge_sheet_test {
namespace {

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

// The notes' sheet: 5 speeds x 4 widths x 2 cases, each strip two 20 mm faces and its actuator,
// all apart, on the bed, coded by (case, speed).
TEST(HingeSheet, StripsAreTheNotesSheetLaidApart) {
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  const HingeSheetPlan plan = plan_hinge_sheet(printer, {});
  ASSERT_EQ(plan.strips.size(), 40u);
  EXPECT_EQ(plan.code_bits, 4);  // 10 codes
  const Eigen::Vector2d half = printer.bed_size / 2 - Eigen::Vector2d::Constant(10);
  for (size_t i = 0; i < plan.strips.size(); ++i) {
    const HingeStrip& s = plan.strips[i];
    EXPECT_EQ(s.id, static_cast<int>(i) + 1);
    EXPECT_EQ(s.pla_on_bed, i < 20);
    EXPECT_EQ(s.speed, (std::vector<double>{50, 75, 100, 125, 150})[(i / 4) % 5]);
    EXPECT_EQ(s.width, (std::vector<double>{5, 10, 15, 20})[i % 4]);
    EXPECT_EQ(s.code, static_cast<int>(i / 4) + 1);
    EXPECT_NEAR(s.outline.sizes().x(), s.width + 40, 1e-9);
    EXPECT_NEAR(s.outline.sizes().y(), 10, 1e-9);
    EXPECT_NEAR(s.actuator.sizes().x(), s.width, 1e-9);
    EXPECT_NEAR(s.actuator.center().x(), s.outline.center().x(), 1e-9);
    EXPECT_NEAR(s.bonded.sizes().x(), s.width + 2, 1e-9);  // 1 mm into each face
    EXPECT_TRUE(s.outline.min().x() >= -half.x() && s.outline.max().x() <= half.x() &&
                s.outline.min().y() >= -half.y() && s.outline.max().y() <= half.y());
    for (size_t j = 0; j < i; ++j) {
      const Eigen::AlignedBox2d& o = plan.strips[j].outline;
      const bool apart = s.outline.min().x() >= o.max().x() + 5 - 1e-9 ||
                         o.min().x() >= s.outline.max().x() + 5 - 1e-9 ||
                         s.outline.min().y() >= o.max().y() + 5 - 1e-9 ||
                         o.min().y() >= s.outline.max().y() + 5 - 1e-9;
      EXPECT_TRUE(apart) << "strips " << j + 1 << " and " << i + 1;
    }
  }
}

// Printed by the ordinary writer on a two-tool printer and read back independently: the actuators'
// PLA lines run across their hinge (within 2°) at the strip's speed, the TPU lies only on the
// actuators (with their 1 mm bond) at 1500 mm/min, layer by layer as the case says (A: three PLA
// layers then TPU; B: TPU then three PLA layers), the faces are PLA at the material's speed, and
// the tools change three times: TPU and PLA in the first layer, PLA in the second, TPU in the last.
TEST(HingeSheet, TwoToolGcodePrintsEachCaseAsTheNotesTable) {
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  const Material pla = load_material("pla-generic"), tpu = load_material("tpu-generic");
  const HingeSheetPlan plan = plan_hinge_sheet(printer, {});
  const GcodeResult gcode = make_gcode(plan.toolpath, printer, {pla, tpu});
  EXPECT_EQ(gcode.tool_changes, 3);
  const testing::ReadGcode read = testing::read_gcode(gcode.text);
  ASSERT_EQ(read.layers.size(), 4u);
  int active_lines = 0, tpu_lines = 0;
  for (size_t k = 0; k < read.layers.size(); ++k) {
    for (const testing::ReadExtrusion& e : read.layers[k].extrusions) {
      const Eigen::Vector2d a = Eigen::Vector2d(e.x0, e.y0) - gcode.plate_to_bed;
      const Eigen::Vector2d b = Eigen::Vector2d(e.x1, e.y1) - gcode.plate_to_bed;
      const Eigen::Vector2d mid = (a + b) / 2;
      if ((b - a).norm() < 1) continue;  // primes, wipes and joins
      const HingeStrip* strip = nullptr;
      for (const HingeStrip& s : plan.strips) {
        if (s.outline.contains(mid)) strip = &s;
      }
      if (strip == nullptr) continue;  // the prime pad
      const bool band = strip->bonded.contains(mid);
      const bool active_layer = strip->pla_on_bed ? k < 3 : k >= 1;
      if (!band) {
        EXPECT_EQ(e.tool, 0) << "a face of strip " << strip->id << " in layer " << k + 1;
        EXPECT_LE(e.feed, 60 * pla.print_speed + 1e-6);  // the material's speed
        continue;
      }
      const double angle = std::atan2(std::abs(b.y() - a.y()), std::abs(b.x() - a.x()));
      if (active_layer) {
        EXPECT_EQ(e.tool, 0) << "strip " << strip->id << ", layer " << k + 1;
        EXPECT_LT(angle, 2 * kDegree) << "strip " << strip->id;  // across the hinge (along y)
        EXPECT_NEAR(e.feed, 60 * strip->speed, 1e-6) << "strip " << strip->id;
        ++active_lines;
      } else {
        EXPECT_EQ(e.tool, 1) << "strip " << strip->id << ", layer " << k + 1;
        EXPECT_NEAR(angle, std::numbers::pi / 2, 2 * kDegree) << "strip " << strip->id;
        EXPECT_NEAR(e.feed, 60 * 25, 1e-6);
        ++tpu_lines;
      }
    }
  }
  // Every strip: 3 active layers of 10 mm / 0.4 mm = 25 lines; one TPU layer of (W + 2) / 0.4.
  EXPECT_EQ(active_lines, 40 * 3 * 25);
  int expected_tpu = 0;
  for (const HingeStrip& s : plan.strips) expected_tpu += std::lround(s.bonded.sizes().x() / 0.4);
  EXPECT_EQ(tpu_lines, expected_tpu);
}

TEST(HingeSheet, RefusesWhatCannotBePrinted) {
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  HingeSheetOptions o;
  o.speeds = {50, 300};
  EXPECT_NE(error_of([&] { plan_hinge_sheet(printer, o); }, ErrorCategory::kOption)
                .find("300 mm/s is above 250 mm/s"),
            std::string::npos);
  o.speeds = {3000};  // mm/min
  EXPECT_NE(
      error_of([&] { plan_hinge_sheet(printer, o); }, ErrorCategory::kOption).find("not mm/min"),
      std::string::npos);
  o = {};
  o.case_a = o.case_b = false;
  EXPECT_NE(error_of([&] { plan_hinge_sheet(printer, o); }, ErrorCategory::kOption).find("case"),
            std::string::npos);
  o = {};
  o.widths = {5, 5};
  EXPECT_NE(error_of([&] { plan_hinge_sheet(printer, o); }, ErrorCategory::kOption).find("twice"),
            std::string::npos);
  o = {};
  o.speeds = {30, 40, 50, 60, 70, 80, 90, 100, 110, 120, 130, 140, 150, 160, 170, 180};
  EXPECT_NE(error_of([&] { plan_hinge_sheet(printer, o); }, ErrorCategory::kOption)
                .find("32 groups of strips"),
            std::string::npos);
  // 40 strips do not fit a 220 mm bed: the message gives the room they need.
  const std::string message =
      error_of([&] { plan_hinge_sheet(load_printer("creality-ender3-v2"), {}); },
               ErrorCategory::kInfeasible);
  EXPECT_NE(message.find("the 40 hinge strips need"), std::string::npos) << message;
  o = {};
  o.case_b = false;
  o.widths = {5, 10};
  EXPECT_NO_THROW(plan_hinge_sheet(load_printer("creality-ender3-v2"), o));
}

// κ_A(v) = 0.03 + 0.0004 v, κ_B = 0.6 κ_A: angles θ = κ W, written into the template with ±0.5°
// of measuring noise, are fitted back to within the noise's reach, and the strips' residuals are
// the noise.
HingeSheet filled_sheet(const std::vector<std::string>& changes = {}) {
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  const HingeSheetPlan plan = plan_hinge_sheet(printer, {});
  std::string text = hinge_sheet_csv_template(plan, load_material("pla-generic"), printer);
  std::string filled;
  size_t pos = 0;
  int row = 0;
  while (pos < text.size()) {
    const size_t end = text.find('\n', pos);
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    if (!line.empty() && line[0] != '#' && line.rfind("strip", 0) != 0) {
      const HingeStrip& s = plan.strips[static_cast<size_t>(row)];
      const double kappa = (0.03 + 0.0004 * s.speed) * (s.pla_on_bed ? 1 : 0.6);
      const double noise = (row % 2 == 0 ? 0.5 : -0.5);
      line += fmt::format("{:.3f}", kappa * s.width / kDegree + noise);
      if (static_cast<size_t>(row) < changes.size() && !changes[static_cast<size_t>(row)].empty()) {
        line = changes[static_cast<size_t>(row)];
      }
      ++row;
    }
    filled += line + "\n";
  }
  return parse_hinge_measurements(filled, "hinge.csv");
}

TEST(HingeSheet, FitRecoversAKnownCurveFromTheFilledInSheet) {
  const HingeSheet sheet = filled_sheet();
  ASSERT_EQ(sheet.rows.size(), 40u);
  EXPECT_EQ(sheet.stack.pla_layers, 3);
  ASSERT_TRUE(sheet.material);
  EXPECT_EQ(sheet.material->name, "pla-generic");
  const HingeCurveFit fit = fit_hinge_curve(sheet);
  EXPECT_TRUE(fit.curve.calibrated);
  EXPECT_EQ(fit.curve.min_speed, 50);
  EXPECT_EQ(fit.curve.max_speed, 150);
  EXPECT_EQ(hinge_curve_problem(fit.curve), "");
  for (double v : {50.0, 90.0, 150.0}) {
    const double a = 0.03 + 0.0004 * v;
    // ±0.5° over widths of 5 to 20 mm moves κ by less than 0.0005 /mm.
    EXPECT_NEAR(hinge_curvature(fit.curve, v, true), a, 5e-4) << v;
    EXPECT_NEAR(hinge_curvature(fit.curve, v, false), 0.6 * a, 5e-4) << v;
  }
  EXPECT_LT(fit.rms_residual_a, 0.6 * kDegree);
  EXPECT_GT(fit.rms_residual_a, 0.3 * kDegree);
  EXPECT_LT(fit.max_residual_b, 1.0 * kDegree);
  ASSERT_EQ(fit.strips.size(), 40u);
  EXPECT_NEAR(fit.strips[0].fold_angle - fit.strips[0].predicted, 0.5 * kDegree, 0.3 * kDegree);
  // The written material file holds it: the curve the designs then use.
  Material m = *sheet.material;
  m.hinge_curve = fit.curve;
  EXPECT_EQ(parse_material_json(material_json(m), "m").hinge_curve->case_a_coefficients,
            fit.curve.case_a_coefficients);
}

TEST(HingeSheet, MeasurementErrorsNameTheLineAndTheColumn) {
  for (const auto& [bad_row, says] : std::vector<std::pair<std::string, std::string>>{
           {"1,A,50,5,1,", "column 6 (fold_angle): the value is missing"},
           {"1,C,50,5,1,10", "\"C\" is no case"},
           {"1,A,3000,5,1,10", "3000 mm/s is faster than any printer"},
           {"1,A,50,5,1,200", "200 degrees is no fold angle"},
           {"1,A,50,5,1,12deg", "\"12deg\" is not a number"},
           {"2,A,50,5,1,10", "strip 2 appears twice"},
       }) {
    const std::string row = bad_row;  // clang 14 lambdas cannot capture a structured binding
    const std::string message = error_of([&] { filled_sheet({row}); }, ErrorCategory::kFormat);
    EXPECT_NE(message.find("hinge.csv: line"), std::string::npos) << message;
    EXPECT_NE(message.find(says), std::string::npos) << message;
  }
  // skip leaves a strip out.
  const HingeSheet sheet = filled_sheet({"1,A,50,5,1,skip"});
  EXPECT_TRUE(sheet.rows[0].skipped);
  EXPECT_EQ(fit_hinge_curve(sheet).strips.size(), 39u);
  EXPECT_FALSE(is_hinge_sheet("strip,case\n1,A"));
  EXPECT_TRUE(is_hinge_sheet("# a comment\n# kind = hinge-sheet\nstrip,case\n"));
}

TEST(HingeSheet, FitRefusesWhatTheAnglesCannotGive) {
  // Case B measured at one speed only: every other case B strip skipped.
  std::vector<std::string> changes(40);
  for (int i = 24; i < 40; ++i) {
    const double v = std::vector<double>{50, 75, 100, 125, 150}[static_cast<size_t>((i / 4) % 5)];
    changes[static_cast<size_t>(i)] =
        fmt::format("{},B,{:g},{:g},{},skip", i + 1, v, 5 + 5.0 * (i % 4), i / 4 + 1);
  }
  std::string message =
      error_of([&] { fit_hinge_curve(filled_sheet(changes)); }, ErrorCategory::kFormat);
  EXPECT_NE(message.find("case B (TPU on the bed) has measured strips at 1 speed"),
            std::string::npos)
      << message;
  // Case A strips at 50 mm/s folding the other way.
  changes.assign(40, "");
  for (int i = 0; i < 4; ++i) {
    changes[static_cast<size_t>(i)] = fmt::format("{},A,50,{:g},1,-20", i + 1, 5 + 5.0 * i);
  }
  message = error_of([&] { fit_hinge_curve(filled_sheet(changes)); }, ErrorCategory::kFormat);
  EXPECT_NE(message.find("not in their case's direction"), std::string::npos) << message;
}

}  // namespace
}  // namespace flatmorph::hinge_sheet_test
