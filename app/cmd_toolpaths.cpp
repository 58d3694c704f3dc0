// flatmorph toolpaths: the print trajectories of every layer of a designed plate, their order, and
// G-code for a printer.
#include <fmt/core.h>

#include <filesystem>

#include "commands.h"
#include "common/error.h"
#include "gcode/gcode_writer.h"
#include "gcode/preview.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "mesh/topology.h"
#include "plate/plate_file.h"
#include "toolpath/layer_paths.h"

namespace flatmorph::cli {
namespace {

struct ToolpathsOptions {
  std::string plate_path;
  std::string printer;
  std::string material = "pla-paper";
  int layers = 10;
  double spacing = 0;  // 0: the printer's nozzle diameter
  std::vector<double> at;
  int skirt = 0;
  std::string output;
};

std::string duration(double seconds) {
  const long s = std::lround(seconds);
  return fmt::format("{}h {:02}m {:02}s", s / 3600, (s / 60) % 60, s % 60);
}

int run_toolpaths(const ToolpathsOptions& o, const GlobalOptions& global) {
  if (o.layers < 1 || o.layers > 1000) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--layers {} is out of range: give 1 to 1000 layers", o.layers));
  }
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
  const Material material = load_material(o.material);
  const PlateFile plate = read_plate_file(o.plate_path);

  LayerPathOptions options;
  options.num_layers = o.layers;
  options.layer_height = material.layer_height;
  options.spacing = o.spacing > 0 ? o.spacing : printer.nozzle_diameter;
  if (!global.quiet) {
    fmt::print("plate: {} ({} faces), {} layers of {} mm, paths {} mm apart\n", o.plate_path,
               plate.F.rows(), options.num_layers, options.layer_height, options.spacing);
  }
  const LayerPaths paths =
      shrink_morph_layer_paths(plate.plate, plate.F, plate.theta1, plate.theta2, options);

  GcodeOptions gcode_options;
  if (!o.at.empty()) gcode_options.at = Eigen::Vector2d(o.at[0], o.at[1]);
  gcode_options.skirt_loops = o.skirt;
  // Plan the G-code (and refuse a plate that does not fit) before writing anything.
  const GcodeResult gcode = make_gcode(paths.toolpath, printer, material, gcode_options);

  std::filesystem::create_directories(o.output);
  PreviewOptions preview;
  for (const std::vector<int>& loop : boundary_loops(plate.F)) {
    Eigen::MatrixX2d outline(loop.size(), 2);
    for (size_t i = 0; i < loop.size(); ++i) outline.row(i) = plate.plate.row(loop[i]);
    preview.outline.push_back(outline);
  }
  const std::filesystem::path out(o.output);
  write_layer_svgs(out / "layers", paths.toolpath, preview);
  write_overview_png(out / "layers" / "overview.png", paths.toolpath, preview);
  write_gcode(out / "plate.gcode", paths.toolpath, printer, material, gcode_options);

  if (!global.quiet) {
    fmt::print("refined plate: {} faces, mean edge {:.3f} mm\n", paths.refined_faces,
               paths.refined_mean_edge_mm);
    fmt::print("layer   z (mm)  paths  printed (mm)  travel (mm)  greedy travel (mm)  forks\n");
    double travel = 0, greedy = 0;
    for (const LayerPathReport& r : paths.layers) {
      fmt::print("{:>5}  {:>7.3f}  {:>5}  {:>12.0f}  {:>11.0f}  {:>18.0f}  {:>5}\n", r.layer, r.z,
                 r.paths, r.extrusion_mm, r.travel_mm, r.travel_greedy_mm,
                 r.stripe_singular_faces);
      travel += r.travel_mm;
      greedy += r.travel_greedy_mm;
    }
    fmt::print("travel: {:.0f} mm ({:.0f} % shorter than greedy nearest neighbour)\n", travel,
               greedy > 0 ? 100 * (1 - travel / greedy) : 0.0);
    fmt::print("time: refinement {:.2f} s, fields {:.2f} s, stripes {:.2f} s, extraction {:.2f} "
               "s, ordering {:.2f} s\n",
               paths.timings.refinement, paths.timings.fields, paths.timings.eigenvector,
               paths.timings.extraction, paths.timings.ordering);
    fmt::print("printer: {} ({}); plate placed at bed = plate + ({:.3f}, {:.3f}) mm\n",
               printer.name, describe_bed(printer), gcode.plate_to_bed.x(),
               gcode.plate_to_bed.y());
    fmt::print("estimated print time {}, filament {:.2f} m ({:.1f} g)\n",
               duration(gcode.print_time), gcode.filament_length / 1000, gcode.filament_mass);
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
      "Trace the print paths of every layer of a designed plate (stripe patterns along theta^k = "
      "theta1 + ((k-1)/(n-1) - 1/2) theta2, k = 1 on the bed), order them to keep travel short, "
      "and write DIR/plate.gcode, DIR/layers/layer_NNN.svg and DIR/layers/overview.png.");
  sub->add_option("plate", o->plate_path, "flat.ply written by 'flatmorph flatten' or 'design'")
      ->required();
  sub->add_option("--printer", o->printer,
                  "Printer preset name or JSON file (see 'flatmorph printers')")
      ->required();
  sub->add_option("--material", o->material,
                  "Material preset name or JSON file: temperatures, speeds, layer height")
      ->capture_default_str();
  sub->add_option("--layers", o->layers, "Number of printed layers")->capture_default_str();
  sub->add_option("--spacing", o->spacing,
                  "Distance between neighbouring paths = extrusion width, mm (default: the "
                  "printer's nozzle diameter)");
  sub->add_option("--at", o->at, "Bed position X,Y (mm) of the plate's centre (default: the "
                                 "bed's centre)")
      ->delimiter(',')
      ->expected(2);
  sub->add_option("--skirt", o->skirt, "Skirt loops around the first layer (0: none)")
      ->capture_default_str();
  sub->add_option("-o,--output", o->output, "Output folder (created if needed)")->required();
  return {sub, [o, &global] { return run_toolpaths(*o, global); }};
}

}  // namespace flatmorph::cli
