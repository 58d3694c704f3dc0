// Geodesy tiles (issue 24): the whole design of each built-in layout, prediction included, with
// its print time and how its tiles rise. The acceptance bar: the 3 x 3 coaster under 5 s.
#include <benchmark/benchmark.h>

#include <cmath>

#include "examples/tile_examples.h"
#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "methods/tiles/design_tiles.h"

namespace flatmorph {
namespace {

void BM_Tiles(benchmark::State& state) {
  const std::vector<std::string> names = tile_example_names();
  const auto index = static_cast<size_t>(state.range(0));
  if (index >= names.size()) {
    state.SkipWithError("no such example");
    return;
  }
  TilesDesignOptions options;
  options.material = load_material("pla-geodesy");
  options.lattice_material = options.material;
  const PrinterProfile printer = load_printer("generic-marlin");
  options.levels.pitch = printer.nozzle_diameter;
  const TileLayout layout = tile_layout_example(names[index]);
  for (auto _ : state) {
    const TilesDesign d = design_tiles(layout, options);
    const GcodeResult gcode = make_gcode(d.print.toolpath, printer, d.plate.design.stack.materials);
    state.SetLabel(names[index]);
    double worst_depth = 0, worst_ring = 0;
    int sides_right = 0;
    for (size_t i = 0; i < d.tiles.size(); ++i) {
      worst_depth = std::max(worst_depth, std::abs(d.tiles[i].measure.depth_error_pct));
      worst_ring = std::max(worst_ring, d.tiles[i].measure.ring_radius_error_mm);
      sides_right += d.tiles[i].measure.side == layout.tiles[i].side;
    }
    state.counters["tiles"] = static_cast<double>(d.tiles.size());
    state.counters["faces"] = static_cast<double>(d.plate.design.F.rows());
    state.counters["layers"] = static_cast<double>(d.print.toolpath.layers.size());
    state.counters["depth_err_pct"] = worst_depth;
    state.counters["ring_err_mm"] = worst_ring;
    state.counters["sides_ok"] = sides_right;
    state.counters["converged"] = d.simulation.converged;
    state.counters["t_mesh_s"] = d.times.mesh;
    state.counters["t_sim_s"] = d.times.simulation;
    state.counters["t_optim_s"] = d.times.optimization;
    state.counters["t_paths_s"] = d.times.paths;
    state.counters["t_design_s"] = d.times.total;
    state.counters["print_min"] = gcode.print_time / 60;
  }
}
BENCHMARK(BM_Tiles)->DenseRange(0, 3)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
}  // namespace flatmorph
