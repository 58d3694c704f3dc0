// The calibration print, judged by the independent G-code reader of tests/gcode/ and the safety
// check: on the bed, the toolpath's volumes, each set at its own temperature, and no travel through
// a set printed earlier.
#include "calibration/calibration_print.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <sstream>

#include "common/error.h"
#include "gcode/gcode_check.h"
#include "gcode/gcode_expectations.h"
#include "gcode/gcode_replay.h"

namespace flatmorph::calibration_print_test {
namespace {

using testing::read_gcode;
using testing::ReadGcode;

struct Box {
  double x0, y0, x1, y1;
};

// Does the segment a-b (xy) pass through the box (grown by `pad`)? Liang-Barsky clipping.
bool crosses(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Box& box, double pad) {
  double t0 = 0, t1 = 1;
  const Eigen::Vector2d d = b - a;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() - (box.x0 - pad), (box.x1 + pad) - a.x(), a.y() - (box.y0 - pad),
                       (box.y1 + pad) - a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  return true;
}

// Replays the head in `text` (absolute X Y Z, as the writer always states G90) and reports every
// move that runs lower than `clearance` above the top of a set printed earlier while crossing its
// samples. `boxes[s]` are the bed boxes of the samples of the s-th set printed; a set counts as
// printed from the section comment of the next one on.
std::vector<std::string> collisions(const std::string& text,
                                    const std::vector<std::vector<Box>>& boxes,
                                    const std::vector<double>& tops) {
  std::vector<std::string> out;
  std::istringstream in(text);
  Eigen::Vector3d pos(0, 0, 0);
  bool known = false;
  int section = -1;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("; ---- section ", 0) == 0) ++section;
    const std::string code = line.substr(0, line.find(';'));
    std::istringstream ws(code);
    std::string word;
    ws >> word;
    if (word != "G0" && word != "G1") continue;
    Eigen::Vector3d next = pos;
    bool moves = false;
    for (std::string w; ws >> w;) {
      const int axis = w[0] == 'X' ? 0 : w[0] == 'Y' ? 1 : w[0] == 'Z' ? 2 : -1;
      if (axis >= 0) {
        next(axis) = std::stod(w.substr(1));
        moves = true;
      }
    }
    if (!moves) continue;
    // Straight up is always safe (the lift at a section change starts on the set just printed).
    const bool up = next.head<2>() == pos.head<2>() && next.z() >= pos.z();
    if (known && section > 0 && !up) {
      for (int s = 0; s < section; ++s) {
        const double low = std::min(pos.z(), next.z());
        if (low >= tops[static_cast<size_t>(s)] + 0.05) continue;
        for (const Box& b : boxes[static_cast<size_t>(s)]) {
          if (crosses(pos.head<2>(), next.head<2>(), b, 0.5)) {
            out.push_back(line);
            break;
          }
        }
      }
    }
    pos = next;
    known = true;
  }
  return out;
}

void expect_sound_plate(const CalibrationPlan& plan, size_t p, const PrinterProfile& printer,
                        const Material& material) {
  const CalibrationPlate& plate = plan.plates[p];
  GcodeOptions options;
  options.sections = plate.sections;
  const Material m = plate_material(plan, p, material);
  const GcodeResult result = make_gcode(plate.toolpath, printer, {m}, options);
  const Eigen::Vector2d center = bed_center(printer);
  const ReadGcode read = read_gcode(result.text, center.x(), center.y());

  // Every layer of every set, with the toolpath's z, height and volume.
  ASSERT_EQ(read.layers.size(), plate.toolpath.layers.size());
  const double area = std::numbers::pi * printer.filament_diameter * printer.filament_diameter / 4;
  for (size_t k = 0; k < read.layers.size(); ++k) {
    const ToolpathLayer& layer = plate.toolpath.layers[k];
    EXPECT_NEAR(read.layers[k].z_tag, layer.z, 5e-4) << k;
    EXPECT_NEAR(read.layers[k].height_tag, layer.height, 5e-4) << k;
    EXPECT_NEAR(read.layers[k].filament() * area, extrusion_volume(layer),
                1e-3 * extrusion_volume(layer))
        << k;
    for (const auto& e : read.layers[k].extrusions) ASSERT_NEAR(e.z, layer.z, 6e-4);
  }
  testing::expect_annotated_and_within_printer(read, printer);

  // Each set at its own nozzle temperature: the target in effect at every layer of the set.
  // (The target in effect at the first extrusion of each layer.)
  std::vector<double> target_at_layer;
  double target = -1;
  bool pending = false;
  for (const std::string& line : read.lines) {
    if (line.rfind("M104 S", 0) == 0 || line.rfind("M109 S", 0) == 0) {
      target = std::stod(line.substr(6));
    }
    if (line == ";LAYER_CHANGE") pending = true;
    if (pending && line.rfind("G1 X", 0) == 0 && line.find(" E") != std::string::npos) {
      target_at_layer.push_back(target);
      pending = false;
    }
  }
  ASSERT_EQ(target_at_layer.size(), plate.toolpath.layers.size());
  std::vector<std::vector<Box>> boxes;
  std::vector<double> tops;
  for (size_t s = 0; s < plate.sections.size(); ++s) {
    const CalibrationSet& set = plan.sets[static_cast<size_t>(plate.sets[s] - 1)];
    const size_t end = s + 1 < plate.sections.size() ? plate.sections[s + 1].first_layer
                                                     : plate.toolpath.layers.size();
    EXPECT_EQ(end - plate.sections[s].first_layer, static_cast<size_t>(set.layers));
    for (size_t k = plate.sections[s].first_layer; k < end; ++k) {
      EXPECT_EQ(target_at_layer[k], set.nozzle_temperature) << "layer " << k;
    }
    std::vector<Box> b;
    for (const CalibrationSample& sample : plan.samples) {
      if (sample.set != set.id) continue;
      const Eigen::Vector2d c = sample.center + result.plate_to_bed;
      b.push_back({c.x() - plan.options.length / 2, c.y() - plan.options.width / 2,
                   c.x() + plan.options.length / 2, c.y() + plan.options.width / 2});
    }
    boxes.push_back(b);
    tops.push_back(set.thickness());
  }
  testing::expect_within_limits_and_off_at_end(read, material);
  EXPECT_TRUE(read.mode_declared_before_extrusion);
  EXPECT_EQ(read.g0_with_e, 0);
  EXPECT_EQ(read.extrusions_while_retracted, 0);

  // No move runs through a set printed before at less than its height.
  const std::vector<std::string> hits = collisions(result.text, boxes, tops);
  EXPECT_TRUE(hits.empty()) << hits.size()
                            << " moves through earlier sets, first: " << hits.front();

  EXPECT_TRUE(check_gcode(result.text, printer, {m}).empty());
}

TEST(CalibrationPrint, PaperSamplesOnTheCr10) {
  const PrinterProfile printer = load_printer("creality-cr10s-pro");
  const Material material = load_material("pla-paper");
  const CalibrationPlan plan = plan_calibration(printer, material, {});
  ASSERT_EQ(plan.sets.size(), 9u);
  ASSERT_EQ(plan.samples.size(), 36u);
  EXPECT_EQ(plan.code_bits, 6);
  EXPECT_NEAR(plan.extrusion_width, 0.4, 1e-12);
  EXPECT_EQ(plan.paths_per_layer, 50);
  // Layers: round(0.8 / h).
  EXPECT_EQ(plan.sets[0].layers, 10);
  EXPECT_EQ(plan.sets[1].layers, 7);
  EXPECT_EQ(plan.sets[2].layers, 5);
  EXPECT_EQ(plan.sets[3].nozzle_temperature, 200);
  EXPECT_GE(plan.plates.size(), 1u);
  size_t sets = 0;
  for (size_t p = 0; p < plan.plates.size(); ++p) {
    sets += plan.plates[p].sets.size();
    SCOPED_TRACE(p);
    expect_sound_plate(plan, p, printer, material);
  }
  EXPECT_EQ(sets, 9u);
}

TEST(CalibrationPrint, SamplesAreSeparateAndEachSetIsOneRectangle) {
  const PrinterProfile printer = load_printer("creality-ender3-v2");
  const CalibrationPlan plan = plan_calibration(printer, load_material("pla-paper"), {});
  EXPECT_GT(plan.plates.size(), 1u);  // 9 sets do not fit 220 x 220
  const double l = plan.options.length, w = plan.options.width;
  for (const CalibrationSample& a : plan.samples) {
    // Inside the bed's usable area once centred (the writer centres the plate).
    for (const CalibrationSample& b : plan.samples) {
      if (a.id >= b.id || a.plate != b.plate) continue;
      const bool apart = std::abs(a.center.x() - b.center.x()) >= l + plan.options.gap - 1e-9 ||
                         std::abs(a.center.y() - b.center.y()) >= w + plan.options.gap - 1e-9;
      EXPECT_TRUE(apart) << a.id << " " << b.id;
      // A sample of another set never lies inside the bounding rectangle of a's set.
      if (a.set == b.set) continue;
      Box box{1e9, 1e9, -1e9, -1e9};
      for (const CalibrationSample& s : plan.samples) {
        if (s.set != a.set) continue;
        box = {std::min(box.x0, s.center.x() - l / 2), std::min(box.y0, s.center.y() - w / 2),
               std::max(box.x1, s.center.x() + l / 2), std::max(box.y1, s.center.y() + w / 2)};
      }
      EXPECT_FALSE(b.center.x() + l / 2 > box.x0 && b.center.x() - l / 2 < box.x1 &&
                   b.center.y() + w / 2 > box.y0 && b.center.y() - w / 2 < box.y1)
          << "sample " << b.id << " lies in the rectangle of set " << a.set;
    }
  }
}

TEST(CalibrationPrint, EveryPrinterGetsSafeGcode) {
  const Material material = load_material("pla-paper");
  CalibrationPrintOptions o;
  o.nozzle_temperatures = {190, 210};
  o.layer_heights = {0.08, 0.16};
  o.repeats = 2;
  for (const std::string& name : printer_preset_names()) {
    SCOPED_TRACE(name);
    const PrinterProfile printer = load_printer(name);
    const CalibrationPlan plan = plan_calibration(printer, material, o);
    for (size_t p = 0; p < plan.plates.size(); ++p) expect_sound_plate(plan, p, printer, material);
  }
}

TEST(CalibrationPrint, NotchCodeIsReadableFromThePaths) {
  const PrinterProfile printer = load_printer("creality-cr10s-pro");
  const CalibrationPlan plan = plan_calibration(printer, load_material("pla-paper"), {});
  std::set<std::vector<bool>> codes;
  for (const CalibrationSample& s : plan.samples) {
    const std::vector<bool> code = notch_code(s.id, plan.code_bits);
    EXPECT_TRUE(codes.insert(code).second) << "two samples share code " << s.id;
    EXPECT_NE(std::count(code.begin(), code.end(), true), 0);
    EXPECT_NE(std::count(code.begin(), code.end(), true), plan.code_bits);
    // Read the code back from the first layer of the sample's set: per slot, whether its paths
    // stop short of the sample's +x end by the notch depth.
    const CalibrationPlate& plate = plan.plates[static_cast<size_t>(s.plate - 1)];
    size_t layer = 0;
    for (size_t i = 0; i < plate.sets.size(); ++i) {
      if (plate.sets[i] == s.set) layer = plate.sections[i].first_layer;
    }
    const double slot = plan.options.width / plan.code_bits;
    std::vector<int> notched(static_cast<size_t>(plan.code_bits), -1);
    for (const PathPolyline& path : plate.toolpath.layers[layer].paths) {
      const double y = path.points(0, 1) - (s.center.y() - plan.options.width / 2);
      const double x_end = path.points.col(0).maxCoeff() - s.center.x();
      if (y < 0 || y > plan.options.width ||
          std::abs(path.points(0, 0) - s.center.x()) > plan.options.length / 2 + 0.5) {
        continue;
      }
      const size_t j = static_cast<size_t>(y / slot);
      const int cut = x_end < plan.options.length / 2 - plan.options.notch_depth ? 1 : 0;
      if (notched[j] == -1) notched[j] = cut;
      EXPECT_EQ(notched[j], cut) << "slot " << j << " of sample " << s.id << " is ragged";
    }
    for (size_t j = 0; j < code.size(); ++j) EXPECT_EQ(notched[j], code[j] ? 1 : 0) << s.id;
  }
  EXPECT_EQ(notch_code(5, 6), (std::vector<bool>{true, false, true, false, false, false}));
}

TEST(CalibrationPrint, ThicknessRampPrintsSixLayersAtEveryHeight) {
  const PrinterProfile printer = load_printer("prusa-mk4");
  const Material material = load_material("pla-paper");
  CalibrationPrintOptions o;
  o.thickness_ramp = true;
  o.nozzle_temperatures = {200};
  o.layer_heights = {0.08, 0.12, 0.16, 0.2, 0.24, 0.28};
  o.repeats = 3;
  const CalibrationPlan plan = plan_calibration(printer, material, o);
  ASSERT_EQ(plan.sets.size(), 6u);
  for (const CalibrationSet& s : plan.sets) EXPECT_EQ(s.layers, 6);
  for (size_t p = 0; p < plan.plates.size(); ++p) expect_sound_plate(plan, p, printer, material);
  const std::string csv = calibration_csv_template(plan, material, printer);
  EXPECT_NE(csv.find("# kind = thickness-ramp"), std::string::npos);
  EXPECT_NE(csv.find("# samples = 18"), std::string::npos);
}

TEST(CalibrationPrint, RefusesWhatCannotBePrinted) {
  const PrinterProfile printer = load_printer("creality-ender3-v2");
  const Material material = load_material("pla-paper");
  auto expect_error = [&](CalibrationPrintOptions o, ErrorCategory category) {
    try {
      plan_calibration(printer, material, o);
      ADD_FAILURE() << "accepted";
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), category) << e.what();
    }
  };
  CalibrationPrintOptions o;
  o.nozzle_temperatures = {250};  // above pla-paper's 230
  expect_error(o, ErrorCategory::kOption);
  o = {};
  o.layer_heights = {0.5};  // above 80 % of the 0.4 mm nozzle
  expect_error(o, ErrorCategory::kOption);
  o = {};
  o.length = 300;  // longer than the bed
  expect_error(o, ErrorCategory::kInfeasible);
  o = {};
  o.width = 5;  // 36 samples need 6 notches: under a mm each
  expect_error(o, ErrorCategory::kOption);
  o = {};
  o.thickness_ramp = true;  // with three temperatures
  expect_error(o, ErrorCategory::kOption);
}

TEST(CalibrationPrint, TemplateHasOneRowPerSample) {
  const PrinterProfile printer = load_printer("creality-cr10s-pro");
  const Material material = load_material("pla-paper");
  const CalibrationPlan plan = plan_calibration(printer, material, {});
  const std::string csv = calibration_csv_template(plan, material, printer);
  std::istringstream in(csv);
  int rows = 0;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#' && line.rfind("sample,", 0) != 0) ++rows;
  }
  EXPECT_EQ(rows, 36);
  EXPECT_NE(csv.find("\n1,1,1,190,0.08,10,80,20,0.8,,,,,,\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n36,9,"), std::string::npos);
  std::vector<Eigen::Vector2d> offsets(plan.plates.size(), Eigen::Vector2d(150, 150));
  const std::string svg = calibration_layout_svg(plan, printer, offsets, {"a.gcode", "b.gcode"});
  EXPECT_NE(svg.find("#36 (set 9)"), std::string::npos);
  EXPECT_NE(svg.find("slots are worth 1, 2, 4, 8, 16, 32"), std::string::npos);
}

}  // namespace
}  // namespace flatmorph::calibration_print_test
