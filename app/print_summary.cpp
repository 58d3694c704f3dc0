#include "print_summary.h"

#include <fmt/core.h>

#include <cmath>
#include <string>

namespace flatmorph::cli {
namespace {

std::string duration(double seconds) {
  const long s = std::lround(seconds);
  return fmt::format("{}h {:02}m {:02}s", s / 3600, (s / 60) % 60, s % 60);
}

}  // namespace

void print_plan_summary(const PrintPlan& plan, const PrinterProfile& printer) {
  const LayerPaths& paths = plan.paths;
  fmt::print("refined plate: {} faces, mean edge {:.3f} mm\n", paths.refined_faces,
             paths.refined_mean_edge_mm);
  if (!paths.stripe_turn_deg.empty()) {
    fmt::print(
        "stripes' mean turn from the layers' directions, per plate face: {:.2f} deg as traced, "
        "{:.2f} deg after {} correction(s) of the fields\n",
        paths.stripe_turn_deg.front(), paths.stripe_turn_deg[paths.field_corrections],
        paths.field_corrections);
  }
  fmt::print("layer   z (mm)  paths  printed (mm)  travel (mm)  greedy travel (mm)  forks\n");
  double travel = 0, greedy = 0;
  for (const LayerPathReport& r : paths.layers) {
    fmt::print("{:>5}  {:>7.3f}  {:>5}  {:>12.0f}  {:>11.0f}  {:>18.0f}  {:>5}\n", r.layer, r.z,
               r.paths, r.extrusion_mm, r.travel_mm, r.travel_greedy_mm, r.stripe_singular_faces);
    travel += r.travel_mm;
    greedy += r.travel_greedy_mm;
  }
  fmt::print("travel: {:.0f} mm ({:.0f} % shorter than greedy nearest neighbour)\n", travel,
             greedy > 0 ? 100 * (1 - travel / greedy) : 0.0);
  fmt::print(
      "time: refinement {:.2f} s, fields {:.2f} s, stripes {:.2f} s, extraction {:.2f} "
      "s, ordering {:.2f} s\n",
      paths.timings.refinement, paths.timings.fields, paths.timings.eigenvector,
      paths.timings.extraction, paths.timings.ordering);
  print_gcode_summary(plan, printer);
}

void print_gcode_summary(const PrintPlan& plan, const PrinterProfile& printer) {
  fmt::print("printer: {} ({}); plate placed at bed = plate + ({:.3f}, {:.3f}) mm\n", printer.name,
             describe_bed(printer), plan.gcode.plate_to_bed.x(), plan.gcode.plate_to_bed.y());
  fmt::print("estimated print time {}, filament {:.2f} m ({:.1f} g)\n",
             duration(plan.gcode.print_time), plan.gcode.filament_length / 1000,
             plan.gcode.filament_mass);
}

}  // namespace flatmorph::cli
