// flatmorph toolpaths: the print trajectories of every layer of a designed plate, their order, and
// G-code for a printer.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>

#include "commands.h"
#include "common/error.h"
#include "output_folder.h"
#include "plate/plate_design.h"
#include "plate_input.h"
#include "progress_display.h"
#include "run/print_summary.h"

namespace flatmorph::cli {
namespace {

struct ToolpathsOptions {
  std::string plate_path;
  std::string printer;
  PlateInputOptions plate_input;
  double spacing = 0;  // 0: the printer's nozzle diameter
  std::vector<double> at;
  int skirt = 0;
  bool json = false;
  std::string output;
};

int run_toolpaths(const ToolpathsOptions& o, const GlobalOptions& global) {
  if (o.spacing < 0 || o.spacing > 5) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--spacing {} mm is out of range: give 0 (the nozzle diameter) "
                                "to 5 mm",
                                o.spacing));
  }
  if (!o.at.empty() && o.at.size() != 2) {
    throw UserError(ErrorCategory::kOption, "--at takes two numbers: X,Y in mm on the bed");
  }
  if (o.skirt < 0 || o.skirt > 20) {
    throw UserError(ErrorCategory::kOption, "--skirt takes 0 to 20 loops");
  }
  const PrinterProfile printer = load_printer(o.printer);
  std::string stack_warning;
  const PlateDesign plate = load_plate_input(o.plate_path, o.plate_input, stack_warning);

  PrintFilesOptions options;
  options.spacing_mm = o.spacing;
  if (!o.at.empty()) options.at_mm = Eigen::Vector2d(o.at[0], o.at[1]);
  options.skirt_loops = o.skirt;
  const bool silent = global.quiet || o.json;
  options.progress = make_progress_display(silent);
  if (!silent) {
    fmt::print("plate: {} ({} faces), {}, paths {} mm apart\n", o.plate_path, plate.F.rows(),
               describe_stack(plate.stack), o.spacing > 0 ? o.spacing : printer.nozzle_diameter);
  }
  // Plans the G-code (and refuses a plate that does not fit) before writing anything.
  const PrintPlan plan = plan_print(plate, printer, options);

  create_output_folder(o.output);
  const std::filesystem::path out(o.output);
  write_print_files(out, plan, printer, plate.stack);
  finish_progress_line();
  if (!stack_warning.empty()) fmt::print(stderr, "flatmorph: warning: {}\n", stack_warning);
  if (o.json) fmt::print("{}\n", plan_summary_json(plan, printer).dump(2));
  if (!silent) {
    for (const std::string& line : plan_summary_lines(plan, printer)) fmt::print("{}\n", line);
    fmt::print("wrote {}, {} and {}\n", (out / "plate.gcode").string(),
               (out / "layers/layer_*.svg").string(), (out / "layers/overview.png").string());
  }
  return 0;
}

}  // namespace

Command make_toolpaths_command(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<ToolpathsOptions>();
  CLI::App* sub = app.add_subcommand(
      "toolpaths",
      "Trace the print paths of every layer of a designed plate (stripe patterns along each "
      "layer's direction field, as its stack file flat.stack.json says: layer count, "
      "thicknesses, materials and tools, docs/plate.md), order them to keep travel short, and "
      "write DIR/plate.gcode, DIR/layers/layer_NNN.svg and DIR/layers/overview.png.");
  sub->add_option("plate", o->plate_path, "flat.ply written by 'flatmorph flatten' or 'design'")
      ->required();
  sub->add_option("--printer", o->printer,
                  "Printer preset name or JSON file (see 'flatmorph printers')")
      ->required();
  add_plate_input_options(sub, o->plate_input);
  sub->add_option("--spacing", o->spacing,
                  "Distance between neighbouring paths = extrusion width, mm (default: the "
                  "printer's nozzle diameter)");
  sub->add_option("--at", o->at,
                  "Bed position X,Y (mm) of the plate's centre (default: the "
                  "bed's centre)")
      ->delimiter(',')
      ->expected(2);
  sub->add_option("--skirt", o->skirt, "Skirt loops around the first layer (0: none)")
      ->capture_default_str();
  sub->add_flag("--json", o->json,
                "Print a JSON summary (layers, travel, print time, filament) on stdout at the end "
                "instead of the human-readable one and progress");
  sub->add_option("-o,--output", o->output, "Output folder (created if needed)")->required();
  return {sub, [o, &global] { return run_toolpaths(*o, global); }};
}

}  // namespace flatmorph::cli
