#include "run/print_plan.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>

#include "gcode/preview.h"
#include "mesh/topology.h"
#include "toolpath/toolpath_file.h"

namespace flatmorph {

PrintPlan plan_print(const PlateDesign& design, const PrinterProfile& printer,
                     const PrintFilesOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  LayerPathOptions path_options;
  path_options.spacing = options.spacing_mm > 0 ? options.spacing_mm : printer.nozzle_diameter;
  path_options.progress = options.progress;
  LayerPaths paths = stack_layer_paths(design.plate, design.F, design.stack, path_options);
  PrintPlan plan = plan_toolpath_print(std::move(paths), design.plate, design.F,
                                       design.stack.materials, printer, options);
  plan.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return plan;
}

LayerPaths traced_layer_paths(Toolpath toolpath) {
  LayerPaths paths;
  paths.toolpath = std::move(toolpath);
  int k = 1;
  for (const ToolpathLayer& layer : paths.toolpath.layers) {
    LayerPathReport report;
    report.layer = k++;
    report.z = layer.z;
    report.paths = static_cast<int>(layer.paths.size());
    report.extrusion_mm = extrusion_length(layer);
    report.travel_mm = travel_length(layer);
    report.travel_greedy_mm = report.travel_mm;
    paths.layers.push_back(report);
  }
  return paths;
}

PrintPlan plan_toolpath_print(LayerPaths paths, const Eigen::MatrixXd& plate,
                              const Eigen::MatrixXi& F, const std::vector<Material>& materials,
                              const PrinterProfile& printer, const PrintFilesOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  PrintPlan plan;
  plan.paths = std::move(paths);
  if (options.at_mm) plan.gcode_options.at = *options.at_mm;
  plan.gcode_options.skirt_loops = options.skirt_loops;
  plan.gcode = make_gcode(plan.paths.toolpath, printer, materials, plan.gcode_options);
  for (const std::vector<int>& loop : boundary_loops(F)) {
    Eigen::MatrixX2d outline(loop.size(), 2);
    for (size_t i = 0; i < loop.size(); ++i) outline.row(i) = plate.row(loop[i]).head<2>();
    plan.outline.push_back(outline);
  }
  plan.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return plan;
}

void write_print_files(const std::filesystem::path& dir, const PrintPlan& plan,
                       const PrinterProfile& printer, const LayerStack& stack) {
  PreviewOptions preview;
  preview.outline = plan.outline;
  for (const LayerPathReport& layer : plan.paths.layers) {
    preview.singularities.push_back({layer.singular_points, layer.fork_points});
  }
  write_layer_svgs(dir / "layers", plan.paths.toolpath, preview);
  write_overview_png(dir / "layers" / "overview.png", plan.paths.toolpath, preview);
  write_gcode(dir / "plate.gcode", plan.paths.toolpath, printer, stack.materials,
              plan.gcode_options);
  write_toolpath_file(dir / "toolpath.json", plan.paths.toolpath, plan.gcode.summary);
}

nlohmann::ordered_json plan_summary_json(const PrintPlan& plan, const PrinterProfile& printer) {
  nlohmann::ordered_json j;
  j["printer"] = printer.name;
  j["refined_faces"] = plan.paths.refined_faces;
  j["stripe_turn_deg"] = plan.paths.stripe_turn_deg;
  j["field_corrections"] = plan.paths.field_corrections;
  nlohmann::ordered_json layers = nlohmann::ordered_json::array();
  double travel = 0, greedy = 0;
  for (const LayerPathReport& r : plan.paths.layers) {
    layers.push_back({{"layer", r.layer},
                      {"z_mm", r.z},
                      {"paths", r.paths},
                      {"printed_mm", r.extrusion_mm},
                      {"travel_mm", r.travel_mm},
                      {"greedy_travel_mm", r.travel_greedy_mm},
                      {"forks", r.stripe_singular_faces}});
    travel += r.travel_mm;
    greedy += r.travel_greedy_mm;
  }
  j["layers"] = layers;
  j["travel_mm"] = travel;
  j["greedy_travel_mm"] = greedy;
  j["plate_to_bed_mm"] = {plan.gcode.plate_to_bed.x(), plan.gcode.plate_to_bed.y()};
  j["print_time_s"] = plan.gcode.print_time;
  j["filament_mm"] = plan.gcode.filament_length;
  j["filament_g"] = plan.gcode.filament_mass;
  j["t_traj_s"] = plan.seconds;
  return j;
}

}  // namespace flatmorph
