#include "run/print_summary.h"

#include <fmt/core.h>

#include <cmath>

namespace flatmorph {
namespace {

std::string hours_minutes_seconds(double seconds) {
  const long s = std::lround(seconds);
  return fmt::format("{}h {:02}m {:02}s", s / 3600, (s / 60) % 60, s % 60);
}

}  // namespace

std::vector<std::string> plan_summary_lines(const PrintPlan& plan, const PrinterProfile& printer) {
  const LayerPaths& paths = plan.paths;
  std::vector<std::string> lines;
  lines.push_back(fmt::format("refined plate: {} faces, mean edge {:.3f} mm", paths.refined_faces,
                              paths.refined_mean_edge_mm));
  if (!paths.stripe_turn_deg.empty()) {
    lines.push_back(fmt::format(
        "stripes' mean turn from the layers' directions, per plate face: {:.2f} deg as traced, "
        "{:.2f} deg after {} correction(s) of the fields",
        paths.stripe_turn_deg.front(), paths.stripe_turn_deg[paths.field_corrections],
        paths.field_corrections));
  }
  lines.push_back("layer   z (mm)  paths  printed (mm)  travel (mm)  greedy travel (mm)  forks");
  double travel = 0, greedy = 0;
  for (const LayerPathReport& r : paths.layers) {
    lines.push_back(fmt::format("{:>5}  {:>7.3f}  {:>5}  {:>12.0f}  {:>11.0f}  {:>18.0f}  {:>5}",
                                r.layer, r.z, r.paths, r.extrusion_mm, r.travel_mm,
                                r.travel_greedy_mm, r.stripe_singular_faces));
    travel += r.travel_mm;
    greedy += r.travel_greedy_mm;
  }
  lines.push_back(fmt::format("travel: {:.0f} mm ({:.0f} % shorter than greedy nearest neighbour)",
                              travel, greedy > 0 ? 100 * (1 - travel / greedy) : 0.0));
  lines.push_back(
      fmt::format("time: refinement {:.2f} s, fields {:.2f} s, stripes {:.2f} s, extraction {:.2f} "
                  "s, ordering {:.2f} s",
                  paths.timings.refinement, paths.timings.fields, paths.timings.eigenvector,
                  paths.timings.extraction, paths.timings.ordering));
  for (std::string& line : gcode_summary_lines(plan, printer)) lines.push_back(std::move(line));
  return lines;
}

std::vector<std::string> gcode_summary_lines(const PrintPlan& plan, const PrinterProfile& printer) {
  return {fmt::format("printer: {} ({}); plate placed at bed = plate + ({:.3f}, {:.3f}) mm",
                      printer.name, describe_bed(printer), plan.gcode.plate_to_bed.x(),
                      plan.gcode.plate_to_bed.y()),
          fmt::format("estimated print time {}, filament {:.2f} m ({:.1f} g)",
                      hours_minutes_seconds(plan.gcode.print_time),
                      plan.gcode.filament_length / 1000, plan.gcode.filament_mass)};
}

}  // namespace flatmorph
