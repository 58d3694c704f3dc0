// The G-code writer, judged by the independent reader of gcode_replay.cpp: what the file makes the
// printer do must be what the toolpath says, on every shipped printer.
#include "gcode/gcode_writer.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "common/error.h"
#include "gcode/gcode_check.h"
#include "gcode_expectations.h"
#include "gcode_fixtures.h"
#include "gcode_replay.h"
#include "test_support.h"

namespace flatmorph::gcode_writer_test {
namespace {

using testing::disk_toolpath;
using testing::read_gcode;
using testing::ReadGcode;

double filament_area(const PrinterProfile& p) {
  return std::numbers::pi * p.filament_diameter * p.filament_diameter / 4;
}

// The extruding segments of a layer, in print order.
struct Segment {
  Eigen::Vector3d a, b;
  SegmentStyle style;
};
std::vector<Segment> extruding_segments(const ToolpathLayer& layer) {
  std::vector<Segment> out;
  for (const PathPolyline& path : layer.paths) {
    for (size_t i = 0; i < path.segments.size(); ++i) {
      if (!path.segments[i].travel) {
        out.push_back(
            {path.points.row(i).transpose(), path.points.row(i + 1).transpose(), path.segments[i]});
      }
    }
  }
  return out;
}

class EveryPrinter : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryPrinter, ReaderRecoversTheToolpath) {
  const PrinterProfile printer = load_printer(GetParam());
  const Material material = load_material("pla-paper");
  const Toolpath toolpath = disk_toolpath();
  const GcodeResult result = make_gcode(toolpath, printer, {material});
  const Eigen::Vector2d center = bed_center(printer);
  const ReadGcode read = read_gcode(result.text, center.x(), center.y());

  // Layers: one ;LAYER_CHANGE each, with the toolpath's z and height.
  ASSERT_EQ(read.layers.size(), toolpath.layers.size());
  const double area = filament_area(printer);
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    const ToolpathLayer& layer = toolpath.layers[k];
    const testing::ReadLayer& got = read.layers[k];
    EXPECT_NEAR(got.z_tag, layer.z, 5e-4) << "layer " << k;
    EXPECT_NEAR(got.height_tag, layer.height, 5e-4) << "layer " << k;
    // Extruded volume within 1 % of the toolpath's (it is far closer: E has 5 decimals).
    const double volume = got.filament() * area;
    EXPECT_NEAR(volume, extrusion_volume(layer), 0.01 * extrusion_volume(layer)) << "layer " << k;
    EXPECT_NEAR(volume, extrusion_volume(layer), 1e-3 * extrusion_volume(layer)) << "layer " << k;
    // Segment by segment: same place, same bead, same annotations.
    const std::vector<Segment> segments = extruding_segments(layer);
    ASSERT_EQ(got.extrusions.size(), segments.size()) << "layer " << k;
    for (size_t i = 0; i < segments.size(); ++i) {
      const Segment& s = segments[i];
      const testing::ReadExtrusion& e = got.extrusions[i];
      const Eigen::Vector2d b = s.b.head<2>() + result.plate_to_bed;
      ASSERT_NEAR(e.x1, b.x(), 6e-4);
      ASSERT_NEAR(e.y1, b.y(), 6e-4);
      ASSERT_NEAR(e.z, layer.z, 6e-4);
      ASSERT_NEAR(e.width, s.style.width, 6e-4);
      ASSERT_NEAR(e.height, s.style.layer_height, 6e-4);
      const double expected = (s.b - s.a).norm() * s.style.width * s.style.layer_height / area;
      ASSERT_NEAR(e.filament, expected, 2e-5 + 1e-4 * expected)
          << "layer " << k << " segment " << i;
    }
  }
  testing::expect_annotated_and_within_printer(read, printer);

  // Temperatures as set by the material, none above its limits, all off at the end.
  EXPECT_NE(std::find(read.nozzle_targets.begin(), read.nozzle_targets.end(), 190.0),
            read.nozzle_targets.end());
  EXPECT_NE(std::find(read.bed_targets.begin(), read.bed_targets.end(), 55.0),
            read.bed_targets.end());
  testing::expect_within_limits_and_off_at_end(read, material);

  // E mode declared before extruding and as the profile says; no extrusion while travelling.
  EXPECT_TRUE(read.mode_declared_before_extrusion);
  EXPECT_EQ(read.relative_e, printer.relative_e);
  EXPECT_EQ(read.g0_with_e, 0);
  EXPECT_EQ(read.extrusions_while_retracted, 0);
  if (!printer.relative_e || printer.flavor == GcodeFlavor::kBambu) {
    EXPECT_EQ(read.g92_e0_in_layers, static_cast<int>(toolpath.layers.size()));
  }

  // The check passes what the writer wrote (make_gcode already refuses otherwise).
  EXPECT_TRUE(check_gcode(result.text, printer, {material}).empty());

  // Estimates in the slicers' form, consistent with the result.
  EXPECT_EQ(read.header.at("filament used [mm]"), fmt::format("{:.2f}", result.filament_length));
  EXPECT_EQ(read.header.at("filament used [g]"), fmt::format("{:.2f}", result.filament_mass));
  EXPECT_TRUE(read.header.count("estimated printing time (normal mode)"));
  double total_volume = 0;
  for (const ToolpathLayer& layer : toolpath.layers) total_volume += extrusion_volume(layer);
  EXPECT_NEAR(result.filament_volume, total_volume, 1e-6 * total_volume);
  EXPECT_NEAR(result.filament_mass, total_volume / 1000 * material.density, 1e-6);
  // At least the time of the extruding moves at their nominal speed.
  double nominal = 0;
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const Segment& s : extruding_segments(layer)) {
      const double speed = s.style.feed_rate > 0                ? s.style.feed_rate
                           : &layer == &toolpath.layers.front() ? material.first_layer_speed
                                                                : material.print_speed;
      nominal += (s.b - s.a).norm() / speed;
    }
  }
  EXPECT_GT(result.print_time, nominal);
  EXPECT_LT(result.print_time, 2 * nominal);
}

INSTANTIATE_TEST_SUITE_P(Presets, EveryPrinter, ::testing::ValuesIn(printer_preset_names()),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(GcodeWriter, ShipsTheRequiredPrinters) {
  const std::vector<std::string> names = printer_preset_names();
  for (const char* required :
       {"creality-cr10s-pro", "creality-ender3-v2", "creality-k1-max", "prusa-mk3s", "prusa-mk4",
        "bambu-x1c", "bambu-p1s", "generic-marlin", "generic-klipper"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
  }
}

// Centre of the bounding box of the points of a toolpath (plate frame), computed here
// independently of the writer.
Eigen::Vector2d bbox_center(const Toolpath& toolpath) {
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      for (Eigen::Index i = 0; i < path.points.rows(); ++i) {
        lo = lo.cwiseMin(path.points.row(i).head<2>().transpose());
        hi = hi.cwiseMax(path.points.row(i).head<2>().transpose());
      }
    }
  }
  return (lo + hi) / 2;
}

// Centre of the bounding box of what the file extrudes (bed coordinates).
Eigen::Vector2d printed_center(const ReadGcode& read) {
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const auto& layer : read.layers) {
    for (const auto& e : layer.extrusions) {
      lo = lo.cwiseMin(Eigen::Vector2d(std::min(e.x0, e.x1), std::min(e.y0, e.y1)));
      hi = hi.cwiseMax(Eigen::Vector2d(std::max(e.x0, e.x1), std::max(e.y0, e.y1)));
    }
  }
  return (lo + hi) / 2;
}

TEST(GcodeWriter, CentresThePlateOnTheBed) {
  const PrinterProfile printer = load_printer("creality-cr10s-pro");
  const Toolpath toolpath = disk_toolpath();  // a disk around (37, -12) in the plate frame
  const GcodeResult result = make_gcode(toolpath, printer, {load_material("pla-paper")});
  const Eigen::Vector2d expected = Eigen::Vector2d(150, 150) - bbox_center(toolpath);
  EXPECT_NEAR((result.plate_to_bed - expected).norm(), 0, 1e-9);
  EXPECT_NEAR(expected.x(), 150 - 37, 0.5);
  EXPECT_NEAR(expected.y(), 150 + 12, 0.5);
  EXPECT_NE(result.text.find(fmt::format("x_bed = x_plate + {:.3f}, y_bed = y_plate + {:.3f}",
                                         expected.x(), expected.y())),
            std::string::npos);
  const Eigen::Vector2d center = printed_center(read_gcode(result.text));
  EXPECT_NEAR(center.x(), 150, 1e-3);
  EXPECT_NEAR(center.y(), 150, 1e-3);
}

TEST(GcodeWriter, PlacesThePlateWhereAsked) {
  const PrinterProfile printer = load_printer("generic-marlin");
  GcodeOptions options;
  options.at = Eigen::Vector2d(60, 150);
  const GcodeResult result =
      make_gcode(disk_toolpath(30), printer, {load_material("pla-paper")}, options);
  const Eigen::Vector2d center = printed_center(read_gcode(result.text));
  EXPECT_NEAR(center.x(), 60, 1e-3);
  EXPECT_NEAR(center.y(), 150, 1e-3);
  EXPECT_NE(result.text.find("placement = plate centre at (60, 150) (--at)"), std::string::npos);
}

TEST(GcodeWriter, RefusesAPlateLargerThanTheBed) {
  const PrinterProfile printer = load_printer("creality-ender3-v2");
  try {
    make_gcode(disk_toolpath(115, 2), printer, {load_material("pla-paper")});
    FAIL() << "a 230 mm plate on a 220 mm bed was accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
    const std::string message = e.what();
    EXPECT_NE(message.find("the plate is 229."), std::string::npos) << message;
    EXPECT_NE(message.find("does not fit the 220 x 220 x 250 mm bed"), std::string::npos)
        << message;
    EXPECT_NE(message.find("creality-ender3-v2"), std::string::npos) << message;
  }
  // Fits alone, but not with a skirt of 5 loops 3 mm away.
  GcodeOptions skirt;
  skirt.skirt_loops = 5;
  EXPECT_NO_THROW(make_gcode(disk_toolpath(108, 2), printer, {load_material("pla-paper")}));
  try {
    make_gcode(disk_toolpath(108, 2), printer, {load_material("pla-paper")}, skirt);
    FAIL() << "the skirt was allowed off the bed";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
    EXPECT_NE(std::string(e.what()).find("with the skirt"), std::string::npos) << e.what();
  }
}

TEST(GcodeWriter, RefusesAPlacementOffTheBed) {
  GcodeOptions options;
  options.at = Eigen::Vector2d(20, 110);
  try {
    make_gcode(disk_toolpath(30, 2), load_printer("generic-marlin"), {load_material("pla-paper")},
               options);
    FAIL() << "a plate reaching x = -10 was accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
    EXPECT_NE(std::string(e.what()).find("--at 20,110"), std::string::npos) << e.what();
  }
}

TEST(GcodeWriter, RefusesOnARoundBedWhatOnlyTheSquareWouldHold) {
  const PrinterProfile delta = load_printer("generic-delta");  // 200 mm round
  Toolpath square;
  ToolpathLayer layer;
  layer.z = layer.height = 0.1;
  // A 150 x 150 mm square outline: fits a 200 mm square, not a 200 mm circle (diagonal 212 mm).
  layer.paths.push_back(
      testing::line_path({-75, -75}, {75, -75}, 0.1, 0.1, 5, 0, PathType::kCustom));
  layer.paths.push_back(testing::line_path({75, -75}, {75, 75}, 0.1, 0.1, 5, 0, PathType::kCustom));
  square.layers.push_back(layer);
  EXPECT_THROW(make_gcode(square, delta, {load_material("pla-paper")}), UserError);
  EXPECT_NO_THROW(make_gcode(disk_toolpath(95, 2, {0, 0}), delta, {load_material("pla-paper")}));
}

TEST(GcodeWriter, RefusesAPrintTallerThanThePrinter) {
  Toolpath toolpath = disk_toolpath(20, 1);
  for (auto& path : toolpath.layers[0].paths) path.points.col(2).setConstant(249.9);
  toolpath.layers[0].z = 249.9;
  try {
    make_gcode(toolpath, load_printer("creality-ender3-v2"), {load_material("pla-paper")});
    FAIL();
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
    EXPECT_NE(std::string(e.what()).find("250"), std::string::npos) << e.what();
  }
}

TEST(GcodeWriter, RefusesAToolThePrinterLacks) {
  Toolpath toolpath = disk_toolpath(20, 1);
  toolpath.layers[0].paths[0].segments[0].tool = 1;
  try {
    make_gcode(toolpath, load_printer("creality-ender3-v2"), {load_material("pla-paper")});
    FAIL();
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
  }
}

TEST(GcodeWriter, SameInputSameBytes) {
  const Toolpath toolpath = disk_toolpath();
  const PrinterProfile printer = load_printer("prusa-mk4");
  const Material material = load_material("pla-paper");
  GcodeOptions options;
  options.skirt_loops = 3;
  const std::filesystem::path dir = testing::scratch_dir();
  write_gcode(dir / "a.gcode", toolpath, printer, {material}, options);
  write_gcode(dir / "b.gcode", toolpath, printer, {material}, options);
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  const std::string a = slurp(dir / "a.gcode");
  EXPECT_GT(a.size(), 100000u);
  EXPECT_EQ(a, slurp(dir / "b.gcode"));
  EXPECT_EQ(a, make_gcode(toolpath, printer, {material}, options).text);
}

TEST(GcodeWriter, AnnotatesLikePrusaSlicer) {
  const GcodeResult result =
      make_gcode(disk_toolpath(), load_printer("prusa-mk3s"), {load_material("pla-paper")});
  std::istringstream in(result.text);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  int layers = 0, types = 0, widths = 0;
  bool type_in_layer = false, width_seen = false;
  double last_width = -1;
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    if (l == ";LAYER_CHANGE") {
      ++layers;
      ASSERT_LT(i + 2, lines.size());
      EXPECT_EQ(lines[i + 1].rfind(";Z:", 0), 0u) << lines[i + 1];
      EXPECT_EQ(lines[i + 2].rfind(";HEIGHT:", 0), 0u) << lines[i + 2];
      type_in_layer = false;
    } else if (l.rfind(";TYPE:", 0) == 0) {
      ++types;
      type_in_layer = true;
      const std::string name = l.substr(6);
      EXPECT_TRUE(name == "Solid infill" || name == "Perimeter" || name == "External perimeter")
          << name;
    } else if (l.rfind(";WIDTH:", 0) == 0) {
      const double w = std::stod(l.substr(7));
      EXPECT_NE(w, last_width) << "a ;WIDTH: that does not change the width, line " << i + 1;
      last_width = w;
      width_seen = true;
      ++widths;
    } else if (l.rfind("G1 X", 0) == 0 && l.find(" E") != std::string::npos && layers > 0) {
      ASSERT_TRUE(type_in_layer) << "extrusion before ;TYPE: in its layer, line " << i + 1;
      ASSERT_TRUE(width_seen) << "extrusion before any ;WIDTH:, line " << i + 1;
    }
  }
  EXPECT_EQ(layers, 10);
  EXPECT_GE(types, 10);
  EXPECT_GT(widths, 10);
}

TEST(GcodeWriter, RetractsAndLiftsOnLongTravelsOnly) {
  // Two parallel lines 0.5 mm apart (no retraction), then a line 30 mm away (retract and lift).
  const PrinterProfile printer = load_printer("creality-cr10s-pro");  // 5 mm, z-hop 0.4, 2 mm
  Toolpath toolpath;
  ToolpathLayer layer;
  layer.z = layer.height = 0.2;
  layer.paths.push_back(
      testing::line_path({0, 0}, {20, 0}, 0.2, 0.2, 20, 0, PathType::kSolidInfill));
  layer.paths.push_back(
      testing::line_path({20, 0.5}, {0, 0.5}, 0.2, 0.2, 20, 0, PathType::kSolidInfill));
  layer.paths.push_back(
      testing::line_path({0, 30}, {20, 30}, 0.2, 0.2, 20, 0, PathType::kSolidInfill));
  toolpath.layers.push_back(layer);
  const GcodeResult result = make_gcode(toolpath, printer, {load_material("pla-paper")});
  const std::string& t = result.text;
  const size_t body = t.find(";LAYER_CHANGE");
  // Absolute E: the retraction goes 5 mm back from the current E, the lift is 0.4 mm.
  // The plate (x 0..20, y 0..30) is centred on the 300 mm bed: offset (140, 135).
  const size_t short_travel = t.find("G0 X160.000 Y135.500", body);
  ASSERT_NE(short_travel, std::string::npos) << t.substr(body, 2000);
  const size_t previous = t.rfind('\n', short_travel - 2) + 1;
  EXPECT_EQ(t.compare(previous, 20, "G1 X160.000 Y135.000"), 0) << t.substr(previous, 40);
  const size_t long_travel = t.find("G0 X140.000 Y165.000", body);
  ASSERT_NE(long_travel, std::string::npos);
  const std::string between = t.substr(short_travel, long_travel - short_travel + 80);
  EXPECT_EQ(between.find("; retract"), between.rfind("; retract\nG0 Z0.600"))  // only there
      << between;
  EXPECT_NE(between.find("; retract\nG0 Z0.600 F300\nG0 X140.000 Y165.000 F7200\n"
                         "G0 Z0.200 F300\nG1 E"),
            std::string::npos)
      << between;
  const ReadGcode read = read_gcode(t);
  EXPECT_EQ(read.extrusions_while_retracted, 0);
}

TEST(GcodeWriter, RelativeEAndFirmwareRetraction) {
  const PrinterProfile delta = load_printer("generic-delta");  // M83, G10/G11, centre origin
  const GcodeResult result =
      make_gcode(disk_toolpath(40, 3, {0, 0}), delta, {load_material("pla-paper")});
  EXPECT_NE(result.text.find("M83 ; relative E"), std::string::npos);
  EXPECT_NE(result.text.find("G10 ; retract (firmware)"), std::string::npos);
  EXPECT_NE(result.text.find("G11 ; unretract (firmware)"), std::string::npos);
  EXPECT_EQ(result.text.find("G92 E0\n;"), std::string::npos);   // no per-layer reset in M83
  EXPECT_NE(result.text.find("M106 S1.00"), std::string::npos);  // RepRapFirmware fan scale
  EXPECT_NEAR(result.plate_to_bed.norm(), 0, 1e-9);
}

TEST(GcodeWriter, FanFollowsTheMaterial) {
  Material material = load_material("pla-paper");
  material.fan_speed = 50;
  const GcodeResult result =
      make_gcode(disk_toolpath(20, 3), load_printer("generic-marlin"), {material});
  const size_t first_layer = result.text.find(";LAYER_CHANGE");
  const size_t second_layer = result.text.find(";LAYER_CHANGE", first_layer + 1);
  EXPECT_LT(result.text.find("M107"), first_layer);  // off on the first layer
  EXPECT_EQ(result.text.find("M106 S128", second_layer), result.text.find("M106", first_layer));
  EXPECT_NE(result.text.find("M106 S128", second_layer), std::string::npos);
}

TEST(GcodeWriter, SkirtSurroundsTheFirstLayer) {
  GcodeOptions options;
  options.skirt_loops = 3;
  options.skirt_distance = 4;
  const Toolpath toolpath = disk_toolpath(30, 2, {0, 0});
  const PrinterProfile printer = load_printer("generic-marlin");
  const GcodeResult result = make_gcode(toolpath, printer, {load_material("pla-paper")}, options);
  const ReadGcode read = read_gcode(result.text, 110, 110);
  double skirt_filament = 0, min_radius = 1e9;
  for (const auto& e : read.layers[0].extrusions) {
    if (e.type != "Skirt/Brim") continue;
    skirt_filament += e.filament;
    min_radius = std::min(min_radius, std::hypot(e.x1 - 110, e.y1 - 110));
  }
  // Three loops of a 0.35 x 0.054 mm bead (the first segment's) around a disk of radius 29.8 mm,
  // at 4 + 0.175, 0.525 and 0.875 mm from it.
  EXPECT_GT(min_radius, 33.5);
  const double bead =
      2 * std::numbers::pi * (3 * 29.8 + 3 * 4 + 0.175 + 0.525 + 0.875) * 0.35 * 0.054;
  EXPECT_NEAR(skirt_filament * filament_area(printer), bead, 0.02 * bead);
  // The layer's own volume is unchanged.
  double plate = 0;
  for (const auto& e : read.layers[0].extrusions) {
    if (e.type != "Skirt/Brim") plate += e.filament;
  }
  EXPECT_NEAR(plate * filament_area(printer), extrusion_volume(toolpath.layers[0]),
              1e-3 * extrusion_volume(toolpath.layers[0]));
}

TEST(GcodeWriter, TemplatesGetThePrintArea) {
  // The Bambu start G-code levels only the print area (G29 A X Y I J).
  const Toolpath toolpath = disk_toolpath(40, 2, {0, 0});
  const GcodeResult result =
      make_gcode(toolpath, load_printer("bambu-x1c"), {load_material("pla-paper")});
  const std::string expected = fmt::format(
      "G29 A X{:.3f} Y{:.3f} I{:.3f} J{:.3f}", result.print_min.x(), result.print_min.y(),
      result.print_max.x() - result.print_min.x(), result.print_max.y() - result.print_min.y());
  EXPECT_NE(result.text.find(expected), std::string::npos) << expected;
  EXPECT_NEAR(result.print_max.x() - result.print_min.x(), 80 - 2 * 0.2, 0.5);
  EXPECT_EQ(result.text.find('{'), std::string::npos);
}

}  // namespace
}  // namespace flatmorph::gcode_writer_test
