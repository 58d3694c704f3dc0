// What a method gives the run pipeline (run.h), and what the pipeline gives back: internal to
// src/run/. Each method's file (run/*_run.cpp) supplies three steps for its options type:
//   prepare_run  checks the options and loads the presets before any work (a bad value leaves no
//                output behind),
//   design_run   designs the plate and says what to print and how to close the loop,
//   report_run   its parameters, metrics, files, warnings and summary, once the print is planned.
// run.cpp chains them with the shared steps. Millimetres and radians.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gcode/deposited_plate.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "mesh/mesh.h"
#include "plate/plate_design.h"
#include "run/gcode_prediction.h"
#include "run/print_plan.h"
#include "run/run_folder.h"
#include "toolpath/toolpath.h"

namespace flatmorph {

// One print job (one bed). Without a toolpath the plate's layer stack is traced (plan_print);
// with one, the method traced its own paths (the height fields' continuous paths, the tiles'
// rings, the origami sheets on this bed).
struct BedPrint {
  std::optional<Toolpath> toolpath;
  Eigen::MatrixXi F;                // the plate's faces this bed prints (the previews' outline)
  std::vector<Material> materials;  // tool i prints materials[i]
  double traced_seconds = 0;        // the method's own tracing, counted in the plan's time
};

// The loop closed on the first bed's G-code (close_the_loop): read back, simulated from `start`,
// compared with `target` and the fields' prediction.
struct LoopClosure {
  std::vector<Material> materials;
  Eigen::MatrixXd start, target, fields_prediction;
  DepositedPlateOptions deposit;
  std::string what = "plate";  // "the plate as plate.gcode prints it", for the progress line
};

// A method's design, as the pipeline needs it.
struct MethodDesign {
  PlateDesign plate;                       // flat.ply + flat.stack.json
  std::optional<Mesh> target;              // target.ply
  std::optional<Mesh> predicted;           // simulated.ply ...
  Eigen::VectorXd predicted_deviation_mm;  // ... and its distance to the target
  std::vector<BedPrint> beds;              // none: no print
  std::optional<LoopClosure> loop;         // none: the method judges its print itself
};

// What the pipeline made of it.
struct PrintOutcome {
  std::vector<PrintPlan> plans;  // one per bed
  std::optional<ClosedLoop> loop;
  double loop_seconds = 0;
};

// A method's account of its run.
struct MethodReport {
  nlohmann::ordered_json parameters;  // design.json's top-level keys
  nlohmann::ordered_json metrics;     // design.json's "metrics"
  std::vector<RunFile> files;         // its own files in the run folder
  std::vector<std::string> warnings, notes;
  // The lines after the print's: the per-layer table of a traced stack (plan_summary_lines)
  // when `layer_table`, else the printer, placement, time and filament (gcode_summary_lines).
  bool layer_table = false;
  std::vector<std::string> summary;
  std::string written;  // what the run folder holds, for the summary's last line
};

}  // namespace flatmorph
