// Fitting the material back from synthetic measurements of known ratios (Shrink & Morph §4.1,
// §4.2), and the errors for bad measurement sheets.
#include "calibration/measurements.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "calibration/calibration_print.h"
#include "calibration/fit.h"
#include "common/error.h"
#include "gcode/printer_profile.h"

namespace flatmorph::measurements_test {
namespace {

struct Truth {
  double lambda1, lambda2, lambda3, kappa;
};

// The template of a 2 temperatures x 2 layer heights x 4 repeats print, filled in with the
// measurements samples of ratios `truth(set)` would give, with relative noise `noise` on every
// length and `rise_chord`: curvature given as rise and chord (and no length_after) instead.
std::string filled_sheet(const std::function<Truth(int)>& truth, double noise, bool rise_chord,
                         unsigned seed = 1) {
  CalibrationPrintOptions o;
  o.nozzle_temperatures = {190, 210};
  o.layer_heights = {0.08, 0.16};
  const PrinterProfile printer = load_printer("creality-cr10s-pro");
  const Material material = load_material("pla-paper");
  const CalibrationPlan plan = plan_calibration(printer, material, o);
  const std::string sheet = calibration_csv_template(plan, material, printer);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, 1);
  auto noisy = [&](double x) { return x * (1 + noise * n(rng)); };
  std::istringstream in(sheet);
  std::string out, line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("sample,", 0) == 0) {
      out += line + "\n";
      continue;
    }
    // sample,set,plate,T,h,layers,L,W,T0,,,,,, -> fill the after columns.
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    const int set = std::stoi(cells[1]);
    const Truth t = truth(set);
    const double l0 = std::stod(cells[6]), w0 = std::stod(cells[7]), t0 = std::stod(cells[8]);
    const double l = noisy(l0 * t.lambda1), w = noisy(w0 * t.lambda2), th = noisy(t0 * t.lambda3);
    const double kappa = noisy(t.kappa);
    std::string row = fmt::format("{},{},{},{},{},{},{},{},{}", cells[0], cells[1], cells[2],
                                  cells[3], cells[4], cells[5], cells[6], cells[7], cells[8]);
    if (rise_chord) {
      // The arc of length l and curvature kappa: chord 2R sin(phi/2), rise R (1 - cos(phi/2)).
      const double r = 1 / kappa, phi = kappa * l;
      row += fmt::format(",,{:.10f},{:.10f},,{:.10f},{:.10f}", w, th, r * (1 - std::cos(phi / 2)),
                         2 * r * std::sin(phi / 2));
    } else {
      row += fmt::format(",{:.10f},{:.10f},{:.10f},{:.10f},,", l, w, th, kappa);
    }
    out += row + "\n";
  }
  return out;
}

Truth four_sets(int set) {
  // Set ids run temperature-major: 1 = (190, 0.08), 2 = (190, 0.16), 3 = (210, 0.08), ...
  switch (set) {
    case 1:
      return {0.58, 1.08, 1.52, 0.0322};
    case 2:
      return {0.66, 1.05, 1.40, 0.0250};
    case 3:
      return {0.62, 1.06, 1.45, 0.0300};
    default:
      return {0.71, 1.03, 1.30, 0.0200};
  }
}

TEST(Measurements, FitsBackKnownRatiosFromNoisyMeasurements) {
  const MeasurementSheet sheet =
      parse_measurements(filled_sheet(four_sets, 0.004, false), "synthetic.csv");
  EXPECT_FALSE(sheet.thickness_ramp);
  EXPECT_EQ(sheet.expected_samples, 16);
  ASSERT_TRUE(sheet.material.has_value());
  EXPECT_EQ(sheet.material->name, "pla-paper");
  std::vector<SetFit> sets = fit_sets(sheet);
  ASSERT_EQ(sets.size(), 4u);
  for (const SetFit& f : sets) {
    const Truth t = four_sets(f.set);
    EXPECT_EQ(f.samples, 4);
    EXPECT_NEAR(f.lambda1.mean, t.lambda1, 0.01) << f.set;
    EXPECT_NEAR(f.lambda2.mean, t.lambda2, 0.01) << f.set;
    EXPECT_NEAR(f.lambda3.mean, t.lambda3, 0.015) << f.set;
    EXPECT_NEAR(f.contraction_pct.mean, 100 * (1 - t.lambda1), 1.0) << f.set;
    // The spread is the noise's: about 0.4 % of the ratio, not zero and not much more.
    EXPECT_GT(f.lambda1.std, 0.0002) << f.set;
    EXPECT_LT(f.lambda1.std, 0.02) << f.set;
    ASSERT_TRUE(f.delta_lambda1.has_value());
    const double dl = -f.thickness * t.lambda3 * t.lambda1 * t.kappa;  // Eq. 18
    EXPECT_NEAR(f.delta_lambda1->mean, dl, 0.05 * std::abs(dl)) << f.set;
    EXPECT_LT(f.delta_lambda1->mean, 0);  // the top shrinks more: the top is concave
  }
  // Set 1 (the paper's 190 C, 0.08 mm) contracts most.
  rank_sets(sets);
  EXPECT_EQ(sets[0].set, 1);
  EXPECT_EQ(sets[1].set, 3);
  EXPECT_EQ(sets[3].set, 4);
  // Its material: the fitted ratios, the set's printing parameters, the rest from the sheet.
  const Material m = fitted_material(*sheet.material, sets[0], "my-pla", "test");
  EXPECT_EQ(m.name, "my-pla");
  EXPECT_NEAR(m.lambda1, 0.58, 0.01);
  EXPECT_NEAR(m.lambda3, 1.52, 0.015);
  EXPECT_NEAR(m.delta_lambda1, -0.8 * 1.52 * 0.58 * 0.0322, 0.002);
  EXPECT_EQ(m.nozzle_temperature, 190);
  EXPECT_EQ(m.layer_height, 0.08);
  EXPECT_EQ(m.bed_temperature, 55);
  EXPECT_EQ(m.print_speed, 30);
}

TEST(Measurements, RiseOverChordGivesTheCurvatureAndTheArcLength) {
  const MeasurementSheet sheet =
      parse_measurements(filled_sheet(four_sets, 0, true), "synthetic.csv");
  for (const SetFit& f : fit_sets(sheet)) {
    const Truth t = four_sets(f.set);
    EXPECT_NEAR(f.lambda1.mean, t.lambda1, 1e-8) << f.set;
    ASSERT_TRUE(f.curvature.has_value());
    EXPECT_NEAR(f.curvature->mean, t.kappa, 1e-8) << f.set;
    EXPECT_NEAR(f.curvature->std, 0, 1e-8);
  }
}

TEST(Measurements, CurvatureAndArcOfACircle) {
  // A half circle of radius 10: chord 20, rise 10, length 10 pi.
  EXPECT_NEAR(curvature_from_rise(10, 20), 0.1, 1e-12);
  EXPECT_NEAR(arc_length_from_rise(10, 20), 10 * M_PI, 1e-9);
  // Three quarters of a circle of radius 10: rise 10 + 10/sqrt(2), chord 10 sqrt(2).
  const double s = 10 + 10 / std::sqrt(2.0), c = 10 * std::sqrt(2.0);
  EXPECT_NEAR(curvature_from_rise(s, c), 0.1, 1e-12);
  EXPECT_NEAR(arc_length_from_rise(s, c), 1.5 * M_PI * 10, 1e-9);
  EXPECT_NEAR(curvature_from_rise(-1, 30), -curvature_from_rise(1, 30), 1e-15);
  EXPECT_EQ(arc_length_from_rise(0, 30), 30);
  // The paper's PLA: kappa = 0.03215 /mm gives its Delta lambda1 (notes §1.3).
  EXPECT_NEAR(
      delta_lambda1_from_curvature(0.8, 1.52, 0.58, 0.0226764665509417 / (0.8 * 1.52 * 0.58)),
      -0.0226764665509417, 1e-15);
}

// The UserError message of parsing `text`, which must name line `line` and column `column`.
std::string sheet_error(const std::string& text, int line, const std::string& column) {
  try {
    parse_measurements(text, "m.csv");
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kFormat);
    const std::string message = e.what();
    EXPECT_NE(message.find("m.csv: line " + std::to_string(line)), std::string::npos) << message;
    EXPECT_NE(message.find(column), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << "accepted";
  return "";
}

const char* kHeader =
    "# samples = 2\n"
    "sample,set,plate,nozzle_temperature,layer_height,layers,length_before,width_before,"
    "thickness_before,length_after,width_after,thickness_after,curvature,rise,chord\n";

TEST(Measurements, BadCellsNameTheLineAndTheColumn) {
  const std::string good = "1,1,1,190,0.08,10,80,20,0.8,46.4,21.6,1.216,0.032,,\n";
  ASSERT_NO_THROW(parse_measurements(std::string(kHeader) + good + good.substr(0, 0) +
                                         "2,1,1,190,0.08,10,80,20,0.8,46,21.6,1.2,0.03,,\n",
                                     "m.csv"));
  // A missing value.
  EXPECT_NE(
      sheet_error(std::string(kHeader) + good + "2,1,1,190,0.08,10,80,20,0.8,46,,1.2,0.03,,\n", 4,
                  "column 11 (width_after)")
          .find("missing"),
      std::string::npos);
  // Not a number.
  EXPECT_NE(
      sheet_error(std::string(kHeader) + good + "2,1,1,190,0.08,10,80,20,0.8,46,21,1.2mm,0.03,,\n",
                  4, "column 12 (thickness_after)")
          .find("not a number"),
      std::string::npos);
  // A length that grew along the path.
  EXPECT_NE(
      sheet_error(std::string(kHeader) + "1,1,1,190,0.08,10,46,20,0.8,80,21,1.2,0.03,,\n" + good, 3,
                  "column 10 (length_after)")
          .find("grew"),
      std::string::npos);
  // A missing curvature.
  sheet_error(std::string(kHeader) + good + "2,1,1,190,0.08,10,80,20,0.8,46,21,1.2,,,\n", 4,
              "column 13 (curvature)");
  // A rise without its chord.
  sheet_error(std::string(kHeader) + good + "2,1,1,190,0.08,10,80,20,0.8,46,21,1.2,,3,\n", 4,
              "column 15 (chord)");
  // A decimal comma splits a cell in two.
  sheet_error(std::string(kHeader) + good + "2,1,1,190,0.08,10,80,20,0.8,46,21,1,2,0.03,,\n", 4,
              "column 16");
  // Units mistake: a width in cm.
  sheet_error(std::string(kHeader) + good + "2,1,1,190,0.08,10,80,20,0.8,46,2.16,1.2,0.03,,\n", 4,
              "width_after");
  // A set whose rows disagree on the layer height.
  sheet_error(std::string(kHeader) + good + "2,1,1,190,0.12,7,80,20,0.84,46,21,1.2,0.03,,\n", 4,
              "layer_height");
  // The same sample twice.
  sheet_error(std::string(kHeader) + good + good, 4, "column 1 (sample)");
}

TEST(Measurements, RowCountMustMatchTheTemplate) {
  const std::string good = "1,1,1,190,0.08,10,80,20,0.8,46.4,21.6,1.216,0.032,,\n";
  const std::string message = sheet_error(std::string(kHeader) + good, 1, "2 samples");
  EXPECT_NE(message.find("1 rows"), std::string::npos) << message;
  // A lost sample stays as a row with skip.
  const MeasurementSheet sheet = parse_measurements(
      std::string(kHeader) + good + "2,1,1,190,0.08,10,80,20,0.8,skip,,,,,\n", "m.csv");
  ASSERT_EQ(sheet.rows.size(), 2u);
  EXPECT_TRUE(sheet.rows[1].skipped);
  const std::vector<SetFit> sets = fit_sets(sheet);
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_EQ(sets[0].samples, 1);
  EXPECT_NEAR(sets[0].lambda1.mean, 0.58, 1e-12);
}

TEST(Measurements, MissingColumnsAndEmptySheetsAreRefused) {
  sheet_error("sample,set\n1,1\n", 1, "length_before");
  EXPECT_THROW(parse_measurements("# only comments\n", "m.csv"), UserError);
}

TEST(Measurements, ThicknessRampSheetGivesTheCurve) {
  // A ramp of known lambda1(h) = 0.45 + 1.2 h, 6 layers, curvature not measured.
  std::string text = "# kind = thickness-ramp\n# samples = 12\n";
  text += std::string(kHeader).substr(std::string(kHeader).find('\n') + 1);
  int id = 1;
  for (double h : {0.08, 0.12, 0.16, 0.20, 0.24, 0.28}) {
    for (int r = 0; r < 2; ++r, ++id) {
      text += fmt::format("{},{},1,200,{},6,80,20,{},{},21,{},,,\n", id, (id + 1) / 2, h, 6 * h,
                          80 * (0.45 + 1.2 * h), 6 * h * 1.4);
    }
  }
  const MeasurementSheet sheet = parse_measurements(text, "ramp.csv");
  EXPECT_TRUE(sheet.thickness_ramp);
  const ThicknessCurve c = fit_thickness_curve(sheet);
  EXPECT_NEAR(lambda1_at_layer_height(c, 0.1), 0.57, 1e-9);
  EXPECT_NEAR(layer_height_for_lambda1(c, 0.69), 0.2, 1e-9);
  EXPECT_EQ(c.layers, 6);
  EXPECT_EQ(c.nozzle_temperature, 200);
  // Sets without curvature keep no delta_lambda1.
  for (const SetFit& f : fit_sets(sheet)) EXPECT_FALSE(f.delta_lambda1.has_value());
}

}  // namespace
}  // namespace flatmorph::measurements_test
