#include "run/run.h"

#include <fmt/core.h>

#include <cmath>
#include <type_traits>
#include <utility>

#include "common/stopwatch.h"
#include "run/method_steps.h"
#include "run/print_summary.h"

namespace flatmorph {
namespace {

// The caller's progress callback, stopping the work at the first report after a cancel.
ProgressCallback cancellable(const RunControl& control) {
  if (control.cancel == nullptr) return control.progress;
  return [cancel = control.cancel, progress = control.progress](const Progress& p) {
    if (cancel->cancelled()) throw Cancelled();
    if (progress) progress(p);
  };
}

// Every bed planned (G-code checked, nothing written yet), then the loop closed on the first.
PrintOutcome print_design(const MethodDesign& design, const PrinterProfile& printer,
                          const ProgressCallback& progress) {
  PrintOutcome out;
  for (const BedPrint& bed : design.beds) {
    PrintFilesOptions options;
    if (!bed.toolpath) {
      options.progress = progress;
      out.plans.push_back(plan_print(design.plate, printer, options));
      continue;
    }
    out.plans.push_back(plan_toolpath_print(traced_layer_paths(*bed.toolpath), design.plate.plate,
                                            bed.F, bed.materials, printer, options));
    out.plans.back().seconds += bed.traced_seconds;
  }
  if (out.plans.empty() || !design.loop) return out;
  const LoopClosure& loop = *design.loop;
  report_progress(progress,
                  {"simulate", 0, 0, NAN, "the " + loop.what + " as plate.gcode prints it"});
  const auto start = Clock::now();
  out.loop = close_the_loop(out.plans.front().gcode.text, "plate.gcode", design.plate.plate,
                            design.plate.F, loop.materials, loop.start, loop.target,
                            loop.fields_prediction, loop.deposit);
  out.loop_seconds = seconds_since(start);
  return out;
}

// The run's outputs assembled, written when asked, and described.
RunResult finish_run(const RunRequest& request, const PrinterProfile& printer, MethodDesign design,
                     PrintOutcome print, MethodReport report, const ProgressCallback& progress) {
  RunResult result;
  RunOutputs& run = result.outputs;
  run.method = design.plate.method;
  run.plate = std::move(design.plate);
  run.target = std::move(design.target);
  run.predicted = std::move(design.predicted);
  run.predicted_deviation_mm = std::move(design.predicted_deviation_mm);
  if (print.loop) {
    // Rigidly fitted to the target, as its distances are measured.
    run.gcode_predicted = Mesh{print.loop->on_target, print.loop->prediction.plate.design.F};
    run.gcode_predicted_deviation_mm = print.loop->to_target.per_vertex_mm;
  }
  if (!print.plans.empty()) run.print = std::move(print.plans.front());
  run.files = std::move(report.files);
  run.parameters = std::move(report.parameters);
  run.metrics = std::move(report.metrics);
  run.metric_list = run_metric_list(run.metrics);
  if (!request.output.empty()) write_run_folder(request.output, run, &printer, progress);
  result.record = run_record(run);
  result.printer = printer;
  result.warnings = std::move(report.warnings);
  result.notes = std::move(report.notes);
  if (run.print) {
    result.summary = report.layer_table ? plan_summary_lines(*run.print, printer)
                                        : gcode_summary_lines(*run.print, printer);
  }
  for (std::string& line : report.summary) result.summary.push_back(std::move(line));
  if (!request.output.empty()) {
    result.summary.push_back(fmt::format("wrote {}: {}", request.output.string(), report.written));
  }
  return result;
}

template <typename Options>
RunResult run_method(const RunRequest& request, const Options& options, const RunControl& control) {
  const ProgressCallback progress = cancellable(control);
  const auto setup = prepare_run(request, options);
  if (!request.output.empty()) require_run_folder_destination(request.output);
  auto state = design_run(setup, progress);
  PrintOutcome print = print_design(state.run, setup.printer, progress);
  MethodReport report = report_run(setup, state, print, progress);
  return finish_run(request, setup.printer, std::move(state.run), std::move(print),
                    std::move(report), progress);
}

}  // namespace

std::string_view method_name(const MethodOptions& options) {
  return std::visit(
      [](const auto& o) -> std::string_view {
        using T = std::decay_t<decltype(o)>;
        if constexpr (std::is_same_v<T, ShrinkMorphRunOptions>) return "shrink_morph";
        if constexpr (std::is_same_v<T, HeightFieldRunOptions>) return "heightfield";
        if constexpr (std::is_same_v<T, TilesRunOptions>) return "tiles";
        return "origami";
      },
      options);
}

RunResult run_design(const RunRequest& request, const RunControl& control) {
  return std::visit([&](const auto& options) { return run_method(request, options, control); },
                    request.options);
}

}  // namespace flatmorph
