// Issue 22's figures: the shape predicted from a design's own plate.gcode. BM_GcodePrediction
// designs each of Table 1's six models with the paper's settings (not timed), writes its G-code
// for a 300 mm bed, and then times reading it back (t_read_s), rasterizing its beads onto the
// plate (t_rasterize_s; the bar: read + rasterize <= 2 s on the hat) and the whole prediction
// (t_total_s, <= 10 s), with the distance of the G-code's shape to the target and to the shape
// predicted from the design's fields (the bar: <= 1 % of the diagonal on average).
#include <benchmark/benchmark.h>

#include <chrono>

#include "gcode/printer_profile.h"
#include "mesh/io.h"
#include "methods/shrink_morph/design.h"
#include "paper_models.h"
#include "run/gcode_prediction.h"
#include "run/print_plan.h"

namespace flatmorph {
namespace {

void BM_GcodePrediction(benchmark::State& state) {
  const PaperModel& model = kPaperModels[state.range(0)];
  const std::filesystem::path path = paper_model_path(model, state);
  if (path.empty()) return;
  const PaperPrint paper = design_paper_model(model, path);
  const Design& design = paper.design;
  const PlateDesign& plate = paper.plate;
  const PrintPlan plan = plan_print(plate, paper.printer, PrintFilesOptions{});
  ClosedLoop loop;
  double total = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    loop = close_the_loop(plan.gcode.text, "plate.gcode", plate.plate, plate.F,
                          {paper.options.material}, design.flat.target.V, design.flat.target.V,
                          design.optimized);
    total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  const GcodePrediction& p = loop.prediction;
  state.counters["faces"] = plate.F.rows();
  state.counters["beads"] = p.num_beads;
  state.counters["gcode_MB"] = plan.gcode.text.size() / 1e6;
  state.counters["t_read_s"] = p.read_seconds;
  state.counters["t_rasterize_s"] = p.rasterize_seconds;
  state.counters["t_sim_s"] = p.result.seconds;
  state.counters["t_total_s"] = total;
  state.counters["converged"] = p.result.converged;
  state.counters["unprinted_faces"] = p.plate.removed_faces;
  state.counters["fields_avg_pct"] = design.metrics.dist_to_optim_avg_pct;
  state.counters["fields_max_pct"] = design.metrics.dist_to_optim_max_pct;
  state.counters["gcode_avg_pct"] = loop.to_target.mean_percent;
  state.counters["gcode_max_pct"] = loop.to_target.max_percent;
  state.counters["vs_fields_avg_pct"] = loop.to_prediction.mean_percent;
  state.counters["vs_fields_max_pct"] = loop.to_prediction.max_percent;
}
BENCHMARK(BM_GcodePrediction)
    ->DenseRange(0, 5)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace
}  // namespace flatmorph
