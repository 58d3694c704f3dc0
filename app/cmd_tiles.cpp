// flatmorph tiles: Geodesy's self-rising tiles (CHI 2019) through the library run (run/run.h):
// its options and their help.
#include <fmt/core.h>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "run_command.h"

namespace flatmorph::cli {

Command make_tiles_command(CLI::App& app, const GlobalOptions& global) {
  auto run = std::make_shared<RunCommandOptions>();
  run->request.options = TilesRunOptions{};
  auto& o = std::get<TilesRunOptions>(run->request.options);
  CLI::App* sub = app.add_subcommand(
      "tiles",
      "Self-rising tiles (Geodesy, CHI 2019): each tile printed as nested rings offset from its "
      "outline, each ring at the layer height that shrinks it as its place in the profile "
      "needs, so that the flat tile rises into a surface of revolution in hot water; a bilayer "
      "picks the side. Writes DIR/flat.ply (per-face tile, ring level, shrinkage, direction), "
      "DIR/simulated.ply, DIR/plate.gcode, DIR/layers/, DIR/profile_N.svg (asked, printed and "
      "simulated profile per tile), DIR/design.json and DIR/report.html. docs/tiles.md explains "
      "each step.");
  sub->add_option("input", run->request.input.path,
                  "A layout (.json, docs/tiles.md) or a drawing whose closed outlines are the "
                  "tiles (.dxf: LWPOLYLINE, POLYLINE, LINE/ARC chains, CIRCLE; .svg: polygon, "
                  "polyline, rect, circle, path with lines and arcs)");
  sub->add_option("--example", run->request.input.example,
                  "A built-in layout instead of a file: dome, spin-top, coaster or bracelet");
  sub->add_option("--profile", o.profile,
                  "Every tile's side profile: spherical-cap, cone, paraboloid, gaussian, concave, "
                  "transition, subtle-cone, dramatic-cone");
  sub->add_option("--profile-csv", o.profile_csv,
                  "Every tile's side profile from a CSV of r,z rows in mm (from the apex on the "
                  "axis to the rim)");
  sub->add_option("--height", o.height_mm, "Every tile's height above its rim, mm");
  sub->add_option("--side", o.side, "Every tile rises up (away from the bed) or down");
  sub->add_option("--hole", o.hole_mm, "Every tile's hole radius, mm (0: none)");
  sub->add_option("--material", o.material,
                  "Material preset or JSON file with a thickness curve (see 'flatmorph materials')")
      ->capture_default_str();
  sub->add_option("--lattice-material", o.lattice_material,
                  "Material of the lattice between tiles (default: the tiles'; another one prints "
                  "with a second tool, e.g. tpu-generic on a two-tool printer)");
  sub->add_option("--printer", o.printer, "Printer preset or JSON file (see 'flatmorph printers')")
      ->capture_default_str();
  sub->add_option("--pitch", o.pitch_mm,
                  "Path width and ring spacing, mm (0: the printer's nozzle)")
      ->capture_default_str();
  sub->add_option("--thickness", o.thickness_mm,
                  "Printed sheet thickness, mm: each ring prints Floor(thickness / t) layers of "
                  "its height t")
      ->capture_default_str();
  sub->add_option("--bilayer", o.bilayer,
                  "Shrink difference between the bed-side and top halves that makes a tile rise "
                  "to its side (a fraction; 0: per ring, the one that bends the ring as the "
                  "risen surface bends)")
      ->capture_default_str();
  sub->add_flag("--strict", o.strict,
                "Refuse a profile that needs a ring outside the material's shrink range instead "
                "of clamping it");
  sub->add_option("--mesh-edge", o.mesh_edge_mm,
                  "Longest edge of the simulator's mesh, mm (0: 1 mm, longer on large sheets to "
                  "keep to about 8000 faces)")
      ->capture_default_str();
  sub->add_flag("!--no-optimize", o.optimize,
                "Print a polygonal tile with the circle's shrink per ring (the paper's mapping) "
                "without refining it against the simulated profile");
  add_run_options(sub, *run);
  return {sub, [run, &global] { return run_and_print(*run, global); }};
}

}  // namespace flatmorph::cli
