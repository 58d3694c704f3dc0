// The self-rising tiles' steps of a run (method_steps.h, docs/tiles.md): the layout from a file or
// an example with the options' overrides, the sheet designed and simulated, its rings printed as
// the method traced them, the loop closed against the shape the layer stack gives (a network of
// tiles has no target surface as a whole: it bends at its joints), and a profile plot per tile.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "examples/example_catalog.h"
#include "examples/tile_examples.h"
#include "methods/tiles/profile_plot.h"
#include "run/method_steps.h"

namespace flatmorph {
namespace {

void check_options(const TilesRunOptions& o, const RunInput& input) {
  require_option(input.path.empty() != input.example.empty(),
                 input.path.empty()
                     ? fmt::format("flatmorph tiles needs tiles: a layout (.json), a drawing "
                                   "(.dxf, .svg) or --example NAME ({})",
                                   fmt::join(example_names("tiles"), ", "))
                     : "give either a file or --example, not both");
  require_option(o.profile.empty() || o.profile_csv.empty(),
                 "give --profile or --profile-csv, not both");
  require_option(o.height_mm >= 0 && std::isfinite(o.height_mm),
                 fmt::format("--height {}: give a positive number of mm", o.height_mm));
  require_option(o.side.empty() || o.side == "up" || o.side == "down",
                 fmt::format("--side {}: give up (away from the bed) or down", o.side));
  require_option(o.hole_mm == -1 || (o.hole_mm >= 0 && std::isfinite(o.hole_mm)),
                 fmt::format("--hole {}: give a radius in mm (0: none)", o.hole_mm));
  require_option(
      o.pitch_mm >= 0 && o.pitch_mm <= 2,
      fmt::format("--pitch {}: give the path width in mm (0: the printer's nozzle)", o.pitch_mm));
  require_option(o.thickness_mm > 0 && o.thickness_mm <= 5,
                 fmt::format("--thickness {}: give the sheet's printed thickness in mm (0.6 in "
                             "the paper)",
                             o.thickness_mm));
  require_option(o.bilayer >= 0 && o.bilayer < 0.3,
                 fmt::format("--bilayer {}: give the shrink difference between the halves as a "
                             "fraction (0.04 = 4 points), or 0 to match each ring's curvature",
                             o.bilayer));
  require_option(
      o.mesh_edge_mm == 0 || (o.mesh_edge_mm >= 0.2 && o.mesh_edge_mm <= 10),
      fmt::format("--mesh-edge {}: give 0.2 to 10 mm, or 0 for automatic", o.mesh_edge_mm));
}

TileLayout load_layout(const RunInput& input, const TilesRunOptions& o) {
  TileLayout layout = input.example.empty() ? load_tile_layout(input.path, TileSpec{})
                                            : tile_layout_example(input.example);
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

// Per tile its settings and, simulated, how it rose; with a profile plot per simulated tile.
nlohmann::ordered_json tiles_json(const TilesState& state, std::vector<RunFile>& files) {
  const TilesDesign& design = state.design;
  nlohmann::ordered_json tiles = nlohmann::ordered_json::array();
  for (size_t i = 0; i < design.tiles.size(); ++i) {
    const TileResult& tile = design.tiles[i];
    const TileSpec& spec = state.layout.tiles[i];
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
  return tiles;
}

nlohmann::ordered_json tiles_metrics(const TilesState& state, const PrintOutcome& print) {
  const TilesDesign& design = state.design;
  nlohmann::ordered_json m;
  m["tiles"] = design.tiles.size();
  m["faces"] = design.plate.design.F.rows();
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
      sides_right = sides_right && tm.side == state.layout.tiles[i].side;
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
  if (!print.plans.empty()) {
    const PrintPlan& plan = print.plans.front();
    m["print_time_s"] = plan.gcode.print_time;
    m["print_time_min"] = plan.gcode.print_time / 60;
    m["filament_mm"] = plan.gcode.filament_length;
    m["filament_g"] = plan.gcode.filament_mass;
    m["path_length_mm"] = design.print.path_length;
  }
  if (print.loop) {
    m["gcode_vs_fields_avg_pct"] = print.loop->to_prediction.mean_percent;
    m["gcode_vs_fields_max_pct"] = print.loop->to_prediction.max_percent;
    m["gcode_converged"] = print.loop->prediction.result.converged;
    m["gcode_unprinted_faces"] = print.loop->prediction.plate.removed_faces;
    m["t_gcode_sim_s"] = print.loop_seconds;
  }
  if (design.simulated) m["sim_stop_reason"] = stop_reason(design.simulation);
  if (print.loop) m["gcode_sim_stop_reason"] = stop_reason(print.loop->prediction.result);
  return m;
}

std::vector<std::string> tiles_summary(const TilesDesign& design, const PrintOutcome& print) {
  std::vector<std::string> lines;
  for (size_t i = 0; i < design.tiles.size(); ++i) {
    const TileResult& tile = design.tiles[i];
    const TileMeasure& tm = tile.measure;
    std::string line = fmt::format(
        "tile {}: {} rings, shrink {:.1f}-{:.1f} %", i, tile.rings.rings.size(),
        100 * tile.levels.levels.back().shrinkage, 100 * tile.levels.levels.front().shrinkage);
    if (design.simulated) {
      line += fmt::format(
          "; rises {} {:.2f} mm (geometrically {:.2f}), depth {:+.1f} %, profile rms "
          "{:.2f} mm",
          tm.side > 0 ? "up" : "down", tm.height_mm, tm.expected_height_mm, tm.depth_error_pct,
          tm.profile_rms_mm);
      if (tile.optimized) {
        line += fmt::format(" (optimized; {:.2f} with the circle's shrink)",
                            tile.mapped_profile_rms_mm);
      }
      if (!tile.circular) {
        line += fmt::format(", inscribed radii {:.2f} mm apart", tm.profile_spread_mm);
      }
    }
    lines.push_back(line);
  }
  if (print.loop) {
    lines.push_back(fmt::format(
        "as plate.gcode prints it: {:.3f} % / {:.3f} % (avg / max of the diagonal) from the "
        "shape the layer stack gives",
        print.loop->to_prediction.mean_percent, print.loop->to_prediction.max_percent));
  }
  lines.push_back(
      fmt::format("design time {:.2f} s (rings {:.2f}, mesh {:.2f}, paths {:.2f}, simulate {:.2f}, "
                  "optimize {:.2f})",
                  design.times.total, design.times.rings, design.times.mesh, design.times.paths,
                  design.times.simulation, design.times.optimization));
  return lines;
}

}  // namespace

TilesSetup prepare_run(const RunRequest& request, const TilesRunOptions& options) {
  check_options(options, request.input);
  TilesSetup setup;
  setup.input = request.input;
  setup.options = options;
  setup.gcode = request.gcode;
  setup.material = load_material(options.material);
  setup.printer = load_printer(options.printer);
  return setup;
}

TilesState design_run(const TilesSetup& setup, const ProgressCallback& progress) {
  const TilesRunOptions& o = setup.options;
  TilesState state;
  state.layout = load_layout(setup.input, o);
  TilesDesignOptions& options = state.design_options;
  options.material = setup.material;
  options.lattice_material =
      o.lattice_material.empty() ? setup.material : load_material(o.lattice_material);
  options.levels.pitch = o.pitch_mm > 0 ? o.pitch_mm : setup.printer.nozzle_diameter;
  options.levels.sheet_thickness = o.thickness_mm;
  options.levels.bilayer_difference = o.bilayer;
  options.levels.strict = o.strict;
  options.mesh_edge = o.mesh_edge_mm;
  options.optimize = o.optimize;
  options.progress = progress;
  state.design = design_tiles(state.layout, options);
  const TilesDesign& design = state.design;
  const PlateDesign& plate = design.plate.design;

  MethodDesign& run = state.run;
  run.plate = plate;
  if (design.simulated) run.predicted = Mesh{design.simulation.V, plate.F};
  if (!setup.gcode) return state;
  run.beds.push_back({design.print.toolpath, plate.F, plate.stack.materials, design.times.paths});
  if (!design.simulated) return state;
  // What plate.gcode deposits, simulated from the same start, against the shape the layer stack
  // gives. A lattice's lines cover only their share of a face in each layer (w / spacing): a face
  // they cross is printed, as the layer stack has it.
  std::vector<TileLevels> levels;
  for (const TileResult& tile : design.tiles) levels.push_back(tile.levels);
  LoopClosure& loop = run.loop.emplace();
  loop.materials = plate.stack.materials;
  loop.start = tile_start(design.plate, levels);
  loop.target = design.simulation.V;
  loop.fields_prediction = design.simulation.V;
  if (state.layout.has_lattice) {
    loop.deposit.min_coverage = std::min(loop.deposit.min_coverage, 0.5 * design.lattice.fill);
  }
  loop.what = "sheet";
  return state;
}

MethodReport report_run(const TilesSetup& setup, const TilesState& state, const PrintOutcome& print,
                        const ProgressCallback&) {
  const TilesDesign& design = state.design;
  MethodReport report;
  nlohmann::ordered_json tiles = tiles_json(state, report.files);
  nlohmann::ordered_json& j = report.parameters;
  j["input"] = describe(setup.input);
  j["pitch_mm"] = state.design_options.levels.pitch;
  j["sheet_thickness_mm"] = state.design_options.levels.sheet_thickness;
  j["bilayer_difference"] = state.design_options.levels.bilayer_difference;
  j["mesh_edge_mm"] = design.mesh_edge;
  j["material"] = setup.material.name;
  j["printer"] = setup.printer.name;
  j["tiles"] = tiles;
  // The report shows the profiles (report/run_folder.h).
  if (const std::vector<std::string> drawings = drawing_names(report.files, "profile_");
      !drawings.empty()) {
    j["drawings"] = drawings;
  }
  if (!design.warnings.empty()) j["warnings"] = design.warnings;
  report.metrics = tiles_metrics(state, print);
  report.warnings = design.warnings;
  if (design.simulated && !design.simulation.converged) {
    report.warnings.push_back("the rise simulation did not converge: " + design.simulation.warning);
  }
  report.summary = tiles_summary(design, print);
  report.written = fmt::format("flat.ply{}{}{}, design.json, report.html",
                               design.simulated ? ", simulated.ply, profile_N.svg" : "",
                               print.loop ? ", gcode_simulated.ply" : "",
                               print.plans.empty() ? "" : ", plate.gcode, toolpath.json, layers/");
  return report;
}

}  // namespace flatmorph
