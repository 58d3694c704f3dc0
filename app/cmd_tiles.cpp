// flatmorph tiles: Geodesy's self-rising tiles (CHI 2019) from a layout, a drawing or a built-in
// example to a run folder like design's, with a profile plot per tile.
#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "commands.h"
#include "common/error.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "methods/tiles/design_tiles.h"
#include "methods/tiles/profile_plot.h"
#include "print_summary.h"
#include "progress_display.h"
#include "run/gcode_prediction.h"
#include "run/print_plan.h"
#include "run/run_folder.h"

namespace flatmorph::cli {
namespace {

struct TilesCliOptions {
  std::string input;  // a .json layout, a .dxf or .svg drawing
  std::string example;
  std::string profile;  // every tile's, when given
  std::string profile_csv;
  double height_mm = 0;
  std::string side;
  double hole_mm = -1;
  std::string material = "pla-geodesy";
  std::string lattice_material;
  std::string printer = "generic-marlin";
  double pitch_mm = 0;
  double thickness_mm = 0.6;
  double bilayer = 0;
  bool strict = false;
  double mesh_edge_mm = 0;
  bool optimize = true;
  bool gcode = true;
  bool json = false;
  std::string output;
};

void require(bool ok, const std::string& message) {
  if (!ok) throw UserError(ErrorCategory::kOption, message);
}

// Checked before anything is read or written, so that a bad value leaves no output behind.
void check(const TilesCliOptions& o) {
  require(o.input.empty() != o.example.empty(),
          o.input.empty() ? "flatmorph tiles needs tiles: a layout (.json), a drawing (.dxf, "
                            ".svg) or --example NAME (dome, spin-top, coaster, bracelet)"
                          : "give either a file or --example, not both");
  require(!o.output.empty(), "flatmorph tiles needs an output folder: -o DIR");
  require(o.profile.empty() || o.profile_csv.empty(), "give --profile or --profile-csv, not both");
  require(o.height_mm >= 0 && std::isfinite(o.height_mm),
          fmt::format("--height {}: give a positive number of mm", o.height_mm));
  require(o.side.empty() || o.side == "up" || o.side == "down",
          fmt::format("--side {}: give up (away from the bed) or down", o.side));
  require(o.hole_mm == -1 || (o.hole_mm >= 0 && std::isfinite(o.hole_mm)),
          fmt::format("--hole {}: give a radius in mm (0: none)", o.hole_mm));
  require(
      o.pitch_mm >= 0 && o.pitch_mm <= 2,
      fmt::format("--pitch {}: give the path width in mm (0: the printer's nozzle)", o.pitch_mm));
  require(o.thickness_mm > 0 && o.thickness_mm <= 5,
          fmt::format("--thickness {}: give the sheet's printed thickness in mm (0.6 in the "
                      "paper)",
                      o.thickness_mm));
  require(o.bilayer >= 0 && o.bilayer < 0.3,
          fmt::format("--bilayer {}: give the shrink difference between the halves as a "
                      "fraction (0.04 = 4 points), or 0 to match each ring's curvature",
                      o.bilayer));
  require(o.mesh_edge_mm == 0 || (o.mesh_edge_mm >= 0.2 && o.mesh_edge_mm <= 10),
          fmt::format("--mesh-edge {}: give 0.2 to 10 mm, or 0 for automatic", o.mesh_edge_mm));
}

TileLayout load_layout(const TilesCliOptions& o) {
  TileSpec defaults;
  TileLayout layout =
      o.example.empty() ? load_tile_layout(o.input, defaults) : tile_layout_example(o.example);
  for (TileSpec& tile : layout.tiles) {
    if (!o.profile.empty()) {
      tile.profile = o.profile;
      tile.profile_csv.clear();
    }
    if (!o.profile_csv.empty()) tile.profile_csv = o.profile_csv;
    if (o.height_mm > 0) tile.height_mm = o.height_mm;
    if (!o.side.empty()) tile.side = o.side == "up" ? +1 : -1;
    if (o.hole_mm >= 0) tile.hole_radius_mm = o.hole_mm;
  }
  return layout;
}

int run_tiles(const TilesCliOptions& o, const GlobalOptions& global) {
  check(o);
  const Material material = load_material(o.material);
  const PrinterProfile printer = load_printer(o.printer);
  require_run_folder_destination(o.output);
  const bool silent = global.quiet || o.json;
  const ProgressCallback progress = make_progress_display(silent);

  const TileLayout layout = load_layout(o);
  TilesDesignOptions options;
  options.material = material;
  options.lattice_material =
      o.lattice_material.empty() ? material : load_material(o.lattice_material);
  options.levels.pitch = o.pitch_mm > 0 ? o.pitch_mm : printer.nozzle_diameter;
  options.levels.sheet_thickness = o.thickness_mm;
  options.levels.bilayer_difference = o.bilayer;
  options.levels.strict = o.strict;
  options.mesh_edge = o.mesh_edge_mm;
  options.optimize = o.optimize;
  options.progress = progress;
  const TilesDesign design = design_tiles(layout, options);
  const PlateDesign& plate = design.plate.design;

  std::optional<PrintPlan> plan;
  if (o.gcode) {
    PrintFilesOptions print_options;
    plan = plan_toolpath_print(traced_layer_paths(design.print.toolpath), plate.plate, plate.F,
                               plate.stack.materials, printer, print_options);
    plan->seconds += design.times.paths;
  }
  // The loop closed: what plate.gcode deposits, simulated from the same start, against the shape
  // the layer stack gives (the tiles have no target surface as a whole: a network bends at its
  // joints).
  std::optional<ClosedLoop> loop;
  double loop_seconds = 0;
  if (plan && design.simulated) {
    report_progress(progress, {"simulate", 0, 0, NAN, "the sheet as plate.gcode prints it"});
    const auto t = std::chrono::steady_clock::now();
    std::vector<TileLevels> levels;
    for (const TileResult& tile : design.tiles) levels.push_back(tile.levels);
    // A lattice's lines cover only their share of a face in each layer (w / spacing): a face
    // they cross is printed, as the layer stack has it.
    DepositedPlateOptions deposit;
    if (layout.has_lattice)
      deposit.min_coverage = std::min(deposit.min_coverage, 0.5 * design.lattice.fill);
    loop = close_the_loop(plan->gcode.text, "plate.gcode", plate.plate, plate.F,
                          plate.stack.materials, tile_start(design.plate, levels),
                          design.simulation.V, design.simulation.V, deposit);
    loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  }

  std::vector<RunFile> files;
  nlohmann::ordered_json tiles = nlohmann::ordered_json::array();
  for (size_t i = 0; i < design.tiles.size(); ++i) {
    const TileResult& tile = design.tiles[i];
    const TileSpec& spec = layout.tiles[i];
    const TileMeasure& m = tile.measure;
    nlohmann::ordered_json t;
    t["source"] = spec.outline.source;
    t["profile"] = spec.profile_csv.empty() ? spec.profile : spec.profile_csv.string();
    t["height_mm"] = spec.height_mm;
    t["side"] = spec.side > 0 ? "up" : "down";
    t["hole_mm"] = spec.hole_radius_mm;
    t["design_radius_mm"] = tile.levels.design_radius;
    t["rings"] = tile.rings.rings.size();
    t["circular"] = tile.circular;
    t["clamped"] = tile.levels.printability.any_clamped;
    if (design.simulated) {
      t["risen_side"] = m.side > 0 ? "up" : "down";
      t["risen_height_mm"] = m.height_mm;
      t["expected_height_mm"] = m.expected_height_mm;
      t["depth_error_pct"] = m.depth_error_pct;
      t["ring_radius_error_mm"] = m.ring_radius_error_mm;
      t["profile_rms_mm"] = m.profile_rms_mm;
      t["profile_spread_mm"] = m.profile_spread_mm;
      if (tile.optimized) t["mapped_profile_rms_mm"] = tile.mapped_profile_rms_mm;
      t["optimized"] = tile.optimized;
      files.push_back(
          {fmt::format("profile_{}.svg", i),
           profile_plot_svg(
               m, fmt::format("tile {}: {} ({} mm high, {})", i, t["profile"].get<std::string>(),
                              spec.height_mm, t["side"].get<std::string>()))});
    }
    tiles.push_back(t);
  }

  nlohmann::ordered_json j;
  j["input"] = o.example.empty() ? o.input : "example " + o.example;
  j["pitch_mm"] = options.levels.pitch;
  j["sheet_thickness_mm"] = options.levels.sheet_thickness;
  j["bilayer_difference"] = options.levels.bilayer_difference;
  j["mesh_edge_mm"] = design.mesh_edge;
  j["material"] = material.name;
  j["printer"] = printer.name;
  j["tiles"] = tiles;
  // The report shows the profiles (report/run_folder.h).
  if (const std::vector<std::string> drawings = drawing_names(files, "profile_");
      !drawings.empty()) {
    j["drawings"] = drawings;
  }
  if (!design.warnings.empty()) j["warnings"] = design.warnings;

  nlohmann::ordered_json m;
  m["tiles"] = design.tiles.size();
  m["faces"] = plate.F.rows();
  m["layers"] = design.print.toolpath.layers.size();
  m["min_layer_height_mm"] = design.print.min_layer_height;
  m["max_layer_height_mm"] = design.print.max_layer_height;
  int most_paths = 0;
  for (const std::vector<int>& passes : design.print.paths_per_pass) {
    for (int n : passes) most_paths = std::max(most_paths, n);
  }
  m["max_paths_per_tile_pass"] = most_paths;
  if (design.simulated) {
    m["sim_converged"] = design.simulation.converged;
    m["sim_iterations"] = design.simulation.iterations;
    double worst_depth = 0, worst_ring = 0;
    bool sides_right = true;
    for (size_t i = 0; i < design.tiles.size(); ++i) {
      const TileMeasure& tm = design.tiles[i].measure;
      worst_depth = std::max(worst_depth, std::abs(tm.depth_error_pct));
      worst_ring = std::max(worst_ring, tm.ring_radius_error_mm);
      sides_right = sides_right && tm.side == layout.tiles[i].side;
    }
    m["depth_error_max_pct"] = worst_depth;
    m["ring_radius_error_max_mm"] = worst_ring;
    m["sides_as_designed"] = sides_right;
  }
  m["t_rings_s"] = design.times.rings;
  m["t_mesh_s"] = design.times.mesh;
  m["t_paths_s"] = design.times.paths;
  m["t_sim_s"] = design.times.simulation;
  m["t_optim_s"] = design.times.optimization;
  m["t_design_s"] = design.times.total;
  if (plan) {
    m["print_time_s"] = plan->gcode.print_time;
    m["print_time_min"] = plan->gcode.print_time / 60;
    m["filament_mm"] = plan->gcode.filament_length;
    m["filament_g"] = plan->gcode.filament_mass;
    m["path_length_mm"] = design.print.path_length;
  }
  if (loop) {
    m["gcode_vs_fields_avg_pct"] = loop->to_prediction.mean_percent;
    m["gcode_vs_fields_max_pct"] = loop->to_prediction.max_percent;
    m["gcode_converged"] = loop->prediction.result.converged;
    m["gcode_unprinted_faces"] = loop->prediction.plate.removed_faces;
    m["t_gcode_sim_s"] = loop_seconds;
  }

  RunOutputs run;
  run.method = plate.method;
  run.plate = plate;
  if (design.simulated) run.predicted = Mesh{design.simulation.V, plate.F};
  if (loop) {
    run.gcode_predicted = Mesh{loop->on_target, loop->prediction.plate.design.F};
    run.gcode_predicted_deviation_mm = loop->to_target.per_vertex_mm;
  }
  run.print = std::move(plan);
  run.files = std::move(files);
  run.parameters = j;
  run.metrics = m;
  run.metric_list = run_metric_list(m);
  write_run_folder(o.output, run, &printer, progress);
  const nlohmann::ordered_json record = run_record(run);

  finish_progress_line();
  for (const std::string& warning : design.warnings) {
    fmt::print(stderr, "flatmorph: warning: {}\n", warning);
  }
  if (design.simulated && !design.simulation.converged) {
    fmt::print(stderr, "flatmorph: warning: the rise simulation did not converge: {}\n",
               design.simulation.warning);
  }
  if (o.json) fmt::print("{}\n", record.dump(2));
  if (silent) return 0;
  if (run.print) print_gcode_summary(*run.print, printer);
  for (size_t i = 0; i < design.tiles.size(); ++i) {
    const TileResult& tile = design.tiles[i];
    const TileMeasure& tm = tile.measure;
    fmt::print("tile {}: {} rings, shrink {:.1f}-{:.1f} %", i, tile.rings.rings.size(),
               100 * tile.levels.levels.back().shrinkage,
               100 * tile.levels.levels.front().shrinkage);
    if (design.simulated) {
      fmt::print(
          "; rises {} {:.2f} mm (geometrically {:.2f}), depth {:+.1f} %, profile rms "
          "{:.2f} mm",
          tm.side > 0 ? "up" : "down", tm.height_mm, tm.expected_height_mm, tm.depth_error_pct,
          tm.profile_rms_mm);
      if (tile.optimized) {
        fmt::print(" (optimized; {:.2f} with the circle's shrink)", tile.mapped_profile_rms_mm);
      }
      if (!tile.circular) fmt::print(", inscribed radii {:.2f} mm apart", tm.profile_spread_mm);
    }
    fmt::print("\n");
  }
  if (loop) {
    fmt::print(
        "as plate.gcode prints it: {:.3f} % / {:.3f} % (avg / max of the diagonal) from the "
        "shape the layer stack gives\n",
        loop->to_prediction.mean_percent, loop->to_prediction.max_percent);
  }
  fmt::print(
      "design time {:.2f} s (rings {:.2f}, mesh {:.2f}, paths {:.2f}, simulate {:.2f}, "
      "optimize {:.2f})\n",
      design.times.total, design.times.rings, design.times.mesh, design.times.paths,
      design.times.simulation, design.times.optimization);
  fmt::print("wrote {}: flat.ply{}{}{}, design.json, report.html\n", o.output,
             design.simulated ? ", simulated.ply, profile_N.svg" : "",
             loop ? ", gcode_simulated.ply" : "",
             run.print ? ", plate.gcode, toolpath.json, layers/" : "");
  return 0;
}

}  // namespace

Command make_tiles_command(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<TilesCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "tiles",
      "Self-rising tiles (Geodesy, CHI 2019): each tile printed as nested rings offset from its "
      "outline, each ring at the layer height that shrinks it as its place in the profile "
      "needs, so that the flat tile rises into a surface of revolution in hot water; a bilayer "
      "picks the side. Writes DIR/flat.ply (per-face tile, ring level, shrinkage, direction), "
      "DIR/simulated.ply, DIR/plate.gcode, DIR/layers/, DIR/profile_N.svg (asked, printed and "
      "simulated profile per tile), DIR/design.json and DIR/report.html. docs/tiles.md explains "
      "each step.");
  sub->add_option("input", o->input,
                  "A layout (.json, docs/tiles.md) or a drawing whose closed outlines are the "
                  "tiles (.dxf: LWPOLYLINE, POLYLINE, LINE/ARC chains, CIRCLE; .svg: polygon, "
                  "polyline, rect, circle, path with lines and arcs)");
  sub->add_option("--example", o->example,
                  "A built-in layout instead of a file: dome, spin-top, coaster or bracelet");
  sub->add_option("--profile", o->profile,
                  "Every tile's side profile: spherical-cap, cone, paraboloid, gaussian, concave, "
                  "transition, subtle-cone, dramatic-cone");
  sub->add_option("--profile-csv", o->profile_csv,
                  "Every tile's side profile from a CSV of r,z rows in mm (from the apex on the "
                  "axis to the rim)");
  sub->add_option("--height", o->height_mm, "Every tile's height above its rim, mm");
  sub->add_option("--side", o->side, "Every tile rises up (away from the bed) or down");
  sub->add_option("--hole", o->hole_mm, "Every tile's hole radius, mm (0: none)");
  sub->add_option("--material", o->material,
                  "Material preset or JSON file with a thickness curve (see 'flatmorph materials')")
      ->capture_default_str();
  sub->add_option("--lattice-material", o->lattice_material,
                  "Material of the lattice between tiles (default: the tiles'; another one prints "
                  "with a second tool, e.g. tpu-generic on a two-tool printer)");
  sub->add_option("--printer", o->printer, "Printer preset or JSON file (see 'flatmorph printers')")
      ->capture_default_str();
  sub->add_option("--pitch", o->pitch_mm,
                  "Path width and ring spacing, mm (0: the printer's nozzle)")
      ->capture_default_str();
  sub->add_option("--thickness", o->thickness_mm,
                  "Printed sheet thickness, mm: each ring prints Floor(thickness / t) layers of "
                  "its height t")
      ->capture_default_str();
  sub->add_option("--bilayer", o->bilayer,
                  "Shrink difference between the bed-side and top halves that makes a tile rise "
                  "to its side (a fraction; 0: per ring, the one that bends the ring as the "
                  "risen surface bends)")
      ->capture_default_str();
  sub->add_flag("--strict", o->strict,
                "Refuse a profile that needs a ring outside the material's shrink range instead "
                "of clamping it");
  sub->add_option("--mesh-edge", o->mesh_edge_mm,
                  "Longest edge of the simulator's mesh, mm (0: 1 mm, longer on large sheets to "
                  "keep to about 8000 faces)")
      ->capture_default_str();
  sub->add_flag("!--no-optimize", o->optimize,
                "Print a polygonal tile with the circle's shrink per ring (the paper's mapping) "
                "without refining it against the simulated profile");
  sub->add_flag("!--no-gcode", o->gcode, "Skip the G-code");
  sub->add_flag("--json", o->json, "Print design.json on stdout at the end instead of the summary");
  sub->add_option("-o,--output", o->output, "Output folder (created if needed)")->required();
  return {sub, [o, &global] { return run_tiles(*o, global); }};
}

}  // namespace flatmorph::cli
