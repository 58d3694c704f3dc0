// flatmorph heightfield: the self-rising height-field method (SCF 2020) through the library run
// (run/run.h): its options and their help.
#include <fmt/core.h>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "run_command.h"

namespace flatmorph::cli {

Command make_heightfield_command(CLI::App& app, const GlobalOptions& global) {
  auto run = std::make_shared<RunCommandOptions>();
  run->request.options = HeightFieldRunOptions{};
  auto& o = std::get<HeightFieldRunOptions>(run->request.options);
  CLI::App* sub = app.add_subcommand(
      "heightfield",
      "A flat sheet that rises into a height field in hot water (SCF 2020): the paths run along "
      "the isolines, each printed at the layer height that shrinks it as much as the sheet needs. "
      "Meshes the isolines and gradient lines, flattens the sheet, simulates the risen shape and "
      "refines the shrink against it, traces one continuous path per hill, and writes "
      "DIR/flat.ply (per-face shrinkage, layer_height, direction), DIR/target.ply, "
      "DIR/simulated.ply, DIR/plate.gcode, DIR/layers/, DIR/texture.png (when the surface has "
      "colours: the screen-print image at print scale), DIR/design.json and DIR/report.html. "
      "docs/heightfield.md explains each step.");
  sub->add_option(
      "input", run->request.input.path,
      "The height field: a mesh that is a graph z = h(x, y) in mm (OBJ, PLY, STL, OFF), "
      "or a grayscale PNG (black = 0, white = --height) with --size");
  sub->add_option("--example", run->request.input.example,
                  "A built-in height field instead of a file: hill, saddle, island or ridge");
  sub->add_option("--diameter", o.diameter_mm, "Diameter of an example, mm")->capture_default_str();
  sub->add_option("--height", o.height_mm,
                  fmt::format("Height of an example (default {}) or of white in an image, mm",
                              kExampleFieldHeightMm));
  sub->add_option("--size", o.size_wxd,
                  "Width and depth an image covers, mm, as WxD (e.g. 160x120)");
  sub->add_option("--resolution", o.resolution_mm, "Grid spacing an image is resampled to, mm")
      ->capture_default_str();
  sub->add_option("--texture", o.texture,
                  "A PNG the OBJ's texture coordinates point into: the surface's colours, printed "
                  "as texture.png (a PLY's vertex colours are read without it)");
  sub->add_option("--checkerboard", o.checkerboard_mm,
                  "Colour the surface with a checkerboard of this square side (mm, in x and y) "
                  "to try the screen print's registration (0: none)")
      ->capture_default_str();
  sub->add_option("--material", o.material,
                  "Material preset or JSON file with a thickness curve (see 'flatmorph materials')")
      ->capture_default_str();
  sub->add_option("--printer", o.printer, "Printer preset or JSON file (see 'flatmorph printers')")
      ->capture_default_str();
  sub->add_option("--level-spacing", o.level_spacing_mm,
                  "Height between isolines, mm (0: a twelfth of the height)")
      ->capture_default_str();
  sub->add_option("--lu", o.upsample_length_mm,
                  "Longest printing edge of the printing graph, mm (the paper's l_u)")
      ->capture_default_str();
  sub->add_option("--layers", o.layers,
                  "Identical layers printed (0: as many as the thickness curve was calibrated "
                  "with; 6 for pla-geodesy)")
      ->capture_default_str();
  sub->add_option("--path-width", o.path_width_mm,
                  "Width of a path and distance between rows, mm (0: the printer's nozzle)")
      ->capture_default_str();
  sub->add_flag("!--no-optimize", o.optimize,
                "Print the flattening's shrink as the paper does, without refining it against the "
                "simulated shape");
  sub->add_flag("--other-shapes", o.other_shapes,
                "Also simulate the sheet from the target's shape and warn when it settles into "
                "another stable shape than the one it rises to from flat (costs as much as the "
                "prediction, or more)");
  sub->add_option("--dpi", o.dpi, "Resolution of texture.png (it prints at scale)")
      ->capture_default_str();
  add_run_options(sub, *run);
  return {sub, [run, &global] { return run_and_print(*run, global); }};
}

}  // namespace flatmorph::cli
