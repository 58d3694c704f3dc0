// flatmorph design: the whole Shrink & Morph pipeline on one target (run/run.h): its options and
// their help.
#include <fmt/core.h>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "mesh_input.h"
#include "run_command.h"

namespace flatmorph::cli {

Command make_design_command(CLI::App& app, const GlobalOptions& global) {
  auto run = std::make_shared<RunCommandOptions>();
  run->request.options = ShrinkMorphRunOptions{};
  auto& o = std::get<ShrinkMorphRunOptions>(run->request.options);
  CLI::App* sub = app.add_subcommand(
      "design",
      "The whole Shrink & Morph design of a target surface: flatten it (plate and theta1), "
      "simulate the plate, optimize the through-thickness variation theta2 so that the predicted "
      "shape matches the target (paper 3.2.2), then trace the print paths of every layer. Writes "
      "DIR/flat.ply (per-face theta1, per-vertex theta2, radians), DIR/target.ply, "
      "DIR/simulated.ply (the predicted shape, per-vertex deviation_mm), DIR/design.json "
      "(parameters and metrics), DIR/plate.gcode, DIR/layers/ (previews) and DIR/report.html "
      "(open it in a browser: 3D view, plate, layers, metrics).");
  add_mesh_input(sub, run->request.input);
  sub->add_option("--width", o.width_mm,
                  fmt::format("Largest extent of the plate, in mm (default {} for --example; "
                              "needed for a mesh file)",
                              kExamplePlateWidthMm));
  sub->add_option("--wD", o.w_D, "Smoothing weight of the print directions (Eq. 12)")
      ->capture_default_str();
  sub->add_option("--wM", o.w_M, "Weight of the theta2 magnitude term (Eq. 13)")
      ->capture_default_str();
  sub->add_option("--wL", o.w_L, "Weight of the theta2 smoothness term (Eq. 13)")
      ->capture_default_str();
  sub->add_option("--path-error", o.path_error_deg,
                  "Paths' angle error in degrees (rms per face and layer, varying over a couple "
                  "of rings of faces): a design whose plate snaps to another shape under errors "
                  "of about 1 degree (a fold of its equilibria) is designed again, from where it "
                  "ended, for the mean over the nominal stack and two samples of errors this "
                  "large, and kept when its printed shape lands closer; 0 turns this off "
                  "(docs/design.md)")
      ->capture_default_str();
  sub->add_option("--faces", o.faces,
                  "Loop-subdivide the target until it has at least this many faces")
      ->capture_default_str();
  sub->add_option("--layers", o.layers, "Number of printed layers")->capture_default_str();
  sub->add_option("--material", o.material, "Material preset name or material JSON file")
      ->capture_default_str();
  sub->add_option("--printer", o.printer,
                  "Printer preset name or JSON file for the G-code (see 'flatmorph printers')")
      ->capture_default_str();
  sub->add_option("--side", o.side,
                  "Which side of the target is printed on top: auto (the side the plate naturally "
                  "curls toward; when the curvature does not tell, both sides are designed one "
                  "subdivision level coarser and the closer one is kept), normal-up or "
                  "normal-down")
      ->capture_default_str();
  sub->add_option("--stretch", o.stretch,
                  "Which of the 4 initial stretches (45 degrees apart) the flattening starts from: "
                  "auto (the one whose print directions follow the target's curvature, see "
                  "docs/design.md), 0 to 3, or all: design from each, side by side on the cores "
                  "there are, and keep the one with the lowest final objective (about twice the "
                  "time on 2 cores). The flattening has several local minima, and the theta2 "
                  "design can land closer from another one; design.json records the one used as "
                  "stretch_candidate (and with all, each one's result as explored_stretches)")
      ->capture_default_str();
  add_run_options(sub, *run);
  return {sub, [run, &global] { return run_and_print(*run, global); }};
}

}  // namespace flatmorph::cli
