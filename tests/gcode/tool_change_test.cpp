// Tool changes as printers make them: the prime pad of a tool changer (the Prusa XL primes each
// tool on the front edge of the bed) and the shared nozzle of a filament changer (a Bambu AMS:
// the firmware swaps the filament, the template flushes the old one, one heater takes each
// material's temperature in turn). Read back by the independent reader of gcode_replay.cpp and
// judged by the check.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "common/error.h"
#include "gcode/gcode_check.h"
#include "gcode/gcode_writer.h"
#include "gcode_fixtures.h"
#include "gcode_replay.h"
#include "test_support.h"

namespace flatmorph::tool_change_test {
namespace {

using testing::read_gcode;
using testing::ReadGcode;

// The disk of gcode_fixtures.h with its odd layers on T1, and every `every`-th path of the others
// too (0: none).
Toolpath odd_layers_on_tool_one(int layers, int every = 0) {
  Toolpath toolpath = testing::disk_toolpath(40, layers);
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    std::vector<PathPolyline>& paths = toolpath.layers[k].paths;
    for (size_t p = 0; p < paths.size(); ++p) {
      const bool one = k % 2 == 1 || (every > 0 && p % static_cast<size_t>(every) == 1);
      for (SegmentStyle& s : paths[p].segments) s.tool = one ? 1 : 0;
    }
  }
  return toolpath;
}

double filament_area(const PrinterProfile& p) {
  return std::numbers::pi * p.filament_diameter * p.filament_diameter / 4;
}

// The number after `axis` on a G-code line (NaN if absent).
double word(const std::string& line, char axis) {
  std::istringstream in(line.substr(0, line.find(';')));
  for (std::string w; in >> w;) {
    if (w[0] == axis && w.size() > 1) return std::stod(w.substr(1));
  }
  return std::nan("");
}

std::vector<testing::ReadExtrusion> extrusions(const ReadGcode& read) {
  std::vector<testing::ReadExtrusion> all;
  for (const auto& layer : read.layers)
    all.insert(all.end(), layer.extrusions.begin(), layer.extrusions.end());
  return all;
}

std::vector<Material> materials(const std::string& t0, const std::string& t1) {
  return {load_material(t0), load_material(t1)};
}

UserError gcode_error(const Toolpath& toolpath, const PrinterProfile& printer,
                      const std::vector<Material>& tool_materials, const GcodeOptions& options) {
  try {
    make_gcode(toolpath, printer, tool_materials, options);
  } catch (const UserError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    return e;
  }
  ADD_FAILURE() << "accepted";
  return UserError(ErrorCategory::kFormat, "");
}

// The XL profile primes 6 mm^3 after each change in x [100, 350], y [1, 7], wiping 3 mm back.
TEST(PrimePad, EachChangePrimesItsVolumeOnThePadWhereTheLastStopped) {
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  const std::vector<Material> pla_tpu = materials("pla-paper", "tpu-generic");
  const Toolpath toolpath = odd_layers_on_tool_one(8);
  const GcodeResult result = make_gcode(toolpath, printer, pla_tpu);
  EXPECT_TRUE(check_gcode(result.text, printer, pla_tpu).empty());
  const ReadGcode read = read_gcode(result.text);
  EXPECT_EQ(read.extrusions_while_retracted, 0);
  EXPECT_EQ(read.g0_with_e, 0);
  ASSERT_EQ(read.tool_changes.size(), 7u);  // between the 8 layers

  const std::vector<testing::ReadExtrusion> all = extrusions(read);
  const double area = filament_area(printer);
  const double width = 1.25 * printer.nozzle_diameter;
  std::map<long, std::vector<std::pair<double, double>>> rows;  // y (um) -> x intervals
  for (size_t c = 0; c < read.tool_changes.size(); ++c) {
    const testing::ReadToolChange& change = read.tool_changes[c];
    double volume = 0;
    size_t i = change.extrusions_before;
    for (; i < all.size() && all[i].type == "Wipe tower"; ++i) {
      const testing::ReadExtrusion& e = all[i];
      EXPECT_EQ(e.tool, change.to);
      EXPECT_NEAR(e.z, 0.2, 1e-9);
      EXPECT_NEAR(e.width, width, 1e-9);
      EXPECT_NEAR(e.height, 0.2, 1e-9);
      for (double x : {e.x0, e.x1}) {
        EXPECT_GE(x, 100 + width / 2 - 1e-6);
        EXPECT_LE(x, 350 - width / 2 + 1e-6);
      }
      for (double y : {e.y0, e.y1}) {
        EXPECT_GE(y, 1 + width / 2 - 1e-6);
        EXPECT_LE(y, 7 - width / 2 + 1e-6);
      }
      if (std::abs(e.y1 - e.y0) < 1e-9) {
        rows[std::lround(e.y0 * 1000)].emplace_back(std::min(e.x0, e.x1), std::max(e.x0, e.x1));
      } else {
        EXPECT_NEAR(e.x0, e.x1, 1e-9);  // a step to the next row
        EXPECT_NEAR(std::abs(e.y1 - e.y0), width, 1e-3);
      }
      volume += e.filament * area;
    }
    EXPECT_NEAR(volume, 6.0, 0.01) << "change " << c;
    ASSERT_LT(i, all.size());
    EXPECT_NE(all[i].type, "Wipe tower");  // the print goes on
  }
  // 7 primes of 60 mm of bead: the first row (249.5 mm) and part of the second.
  ASSERT_EQ(rows.size(), 2u);
  for (auto& [y, intervals] : rows) {
    std::sort(intervals.begin(), intervals.end());
    for (size_t k = 1; k < intervals.size(); ++k) {
      EXPECT_GE(intervals[k].first, intervals[k - 1].second - 1e-6) << "primes overlap at y " << y;
    }
  }

  // Each prime ends with a wipe: 3 mm back along the bead without extruding, then a retraction.
  const std::vector<std::string>& lines = read.lines;
  int wipes = 0;
  for (size_t l = 0; l < lines.size(); ++l) {
    if (lines[l] != ";TYPE:Wipe tower") continue;
    size_t k = l + 1;
    double x = std::nan(""), y = std::nan("");
    for (; k < lines.size() && lines[k].rfind("G0 ", 0) != 0; ++k) {
      if (!std::isnan(word(lines[k], 'X'))) x = word(lines[k], 'X');
      if (!std::isnan(word(lines[k], 'Y'))) y = word(lines[k], 'Y');
    }
    double wiped = 0;
    for (; k < lines.size() && lines[k].rfind("G0 ", 0) == 0; ++k) {
      const double nx = std::isnan(word(lines[k], 'X')) ? x : word(lines[k], 'X');
      const double ny = std::isnan(word(lines[k], 'Y')) ? y : word(lines[k], 'Y');
      wiped += std::hypot(nx - x, ny - y);
      x = nx;
      y = ny;
    }
    EXPECT_NEAR(wiped, 3.0, 2e-3) << "after line " << l + 1;
    ASSERT_LT(k + 1, lines.size());
    EXPECT_LT(word(lines[k], 'E'), 0) << lines[k];
    // Then up, 2 mm above everything printed, before any move across the bed.
    double top = 0.2;
    const size_t before = read.tool_changes[static_cast<size_t>(wipes)].extrusions_before;
    for (size_t i = 0; i < before; ++i) top = std::max(top, all[i].z);
    EXPECT_EQ(lines[k + 1].rfind("G0 Z", 0), 0u) << lines[k + 1];
    EXPECT_NEAR(word(lines[k + 1], 'Z'), top + 2, 1e-9) << lines[k + 1];
    ++wipes;
  }
  EXPECT_EQ(wipes, 7);
  EXPECT_NE(result.text.find("6 mm^3 primed on the bed at each, wiped 3 mm"), std::string::npos);
}

TEST(PrimePad, MoreChangesThanThePadHoldsIsAClearError) {
  // Every other path of the even layers on T1 too: hundreds of changes.
  const UserError e = gcode_error(odd_layers_on_tool_one(4, 2), load_printer("prusa-xl-2t"),
                                  materials("pla-paper", "tpu-generic"), {});
  EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
  // 12 rows of 249.5 mm and 11 steps of 0.5 mm, 60 mm a prime.
  EXPECT_NE(std::string(e.what()).find("holds 49 primes"), std::string::npos) << e.what();
  // A profile with a pad 5 times as deep takes them.
  PrinterProfile deep = load_printer("prusa-xl-2t");
  deep.tool_change.prime_area_max.y() = 31;
  const Toolpath few = odd_layers_on_tool_one(4, 20);
  EXPECT_NO_THROW(make_gcode(few, deep, materials("pla-paper", "tpu-generic")));
}

TEST(PrimePad, APrintOverThePadIsRefusedAndAnotherPlaceAccepted) {
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  GcodeOptions options;
  options.at = Eigen::Vector2d(180, 42);  // the disk (80 mm across) reaches down to y = 2.5
  const UserError e = gcode_error(odd_layers_on_tool_one(2), printer,
                                  materials("pla-paper", "tpu-generic"), options);
  EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
  EXPECT_NE(std::string(e.what()).find("place it elsewhere with --at X,Y"), std::string::npos)
      << e.what();
  options.at = Eigen::Vector2d(180, 52);  // from y = 12.5: clear of the pad by 5.5 mm
  const GcodeResult result = make_gcode(odd_layers_on_tool_one(2), printer,
                                        materials("pla-paper", "tpu-generic"), options);
  EXPECT_TRUE(check_gcode(result.text, printer, materials("pla-paper", "tpu-generic")).empty());
}

// Bambu's AMS: four slots, one nozzle. PLA of two temperatures on T0 and T1.
TEST(SharedNozzle, AmsChangesAreTheFirmwaresWithAFlushAndOneHeater) {
  const PrinterProfile printer = load_printer("bambu-x1c-ams");
  ASSERT_TRUE(printer.tool_change.shared_nozzle);
  const std::vector<Material> two_plas = materials("pla-paper", "pla-generic");  // 190 and 200 C
  const Toolpath toolpath = odd_layers_on_tool_one(6);
  const GcodeResult result = make_gcode(toolpath, printer, two_plas);
  EXPECT_TRUE(check_gcode(result.text, printer, two_plas).empty());
  const ReadGcode read = read_gcode(result.text);
  EXPECT_EQ(read.extrusions_while_retracted, 0);
  ASSERT_EQ(read.tool_changes.size(), 5u);
  EXPECT_EQ(result.tool_changes, 5);

  // One heater: no per-tool heating, and every extrusion at its own material's temperature as
  // the last target given.
  EXPECT_EQ(result.text.find("M104 T"), std::string::npos);
  EXPECT_EQ(result.text.find("M109 T"), std::string::npos);
  const std::vector<testing::ReadExtrusion> all = extrusions(read);
  for (size_t i = 0; i < all.size(); ++i) {
    ASSERT_EQ(all[i].heater_target, two_plas[static_cast<size_t>(all[i].tool)].nozzle_temperature)
        << "extrusion " << i << " with T" << all[i].tool;
  }
  EXPECT_EQ(read.nozzle_targets.back(), 0);  // the heater's last target

  // Each change: M620 S<n>A, the flush temperature (200 C, the hotter, both allow it), the T line,
  // the flush of 140 mm^3, the next temperature, M621 S<n>A, all before the next extrusion.
  const double flush = std::round(140 / filament_area(printer) * 100) / 100;
  const std::vector<std::string>& lines = read.lines;
  for (const testing::ReadToolChange& change : read.tool_changes) {
    const size_t t = static_cast<size_t>(change.line) - 1;
    std::vector<std::string> expected_before = {fmt::format("M620 S{}A", change.to), "M109 S200"};
    std::vector<std::string> expected_after = {
        fmt::format("G1 E{:.2f} F150", flush),
        fmt::format("M109 S{:g}", two_plas[static_cast<size_t>(change.to)].nozzle_temperature),
        "G1 E-0.8 F1800", fmt::format("M621 S{}A", change.to)};
    size_t at = t;
    for (auto it = expected_before.rbegin(); it != expected_before.rend(); ++it) {
      while (at > 0 && lines[at].rfind(*it, 0) != 0) --at;
      EXPECT_EQ(lines[at].rfind(*it, 0), 0u) << *it << " before line " << change.line;
    }
    at = t;
    for (const std::string& want : expected_after) {
      while (at + 1 < lines.size() && lines[at].rfind(want, 0) != 0 &&
             lines[at].rfind(";TYPE:", 0) != 0) {
        ++at;
      }
      EXPECT_EQ(lines[at].rfind(want, 0), 0u) << want << " after line " << change.line;
    }
  }
  // The flushes are filament the printer pushes: in the per-tool totals, beside what the reader
  // sees extruded over the bed.
  std::vector<double> seen(2, 0.0);
  for (const auto& e : all) seen[static_cast<size_t>(e.tool)] += e.filament;
  const std::vector<long> into = {2, 3};  // T0 -> T1 -> T0 ... over 6 layers: 3 into T1, 2 into T0
  for (size_t t = 0; t < 2; ++t) {
    EXPECT_NEAR(result.tool_filament_length[t], seen[t] + flush * static_cast<double>(into[t]),
                1e-3)
        << "T" << t;
  }
  EXPECT_NE(result.text.find("one shared nozzle, 140 mm^3 flushed at each"), std::string::npos);
}

TEST(SharedNozzle, MaterialsWithoutACommonTemperatureAreRefused) {
  Material hot = load_material("tpu-generic");
  hot.name = "hot-material";
  hot.min_nozzle_temperature = 240;
  hot.nozzle_temperature = 250;
  hot.max_nozzle_temperature = 260;
  const std::vector<Material> clash = {load_material("pla-paper"), hot};
  const UserError e =
      gcode_error(odd_layers_on_tool_one(2), load_printer("bambu-x1c-ams"), clash, {});
  EXPECT_EQ(e.category(), ErrorCategory::kOption);
  EXPECT_NE(std::string(e.what()).find("no temperature suits both"), std::string::npos) << e.what();
  // On a printer with a nozzle per tool the same pair is fine.
  EXPECT_NO_THROW(make_gcode(odd_layers_on_tool_one(2), load_printer("prusa-xl-2t"), clash));
}

// The same file on a shared nozzle and on two nozzles: heating "the nozzle" to 240 C while T1 is
// active leaves T0's own nozzle at 190 C on the XL, but is the one nozzle T0 then prints through
// on the AMS, too hot for PLA.
TEST(SharedNozzle, TheCheckFollowsTheOneHeater) {
  const std::string text =
      "M83\nM104 S190\nM109 S190\nG1 X10 Y10 F3000\nT1\nM109 S240\nT0\nG1 X20 Y10 E0.5 F1200\n"
      "M104 S0\nM104 T1 S0\nM84\n";
  const std::vector<Material> pla_tpu = materials("pla-paper", "tpu-generic");
  EXPECT_TRUE(check_gcode(text, load_printer("prusa-xl-2t"), pla_tpu).empty());
  PrinterProfile ams = load_printer("bambu-x1c-ams");
  const std::vector<GcodeViolation> found = check_gcode(text, ams, pla_tpu);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].kind, ViolationKind::kNozzleTemperature);
  EXPECT_EQ(found[0].line, 8);
  EXPECT_NE(found[0].reason.find("above 230 C"), std::string::npos) << found[0].reason;
}

TEST(SharedNozzle, ProfilesSayHowTheyChange) {
  auto profile_text = [](const std::string& name) {
    const testing::CliResult r = testing::run_cli({"printers", name});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.out;
  };
  auto error_with = [](std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    try {
      parse_printer(text, "my-printer.json");
    } catch (const UserError& e) {
      EXPECT_EQ(e.category(), ErrorCategory::kProfile);
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string ams = profile_text("bambu-x1c-ams");
  const std::string xl = profile_text("prusa-xl-2t");
  EXPECT_EQ(error_with(ams, "", ""), "accepted");
  EXPECT_EQ(error_with(xl, "", ""), "accepted");
  EXPECT_NE(error_with(ams, "\"shared_nozzle\": true", "\"shared_nozzle\": false")
                .find("flush_volume applies to a shared nozzle only"),
            std::string::npos);
  EXPECT_NE(error_with(ams, "E{flush_length}", "E5").find("never uses {flush_length}"),
            std::string::npos);
  EXPECT_NE(error_with(xl, "[100, 350]", "[100, 400]").find("leaves the reachable area"),
            std::string::npos);
  EXPECT_NE(error_with(xl, "[100, 350]", "[100, 100.5]").find("at least two nozzle widths"),
            std::string::npos);
  EXPECT_NE(error_with(xl, "\"wipe\"", "\"wipes\"").find("missing key \"tool_change.prime.wipe\""),
            std::string::npos);
}

}  // namespace
}  // namespace flatmorph::tool_change_test
