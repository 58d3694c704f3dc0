// The self-rising height fields' steps of a run (method_steps.h, docs/heightfield.md): the field
// read from a mesh, an image or an example, the sheet designed, its continuous paths printed as
// one object, the loop closed from the flat sheet, and the screen-print texture when the surface
// has colours.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/error.h"
#include "common/stopwatch.h"
#include "examples/example_catalog.h"
#include "examples/height_field_examples.h"
#include "mesh/io.h"
#include "methods/heightfield/gray_image.h"
#include "methods/heightfield/texture.h"
#include "run/method_steps.h"

namespace flatmorph {
namespace {

bool has_extension(const std::string& path, const char* extension) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == extension;
}

void check_options(const HeightFieldRunOptions& o, const RunInput& input) {
  require_option(input.path.empty() != input.example.empty(),
                 input.path.empty()
                     ? fmt::format("flatmorph heightfield needs a height field: a mesh file, a PNG "
                                   "(with --size and --height) or --example NAME ({})",
                                   fmt::join(example_names("heightfield"), ", "))
                     : "give either a file or --example, not both");
  const bool image = !input.path.empty() && has_extension(input.path, ".png");
  if (image) {
    require_option(!o.size_wxd.empty() && std::isfinite(o.height_mm),
                   fmt::format("{}: a height image needs --size WxD (its width and depth in mm, "
                               "e.g. --size 160x120) and --height H (the height of white, in mm)",
                               input.path));
  } else {
    require_option(o.size_wxd.empty(),
                   "--size is for a height image (PNG); a mesh has its own size");
  }
  if (!input.path.empty() && !image) {
    require_option(std::isnan(o.height_mm),
                   "--height is for a height image or an example; a mesh has its own height");
  }
  require_option(o.diameter_mm > 0 && std::isfinite(o.diameter_mm),
                 fmt::format("--diameter {}: give a positive number of mm", o.diameter_mm));
  require_option(std::isnan(o.height_mm) || (o.height_mm > 0 && std::isfinite(o.height_mm)),
                 fmt::format("--height {}: give a positive number of mm", o.height_mm));
  require_option(o.resolution_mm > 0 && std::isfinite(o.resolution_mm),
                 fmt::format("--resolution {}: give a positive number of mm", o.resolution_mm));
  require_option(o.checkerboard_mm >= 0 && std::isfinite(o.checkerboard_mm),
                 fmt::format("--checkerboard {}: give the side of a square in mm (0: none)",
                             o.checkerboard_mm));
  require_option(o.texture.empty() || o.checkerboard_mm == 0,
                 "--texture and --checkerboard both colour the surface: give one");
  require_option(o.level_spacing_mm >= 0 && std::isfinite(o.level_spacing_mm),
                 fmt::format("--level-spacing {}: give a positive number of mm, or 0 for "
                             "automatic",
                             o.level_spacing_mm));
  require_option(o.upsample_length_mm > 0 && std::isfinite(o.upsample_length_mm),
                 fmt::format("--lu {}: give a positive number of mm", o.upsample_length_mm));
  require_option(
      o.layers >= 0 && o.layers <= 100,
      fmt::format("--layers {}: give 1 to 100 layers, or 0 for the thickness curve's", o.layers));
  require_option(o.path_width_mm >= 0 && std::isfinite(o.path_width_mm),
                 fmt::format("--path-width {}: give a positive number of mm, or 0 for the "
                             "nozzle's",
                             o.path_width_mm));
  require_option(o.dpi > 0 && o.dpi <= 2400, fmt::format("--dpi {}: give 1 to 2400", o.dpi));
}

// "WxD" in mm.
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

HeightField load_height_field(const RunInput& input, const HeightFieldRunOptions& o) {
  if (!input.example.empty()) {
    HeightFieldExampleOptions options;
    options.diameter_mm = o.diameter_mm;
    options.height_mm = std::isnan(o.height_mm) ? kExampleFieldHeightMm : o.height_mm;
    return height_field_example(input.example, options);
  }
  const std::string& path = input.path;
  if (has_extension(path, ".png")) {
    const Eigen::Vector2d size = parse_size(o.size_wxd);
    return height_field_from_image(read_gray_png(path), size.x(), size.y(), o.height_mm,
                                   o.resolution_mm, path);
  }
  HeightField field = height_field_from_mesh(read_mesh(path).mesh, path);
  if (!o.texture.empty()) return with_texture(std::move(field), path, o.texture);
  // A PLY's vertex colours come with it.
  if (has_extension(path, ".ply")) {
    try {
      return with_texture(std::move(field), path);
    } catch (const UserError& e) {
      if (e.category() != ErrorCategory::kFormat) throw;
    }
    return height_field_from_mesh(read_mesh(path).mesh, path);
  }
  return field;
}

// A checkerboard of squares of side `square_mm` in the target's x and y (V: #V x 3, mm), to try the
// screen print's registration.
Eigen::MatrixXd checkerboard_colors(const Eigen::MatrixXd& V, double square_mm) {
  Eigen::MatrixXd colors(V.rows(), 3);
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const long long i = static_cast<long long>(std::floor(V(v, 0) / square_mm));
    const long long j = static_cast<long long>(std::floor(V(v, 1) / square_mm));
    colors.row(v).setConstant(((i + j) % 2 + 2) % 2 == 0 ? 0.1 : 0.9);
  }
  return colors;
}

nlohmann::ordered_json json_vector(const std::vector<int>& values) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (int v : values) j.push_back(v);
  return j;
}

nlohmann::ordered_json heightfield_parameters(const HeightFieldSetup& setup,
                                              const HeightFieldState& state) {
  const HeightFieldRunOptions& o = setup.options;
  const Material& material = setup.material;
  const HeightFieldDesign& design = state.design;
  nlohmann::ordered_json j;
  j["input"] = describe(setup.input);
  if (!setup.input.example.empty()) {
    j["diameter_mm"] = o.diameter_mm;
    j["height_mm"] = std::isnan(o.height_mm) ? kExampleFieldHeightMm : o.height_mm;
  }
  j["level_spacing_mm"] = o.level_spacing_mm;
  j["upsample_length_mm"] = o.upsample_length_mm;
  j["optimize"] = o.optimize;
  j["path_width_mm"] = state.design_options.path_options.path_width;
  j["material"] = {{"name", material.name},
                   {"lambda2", material.lambda2},
                   {"lambda3", material.lambda3},
                   {"min_layer_height", material.thickness_curve->min_layer_height},
                   {"max_layer_height", material.thickness_curve->max_layer_height}};
  j["printer"] = setup.printer.name;
  if (design.optimized) j["optim_stop_reason"] = design.optimization.stop_reason;
  j["flatten_stop_reason"] = design.sheet.stop_reason;
  return j;
}

nlohmann::ordered_json heightfield_metrics(const HeightFieldState& state,
                                           const PrintOutcome& print) {
  const HeightFieldDesign& design = state.design;
  const IsolineMesh& mesh = design.mesh;
  const RisePrediction& p = design.prediction;
  const RisePrediction& p0 = design.flattened_prediction;
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
  m["t_load_s"] = state.load_seconds;
  m["t_mesh_s"] = design.times.meshing;
  m["t_flatten_s"] = design.times.flattening;
  m["t_sim_s"] = design.times.prediction + design.times.final_prediction;
  m["t_optim_s"] = design.times.optimization;
  m["t_traj_s"] = design.times.paths;
  m["t_design_s"] = design.times.total;
  if (!print.plans.empty()) {
    const PrintPlan& plan = print.plans.front();
    const ClosedLoop& loop = *print.loop;
    const ContinuousPaths& cp = design.paths;
    m["traces"] = cp.num_traces;
    m["paths_per_hill"] = json_vector(cp.paths_per_hill);
    m["double_backs"] = cp.num_double_backs;
    m["saddle_patches"] = cp.num_saddle_patches;
    m["min_layer_height_mm"] = cp.min_layer_height;
    m["max_layer_height_mm"] = cp.max_layer_height;
    m["clamped_segments"] = cp.clamped_segments;
    m["path_length_mm"] = cp.path_length;
    m["print_time_s"] = plan.gcode.print_time;
    m["print_time_min"] = plan.gcode.print_time / 60;
    m["filament_mm"] = plan.gcode.filament_length;
    m["filament_g"] = plan.gcode.filament_mass;
    m["gcode_dist_avg_pct"] = loop.to_target.mean_percent;
    m["gcode_dist_max_pct"] = loop.to_target.max_percent;
    m["gcode_vs_fields_avg_pct"] = loop.to_prediction.mean_percent;
    m["gcode_vs_fields_max_pct"] = loop.to_prediction.max_percent;
    m["gcode_converged"] = loop.prediction.result.converged;
    m["t_gcode_sim_s"] = print.loop_seconds;
  }
  m["sim_stop_reason"] = stop_reason(p.from_flat);
  if (print.loop) m["gcode_sim_stop_reason"] = stop_reason(print.loop->prediction.result);
  return m;
}

std::vector<std::string> heightfield_warnings(const HeightFieldDesign& design) {
  std::vector<std::string> warnings;
  const RisePrediction& p = design.prediction;
  if (design.sheet.flipped_faces > 0 || !design.sheet.converged) {
    warnings.push_back("flatten: " + design.sheet.stop_reason);
  }
  if (design.sheet.invalid_edge_percent > 5) {
    warnings.push_back(fmt::format(
        "{:.1f} % of the paths need a shrink the material cannot print (the paper's designs have "
        "0.4-4.7 %): expect the risen shape to differ there; a lower or smoother height field "
        "helps",
        design.sheet.invalid_edge_percent));
  }
  if (!p.from_flat.converged) {
    warnings.push_back("the rise simulation did not converge: " + p.from_flat.warning);
  }
  if (p.has_from_target && !p.starts_agree) {
    warnings.push_back(fmt::format(
        "the sheet has another stable shape {:.2f} % of the diagonal away (simulated from the "
        "target): it may rise into either",
        p.starts_difference_percent));
  }
  if (p.side < 0) {
    warnings.push_back(
        "the simulated sheet rises toward the bed side; turn it over in the water (the sheet is "
        "the same on both sides)");
  }
  return warnings;
}

std::vector<std::string> heightfield_summary(const HeightFieldSetup& setup,
                                             const HeightFieldDesign& design,
                                             const PrintOutcome& print) {
  const IsolineMesh& mesh = design.mesh;
  const RisePrediction& p = design.prediction;
  const RisePrediction& p0 = design.flattened_prediction;
  std::vector<std::string> lines;
  lines.push_back(fmt::format(
      "printing graph: {} levels, {} loops, {} faces; invalid edges {:.2f} % (paths that would "
      "have to grow, or shrink more than the {:.1f} % the material gives)",
      mesh.levels.size(), mesh.loops.size(), mesh.F.rows(), design.sheet.invalid_edge_percent,
      100 * reachable_shrinkage(*setup.material.thickness_curve).second));
  lines.push_back(fmt::format(
      "risen shape: {:.3f} % / {:.3f} % (avg / max of the diagonal) from the target with the "
      "flattening's shrink, {:.3f} % / {:.3f} % ({:.2f} / {:.2f} mm) as designed",
      p0.distance.mean_percent, p0.distance.max_percent, p.distance.mean_percent,
      p.distance.max_percent, p.distance.mean_mm, p.distance.max_mm));
  if (print.loop) {
    lines.push_back(fmt::format(
        "as plate.gcode prints it: {:.3f} % / {:.3f} % from the target; {} trace(s) per layer, "
        "layer heights {:.3f}-{:.3f} mm",
        print.loop->to_target.mean_percent, print.loop->to_target.max_percent,
        design.paths.num_traces, design.paths.min_layer_height, design.paths.max_layer_height));
  }
  lines.push_back(fmt::format(
      "design time {:.2f} s (mesh {:.2f}, flatten {:.2f}, simulate {:.2f}, optimize {:.2f}, "
      "paths {:.2f})",
      design.times.total, design.times.meshing, design.times.flattening,
      design.times.prediction + design.times.final_prediction, design.times.optimization,
      design.times.paths));
  return lines;
}

}  // namespace

HeightFieldSetup prepare_run(const RunRequest& request, const HeightFieldRunOptions& options) {
  check_options(options, request.input);
  HeightFieldSetup setup;
  setup.input = request.input;
  setup.options = options;
  setup.gcode = request.gcode;
  setup.material = load_material(options.material);
  setup.printer = load_printer(options.printer);
  return setup;
}

HeightFieldState design_run(const HeightFieldSetup& setup, const ProgressCallback& progress) {
  const HeightFieldRunOptions& o = setup.options;
  HeightFieldState state;
  const auto start = Clock::now();
  state.field = load_height_field(setup.input, o);
  state.load_seconds = seconds_since(start);

  HeightFieldDesignOptions& options = state.design_options;
  options.material = setup.material;
  options.meshing.level_spacing_mm = o.level_spacing_mm;
  options.meshing.upsample_length_mm = o.upsample_length_mm;
  options.optimize = o.optimize;
  options.prediction.from_target = o.other_shapes;
  options.paths = setup.gcode;
  options.path_options.path_width =
      o.path_width_mm > 0 ? o.path_width_mm : setup.printer.nozzle_diameter;
  options.num_layers = o.layers;
  options.progress = progress;
  state.design = design_height_field(state.field, describe(setup.input), options);
  const HeightFieldDesign& design = state.design;
  const IsolineMesh& mesh = design.mesh;
  const PlateDesign& plate = design.plate.design;

  MethodDesign& run = state.run;
  run.plate = plate;
  run.target = Mesh{mesh.V, mesh.F};
  run.predicted = Mesh{design.prediction.aligned, mesh.F};
  run.predicted_deviation_mm = design.prediction.distance.per_vertex_mm;
  if (setup.gcode) {
    // The continuous paths as one object; what plate.gcode deposits, simulated from the flat
    // sheet as the design was.
    run.beds.push_back({design.paths.toolpath, plate.F, plate.stack.materials, design.times.paths});
    run.loop = LoopClosure{{setup.material},
                           biased_flat_start(plate.plate, options.prediction.bias),
                           mesh.V,
                           design.prediction.aligned,
                           {},
                           "sheet"};
  }
  return state;
}

MethodReport report_run(const HeightFieldSetup& setup, const HeightFieldState& state,
                        const PrintOutcome& print, const ProgressCallback&) {
  const HeightFieldRunOptions& o = setup.options;
  const HeightFieldDesign& design = state.design;
  const IsolineMesh& mesh = design.mesh;
  MethodReport report;
  report.parameters = heightfield_parameters(setup, state);
  report.metrics = heightfield_metrics(state, print);
  // The screen-print texture, when the surface has colours.
  const Eigen::MatrixXd colors =
      o.checkerboard_mm > 0           ? checkerboard_colors(mesh.V, o.checkerboard_mm)
      : state.field.colors.rows() > 0 ? colors_at(state.field, mesh.V.leftCols(2))
                                      : Eigen::MatrixXd();
  if (colors.rows() > 0) {
    ScreenPrintOptions texture_options;
    texture_options.dpi = o.dpi;
    const ScreenPrint texture =
        render_screen_print(design.plate.design.plate, mesh.V, mesh.F, colors, texture_options);
    const std::vector<unsigned char> png = screen_print_png(texture);
    report.files.push_back({"texture.png", std::string(png.begin(), png.end())});
    report.metrics["texture_dpi"] = texture.dpi;
    report.metrics["texture_width_px"] = texture.placement.width;
    report.metrics["texture_height_px"] = texture.placement.height;
    nlohmann::ordered_json marks = nlohmann::ordered_json::array();
    for (const Eigen::Vector2d& mark : texture.marks) marks.push_back({mark.x(), mark.y()});
    report.parameters["texture_marks_mm"] = marks;
  }
  report.warnings = heightfield_warnings(design);
  report.summary = heightfield_summary(setup, design, print);
  report.written = fmt::format("flat.ply, target.ply, simulated.ply, design.json{}{}, report.html",
                               print.plans.empty() ? "" : ", plate.gcode, toolpath.json, layers/",
                               colors.rows() > 0 ? ", texture.png" : "");
  return report;
}

}  // namespace flatmorph
