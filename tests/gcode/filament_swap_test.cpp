// Two materials on a printer with one nozzle (notes §8): the profile's filament_swap makes every
// change of material a pause for a manual swap, with the next material's temperature waited for
// around it; the check follows the swaps and catches a file that extrudes the new material without
// waiting; the reader and the tests' own replay see each bead's material; and a print can be cut
// into one file per run of a material (the paper's F1-F5) for printers that cannot pause.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>

#include "common/embedded_profiles.h"
#include "common/error.h"
#include "gcode/gcode_check.h"
#include "gcode/gcode_reader.h"
#include "gcode/gcode_writer.h"
#include "gcode_expectations.h"
#include "gcode_fixtures.h"
#include "gcode_replay.h"
#include "test_support.h"

namespace flatmorph::filament_swap_test {
namespace {

using nlohmann::json;
using testing::read_gcode;
using testing::ReadGcode;

// The disk of gcode_fixtures.h with TPU on T1: the odd layers, and every fourth line of layer 3.
Toolpath two_material_toolpath() {
  Toolpath toolpath = testing::disk_toolpath(30, 5);
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    std::vector<PathPolyline>& paths = toolpath.layers[k].paths;
    for (size_t p = 0; p < paths.size(); ++p) {
      const bool tpu = k % 2 == 1 || (k == 2 && p % 4 == 2);
      for (SegmentStyle& s : paths[p].segments) s.tool = tpu ? 1 : 0;
    }
  }
  return toolpath;
}

// PLA and TPU whose nozzle temperatures differ (200 and 225 C).
std::vector<Material> pla_tpu() {
  return {load_material("pla-generic"), load_material("tpu-generic")};
}

// The tools of the extruding segments in print order, one entry per run, from T0.
std::vector<int> tool_runs(const Toolpath& toolpath) {
  std::vector<int> runs = {0};
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      for (const SegmentStyle& s : path.segments) {
        if (!s.travel && s.tool != runs.back()) runs.push_back(s.tool);
      }
    }
  }
  return runs;
}

json preset_json(const std::string& name) {
  for (const EmbeddedProfile& p : embedded_profiles()) {
    if (p.kind == "printers" && p.name == name) return json::parse(p.text);
  }
  throw std::runtime_error("no preset " + name);
}

std::string profile_error(const json& j) {
  try {
    parse_printer(j.dump(), "my-printer.json");
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kProfile);
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    return e.what();
  }
  return "accepted";
}

TEST(FilamentSwap, ProfilesTakeTheFirmwaresPause) {
  // An empty object takes the flavor's defaults.
  const std::vector<std::tuple<std::string, std::string, std::string>> flavors = {
      {"marlin", "M117 {message}", "M600"},
      {"klipper", "M117 {message}", "M600"},
      {"reprapfirmware", "M117 \"{message}\"", "M600"},
      {"bambu", "; {message}", "M400 U1"}};
  for (const auto& [flavor, message, pause] : flavors) {
    json j = preset_json("generic-marlin");
    j.erase("filament_swap");
    j["flavor"] = flavor;
    j["filament_swap"] = json::object();
    const PrinterProfile p = parse_printer(j.dump(), "mine.json");
    ASSERT_TRUE(p.filament_swap) << flavor;
    EXPECT_EQ(p.filament_swap->message, message);
    EXPECT_EQ(p.filament_swap->gcode, pause);
  }
  // The shipped single-nozzle printers whose firmware pauses for a swap say so; the others and
  // the tool changers do not.
  for (const std::string& name : printer_preset_names()) {
    const PrinterProfile p = load_printer(name);
    const bool pauses = name == "prusa-mk3s" || name == "prusa-mk4" || name == "generic-marlin" ||
                        name == "bambu-p1s" || name == "bambu-x1c";
    EXPECT_EQ(p.filament_swap.has_value(), pauses) << name;
    if (!p.filament_swap) continue;
    EXPECT_EQ(p.extruder_count, 1);
    EXPECT_EQ(p.filament_swap->gcode.rfind(p.flavor == GcodeFlavor::kBambu ? "M400 U1" : "M600", 0),
              0u)
        << name;
  }
}

TEST(FilamentSwap, ProfileMistakesAreNamed) {
  json j = preset_json("prusa-mk4");
  j["extruders"] = 2;
  j["tool_change"] = {{"gcode", {"T{next_tool}"}}};
  EXPECT_NE(profile_error(j).find("filament_swap applies to printers with one extruder"),
            std::string::npos);
  j = preset_json("prusa-mk4");
  j["filament_swap"]["pause"] = "M601";
  EXPECT_NE(profile_error(j).find("unknown key \"filament_swap.pause\""), std::string::npos);
  j = preset_json("prusa-mk4");
  j["filament_swap"]["gcode"] = json::array();
  EXPECT_NE(profile_error(j).find("filament_swap.gcode is empty"), std::string::npos);
  j = preset_json("prusa-mk4");
  j["filament_swap"]["gcode"] = {"M600 R{next_temprature}"};
  EXPECT_NE(profile_error(j).find("unknown placeholder {next_temprature}"), std::string::npos);
  j = preset_json("prusa-mk4");
  j["filament_swap"]["message"] = "M117 {message}\nM300";
  EXPECT_NE(profile_error(j).find("filament_swap.message must be one line"), std::string::npos);
  // The placeholders a template may use are accepted.
  j = preset_json("prusa-mk4");
  j["filament_swap"]["gcode"] = {
      "M600 R{next_temperature} Z{safe_z} ; {previous_material} to "
      "{next_material} at {swap_temperature}"};
  EXPECT_EQ(profile_error(j), "accepted");
}

TEST(FilamentSwap, WriterPausesAtEveryChangeOfMaterial) {
  const Toolpath toolpath = two_material_toolpath();
  const PrinterProfile printer = load_printer("prusa-mk4");
  const std::vector<Material> materials = pla_tpu();
  const GcodeResult result = make_gcode(toolpath, printer, materials);
  EXPECT_EQ(make_gcode(toolpath, printer, materials).text, result.text);  // deterministic
  EXPECT_TRUE(check_gcode(result.text, printer, materials).empty());
  const ReadGcode read = read_gcode(result.text);
  testing::expect_annotated_and_within_printer(read, printer);
  EXPECT_EQ(read.g0_with_e, 0);
  EXPECT_EQ(read.extrusions_while_retracted, 0);
  EXPECT_EQ(read.final_nozzle, 0);
  EXPECT_TRUE(read.motors_off_at_end);

  // A swap wherever the material changes, to the tool the toolpath prints next; no T command.
  const std::vector<int> runs = tool_runs(toolpath);
  ASSERT_EQ(read.filament_swaps.size(), runs.size() - 1);
  EXPECT_EQ(result.tool_changes, static_cast<int>(runs.size()) - 1);
  EXPECT_TRUE(read.tool_changes.empty());
  ASSERT_EQ(read.pauses.size(), read.filament_swaps.size());
  for (size_t i = 0; i < read.filament_swaps.size(); ++i) {
    SCOPED_TRACE(fmt::format("swap {}", i + 1));
    const testing::ReadToolChange& swap = read.filament_swaps[i];
    EXPECT_EQ(swap.from, runs[i]);
    EXPECT_EQ(swap.to, runs[i + 1]);
    const Material& from = materials[static_cast<size_t>(swap.from)];
    const Material& to = materials[static_cast<size_t>(swap.to)];
    // From the swap to the next extrusion: lift above what is printed, the message, a wait at a
    // temperature both materials take, the pause, the next material's own temperature.
    const int pause = read.pauses[i];
    EXPECT_EQ(read.lines[static_cast<size_t>(pause) - 1].rfind("M600", 0), 0u);
    double printed_top = 0;
    size_t before = 0;
    for (const testing::ReadLayer& layer : read.layers) {
      for (const testing::ReadExtrusion& e : layer.extrusions) {
        if (before++ < swap.extrusions_before) printed_top = std::max(printed_top, e.z);
      }
    }
    bool lifted = false, message = false;
    std::vector<double> waits_before, waits_after;
    for (int line = swap.line + 1; line < pause; ++line) {
      const std::string& text = read.lines[static_cast<size_t>(line) - 1];
      if (text.rfind("G0 Z", 0) == 0) lifted = std::stod(text.substr(4)) >= printed_top + 2 - 1e-9;
      if (text == fmt::format("M117 Load {} (T{})", to.name, swap.to)) message = true;
      if (text.rfind("M109 S", 0) == 0) waits_before.push_back(std::stod(text.substr(6)));
      EXPECT_EQ(text.find(" E"), std::string::npos) << text;  // nothing extruded
    }
    for (size_t line = static_cast<size_t>(pause) + 1; line <= read.lines.size(); ++line) {
      const std::string& text = read.lines[line - 1];
      if (text.rfind("G1 X", 0) == 0) break;  // the first extrusion after it
      if (text.rfind("M109 ", 0) == 0) waits_after.push_back(std::stod(text.substr(6)));
    }
    EXPECT_TRUE(lifted);
    EXPECT_TRUE(message);
    ASSERT_EQ(waits_before.size(), 1u);
    for (const Material* m : {&from, &to}) {
      EXPECT_GE(waits_before[0], m->min_nozzle_temperature);
      EXPECT_LE(waits_before[0], m->max_nozzle_temperature);
    }
    EXPECT_EQ(waits_before[0], std::max(from.nozzle_temperature, to.nozzle_temperature));
    if (waits_before[0] != to.nozzle_temperature) {
      EXPECT_EQ(waits_after, std::vector<double>{to.nozzle_temperature});
    } else {
      EXPECT_TRUE(waits_after.empty());
    }
  }
  // Every bead of each material at that material's temperature, and as much of it as the
  // toolpath asks for.
  std::vector<double> volume(2, 0.0), read_filament(2, 0.0);
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      for (size_t i = 0; i < path.segments.size(); ++i) {
        const SegmentStyle& s = path.segments[i];
        if (s.travel) continue;
        volume[static_cast<size_t>(s.tool)] +=
            (path.points.row(i + 1) - path.points.row(i)).norm() * s.width * s.layer_height;
      }
    }
  }
  for (const testing::ReadLayer& layer : read.layers) {
    for (const testing::ReadExtrusion& e : layer.extrusions) {
      EXPECT_EQ(e.heater_target, materials[static_cast<size_t>(e.tool)].nozzle_temperature);
      read_filament[static_cast<size_t>(e.tool)] += e.filament;
    }
  }
  const double area = std::numbers::pi * 1.75 * 1.75 / 4;
  for (int t = 0; t < 2; ++t) {
    EXPECT_NEAR(read_filament[static_cast<size_t>(t)] * area, volume[static_cast<size_t>(t)],
                1e-3 * volume[static_cast<size_t>(t)]);
  }
  EXPECT_NE(
      read.header.at("filament_swaps").find(fmt::format("{} (the printer pauses", runs.size() - 1)),
      std::string::npos);
}

TEST(FilamentSwap, CliChecksTheSwaps) {
  const std::filesystem::path dir = testing::scratch_dir();
  const GcodeResult result = write_gcode(dir / "plate.gcode", two_material_toolpath(),
                                         load_printer("prusa-mk4"), pla_tpu());
  // The header names the printer and both materials.
  testing::CliResult r = testing::run_cli({"check", (dir / "plate.gcode").string()});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("safe for prusa-mk4 with pla-generic,tpu-generic"), std::string::npos)
      << r.out;
  // Without the waits after the swaps to TPU.
  std::string text = result.text;
  const std::string wait = "M109 S225 ; wait: pla-generic unloads and tpu-generic purges at this\n";
  ASSERT_NE(text.find(wait), std::string::npos);
  for (size_t at = text.find(wait); at != std::string::npos; at = text.find(wait)) {
    text.erase(at, wait.size());
  }
  std::ofstream(dir / "bad.gcode") << text;
  r = testing::run_cli({"check", (dir / "bad.gcode").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find(": swap-temperature: extrudes tpu-generic after the filament swap of line"),
            std::string::npos)
      << r.out;
}

TEST(FilamentSwap, OtherPrintsAreAsBefore) {
  // One material on a printer that could swap: no swap, no pause.
  const std::string one = make_gcode(testing::disk_toolpath(30, 2), load_printer("prusa-mk4"),
                                     {load_material("pla-generic")})
                              .text;
  EXPECT_EQ(one.find("FILAMENT_SWAP"), std::string::npos);
  EXPECT_EQ(one.find("M600"), std::string::npos);
  // Two materials on a printer that cannot swap: refused, saying how it could.
  try {
    make_gcode(two_material_toolpath(), load_printer("creality-ender3-v2"), {pla_tpu()[0]});
    ADD_FAILURE() << "accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kInfeasible);
    EXPECT_NE(std::string(e.what()).find("filament_swap"), std::string::npos) << e.what();
  }
}

TEST(FilamentSwap, CheckFollowsTheSwaps) {
  const PrinterProfile printer = load_printer("generic-marlin");
  Material pla = load_material("pla-generic");
  pla.nozzle_temperature = 215;  // within TPU's range too: only the missing wait is wrong
  const std::vector<Material> materials = {pla, load_material("tpu-generic")};
  auto check = [&](const std::string& middle) {
    const std::string text =
        "M83\nM140 S50\nM104 S215\nM109 S215\nG1 X10 Y10 F3000\n"
        "G1 X20 Y10 E0.5 F1200\n" +
        middle + "G1 X30 Y10 E0.5 F1200\nM104 S0\nM140 S0\nM84\n";
    std::vector<std::pair<std::string, int>> found;
    for (const GcodeViolation& v : check_gcode(text, printer, materials)) {
      found.emplace_back(std::string(to_string(v.kind)), v.line);
    }
    return found;
  };
  using Found = std::vector<std::pair<std::string, int>>;
  EXPECT_EQ(check(";FILAMENT_SWAP:T1\nM109 S225\nM600\n"), Found{});
  // No wait after the swap: flagged at the first extrusion.
  EXPECT_EQ(check(";FILAMENT_SWAP:T1\nM600\n"), (Found{{"swap-temperature", 9}}));
  // A wait before the swap does not count.
  EXPECT_EQ(check("M109 S225\n;FILAMENT_SWAP:T1\nM600\n"), (Found{{"swap-temperature", 10}}));
  // TPU judged as TPU after the swap, PLA as PLA after the next.
  EXPECT_EQ(check(";FILAMENT_SWAP:T1\nM109 S205\nM600\n"), (Found{{"cold-extrusion", 10}}));
  // Back to PLA with the nozzle left at TPU's 240 C.
  EXPECT_EQ(check(";FILAMENT_SWAP:T1\nM109 S240\nM600\nG1 X25 Y10 E0.5\n;FILAMENT_SWAP:T0\nM600\n"),
            (Found{{"swap-temperature", 13}, {"nozzle-temperature", 13}}));
  // A material nobody gave.
  EXPECT_EQ(check(";FILAMENT_SWAP:T2\nM109 S225\n"), (Found{{"tool-without-material", 7}}));
  EXPECT_EQ(check(";FILAMENT_SWAP:Tx\nM109 S225\n"), (Found{{"malformed", 7}}));
  // Tool changers say T<n>: the annotation means nothing there.
  const std::string xl_text =
      "M83\nM104 S215\nM109 S215\n;FILAMENT_SWAP:T1\nG1 X20 Y10 F3000\nG1 X30 Y10 E0.5 "
      "F1200\nM104 S0\nM84\n";
  EXPECT_TRUE(check_gcode(xl_text, load_printer("prusa-xl-2t"), materials).empty());
}

TEST(FilamentSwap, ReaderGivesEachBeadItsMaterial) {
  const Toolpath toolpath = two_material_toolpath();
  const GcodeResult result = make_gcode(toolpath, load_printer("prusa-mk4"), pla_tpu());
  const GcodeDeposition d = read_gcode_deposition(result.text, "swap.gcode");
  std::vector<int> expected;
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      for (const SegmentStyle& s : path.segments) {
        if (!s.travel) expected.push_back(s.tool);
      }
    }
  }
  std::vector<int> tools;
  for (const DepositedBead& bead : d.beads) {
    if (!bead.type.empty()) tools.push_back(bead.tool);  // not the start G-code's purge line
  }
  EXPECT_EQ(tools, expected);
  EXPECT_EQ(d.tool_changes, 0);
  EXPECT_EQ(d.header.tool_materials, (std::vector<std::string>{"pla-generic", "tpu-generic"}));
}

TEST(MaterialFiles, OneFilePerRunOfAMaterial) {
  const Toolpath toolpath = two_material_toolpath();
  const PrinterProfile printer = load_printer("prusa-mk4");
  const std::vector<Material> materials = pla_tpu();
  GcodeOptions options;
  options.skirt_loops = 1;
  const std::vector<MaterialFile> files =
      make_material_files(toolpath, printer, materials, options);
  const std::vector<int> runs = tool_runs(toolpath);
  // The runs from T0 (the first entry) on, without an empty first run of T0.
  const std::vector<int> used(
      runs.begin() + (toolpath.layers[0].paths[0].segments[0].tool == 0 ? 0 : 1), runs.end());
  ASSERT_EQ(files.size(), used.size());
  // Together the files print what the one file with swaps prints, where it prints it.
  const ReadGcode whole = read_gcode(make_gcode(toolpath, printer, materials, options).text);
  std::vector<testing::ReadExtrusion> whole_beads, file_beads;
  for (const testing::ReadLayer& layer : whole.layers) {
    for (const testing::ReadExtrusion& e : layer.extrusions) whole_beads.push_back(e);
  }
  for (size_t i = 0; i < files.size(); ++i) {
    SCOPED_TRACE(files[i].label);
    EXPECT_EQ(files[i].label, fmt::format("F{}", i + 1));
    EXPECT_EQ(files[i].tool, used[i]);
    const Material& m = materials[static_cast<size_t>(files[i].tool)];
    EXPECT_TRUE(check_gcode(files[i].gcode.text, printer, {m}).empty());
    const ReadGcode read = read_gcode(files[i].gcode.text);
    EXPECT_EQ(read.header.at("material"), m.name);
    EXPECT_EQ(read.nozzle_targets.back(), 0);
    EXPECT_TRUE(
        std::count(read.nozzle_targets.begin(), read.nozzle_targets.end(), m.nozzle_temperature));
    EXPECT_EQ(files[i].gcode.text.find("FILAMENT_SWAP"), std::string::npos);
    EXPECT_EQ(files[i].gcode.text.find(";TYPE:Skirt/Brim") != std::string::npos, i == 0);
    for (const testing::ReadLayer& layer : read.layers) {
      for (const testing::ReadExtrusion& e : layer.extrusions) {
        EXPECT_EQ(e.heater_target, m.nozzle_temperature);
        file_beads.push_back(e);
      }
    }
    EXPECT_LE(files[i].first_layer, files[i].last_layer);
  }
  ASSERT_EQ(file_beads.size(), whole_beads.size());
  for (size_t i = 0; i < file_beads.size(); ++i) {
    EXPECT_NEAR(file_beads[i].x0, whole_beads[i].x0, 2e-3) << i;
    EXPECT_NEAR(file_beads[i].y1, whole_beads[i].y1, 2e-3) << i;
    EXPECT_NEAR(file_beads[i].z, whole_beads[i].z, 1e-9) << i;
  }
  // Written beside the plate's file.
  const std::filesystem::path dir = testing::scratch_dir();
  write_material_files(dir / "plate.gcode", toolpath, printer, materials, options);
  for (size_t i = 0; i < files.size(); ++i) {
    EXPECT_EQ(testing::read_file(dir / fmt::format("plate-F{}.gcode", i + 1)), files[i].gcode.text);
  }
  options.sections = {{0, 0, ""}};
  EXPECT_THROW(make_material_files(toolpath, printer, materials, options), std::invalid_argument);
}

}  // namespace
}  // namespace flatmorph::filament_swap_test
