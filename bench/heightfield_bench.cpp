// The height-field method (SCF 2020) on the built-in examples at their default size (160 mm
// across, 35 mm high) and on three fields at the paper's Table 1 sizes: the invalid-edge share, the
// distance of the shape risen from the flat sheet to the target (flattening's shrink, then
// optimized), the design time, and the print time of the G-code next to the paper's 92-141 min.
// The figures of docs/heightfield.md.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "examples/height_field_examples.h"
#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "methods/heightfield/design_height_field.h"

namespace flatmorph {
namespace {

struct HeightFieldCase {
  std::string name;  // a built-in example
  double diameter_mm;
  double height_mm;
};

// Rows 0-3: the examples at the default size; 4-6: the paper's sizes (Table 1: Starfish 175.2 x
// 33.4 mm, a single peak; Mask 146.4 x 42.3, a saddle between brows and nose; Hawaii 159.0 x 34.7,
// three peaks).
const std::vector<HeightFieldCase>& cases() {
  static const std::vector<HeightFieldCase> all = {
      {"hill", 160, 35},     {"saddle", 160, 35},     {"island", 160, 35},    {"ridge", 160, 35},
      {"hill", 175.2, 33.4}, {"saddle", 146.4, 42.3}, {"island", 159.0, 34.7}};
  return all;
}

void BM_HeightField(benchmark::State& state) {
  const auto index = static_cast<size_t>(state.range(0));
  if (index >= cases().size()) {
    state.SkipWithError("no such case");
    return;
  }
  const HeightFieldCase& c = cases()[index];
  const HeightField field = height_field_example(c.name, {c.diameter_mm, c.height_mm, 2.0});
  HeightFieldDesignOptions options;
  options.material = load_material("pla-geodesy");
  const PrinterProfile printer = load_printer("generic-marlin");
  options.path_options.path_width = printer.nozzle_diameter;
  for (auto _ : state) {
    const HeightFieldDesign d = design_height_field(field, c.name, options);
    const GcodeResult gcode = make_gcode(d.paths.toolpath, printer, d.plate.design.stack.materials);
    state.SetLabel(c.name + " " + std::to_string(static_cast<int>(c.diameter_mm)) + " x " +
                   std::to_string(static_cast<int>(c.height_mm)) + " mm");
    state.counters["faces"] = static_cast<double>(d.mesh.F.rows());
    state.counters["inv_pct"] = d.sheet.invalid_edge_percent;
    state.counters["flat_avg_pct"] = d.flattened_prediction.distance.mean_percent;
    state.counters["flat_max_pct"] = d.flattened_prediction.distance.max_percent;
    state.counters["avg_pct"] = d.prediction.distance.mean_percent;
    state.counters["max_pct"] = d.prediction.distance.max_percent;
    state.counters["avg_mm"] = d.prediction.distance.mean_mm;
    state.counters["rises_up"] = d.prediction.side > 0;
    state.counters["t_mesh_s"] = d.times.meshing;
    state.counters["t_flat_s"] = d.times.flattening;
    state.counters["t_sim_s"] = d.times.prediction + d.times.final_prediction;
    state.counters["t_optim_s"] = d.times.optimization;
    state.counters["t_paths_s"] = d.times.paths;
    state.counters["t_design_s"] = d.times.total;
    state.counters["traces"] = d.paths.num_traces;
    state.counters["print_min"] = gcode.print_time / 60;
  }
}
BENCHMARK(BM_HeightField)->DenseRange(0, 6)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
}  // namespace flatmorph
