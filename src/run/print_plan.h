// The print of a designed plate, shared by every run: the trajectories of every layer of its stack
// (toolpath/layer_paths.h), the checked G-code for a printer, the layer previews and the toolpath
// as data (toolpath.json).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "plate/plate_design.h"
#include "toolpath/layer_paths.h"

namespace flatmorph {

struct PrintFilesOptions {
  double spacing_mm = 0;                 // 0: the printer's nozzle diameter
  std::optional<Eigen::Vector2d> at_mm;  // plate placement on the bed; default centred
  int skirt_loops = 0;
  ProgressCallback progress;
};

struct PrintPlan {
  LayerPaths paths;
  GcodeOptions gcode_options;
  GcodeResult gcode;  // planned and checked, not yet written
  std::vector<Eigen::MatrixX2d> outline;
  double seconds = 0;  // trajectories and G-code planning, wall clock
};

// Traces and orders the trajectories of every layer of the plate's stack and plans the G-code
// (each tool prints with the stack's material of that index); throws UserError (kInfeasible)
// when the plate does not fit the printer, before anything is written.
PrintPlan plan_print(const PlateDesign& design, const PrinterProfile& printer,
                     const PrintFilesOptions& options);

// A toolpath a method traced itself (the height fields' continuous paths, the tiles' rings) with
// one report per layer: its z, number of paths, printed and travel lengths.
LayerPaths traced_layer_paths(Toolpath toolpath);

// The G-code plan of a toolpath already traced (a method that traces its own paths, such as the
// height fields' continuous paths): `paths.toolpath` printed with `materials` (tool i prints
// materials[i]) on `printer`, placed as `options` says, the plate's outline (plate #V x 2, mm, F)
// kept for the previews. `paths.layers` should hold one report per layer. Throws make_gcode's
// UserErrors (a plate larger than the bed).
PrintPlan plan_toolpath_print(LayerPaths paths, const Eigen::MatrixXd& plate,
                              const Eigen::MatrixXi& F, const std::vector<Material>& materials,
                              const PrinterProfile& printer, const PrintFilesOptions& options);

// Writes dir/plate.gcode, dir/toolpath.json, dir/layers/layer_NNN.svg and dir/layers/overview.png.
void write_print_files(const std::filesystem::path& dir, const PrintPlan& plan,
                       const PrinterProfile& printer, const LayerStack& stack);

// The figures of plan_summary_lines (print_summary.h) as JSON: per layer (z, paths, printed and
// travel mm), totals, print time (s), filament (mm, g), placement on the bed (mm).
nlohmann::ordered_json plan_summary_json(const PrintPlan& plan, const PrinterProfile& printer);

}  // namespace flatmorph
