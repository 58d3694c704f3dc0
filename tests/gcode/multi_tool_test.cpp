// Prints with several tools, one material each (PLA and TPU on a two-tool Prusa XL): the
// independent reader of gcode_replay.cpp sees each tool at its own material's temperature and
// speed, a tool change exactly where the toolpath changes tool, the profile's tool-change template
// and a prime on the pad at each, and per-tool filament matching the toolpath; the check judges
// each tool by its own material. Primes and shared nozzles in detail: tool_change_test.cpp.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>

#include "common/error.h"
#include "gcode/gcode_check.h"
#include "gcode/gcode_writer.h"
#include "gcode_expectations.h"
#include "gcode_fixtures.h"
#include "gcode_replay.h"
#include "test_support.h"

namespace flatmorph::multi_tool_test {
namespace {

using testing::read_gcode;
using testing::ReadGcode;

double filament_area(const PrinterProfile& p) {
  return std::numbers::pi * p.filament_diameter * p.filament_diameter / 4;
}

// The disk of gcode_fixtures.h with PLA on T0 and TPU on T1: the odd layers (arcs) on T1, every
// third line of layer 2 on T1, and the second half of one line of layer 4 on T1 (a change in the
// middle of a path).
Toolpath two_tool_toolpath() {
  Toolpath toolpath = testing::disk_toolpath(40, 6);
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    std::vector<PathPolyline>& paths = toolpath.layers[k].paths;
    for (size_t p = 0; p < paths.size(); ++p) {
      const bool tpu = k % 2 == 1 || (k == 2 && p % 3 == 1);
      for (SegmentStyle& s : paths[p].segments) s.tool = tpu ? 1 : 0;
    }
  }
  PathPolyline& split = toolpath.layers[4].paths[5];
  for (size_t i = split.segments.size() / 2; i < split.segments.size(); ++i) {
    split.segments[i].tool = 1;
  }
  return toolpath;
}

std::vector<Material> pla_tpu() {
  return {load_material("pla-paper"), load_material("tpu-generic")};
}

struct Expected {
  int tool;
  double volume;  // mm^3
  double speed;   // mm/s
};

// The extruding segments of the toolpath in print order, with the tool, volume and speed each
// should get; the skirt (`skirt_segments` on the first layer's first tool) comes first.
std::vector<Expected> expected_extrusions(const Toolpath& toolpath,
                                          const std::vector<Material>& materials) {
  std::vector<Expected> out;
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    for (const PathPolyline& path : toolpath.layers[k].paths) {
      for (size_t i = 0; i < path.segments.size(); ++i) {
        const SegmentStyle& s = path.segments[i];
        if (s.travel) continue;
        const Material& m = materials[static_cast<size_t>(s.tool)];
        const double speed = s.feed_rate > 0 ? s.feed_rate
                             : k == 0        ? m.first_layer_speed
                                             : m.print_speed;
        out.push_back(
            {s.tool,
             (path.points.row(i + 1) - path.points.row(i)).norm() * s.width * s.layer_height,
             speed});
      }
    }
  }
  return out;
}

std::string fan_line(const Material& m, bool first_layer) {
  const double percent = first_layer ? m.first_layer_fan_speed : m.fan_speed;
  return percent <= 0 ? "M107" : fmt::format("M106 S{}", std::lround(percent / 100 * 255));
}

class TwoTools : public ::testing::TestWithParam<bool> {};

// With relative E (the XL's) and absolute E (each tool change restarts the register).
TEST_P(TwoTools, PrintIsTheToolpathToolByTool) {
  PrinterProfile printer = load_printer("prusa-xl-2t");
  printer.relative_e = GetParam();
  const std::vector<Material> materials = pla_tpu();
  const Toolpath toolpath = two_tool_toolpath();
  GcodeOptions options;
  options.skirt_loops = 2;
  const GcodeResult result = make_gcode(toolpath, printer, materials, options);
  EXPECT_TRUE(check_gcode(result.text, printer, materials).empty());
  const ReadGcode read = read_gcode(result.text);
  ASSERT_EQ(read.layers.size(), toolpath.layers.size());
  testing::expect_annotated_and_within_printer(read, printer);

  // Every extrusion of the plate (the skirt apart) with its segment's tool, volume and speed, at
  // its tool's material temperature.
  const std::vector<Expected> expected = expected_extrusions(toolpath, materials);
  const double area = filament_area(printer);
  std::vector<testing::ReadExtrusion> all, plate;
  for (const auto& layer : read.layers) {
    for (const auto& e : layer.extrusions) {
      all.push_back(e);
      if (e.type != "Skirt/Brim" && e.type != "Wipe tower") plate.push_back(e);
    }
  }
  ASSERT_EQ(plate.size(), expected.size());
  std::vector<double> volume(2, 0.0), read_volume(2, 0.0), read_filament(2, 0.0);
  for (size_t i = 0; i < plate.size(); ++i) {
    const testing::ReadExtrusion& e = plate[i];
    ASSERT_EQ(e.tool, expected[i].tool) << "extrusion " << i;
    ASSERT_NEAR(e.filament * area, expected[i].volume, 3e-5 + 1e-4 * expected[i].volume) << i;
    ASSERT_EQ(e.feed, std::round(expected[i].speed * 60)) << "extrusion " << i;
    ASSERT_EQ(e.nozzle_target, materials[static_cast<size_t>(e.tool)].nozzle_temperature) << i;
    volume[static_cast<size_t>(e.tool)] += expected[i].volume;
    read_volume[static_cast<size_t>(e.tool)] += e.filament * area;
  }
  std::vector<double> primed(2, 0.0);
  for (const auto& e : all) {
    read_filament[static_cast<size_t>(e.tool)] += e.filament;
    if (e.type == "Skirt/Brim") {
      EXPECT_EQ(e.tool, 0);  // the skirt primes the first tool
    }
    if (e.type == "Wipe tower") primed[static_cast<size_t>(e.tool)] += e.filament * area;
  }
  // Per-tool totals: the toolpath's volumes, and the result's lengths and masses.
  ASSERT_EQ(result.tool_filament_length.size(), 2u);
  ASSERT_EQ(result.tool_filament_mass.size(), 2u);
  for (size_t t = 0; t < 2; ++t) {
    EXPECT_GT(volume[t], 100);
    EXPECT_NEAR(read_volume[t], volume[t], 1e-4 * volume[t]) << "T" << t;
    EXPECT_NEAR(result.tool_filament_length[t], read_filament[t], 1e-4 * read_filament[t]);
    EXPECT_NEAR(result.tool_filament_mass[t],
                result.tool_filament_length[t] * area / 1000 * materials[t].density, 1e-9);
  }
  EXPECT_NEAR(result.filament_length, read_filament[0] + read_filament[1],
              1e-4 * result.filament_length);
  EXPECT_NEAR(result.filament_mass, result.tool_filament_mass[0] + result.tool_filament_mass[1],
              1e-9);
  EXPECT_EQ(read.header.at("filament used [mm]"),
            fmt::format("{:.2f}, {:.2f}", result.tool_filament_length[0],
                        result.tool_filament_length[1]));
  EXPECT_EQ(read.header.at("T1 material"), "tpu-generic");

  // A tool change exactly where consecutive extrusions change tool, and nowhere else.
  std::vector<testing::ReadToolChange> changes;
  int tool = 0;
  for (size_t i = 0; i < all.size(); ++i) {
    if (all[i].tool != tool) changes.push_back({0, tool, all[i].tool, i});
    tool = all[i].tool;
  }
  EXPECT_GT(changes.size(), 10u);
  ASSERT_EQ(read.tool_changes.size(), changes.size());
  EXPECT_EQ(result.tool_changes, static_cast<int>(changes.size()));
  for (size_t c = 0; c < changes.size(); ++c) {
    const testing::ReadToolChange& got = read.tool_changes[c];
    EXPECT_EQ(got.from, changes[c].from);
    EXPECT_EQ(got.to, changes[c].to);
    EXPECT_EQ(got.extrusions_before, changes[c].extrusions_before);
    // The template around it: park, wait for the next tool at its material's temperature, pick it
    // up (the T line); then that tool's fan and its prime on the pad.
    const auto& lines = read.lines;
    const size_t t_line = static_cast<size_t>(got.line) - 1;
    ASSERT_GE(t_line, 2u);
    EXPECT_EQ(lines[t_line - 2].rfind(fmt::format("P0 S1 L2 D0 ; park T{}", got.from), 0), 0u)
        << lines[t_line - 2];
    EXPECT_EQ(
        lines[t_line - 1].rfind(fmt::format(
            "M109 T{} S{:g}", got.to, materials[static_cast<size_t>(got.to)].nozzle_temperature)),
        0u)
        << lines[t_line - 1];
    EXPECT_EQ(lines[t_line].rfind(fmt::format("T{} S1 L0 D0", got.to), 0), 0u) << lines[t_line];
    EXPECT_EQ(all[got.extrusions_before].type, "Wipe tower") << "change " << c;
    const bool first_layer = got.extrusions_before < read.layers[0].extrusions.size();
    const std::string fan = fan_line(materials[static_cast<size_t>(got.to)], first_layer);
    bool fan_seen = false;
    for (size_t l = t_line + 1; l < lines.size() && lines[l].rfind("G1 X", 0) != 0; ++l) {
      fan_seen = fan_seen || lines[l] == fan;
    }
    EXPECT_TRUE(fan_seen) << "no \"" << fan << "\" after the change at line " << got.line;
  }
  EXPECT_EQ(
      std::count_if(read.lines.begin(), read.lines.end(),
                    [](const std::string& l) { return l.rfind("P0 S1 L2 D0 ; park T", 0) == 0; }),
      static_cast<long>(changes.size()));
  // The profile's 6 mm^3 for each change into a tool (the first, T0 -> T0, is none).
  for (size_t t = 0; t < 2; ++t) {
    const long into = std::count_if(changes.begin(), changes.end(),
                                    [&](const auto& c) { return c.to == static_cast<int>(t); });
    EXPECT_NEAR(primed[t], 6.0 * static_cast<double>(into), 0.01 * static_cast<double>(into))
        << "T" << t;
  }

  // Both tools heated before printing and off at the end.
  EXPECT_EQ(read.tool_nozzle_targets.at(1).front(), 225);
  EXPECT_EQ(read.final_tool_nozzle.at(0), 0);
  EXPECT_EQ(read.final_tool_nozzle.at(1), 0);
  EXPECT_EQ(read.final_bed, 0);
  EXPECT_EQ(read.extrusions_while_retracted, 0);
  EXPECT_EQ(result.text.find('{'), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(MultiTool, TwoTools, ::testing::Values(true, false), [](const auto& info) {
  return std::string(info.param ? "RelativeE" : "AbsoluteE");
});

TEST(MultiTool, APrintOnToolOneSelectsItAfterTheStart) {
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  Toolpath toolpath = testing::disk_toolpath(30, 3);
  for (auto& layer : toolpath.layers) {
    for (auto& path : layer.paths) {
      for (auto& s : path.segments) s.tool = 1;
    }
  }
  GcodeOptions options;
  options.skirt_loops = 1;
  const GcodeResult result = make_gcode(toolpath, printer, pla_tpu(), options);
  const ReadGcode read = read_gcode(result.text);
  ASSERT_EQ(read.tool_changes.size(), 1u);
  EXPECT_EQ(read.tool_changes[0].from, 0);
  EXPECT_EQ(read.tool_changes[0].to, 1);
  EXPECT_EQ(read.tool_changes[0].extrusions_before, 0u);
  for (const auto& layer : read.layers) {
    for (const auto& e : layer.extrusions) ASSERT_EQ(e.tool, 1);  // the skirt too
  }
  // The start G-code heated T0, which the print does not use: off before printing.
  EXPECT_NE(result.text.find("M104 T0 S0 ; the print does not use tool 0"), std::string::npos);
  EXPECT_EQ(result.tool_filament_length[0], 0);
  EXPECT_GT(result.tool_filament_length[1], 0);
  EXPECT_TRUE(check_gcode(result.text, printer, pla_tpu()).empty());
}

TEST(MultiTool, SingleToolPrintsHaveNoToolChange) {
  const GcodeResult result = make_gcode(testing::disk_toolpath(30, 3), load_printer("prusa-xl-2t"),
                                        {load_material("pla-paper")});
  EXPECT_TRUE(read_gcode(result.text).tool_changes.empty());
  EXPECT_EQ(result.text.find("P0 S1 L2 D0 ; park T"), std::string::npos);
}

UserError make_error(const Toolpath& toolpath, const std::string& printer,
                     const std::vector<Material>& materials) {
  try {
    make_gcode(toolpath, load_printer(printer), materials);
  } catch (const UserError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    return e;
  }
  ADD_FAILURE() << "accepted";
  return UserError(ErrorCategory::kFormat, "");
}

TEST(MultiTool, RefusesMissingOrExtraMaterialsAndTools) {
  const Toolpath two = two_tool_toolpath();
  // T1 without a material.
  UserError e = make_error(two, "prusa-xl-2t", {load_material("pla-paper")});
  EXPECT_EQ(e.category(), ErrorCategory::kOption);
  EXPECT_NE(std::string(e.what()).find("tool T1 but only 1 material"), std::string::npos)
      << e.what();
  // Two materials for a one-tool printer that cannot swap filament.
  e = make_error(testing::disk_toolpath(30, 2), "creality-ender3-v2", pla_tpu());
  EXPECT_EQ(e.category(), ErrorCategory::kOption);
  EXPECT_NE(
      std::string(e.what()).find("2 materials given but the printer creality-ender3-v2 has 1"),
      std::string::npos)
      << e.what();
  // A tool the printer lacks.
  Toolpath three = two;
  three.layers[1].paths[0].segments[0].tool = 2;
  e = make_error(three, "prusa-xl-2t", pla_tpu());
  EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
  EXPECT_NE(std::string(e.what()).find("T2"), std::string::npos) << e.what();
  // T0's bed too hot for T1's material.
  Material cool = load_material("tpu-generic");
  cool.max_bed_temperature = 45;
  cool.bed_temperature = 40;
  e = make_error(two, "prusa-xl-2t", {load_material("pla-paper"), cool});
  EXPECT_EQ(e.category(), ErrorCategory::kOption);
  EXPECT_NE(std::string(e.what()).find("bed temperature 55 C of pla-paper"), std::string::npos)
      << e.what();
}

TEST(MultiTool, ProfilesStateTheirToolChange) {
  auto error = [](const std::string& json_text) -> std::string {
    try {
      parse_printer(json_text, "my-printer.json");
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kProfile);
      return e.what();
    }
    return "accepted";
  };
  const PrinterProfile xl = load_printer("prusa-xl-2t");
  EXPECT_EQ(xl.extruder_count, 2);
  EXPECT_EQ(xl.bed_size, Eigen::Vector2d(360, 360));
  EXPECT_EQ(xl.max_height, 360);
  EXPECT_NE(xl.tool_change.gcode.find("T{next_tool} S1 L0 D0"), std::string::npos);
  EXPECT_FALSE(xl.tool_change.shared_nozzle);
  EXPECT_EQ(xl.tool_change.prime_volume, 6);
  // The XL preset with one key changed.
  std::string text;
  {
    const testing::CliResult r = testing::run_cli({"printers", "prusa-xl-2t"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    text = r.out;
  }
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? t : t.replace(at, from.size(), to);
  };
  EXPECT_EQ(error(text), "accepted");
  EXPECT_NE(error(with("\"extruders\": 2,", ""))
                .find("tool_change applies to printers with more than one tool"),
            std::string::npos);
  EXPECT_NE(error(with("\"tool_change\"", "\"tool_changes\"")).find("\"tool_change\""),
            std::string::npos);
  EXPECT_NE(error(with("\"T{next_tool} S1 L0 D0", "\"M117 T{next_tool}"))
                .find("never selects the next tool"),
            std::string::npos);
  EXPECT_NE(error(with("M140 S{bed_temperature} ;", "M140 S{bed_temperature} T{next_tool} ;"))
                .find("unknown placeholder {next_tool}"),
            std::string::npos);
  EXPECT_NE(error(with("S{next_temperature}", "S{bed_size_x}")).find("unknown placeholder"),
            std::string::npos);
}

TEST(MultiTool, CheckJudgesEachToolByItsMaterial) {
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  const std::string text = make_gcode(two_tool_toolpath(), printer, pla_tpu()).text;
  auto kinds = [](const std::vector<GcodeViolation>& found) {
    std::set<std::string> k;
    for (const GcodeViolation& v : found) k.insert(std::string(to_string(v.kind)));
    return k;
  };
  auto line_of = [&](const std::string& t, const std::string& needle) {
    const size_t at = t.find(needle);
    return at == std::string::npos
               ? -1
               : static_cast<int>(std::count(t.begin(), t.begin() + at, '\n')) + 1;
  };
  // The PLA temperature on the TPU tool: its extrusions are cold for TPU.
  std::string cold = text;
  for (size_t at; (at = cold.find("T1 S225")) != std::string::npos;) cold.replace(at, 7, "T1 S190");
  std::vector<GcodeViolation> found = check_gcode(cold, printer, pla_tpu());
  ASSERT_FALSE(found.empty());
  EXPECT_EQ(kinds(found), std::set<std::string>{"cold-extrusion"});
  EXPECT_NE(found.front().reason.find("(T1) is set to 190 C, below 210 C"), std::string::npos)
      << found.front().reason;
  // The same file with the materials swapped: PLA's 190 C is cold for TPU on T0, and nothing else.
  found = check_gcode(text, printer, {load_material("tpu-generic"), load_material("pla-paper")});
  EXPECT_EQ(kinds(found), std::set<std::string>{"cold-extrusion"});
  // A TPU temperature on the PLA tool is above PLA's maximum.
  std::string hot = text;
  hot.replace(hot.find("M109 S190"), 9, "M109 S245");
  found = check_gcode(hot, printer, pla_tpu());
  ASSERT_FALSE(found.empty());
  EXPECT_EQ(found.front().kind, ViolationKind::kNozzleTemperature);
  EXPECT_NE(found.front().reason.find("(T0) set to 245 C, above 230 C"), std::string::npos);
  // One material for a file that heats and extrudes with T1.
  found = check_gcode(text, printer, {load_material("pla-paper")});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].kind, ViolationKind::kToolWithoutMaterial);
  EXPECT_EQ(found[0].line, line_of(text, "M104 T1 S225"));
  // On a printer with one tool, T1 does not exist.
  PrinterProfile one = printer;
  one.extruder_count = 1;
  found = check_gcode(text, one, {load_material("pla-paper")});
  ASSERT_FALSE(found.empty());
  EXPECT_EQ(kinds(found), std::set<std::string>{"unknown-tool"});
  EXPECT_EQ(found[0].line, line_of(text, "M104 T1 S225"));
  // Extrusion with a tool past the printer's: flagged where it is selected.
  const std::string t2 =
      "M83\nM104 S190\nM109 S190\nG1 X10 Y10 F3000\nT2\nG1 X20 Y10 E0.5 F1200\nT0\nM104 S0\n"
      "M104 T1 S0\nM84\n";
  found = check_gcode(t2, printer, pla_tpu());
  ASSERT_EQ(found.size(), 1u) << found.front().reason;
  EXPECT_EQ(found[0].kind, ViolationKind::kUnknownTool);
  EXPECT_EQ(found[0].line, 5);
  EXPECT_NE(found[0].reason.find("T2 but prusa-xl-2t has 2 tool(s)"), std::string::npos)
      << found[0].reason;
}

TEST(MultiTool, CliChecksOneMaterialPerTool) {
  const std::filesystem::path path = testing::scratch_dir() / "two-tool.gcode";
  write_gcode(path, two_tool_toolpath(), load_printer("prusa-xl-2t"), pla_tpu());
  const std::string file = path.string();
  testing::CliResult r = testing::run_cli(
      {"check", file, "--printer", "prusa-xl-2t", "--material", "pla-paper,tpu-generic"});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("safe for prusa-xl-2t with pla-paper,tpu-generic"), std::string::npos)
      << r.out;
  r = testing::run_cli(
      {"check", file, "--printer", "prusa-xl-2t", "--material", "tpu-generic,pla-paper"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find(": cold-extrusion: extrudes while the nozzle (T0) is set to 190 C"),
            std::string::npos)
      << r.out;
  r = testing::run_cli({"check", file, "--printer", "prusa-xl-2t", "--material", "pla-paper"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("tool-without-material"), std::string::npos) << r.out;
  r = testing::run_cli({"check", file, "--printer", "prusa-xl-2t", "--material", "pla-paper,"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("empty name"), std::string::npos) << r.err;
  r = testing::run_cli(
      {"check", file, "--printer", "creality-ender3-v2", "--material", "pla-paper,tpu-generic"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("creality-ender3-v2 has 1 tool(s)"), std::string::npos) << r.err;
  r = testing::run_cli({"check", "--help"});
  EXPECT_NE(r.out.find("comma-separated"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace flatmorph::multi_tool_test
