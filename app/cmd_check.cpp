// flatmorph check: the G-code safety check (the one every written file passes) on any G-code.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>

#include "commands.h"
#include "common/error.h"
#include "common/file_text.h"
#include "gcode/gcode_check.h"
#include "gcode/gcode_reader.h"
#include "gcode/printer_profile.h"
#include "gcode_input.h"
#include "material/material.h"
#include "plate/plate_design.h"

namespace flatmorph::cli {
namespace {

struct CheckOptions {
  std::string file;
  std::optional<std::string> printer;
  std::optional<std::string> material;
};

// The materials of the run the G-code belongs to: the stack file beside it (a run folder holds
// plate.gcode and flat.stack.json), else pla-paper for T0.
std::vector<Material> run_materials(const std::string& gcode_path, std::string& source) {
  const std::filesystem::path stack = std::filesystem::path(gcode_path).parent_path() / "flat.ply";
  std::error_code error;
  if (std::filesystem::exists(stack_file_path(stack), error)) {
    source = stack_file_path(stack).string();
    return read_plate_design(stack, Material{}, 1).design.stack.materials;
  }
  source = "the default";
  return {load_material("pla-paper")};
}

int run_check(const CheckOptions& options, const GlobalOptions& global) {
  // Options first: a bad one is said before the file is read.
  std::optional<PrinterProfile> printer;
  if (options.printer) printer = load_printer(*options.printer);
  std::vector<Material> materials;
  std::string source = "--material";
  if (options.material) materials = load_tool_materials(*options.material);
  const std::string text = read_file_text(options.file, "G-code file");
  // The printer and the materials the file names in its header (flatmorph's own files do), unless
  // given.
  const GcodeHeaderInfo header = read_gcode_header(text);
  if (!printer) printer = header_printer(header, options.file);
  if (materials.empty()) {
    materials = header_tool_materials(header, options.file);
    if (!materials.empty()) source = "the file's header";
  }
  if (materials.empty()) materials = run_materials(options.file, source);
  // A printer that swaps filament by hand prints every tool's material through its one nozzle.
  if (materials.size() > static_cast<size_t>(printer->extruder_count) && !printer->filament_swap) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--material names {} materials but {} has {} tool(s) and no "
                                "filament_swap: give one material per tool",
                                materials.size(), printer->name, printer->extruder_count));
  }
  std::string material_names;
  for (const Material& m : materials) {
    material_names += (material_names.empty() ? "" : ",") + m.name;
  }
  const std::vector<GcodeViolation> violations = check_gcode(text, *printer, materials, 1000);
  for (const GcodeViolation& v : violations) {
    fmt::print("{}:{}: {}: {}\n", options.file, v.line, to_string(v.kind), v.reason);
  }
  if (violations.empty()) {
    if (!global.quiet) {
      fmt::print("{}: safe for {} with {} (materials from {})\n", options.file, printer->name,
                 material_names, source);
    }
    return 0;
  }
  fmt::print(stderr,
             "flatmorph: error: {} is unsafe for {} with {}: {}{} violation(s), the first "
             "at line {} ({})\n",
             options.file, printer->name, material_names, violations.size(),
             violations.size() >= 1000 ? "+" : "", violations.front().line,
             to_string(violations.front().kind));
  return 2;
}

}  // namespace

Command make_check_command(CLI::App& app, const GlobalOptions& global) {
  auto options = std::make_shared<CheckOptions>();
  CLI::App* sub = app.add_subcommand(
      "check",
      "Check that a G-code file is safe to send to a printer: every move on the bed and below "
      "the maximum height, temperatures within the material's limits, no extrusion while "
      "travelling, extrusion distances consistent with M82/M83, heaters and motors off at the "
      "end. Prints one line per violation and exits with status 2 if there is any.");
  sub->add_option("file", options->file, "The G-code file")->required();
  sub->add_option("--printer", options->printer,
                  "Printer preset name or profile JSON file (default: the printer the file's "
                  "header names, as flatmorph's own files do)");
  sub->add_option("--material", options->material,
                  "Material preset name or material JSON file (default: the materials the file's "
                  "header names, else those of the run the file belongs to, from "
                  "flat.stack.json beside it, else pla-paper); on a "
                  "printer "
                  "with several tools, one per tool, comma-separated in tool order (T0,T1,...: "
                  "pla-paper,tpu-generic; also on a printer with one nozzle that swaps filament "
                  "by hand). Each tool's temperatures and extrusion are checked "
                  "against its own material, the bed against the lowest maximum; a tool the file "
                  "heats or extrudes with but has no material is a violation");
  return {sub, [options, &global] { return run_check(*options, global); }};
}

}  // namespace flatmorph::cli
