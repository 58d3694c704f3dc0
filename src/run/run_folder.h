// A run's outputs written as one unit: the plate (flat.ply + flat.stack.json), the target, the
// predicted shape, the print (plate.gcode, toolpath.json, layers/), design.json and the report.
// Every design method ends by calling write_run_folder; docs/architecture.md.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/progress.h"
#include "gcode/printer_profile.h"
#include "mesh/mesh.h"
#include "plate/plate_design.h"
#include "run/print_plan.h"

namespace flatmorph {

// A figure of the run, for any method: e.g. {"dist_to_optim_avg", 0.25, "% of diagonal"}.
struct RunMetric {
  std::string name;
  double value = 0;
  std::string unit;
};

// A file a method adds to its run folder as it is (e.g. the height fields' texture.png).
struct RunFile {
  std::string name;  // relative to the folder
  std::string bytes;
};

struct RunOutputs {
  std::string method;  // "shrink_morph", ...
  PlateDesign plate;   // flat.ply + flat.stack.json
  // target.ply (mm): the plate's vertex and face order, or, for a G-code compared by shape, the
  // target mesh as given.
  std::optional<Mesh> target;
  std::optional<Mesh> predicted;           // simulated.ply: the predicted shape (mm) ...
  Eigen::VectorXd predicted_deviation_mm;  // ... and its per-vertex distance to the target
  // gcode_simulated.ply: the shape predicted from the run's own plate.gcode (gcode_prediction.h),
  // on the faces it prints, with its per-vertex distance to the target.
  std::optional<Mesh> gcode_predicted;
  Eigen::VectorXd gcode_predicted_deviation_mm;
  std::optional<PrintPlan> print;  // plate.gcode, toolpath.json, layers/ (none: no print)
  std::vector<RunFile> files;      // the method's own files
  // design.json: every parameter as top-level keys, the method's own metrics object (the keys
  // the report and the paper's tables read), and the generic list of figures.
  nlohmann::ordered_json parameters;
  nlohmann::ordered_json metrics;
  std::vector<RunMetric> metric_list;
};

// The names of `files` that start with `prefix` and end in ".svg": the drawings a run lists in
// design.json under "drawings" for the report to show (report/run_folder.h).
std::vector<std::string> drawing_names(const std::vector<RunFile>& files, std::string_view prefix);

// The numbers and flags of a metrics object as RunMetrics, each with the unit its key's suffix
// names (_pct: % of the target's diagonal, _s, _rad, _mm, _g).
std::vector<RunMetric> run_metric_list(const nlohmann::ordered_json& metrics);

// design.json's content: run.parameters, then "method", "flatmorph_version", "metrics" and
// "metrics_list" ([{name, value, unit}]).
nlohmann::ordered_json run_record(const RunOutputs& run);

// Throws write_run_folder's UserError for a `dir` it would refuse: for commands to say so before
// minutes of work.
void require_run_folder_destination(const std::filesystem::path& dir);

// Writes every file of the run into a temporary folder beside `dir`, then puts it in the place of
// `dir`: an interrupt leaves `dir` as it was, and a run never leaves files of an earlier one (a
// rerun with no print leaves no G-code). `printer` is needed when run.print is set. Refuses
// (UserError kFile) a `dir` that exists, is not empty and is not a run folder (none of
// design.json, flat.ply, plate.gcode, report.html in it): its files would be lost.
void write_run_folder(const std::filesystem::path& dir, const RunOutputs& run,
                      const PrinterProfile* printer, const ProgressCallback& progress = {});

}  // namespace flatmorph
