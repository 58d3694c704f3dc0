// The speed curve (Thermorph Fig. 6): fitted back from samples of a known polynomial, inverted,
// refused outside its calibrated range; the speed-ramp print that measures it (one set per speed,
// every layer but the first at that speed, read back from its G-code) and its measurement sheet.
#include "material/speed_curve.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "calibration/calibration_print.h"
#include "calibration/fit.h"
#include "calibration/measurements.h"
#include "common/error.h"
#include "gcode/gcode_reader.h"
#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"

namespace flatmorph::speed_curve_test {
namespace {

// A cubic in v (mm/s), decreasing on [20, 150] (lambda1' < 0 there: faster shrinks more), from
// 0.765 at 20 mm/s to 0.5725 at 150 mm/s.
const std::vector<double> kTrue = {0.82, -3.0e-3, 1.2e-5, -2.0e-8};
const std::vector<double> kSpeeds = {20, 40, 60, 90, 120, 150};

double truth(double v) {
  double value = 0;
  for (size_t i = kTrue.size(); i-- > 0;) value = value * v + kTrue[i];
  return value;
}

SpeedCurve exact_fit() {
  std::vector<double> v, l1;
  for (double s : kSpeeds) {
    for (int r = 0; r < 3; ++r) {
      v.push_back(s);
      l1.push_back(truth(s));
    }
  }
  return fit_speed_curve(v, l1, 0.08, 200);
}

TEST(SpeedCurve, ExactSamplesGiveBackTheCubic) {
  const SpeedCurve c = exact_fit();
  // Six speeds allow degree 4; its v^4 coefficient comes out zero. Compared scaled by the range's
  // top speed, so that every power weighs alike.
  ASSERT_EQ(c.lambda1_coefficients.size(), 5u);
  for (size_t i = 0; i < 5; ++i) {
    const double want = i < kTrue.size() ? kTrue[i] : 0.0;
    EXPECT_NEAR(c.lambda1_coefficients[i] * std::pow(150.0, i), want * std::pow(150.0, i), 1e-9)
        << i;
  }
  EXPECT_EQ(c.min_print_speed, 20);
  EXPECT_EQ(c.max_print_speed, 150);
  EXPECT_EQ(c.layer_height, 0.08);
  EXPECT_EQ(c.nozzle_temperature, 200);
  EXPECT_TRUE(speed_curve_problem(c).empty());
  for (double v = 20; v <= 150; v += 2.5) EXPECT_NEAR(lambda1_at_print_speed(c, v), truth(v), 1e-9);
}

TEST(SpeedCurve, InverseOfTheForwardWithin1e9) {
  const SpeedCurve c = exact_fit();
  for (double v = 20; v <= 150; v += 5) {
    EXPECT_NEAR(print_speed_for_lambda1(c, lambda1_at_print_speed(c, v)), v, 1e-9) << v;
  }
  // A wanted ratio gives a speed where the true curve has that ratio.
  EXPECT_NEAR(truth(print_speed_for_lambda1(c, 0.7)), 0.7, 1e-9);
}

TEST(SpeedCurve, RefusesValuesOutsideTheCalibratedRange) {
  const SpeedCurve c = exact_fit();
  for (double v : {19.0, 151.0, 1500.0}) {
    try {
      lambda1_at_print_speed(c, v);
      ADD_FAILURE() << v << " mm/s was accepted";
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
      EXPECT_NE(std::string(e.what()).find("[20, 150] mm/s"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--speed-ramp"), std::string::npos) << e.what();
    }
  }
  for (double lambda1 : {truth(150) - 0.01, truth(20) + 0.01, 0.3, 1.0}) {
    try {
      print_speed_for_lambda1(c, lambda1);
      ADD_FAILURE() << lambda1 << " was accepted";
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
      EXPECT_NE(std::string(e.what()).find("print speeds 20 to 150 mm/s"), std::string::npos)
          << e.what();
    }
  }
}

TEST(SpeedCurve, NeedsTwoSpeedsAndARateThatChanges) {
  EXPECT_THROW(fit_speed_curve({60, 60, 60}, {0.6, 0.61, 0.6}, 0.08, 200), UserError);
  EXPECT_THROW(fit_speed_curve({20, 60, 100}, {0.6, 0.6, 0.6}, 0.08, 200), UserError);
}

CalibrationPrintOptions speed_ramp_options() {
  CalibrationPrintOptions o;
  o.speed_ramp = true;
  o.nozzle_temperatures = {200};
  o.layer_heights = {0.08};
  o.print_speeds = kSpeeds;
  o.repeats = 2;
  return o;
}

TEST(SpeedRampPrint, OneSetPerSpeedAndTheGcodePrintsEachAtItsSpeed) {
  const PrinterProfile printer = load_printer("prusa-mk4");
  const Material material = load_material("pla-paper");
  const CalibrationPlan plan = plan_calibration(printer, material, speed_ramp_options());
  ASSERT_EQ(plan.sets.size(), kSpeeds.size());
  for (size_t i = 0; i < plan.sets.size(); ++i) {
    EXPECT_EQ(plan.sets[i].print_speed, kSpeeds[i]);
    EXPECT_EQ(plan.sets[i].layer_height, 0.08);
    EXPECT_EQ(plan.sets[i].nozzle_temperature, 200);
    EXPECT_EQ(plan.sets[i].layers, 10);  // round(0.8 / 0.08)
  }
  int checked_sets = 0;
  for (size_t p = 0; p < plan.plates.size(); ++p) {
    const CalibrationPlate& plate = plan.plates[p];
    GcodeOptions options;
    options.sections = plate.sections;
    const GcodeResult result =
        make_gcode(plate.toolpath, printer, {plate_material(plan, p, material)}, options);
    const GcodeDeposition read = read_gcode_deposition(result.text, "speed-ramp.gcode");
    // The feed rates (mm/min) of the print's beads per layer; layer k of the file is layer k of
    // the toolpath (the start G-code's purge, before the first layer change, carries no ;TYPE:).
    std::map<int, std::set<double>> feeds;
    for (const DepositedBead& bead : read.beads) {
      if (!bead.type.empty()) feeds[bead.layer].insert(bead.feed_rate);
    }
    for (size_t s = 0; s < plate.sections.size(); ++s) {
      const CalibrationSet& set = plan.sets[static_cast<size_t>(plate.sets[s] - 1)];
      const size_t first = plate.sections[s].first_layer;
      SCOPED_TRACE(set.label());
      EXPECT_EQ(feeds[static_cast<int>(first)], std::set<double>{material.first_layer_speed * 60});
      for (size_t k = first + 1; k < first + static_cast<size_t>(set.layers); ++k) {
        EXPECT_EQ(feeds[static_cast<int>(k)], std::set<double>{set.print_speed * 60}) << k;
      }
      ++checked_sets;
    }
  }
  EXPECT_EQ(checked_sets, static_cast<int>(kSpeeds.size()));

  const std::string csv = calibration_csv_template(plan, material, printer);
  EXPECT_NE(csv.find("# kind = speed-ramp\n"), std::string::npos);
  EXPECT_NE(csv.find("\nsample,set,plate,nozzle_temperature,layer_height,layers,print_speed,"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\n1,1,1,200,0.08,10,20,80,20,0.8,,,,,,\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n12,6,"), std::string::npos);
}

TEST(SpeedRampPrint, RefusesWhatItCannotPrint) {
  const PrinterProfile printer = load_printer("creality-cr10s-pro");  // travels at 120 mm/s
  const Material material = load_material("pla-paper");
  auto message = [&](const CalibrationPrintOptions& o) -> std::string {
    try {
      plan_calibration(printer, material, o);
      ADD_FAILURE() << "accepted";
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kOption) << e.what();
      return e.what();
    }
    return "";
  };
  CalibrationPrintOptions o = speed_ramp_options();  // up to 150 mm/s
  EXPECT_NE(message(o).find("150 mm/s is above 120 mm/s, the travel speed of printer"),
            std::string::npos);
  o = speed_ramp_options();
  o.thickness_ramp = true;
  EXPECT_NE(message(o).find("print them one at a time"), std::string::npos);
  o = speed_ramp_options();
  o.nozzle_temperatures = {190, 210};
  EXPECT_NE(message(o).find("one nozzle temperature and one layer height"), std::string::npos);
  o = speed_ramp_options();
  o.print_speeds = {20, 60, 20};
  EXPECT_NE(message(o).find("listed twice"), std::string::npos);
  o = speed_ramp_options();
  o.print_speeds = {1500, 3000};  // mm/min
  EXPECT_FALSE(message(o).empty());
  o = speed_ramp_options();
  o.print_speeds = {20, 60};
  o.thickness = 0.08;  // one layer: only the first-layer speed
  EXPECT_NE(message(o).find("one layer"), std::string::npos);
}

// The template of a speed ramp on the MK4, filled in with samples of lambda1 = truth(v).
MeasurementSheet measured_speed_ramp() {
  const PrinterProfile printer = load_printer("prusa-mk4");
  const Material material = load_material("pla-paper");
  const CalibrationPlan plan = plan_calibration(printer, material, speed_ramp_options());
  std::istringstream in(calibration_csv_template(plan, material, printer));
  std::string text;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line.rfind("sample,", 0) == 0) {
      text += line + "\n";
      continue;
    }
    // sample .. print_speed, length_before, width_before, thickness_before: then the after columns
    std::vector<std::string> c;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
    const double v = std::stod(c[6]);
    text += fmt::format("{},{},{},{},{},{},{},{},{},{},{:.9f},21.4,1.2,,,\n", c[0], c[1], c[2],
                        c[3], c[4], c[5], c[6], c[7], c[8], c[9], 80 * truth(v));
  }
  return parse_measurements(text, "speed-ramp.csv");
}

TEST(SpeedRampSheet, FitsTheCurveAndTheSetsKeepTheirSpeed) {
  const MeasurementSheet sheet = measured_speed_ramp();
  EXPECT_TRUE(sheet.speed_ramp);
  EXPECT_FALSE(sheet.thickness_ramp);
  const SpeedCurve c = fit_speed_curve(sheet);
  EXPECT_EQ(c.min_print_speed, 20);
  EXPECT_EQ(c.max_print_speed, 150);
  EXPECT_EQ(c.layer_height, 0.08);
  for (double v = 20; v <= 150; v += 10) EXPECT_NEAR(lambda1_at_print_speed(c, v), truth(v), 1e-8);

  std::vector<SetFit> sets = fit_sets(sheet);
  ASSERT_EQ(sets.size(), kSpeeds.size());
  for (size_t i = 0; i < sets.size(); ++i) {
    EXPECT_TRUE(sets[i].speed_ramp);
    EXPECT_EQ(sets[i].print_speed, kSpeeds[i]);
  }
  // The fastest shrinks most and is written with the speed its ratios hold at.
  rank_sets(sets);
  EXPECT_EQ(sets.front().print_speed, 150);
  // A base calibrated before, with a speed curve that ends at 100 mm/s, does not pass its curve on.
  Material base = load_material("pla-paper");
  base.speed_curve = SpeedCurve{{0.7, -0.002}, 20, 100, 0.08, 190};
  const Material m = fitted_material(base, sets.front(), "fast", "");
  EXPECT_EQ(m.print_speed, 150);
  EXPECT_NEAR(m.lambda1, truth(150), 1e-8);
  EXPECT_FALSE(m.speed_curve.has_value());

  // The speed column is required, and constant within a set.
  std::string text =
      "# kind = speed-ramp\nsample,set,nozzle_temperature,layer_height,layers,"
      "length_before,width_before,thickness_before,length_after,width_after,"
      "thickness_after\n1,1,200,0.08,10,80,20,0.8,60,21,1.2\n";
  try {
    parse_measurements(text, "no-speed.csv");
    ADD_FAILURE() << "a speed ramp without print_speed was accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("no-speed.csv: line 2: no column \"print_speed\""),
              std::string::npos)
        << e.what();
  }
  text =
      "# kind = speed-ramp\nsample,set,nozzle_temperature,layer_height,layers,print_speed,"
      "length_before,width_before,thickness_before,length_after,width_after,thickness_after\n"
      "1,1,200,0.08,10,20,80,20,0.8,60,21,1.2\n2,1,200,0.08,10,40,80,20,0.8,60,21,1.2\n";
  EXPECT_THROW(parse_measurements(text, "mixed.csv"), UserError);
}

}  // namespace
}  // namespace flatmorph::speed_curve_test
