// flatmorph origami: Thermorph's self-folding sheets (CHI 2018) through the library run
// (run/run.h): its options and their help.
#include <fmt/core.h>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "run_command.h"

namespace flatmorph::cli {

Command make_origami_command(CLI::App& app, const GlobalOptions& global) {
  auto run = std::make_shared<RunCommandOptions>();
  run->request.options = OrigamiRunOptions{};
  auto& o = std::get<OrigamiRunOptions>(run->request.options);
  CLI::App* sub = app.add_subcommand(
      "origami",
      "Self-folding origami (Thermorph, CHI 2018): the solid simplified to planar faces, "
      "unfolded into nets, every fold given a curved actuator (active PLA lines across the hinge "
      "on a TPU layer) whose width bends it by the fold's angle, printed in two materials "
      "(two tools, or pauses to swap the filament). In 70 C water the sheet folds into the "
      "solid. Writes DIR/net.svg (the printed sheet), DIR/crease_pattern.svg and DIR/pattern.fold "
      "(Origami Simulator opens both), DIR/folded.ply (the folded sheet), DIR/flat.ply, "
      "DIR/plate.gcode (and DIR/plate_2.gcode, ... when the sheets need several beds), "
      "DIR/layers/, DIR/design.json and DIR/report.html. docs/origami.md explains each step.");
  sub->add_option("input", run->request.input.path,
                  "A mesh (.obj, .ply, .stl, .off: simplified to at most --faces planar faces) or "
                  "a crease pattern (.svg: outline black, mountains red, valleys blue, the angle "
                  "from data-fold-angle or the stroke opacity x 180 deg, as Origami Simulator)");
  sub->add_option("--example", run->request.input.example,
                  "A built-in solid: tetrahedron, cube, octahedron, dodecahedron, icosahedron, "
                  "pyramid or bunny");
  sub->add_option("--faces", o.faces, "At most this many faces (meshes and the bunny)")
      ->capture_default_str();
  sub->add_option("--size", o.size_mm,
                  "The solid's longest side, mm (0: as the file gives it; examples have their "
                  "own)")
      ->capture_default_str();
  sub->add_option("--material", o.material,
                  "The PLA of the faces and the actuators (see 'flatmorph materials'); its "
                  "hinge_curve, when calibrated, sets how far a hinge bends")
      ->capture_default_str();
  sub->add_option("--hinge-material", o.hinge_material, "The actuators' constraint layer (TPU)")
      ->capture_default_str();
  sub->add_option("--printer", o.printer,
                  "Printer preset or JSON file: two tools (T0 PLA, T1 TPU) or one with a "
                  "filament swap (see 'flatmorph printers')")
      ->capture_default_str();
  sub->add_option("--actuator-speed", o.actuator_speed,
                  "Print speed of the actuators' active PLA, mm/s: faster stores more stretch and "
                  "bends on a tighter arc (narrower actuators)")
      ->capture_default_str();
  sub->add_option("--actuator-width", o.actuator_width,
                  "Make every actuator this wide, mm, and solve each one's speed from its angle "
                  "(0: the width follows from --actuator-speed)")
      ->capture_default_str();
  sub->add_option("--flat-angle", o.flat_angle_deg,
                  "Folds of less than this many degrees print no actuator")
      ->capture_default_str();
  sub->add_flag("--case-b-hinges", o.case_b_hinges,
                "A mesh's valleys may print as case B hinges (TPU on the bed) though the hinge "
                "curve is uncalibrated: fewer nets, but such a hinge folds less than the curve "
                "promises once longer than wide, and each is named in a warning (default: they "
                "are cut, and every hinge is case A)");
  sub->add_flag("--simulate", o.simulate,
                "Fold each printed sheet with the shared simulator (faces and actuators meshed as "
                "one plate with the layers printed there, started from the design), once from the "
                "design's layers and once from what plate.gcode deposits: each hinge's simulated "
                "angles in design.json, DIR/sheet_simulated.ply and sheet_gcode_simulated.ply");
  sub->add_option("--fit-hinges", o.fit_hinges,
                  "Correct each actuator's width against the shared simulator, at most this many "
                  "rounds (each simulates every sheet on a 3 mm mesh and scales each width by "
                  "the square root of designed / simulated angle); the design whose worst hinge "
                  "came closest is printed. 0: the hinge curve's widths")
      ->capture_default_str();
  sub->add_option("--mesh-edge", o.mesh_edge_mm, "Longest edge of --simulate's mesh, mm")
      ->capture_default_str();
  sub->add_flag("!--no-slicer", o.slicer,
                "Do not run PrusaSlicer (when installed) for the solid's print time; use the "
                "volume estimate");
  add_run_options(sub, *run);
  return {sub, [run, &global] { return run_and_print(*run, global); }};
}

}  // namespace flatmorph::cli
