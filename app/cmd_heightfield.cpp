// flatmorph heightfield: the self-rising height-field method (SCF 2020) on a height field given as
// a mesh, a grayscale PNG or a built-in example: the printing graph, the flat sheet, its shrink per
// path (refined against the simulated risen shape), the continuous paths and their G-code, the
// screen-print texture, and a run folder like design's.
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "commands.h"
#include "common/error.h"
#include "examples/height_field_examples.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "mesh/io.h"
#include "methods/heightfield/design_height_field.h"
#include "methods/heightfield/gray_image.h"
#include "methods/heightfield/texture.h"
#include "print_summary.h"
#include "progress_display.h"
#include "run/gcode_prediction.h"
#include "run/print_plan.h"
#include "run/run_folder.h"

namespace flatmorph::cli {
namespace {

struct HeightFieldCliOptions {
  std::string input;    // a mesh file or a PNG
  std::string example;  // or a built-in height field
  double diameter_mm = 160.0;
  double height_mm = std::numeric_limits<double>::quiet_NaN();
  std::string size;  // WxD, mm, for an image
  double resolution_mm = 1.0;
  std::string texture;  // a PNG for an OBJ's texture coordinates
  double checkerboard_mm = 0;
  std::string material = "pla-geodesy";
  std::string printer = "generic-marlin";
  double level_spacing_mm = 0;
  double upsample_length_mm = 2.0;
  int layers = 0;
  double path_width_mm = 0;
  bool optimize = true;
  bool other_shapes = false;
  double dpi = 300;
  bool gcode = true;
  bool json = false;
  std::string output;
};

constexpr double kExampleHeightMm = 35.0;

void require(bool ok, const std::string& message) {
  if (!ok) throw UserError(ErrorCategory::kOption, message);
}

bool is_png(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".png";
}

// Checked before anything is read or written, so that a bad value leaves no output behind.
void check(const HeightFieldCliOptions& o) {
  require(o.input.empty() != o.example.empty(),
          o.input.empty() ? "flatmorph heightfield needs a height field: a mesh file, a PNG "
                            "(with --size and --height) or --example NAME (hill, saddle, island, "
                            "ridge)"
                          : "give either a file or --example, not both");
  require(!o.output.empty(), "flatmorph heightfield needs an output folder: -o DIR");
  const bool image = !o.input.empty() && is_png(o.input);
  if (image) {
    require(!o.size.empty() && std::isfinite(o.height_mm),
            fmt::format("{}: a height image needs --size WxD (its width and depth in mm, e.g. "
                        "--size 160x120) and --height H (the height of white, in mm)",
                        o.input));
  } else {
    require(o.size.empty(), "--size is for a height image (PNG); a mesh has its own size");
  }
  if (!o.input.empty() && !image) {
    require(std::isnan(o.height_mm),
            "--height is for a height image or an example; a mesh has its own height");
  }
  require(o.diameter_mm > 0 && std::isfinite(o.diameter_mm),
          fmt::format("--diameter {}: give a positive number of mm", o.diameter_mm));
  require(std::isnan(o.height_mm) || (o.height_mm > 0 && std::isfinite(o.height_mm)),
          fmt::format("--height {}: give a positive number of mm", o.height_mm));
  require(o.resolution_mm > 0 && std::isfinite(o.resolution_mm),
          fmt::format("--resolution {}: give a positive number of mm", o.resolution_mm));
  require(o.checkerboard_mm >= 0 && std::isfinite(o.checkerboard_mm),
          fmt::format("--checkerboard {}: give the side of a square in mm (0: none)",
                      o.checkerboard_mm));
  require(o.texture.empty() || o.checkerboard_mm == 0,
          "--texture and --checkerboard both colour the surface: give one");
  require(o.level_spacing_mm >= 0 && std::isfinite(o.level_spacing_mm),
          fmt::format("--level-spacing {}: give a positive number of mm, or 0 for automatic",
                      o.level_spacing_mm));
  require(o.upsample_length_mm > 0 && std::isfinite(o.upsample_length_mm),
          fmt::format("--lu {}: give a positive number of mm", o.upsample_length_mm));
  require(
      o.layers >= 0 && o.layers <= 100,
      fmt::format("--layers {}: give 1 to 100 layers, or 0 for the thickness curve's", o.layers));
  require(o.path_width_mm >= 0 && std::isfinite(o.path_width_mm),
          fmt::format("--path-width {}: give a positive number of mm, or 0 for the nozzle's",
                      o.path_width_mm));
  require(o.dpi > 0 && o.dpi <= 2400, fmt::format("--dpi {}: give 1 to 2400", o.dpi));
}

Eigen::Vector2d parse_size(const std::string& size) {
  double w = 0, d = 0;
  char x = 0, extra = 0;
  if (std::sscanf(size.c_str(), "%lf%c%lf%c", &w, &x, &d, &extra) != 3 || (x != 'x' && x != 'X') ||
      !(w > 0) || !(d > 0) || !std::isfinite(w) || !std::isfinite(d)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--size {}: give the image's width and depth in mm as WxD, e.g. "
                                "--size 160x120",
                                size));
  }
  return {w, d};
}

std::string describe(const HeightFieldCliOptions& o) {
  return o.example.empty() ? o.input : "example " + o.example;
}

HeightField load_height_field(const HeightFieldCliOptions& o) {
  if (!o.example.empty()) {
    HeightFieldExampleOptions options;
    options.diameter_mm = o.diameter_mm;
    options.height_mm = std::isnan(o.height_mm) ? kExampleHeightMm : o.height_mm;
    return height_field_example(o.example, options);
  }
  if (is_png(o.input)) {
    const Eigen::Vector2d size = parse_size(o.size);
    return height_field_from_image(read_gray_png(o.input), size.x(), size.y(), o.height_mm,
                                   o.resolution_mm, o.input);
  }
  HeightField field = height_field_from_mesh(read_mesh(o.input).mesh, o.input);
  if (!o.texture.empty()) return with_texture(std::move(field), o.input, o.texture);
  // A PLY's vertex colours come with it.
  std::string ext = std::filesystem::path(o.input).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".ply") {
    try {
      return with_texture(std::move(field), o.input);
    } catch (const UserError& e) {
      if (e.category() != ErrorCategory::kFormat) throw;
    }
    return height_field_from_mesh(read_mesh(o.input).mesh, o.input);
  }
  return field;
}

// The colours of the printing graph's vertices: the field's, or a checkerboard of the target's xy.
Eigen::MatrixXd vertex_colors(const HeightField& field, const Eigen::MatrixXd& V,
                              double checkerboard_mm) {
  if (checkerboard_mm > 0) {
    Eigen::MatrixXd colors(V.rows(), 3);
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      const long long i = static_cast<long long>(std::floor(V(v, 0) / checkerboard_mm));
      const long long j = static_cast<long long>(std::floor(V(v, 1) / checkerboard_mm));
      colors.row(v).setConstant(((i + j) % 2 + 2) % 2 == 0 ? 0.1 : 0.9);
    }
    return colors;
  }
  if (field.colors.rows() == 0) return {};
  return colors_at(field, V.leftCols(2));
}

nlohmann::ordered_json json_vector(const std::vector<int>& values) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (int v : values) j.push_back(v);
  return j;
}

int run_heightfield(const HeightFieldCliOptions& o, const GlobalOptions& global) {
  check(o);
  const Material material = load_material(o.material);
  const PrinterProfile printer = load_printer(o.printer);
  require_run_folder_destination(o.output);
  const std::string source = describe(o);
  const bool silent = global.quiet || o.json;
  const ProgressCallback progress = make_progress_display(silent);

  const auto start = std::chrono::steady_clock::now();
  const HeightField field = load_height_field(o);
  const double load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  HeightFieldDesignOptions options;
  options.material = material;
  options.meshing.level_spacing_mm = o.level_spacing_mm;
  options.meshing.upsample_length_mm = o.upsample_length_mm;
  options.optimize = o.optimize;
  options.prediction.from_target = o.other_shapes;
  options.paths = o.gcode;
  options.path_options.path_width = o.path_width_mm > 0 ? o.path_width_mm : printer.nozzle_diameter;
  options.num_layers = o.layers;
  options.progress = progress;
  const HeightFieldDesign design = design_height_field(field, source, options);
  const IsolineMesh& mesh = design.mesh;
  const PlateDesign& plate = design.plate.design;

  // The print: the continuous paths as one object, checked and placed on the bed.
  std::optional<PrintPlan> plan;
  std::optional<ClosedLoop> loop;
  double loop_seconds = 0;
  if (o.gcode) {
    LayerPaths paths = traced_layer_paths(design.paths.toolpath);
    PrintFilesOptions print_options;
    plan = plan_toolpath_print(std::move(paths), plate.plate, plate.F, plate.stack.materials,
                               printer, print_options);
    plan->seconds += design.times.paths;
    // The loop closed: what plate.gcode deposits, simulated from the flat sheet as the design was.
    report_progress(progress, {"simulate", 0, 0, NAN, "the sheet as plate.gcode prints it"});
    const auto t = std::chrono::steady_clock::now();
    loop = close_the_loop(plan->gcode.text, "plate.gcode", plate.plate, plate.F, {material},
                          biased_flat_start(plate.plate, options.prediction.bias), mesh.V,
                          design.prediction.aligned);
    loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  }

  // The screen-print texture, when the surface has colours.
  std::vector<RunFile> files;
  const Eigen::MatrixXd colors = vertex_colors(field, mesh.V, o.checkerboard_mm);
  std::optional<ScreenPrint> texture;
  if (colors.rows() > 0) {
    ScreenPrintOptions texture_options;
    texture_options.dpi = o.dpi;
    texture = render_screen_print(plate.plate, mesh.V, mesh.F, colors, texture_options);
    const std::vector<unsigned char> png = screen_print_png(*texture);
    files.push_back({"texture.png", std::string(png.begin(), png.end())});
  }

  const RisePrediction& p = design.prediction;
  const RisePrediction& p0 = design.flattened_prediction;
  nlohmann::ordered_json j;
  j["input"] = source;
  if (!o.example.empty()) {
    j["diameter_mm"] = o.diameter_mm;
    j["height_mm"] = std::isnan(o.height_mm) ? kExampleHeightMm : o.height_mm;
  }
  j["level_spacing_mm"] = o.level_spacing_mm;
  j["upsample_length_mm"] = o.upsample_length_mm;
  j["optimize"] = o.optimize;
  j["path_width_mm"] = options.path_options.path_width;
  j["material"] = {{"name", material.name},
                   {"lambda2", material.lambda2},
                   {"lambda3", material.lambda3},
                   {"min_layer_height", material.thickness_curve->min_layer_height},
                   {"max_layer_height", material.thickness_curve->max_layer_height}};
  j["printer"] = printer.name;
  if (design.optimized) j["optim_stop_reason"] = design.optimization.stop_reason;
  j["flatten_stop_reason"] = design.sheet.stop_reason;

  nlohmann::ordered_json m;
  m["vertices"] = mesh.V.rows();
  m["faces"] = mesh.F.rows();
  m["levels"] = mesh.levels.size();
  m["loops"] = mesh.loops.size();
  m["invalid_edges_pct"] = design.sheet.invalid_edge_percent;
  m["flipped_faces"] = design.sheet.flipped_faces;
  m["flatten_steps"] = design.sheet.steps;
  m["clamped_faces"] = design.plate.num_clamped();
  m["dist_flattened_avg_pct"] = p0.distance.mean_percent;
  m["dist_flattened_max_pct"] = p0.distance.max_percent;
  m["dist_avg_pct"] = p.distance.mean_percent;
  m["dist_max_pct"] = p.distance.max_percent;
  m["dist_avg_mm"] = p.distance.mean_mm;
  m["dist_max_mm"] = p.distance.max_mm;
  m["rises_up"] = p.side > 0;
  m["rise_mm"] = p.rise_mm;
  if (p.has_from_target) {
    m["starts_agree"] = p.starts_agree;
    m["starts_difference_pct"] = p.starts_difference_percent;
  }
  m["sim_converged"] = p.from_flat.converged;
  if (design.optimized) {
    m["optim_iterations"] = design.optimization.iterations;
    m["optim_kept"] = design.vertex_shrinkage == design.optimization.vertex_shrinkage;
  }
  m["t_load_s"] = load_seconds;
  m["t_mesh_s"] = design.times.meshing;
  m["t_flatten_s"] = design.times.flattening;
  m["t_sim_s"] = design.times.prediction + design.times.final_prediction;
  m["t_optim_s"] = design.times.optimization;
  m["t_traj_s"] = design.times.paths;
  m["t_design_s"] = design.times.total;
  if (plan) {
    const ContinuousPaths& cp = design.paths;
    m["traces"] = cp.num_traces;
    m["paths_per_hill"] = json_vector(cp.paths_per_hill);
    m["double_backs"] = cp.num_double_backs;
    m["saddle_patches"] = cp.num_saddle_patches;
    m["min_layer_height_mm"] = cp.min_layer_height;
    m["max_layer_height_mm"] = cp.max_layer_height;
    m["clamped_segments"] = cp.clamped_segments;
    m["path_length_mm"] = cp.path_length;
    m["print_time_s"] = plan->gcode.print_time;
    m["print_time_min"] = plan->gcode.print_time / 60;
    m["filament_mm"] = plan->gcode.filament_length;
    m["filament_g"] = plan->gcode.filament_mass;
    m["gcode_dist_avg_pct"] = loop->to_target.mean_percent;
    m["gcode_dist_max_pct"] = loop->to_target.max_percent;
    m["gcode_vs_fields_avg_pct"] = loop->to_prediction.mean_percent;
    m["gcode_vs_fields_max_pct"] = loop->to_prediction.max_percent;
    m["gcode_converged"] = loop->prediction.result.converged;
    m["t_gcode_sim_s"] = loop_seconds;
  }
  if (texture) {
    m["texture_dpi"] = texture->dpi;
    m["texture_width_px"] = texture->placement.width;
    m["texture_height_px"] = texture->placement.height;
    nlohmann::ordered_json marks = nlohmann::ordered_json::array();
    for (const Eigen::Vector2d& mark : texture->marks) marks.push_back({mark.x(), mark.y()});
    j["texture_marks_mm"] = marks;
  }

  RunOutputs run;
  run.method = plate.method;
  run.plate = plate;
  run.target = Mesh{mesh.V, mesh.F};
  run.predicted = Mesh{p.aligned, mesh.F};
  run.predicted_deviation_mm = p.distance.per_vertex_mm;
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
  if (design.sheet.flipped_faces > 0 || !design.sheet.converged) {
    fmt::print(stderr, "flatmorph: warning: flatten: {}\n", design.sheet.stop_reason);
  }
  if (design.sheet.invalid_edge_percent > 5) {
    fmt::print(stderr,
               "flatmorph: warning: {:.1f} % of the paths need a shrink the material cannot "
               "print (the paper's designs have 0.4-4.7 %): expect the risen shape to differ "
               "there; a lower or smoother height field helps\n",
               design.sheet.invalid_edge_percent);
  }
  if (!p.from_flat.converged) {
    fmt::print(stderr, "flatmorph: warning: the rise simulation did not converge: {}\n",
               p.from_flat.warning);
  }
  if (p.has_from_target && !p.starts_agree) {
    fmt::print(stderr,
               "flatmorph: warning: the sheet has another stable shape {:.2f} % of the diagonal "
               "away (simulated from the target): it may rise into either\n",
               p.starts_difference_percent);
  }
  if (p.side < 0) {
    fmt::print(stderr,
               "flatmorph: warning: the simulated sheet rises toward the bed side; turn it over in "
               "the water (the sheet is the same on both sides)\n");
  }
  if (o.json) fmt::print("{}\n", record.dump(2));
  if (silent) return 0;
  if (run.print) print_gcode_summary(*run.print, printer);
  fmt::print(
      "printing graph: {} levels, {} loops, {} faces; invalid edges {:.2f} % (paths that would "
      "have to grow, or shrink more than the {:.1f} % the material gives)\n",
      mesh.levels.size(), mesh.loops.size(), mesh.F.rows(), design.sheet.invalid_edge_percent,
      100 * reachable_shrinkage(*material.thickness_curve).second);
  fmt::print(
      "risen shape: {:.3f} % / {:.3f} % (avg / max of the diagonal) from the target with the "
      "flattening's shrink, {:.3f} % / {:.3f} % ({:.2f} / {:.2f} mm) as designed\n",
      p0.distance.mean_percent, p0.distance.max_percent, p.distance.mean_percent,
      p.distance.max_percent, p.distance.mean_mm, p.distance.max_mm);
  if (loop) {
    fmt::print(
        "as plate.gcode prints it: {:.3f} % / {:.3f} % from the target; {} trace(s) per layer, "
        "layer heights {:.3f}-{:.3f} mm\n",
        loop->to_target.mean_percent, loop->to_target.max_percent, design.paths.num_traces,
        design.paths.min_layer_height, design.paths.max_layer_height);
  }
  fmt::print(
      "design time {:.2f} s (mesh {:.2f}, flatten {:.2f}, simulate {:.2f}, optimize {:.2f}, "
      "paths {:.2f})\n",
      design.times.total, design.times.meshing, design.times.flattening,
      design.times.prediction + design.times.final_prediction, design.times.optimization,
      design.times.paths);
  fmt::print("wrote {}: flat.ply, target.ply, simulated.ply, design.json{}{}, report.html\n",
             o.output, run.print ? ", plate.gcode, toolpath.json, layers/" : "",
             texture ? ", texture.png" : "");
  return 0;
}

}  // namespace

Command make_heightfield_command(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<HeightFieldCliOptions>();
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
      "input", o->input,
      "The height field: a mesh that is a graph z = h(x, y) in mm (OBJ, PLY, STL, OFF), "
      "or a grayscale PNG (black = 0, white = --height) with --size");
  sub->add_option("--example", o->example,
                  "A built-in height field instead of a file: hill, saddle, island or ridge");
  sub->add_option("--diameter", o->diameter_mm, "Diameter of an example, mm")
      ->capture_default_str();
  sub->add_option("--height", o->height_mm,
                  fmt::format("Height of an example (default {}) or of white in an image, mm",
                              kExampleHeightMm));
  sub->add_option("--size", o->size, "Width and depth an image covers, mm, as WxD (e.g. 160x120)");
  sub->add_option("--resolution", o->resolution_mm, "Grid spacing an image is resampled to, mm")
      ->capture_default_str();
  sub->add_option("--texture", o->texture,
                  "A PNG the OBJ's texture coordinates point into: the surface's colours, printed "
                  "as texture.png (a PLY's vertex colours are read without it)");
  sub->add_option("--checkerboard", o->checkerboard_mm,
                  "Colour the surface with a checkerboard of this square side (mm, in x and y) "
                  "to try the screen print's registration (0: none)")
      ->capture_default_str();
  sub->add_option("--material", o->material,
                  "Material preset or JSON file with a thickness curve (see 'flatmorph materials')")
      ->capture_default_str();
  sub->add_option("--printer", o->printer, "Printer preset or JSON file (see 'flatmorph printers')")
      ->capture_default_str();
  sub->add_option("--level-spacing", o->level_spacing_mm,
                  "Height between isolines, mm (0: a twelfth of the height)")
      ->capture_default_str();
  sub->add_option("--lu", o->upsample_length_mm,
                  "Longest printing edge of the printing graph, mm (the paper's l_u)")
      ->capture_default_str();
  sub->add_option("--layers", o->layers,
                  "Identical layers printed (0: as many as the thickness curve was calibrated "
                  "with; 6 for pla-geodesy)")
      ->capture_default_str();
  sub->add_option("--path-width", o->path_width_mm,
                  "Width of a path and distance between rows, mm (0: the printer's nozzle)")
      ->capture_default_str();
  sub->add_flag("!--no-optimize", o->optimize,
                "Print the flattening's shrink as the paper does, without refining it against the "
                "simulated shape");
  sub->add_flag("--other-shapes", o->other_shapes,
                "Also simulate the sheet from the target's shape and warn when it settles into "
                "another stable shape than the one it rises to from flat (costs as much as the "
                "prediction, or more)");
  sub->add_option("--dpi", o->dpi, "Resolution of texture.png (it prints at scale)")
      ->capture_default_str();
  sub->add_flag("!--no-gcode", o->gcode, "Skip the paths and the G-code");
  sub->add_flag("--json", o->json, "Print design.json on stdout at the end instead of the summary");
  sub->add_option("-o,--output", o->output, "Output folder (created if needed)")->required();
  return {sub, [o, &global] { return run_heightfield(*o, global); }};
}

}  // namespace flatmorph::cli
