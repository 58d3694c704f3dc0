// The paper's six models (tests/methods/shrink_morph/paper_table1.h) for the benchmarks.
#pragma once

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "../tests/methods/shrink_morph/paper_table1.h"
#include "gcode/printer_profile.h"
#include "mesh/io.h"
#include "methods/shrink_morph/design.h"
#include "run/gcode_prediction.h"
#include "run/print_plan.h"

namespace flatmorph {

using testing::kPaperModels;
using testing::paper_design_options;
using testing::PaperModel;

// The model's file in ../shared/meshes; empty (and the benchmark skipped) when it is missing.
inline std::filesystem::path paper_model_path(const PaperModel& model, benchmark::State& state) {
  state.SetLabel(model.name);
  const std::filesystem::path path =
      std::filesystem::path(FLATMORPH_SHARED_DIR) / "meshes" / (std::string(model.name) + ".obj");
  if (std::filesystem::exists(path)) return path;
  state.SkipWithError("../shared/meshes is not beside the project");
  return {};
}

// A model designed with Table 1's settings (theta2 optimized), its plate and the print planned
// for a 300 mm bed (the top is 250 mm wide): what the print benchmarks start from, not timed.
struct PaperPrint {
  DesignOptions options;
  Design design;
  PlateDesign plate;
  PrinterProfile printer;
};
inline PaperPrint design_paper_model(const PaperModel& model, const std::filesystem::path& path) {
  PaperPrint out;
  out.options = paper_design_options(model);
  out.design = design_shrink_morph(read_mesh(path).mesh, path.string(), out.options);
  out.plate = shrink_morph_plate_design(out.design.flat, out.design.theta2, out.options.material,
                                        out.options.layers);
  out.printer = load_printer("creality-cr10s-pro");
  return out;
}

// The shape a design's own plate.gcode prints on `printer`: planned, read back, rasterized and
// simulated from the target (run/gcode_prediction.h), not timed. Its distance to the target and
// to the fields' prediction, as counters gcode_avg_pct, gcode_max_pct, vs_fields_avg_pct and
// vs_fields_max_pct (% of the diagonal); returned for further counters.
inline ClosedLoop count_printed_shape(benchmark::State& state, const Design& d,
                                      const DesignOptions& options, const std::string& printer) {
  state.PauseTiming();
  const PlateDesign plate =
      shrink_morph_plate_design(d.flat, d.theta2, options.material, options.layers);
  const PrintPlan plan = plan_print(plate, load_printer(printer), PrintFilesOptions{});
  ClosedLoop loop =
      close_the_loop(plan.gcode.text, "plate.gcode", plate.plate, plate.F, {options.material},
                     d.flat.target.V, d.flat.target.V, d.optimized);
  state.counters["gcode_avg_pct"] = loop.to_target.mean_percent;
  state.counters["gcode_max_pct"] = loop.to_target.max_percent;
  state.counters["vs_fields_avg_pct"] = loop.to_prediction.mean_percent;
  state.counters["vs_fields_max_pct"] = loop.to_prediction.max_percent;
  state.ResumeTiming();
  return loop;
}

}  // namespace flatmorph
