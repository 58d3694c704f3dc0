// Thermorph origami (issue 27): the whole design of each built-in solid, from its faces to the
// two-material toolpath and the folded check, with the G-code's print time. The acceptance bar:
// a low-poly bunny of at most 70 faces in under 10 s.
#include <benchmark/benchmark.h>

#include <chrono>

#include "common/error.h"
#include "examples/origami_examples.h"
#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "methods/origami/design_origami.h"

namespace flatmorph {
namespace {

void BM_Origami(benchmark::State& state) {
  const std::vector<std::string> names = origami_example_names();
  const auto index = static_cast<size_t>(state.range(0));
  if (index >= names.size()) {
    state.SkipWithError("no such example");
    return;
  }
  OrigamiOptions options;
  options.pla = load_material("pla-generic");
  options.tpu = load_material("tpu-generic");
  const PrinterProfile printer = load_printer("prusa-xl-2t");
  options.room = printer.bed_size.array() - 20;
  state.SetLabel(names[index]);
  for (auto _ : state) {
    try {
      const auto start = std::chrono::steady_clock::now();
      const Polyhedron solid = origami_example(names[index], 70);
      const OrigamiDesign d = design_origami(solid, options);
      double print_time = 0;
      for (const Toolpath& toolpath : d.bed_toolpaths) {
        print_time += make_gcode(toolpath, printer, {options.pla, options.tpu}).print_time;
      }
      int hinges = 0, collisions = 0;
      for (const OrigamiSheet& sheet : d.sheets) {
        hinges += static_cast<int>(sheet.hinges.size());
        collisions += sheet.collision.has_value();
      }
      state.counters["faces"] = static_cast<double>(solid.faces.size());
      state.counters["nets"] = static_cast<double>(d.sheets.size());
      state.counters["hinges"] = hinges;
      state.counters["collisions"] = collisions;
      state.counters["sharp_err_pct"] = d.sharp_error_pct;
      state.counters["curved_err_pct"] = d.curved_plane_error_pct;
      state.counters["t_design_s"] = d.times.total;
      state.counters["t_total_s"] =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      state.counters["beds"] = d.num_beds;
      state.counters["print_min"] = print_time / 60;
    } catch (const UserError& e) {
      state.SkipWithError(e.what());
      return;
    }
  }
}
BENCHMARK(BM_Origami)
    ->DenseRange(0, 6)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace
}  // namespace flatmorph
