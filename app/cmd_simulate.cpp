// flatmorph simulate: predict the shape a printed plate takes in hot water.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <vector>

#include "commands.h"
#include "common/angles.h"
#include "common/error.h"
#include "gcode/printer_profile.h"
#include "gcode_input.h"
#include "material/material.h"
#include "mesh/io.h"
#include "mesh/operators.h"
#include "mesh/validate.h"
#include "output_folder.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "plate/plate_design.h"
#include "plate_input.h"
#include "run/gcode_prediction.h"
#include "run/run_folder.h"
#include "simulate/distance.h"
#include "simulate/simulate.h"
#include "simulate/surface_fit.h"

namespace flatmorph::cli {
namespace {

struct SimulateOptions {
  std::string plate_path;
  PlateInputOptions plate_input;
  // G-code input only.
  std::optional<std::string> printer;
  std::optional<std::string> plate_mesh;
  double resolution_mm = 1.0;
  double min_cover = DepositedPlateOptions{}.min_coverage;
  std::string from = "flat";
  std::string target_path;
  double max_seconds = SimulationOptions{}.max_seconds;
  bool json = false;
  std::string output;
};

Eigen::MatrixXd read_shape(const std::string& path, const PlateDesign& plate, const char* role) {
  MeshFile file = read_mesh(path);
  if (file.mesh.num_vertices() != plate.plate.rows() || file.mesh.F != plate.F) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: the {} must have the plate's vertices and faces in the same "
                                "order ({} vertices, {} faces); use the target.ply written next "
                                "to flat.ply",
                                path, role, plate.plate.rows(), plate.F.rows()));
  }
  return file.mesh.V;
}

// A shape with the vertices and faces of `plate` (as read_shape, for a plate mesh).
Eigen::MatrixXd read_shape_of(const std::string& path, const Mesh& plate, const char* role) {
  MeshFile file = read_mesh(path);
  if (file.mesh.num_vertices() != plate.num_vertices() || file.mesh.F != plate.F) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: the {} must have the plate's vertices and faces in the same "
                                "order ({} vertices, {} faces); use the target.ply written next "
                                "to flat.ply",
                                path, role, plate.num_vertices(), plate.num_faces()));
  }
  return file.mesh.V;
}

// A target for a G-code simulated on its own footprint: any triangle mesh with finite
// coordinates and some area (closed, in pieces or with holes alike), compared by shape.
Mesh read_target_surface(const std::string& path) {
  Mesh mesh = read_mesh(path).mesh;
  for (const MeshProblem& problem : diagnose_mesh(mesh).problems) {
    if (problem.kind == MeshProblemKind::kEmpty || problem.kind == MeshProblemKind::kNotTriangles ||
        problem.kind == MeshProblemKind::kBadCoordinates ||
        problem.kind == MeshProblemKind::kMissingVertices) {
      throw UserError(problem.category, problem_line(path, problem));
    }
  }
  if (!(face_areas(mesh.V, mesh.F).sum() > 0)) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: the target has no face of positive area; give the target "
                                "surface as a triangle mesh (PLY, OBJ, STL, OFF)",
                                path));
  }
  return mesh;
}

void print_result(const char* label, const SimulationResult& r) {
  fmt::print(
      "{}: energy {:.6g} mJ (membrane {:.4g}, bending {:.4g}), {} Newton iterations ({} "
      "projected{}), {}, {:.2f} s\n",
      label, r.energy, r.membrane_energy, r.bending_energy, r.iterations, r.projected_iterations,
      r.stimulus_steps > 1 ? fmt::format(", the stimulus in {} steps", r.stimulus_steps) : "",
      to_string(r.status), r.seconds);
}

// The warning a simulation that did not converge gets on stderr (its best state is still written).
void warn_unless_converged(const SimulationResult& r) {
  if (!r.converged) fmt::print(stderr, "flatmorph: warning: simulation: {}\n", stop_reason(r));
}

SimulationOptions simulation_options(const SimulateOptions& o) {
  if (!(o.max_seconds > 0)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--max-seconds {}: give the wall-clock seconds the simulation may "
                                "take, a positive number (default {})",
                                o.max_seconds, SimulationOptions{}.max_seconds));
  }
  SimulationOptions options;
  options.max_seconds = o.max_seconds;
  return options;
}

bool is_gcode_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".gcode" || ext == ".gco" || ext == ".g" || ext == ".nc" || ext == ".bgcode";
}

// ", N faces the file does not print left out", ", M faces in loose pieces left out ...", or
// nothing: what of the plate mesh the simulation leaves out, and why.
std::string left_out(const DepositedPlate& plate, bool given_mesh, Eigen::Index kept) {
  std::string said;
  const int unprinted = plate.removed_faces - plate.loose_faces;
  if (unprinted > 0) {
    said +=
        fmt::format(", {} faces the file does not print left out{}", unprinted,
                    given_mesh && unprinted > kept ? " (a sparse lattice? lower --min-cover)" : "");
  }
  if (plate.loose_faces > 0) {
    said += fmt::format(
        ", {} faces in pieces apart from the largest left out (they would float free){}",
        plate.loose_faces,
        given_mesh ? ": the plate mesh is in several pieces; leave out --plate to mesh the file's "
                     "footprint as one"
                   : "");
  }
  return said;
}

// The materials of the file's tools: --material A[,B] when given, else those its header names
// (flatmorph's own files do), else the paper's PLA.
std::vector<Material> tool_materials(const SimulateOptions& o, const GcodeHeaderInfo& header,
                                     std::string& said) {
  if (o.plate_input.material) {
    said = "--material";
    return load_tool_materials(*o.plate_input.material);
  }
  std::vector<Material> materials = header_tool_materials(header, o.plate_path);
  if (!materials.empty()) {
    const bool models = std::any_of(header.tool_shrink.begin(), header.tool_shrink.end(),
                                    [](const auto& m) { return m.has_value(); });
    said = models ? "the file's header, with the shrink ratios and curves it was designed with"
                  : "the file's header";
    return materials;
  }
  said = "no material named in the file: pla-paper (give --material A[,B])";
  return {load_material("pla-paper")};
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw UserError(ErrorCategory::kFile, fmt::format("{}: cannot open it; check the path", path));
  }
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.rfind("GCDE", 0) == 0) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: binary G-code (bgcode) is not read; export plain text "
                                "G-code from the slicer",
                                path));
  }
  return text;
}

// flatmorph simulate FILE.gcode: the shape the printed file makes, and a run folder beside the
// predicted shape (OUT.ply -> OUT/) that `flatmorph report` shows.
int run_simulate_gcode(const SimulateOptions& o, const SimulationOptions& simulation,
                       const GlobalOptions& global) {
  if (o.plate_input.layers) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: --layers does not apply to G-code: its layers are those it "
                                "prints",
                                o.plate_path));
  }
  if (o.from != "flat") {
    throw UserError(ErrorCategory::kOption,
                    "--from applies to a flat.ply; a G-code's plate is simulated from flat");
  }
  if (!(o.resolution_mm > 0) || !std::isfinite(o.resolution_mm)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--resolution {}: give the plate mesh's edge length in mm (e.g. 1)",
                                o.resolution_mm));
  }
  if (!(o.min_cover > 0 && o.min_cover <= 1)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--min-cover {}: give the share of a face, in (0, 1], a layer's "
                                "beads must cover for the layer to count there (e.g. 0.25; a "
                                "lattice of lines w wide every s mm: w / (2 s))",
                                o.min_cover));
  }
  const std::filesystem::path run_dir = std::filesystem::path(o.output).replace_extension();
  require_run_folder_destination(run_dir);
  // The folder of the outputs, made before minutes of work rather than failing after them.
  create_output_folder(run_dir.parent_path());
  GcodePredictionOptions options;
  if (o.printer) {
    const PrinterProfile printer = load_printer(*o.printer);
    options.read.filament_diameter = printer.filament_diameter;
  }
  options.deposit.resolution_mm = o.resolution_mm;
  options.deposit.min_coverage = o.min_cover;
  options.simulation = simulation;
  Mesh plate_mesh;
  if (o.plate_mesh) {
    plate_mesh = read_mesh(*o.plate_mesh).mesh;
    if (plate_mesh.V.cols() == 3 && plate_mesh.V.col(2).cwiseAbs().maxCoeff() > 1e-6) {
      throw UserError(ErrorCategory::kGeometry,
                      fmt::format("{}: the plate must be flat (z = 0): give the flat.ply of the "
                                  "design the G-code was printed from",
                                  *o.plate_mesh));
    }
    options.plate_V = plate_mesh.V.leftCols(2);
    options.plate_F = plate_mesh.F;
  }
  // Without the plate it was designed on, the target is compared by shape: read and checked
  // before minutes of work rather than after them.
  std::optional<Mesh> target_surface;
  if (!o.target_path.empty() && !o.plate_mesh) target_surface = read_target_surface(o.target_path);
  const std::string text = read_text(o.plate_path);
  // A file cut short (a copy or an upload that stopped) ends in the middle of a line, before the
  // end G-code turns the motors off: predicting half a print would be a silent wrong answer.
  if (!text.empty() && text.back() != '\n') {
    const std::string_view tail =
        std::string_view(text).substr(text.size() - std::min<size_t>(text.size(), 4096));
    if (tail.find("M84") == std::string_view::npos && tail.find("M18") == std::string_view::npos) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: the file ends in the middle of a line, before its end "
                                  "G-code: it looks cut short; copy or export it again",
                                  o.plate_path));
    }
  }
  const GcodeHeaderInfo header = read_gcode_header(text);
  std::string materials_from;
  const std::vector<Material> materials = tool_materials(o, header, materials_from);
  const GcodePrediction p = predict_from_gcode(text, o.plate_path, materials, options);
  const PlateDesign& plate = p.plate.design;
  const bool silent = global.quiet || o.json;
  if (!silent) {
    fmt::print(
        "read {}: {} beads in {:.2f} s; plate: {} ({} vertices, {} faces{}), {}; "
        "materials from {}\n",
        o.plate_path, p.num_beads, p.read_seconds,
        o.plate_mesh ? *o.plate_mesh
                     : fmt::format("the first layer's footprint at {} mm on the part's axes "
                                   "({:.1f}° from the bed's x)",
                                   o.resolution_mm, p.footprint_frame.angle * kDegreesPerRadian),
        plate.plate.rows(), plate.F.rows(),
        left_out(p.plate, o.plate_mesh.has_value(), plate.F.rows()), describe_stack(plate.stack),
        materials_from);
    if (o.plate_mesh) {
      fmt::print("placed at bed = plate + ({:.3f}, {:.3f}) mm ({})\n", p.plate_to_bed.x(),
                 p.plate_to_bed.y(),
                 p.placed_by_header ? "the file's plate_to_bed"
                                    : "bounding box centred on the first layer's");
    }
    print_result("from flat", p.result);
  }
  warn_unless_converged(p.result);
  RunOutputs run;
  run.method = "gcode";
  run.plate = plate;
  Eigen::MatrixXd predicted = p.result.V;
  nlohmann::ordered_json metrics;
  MeshProperties properties;
  if (target_surface) {
    const SurfaceFit fit =
        closest_point_rigid_fit(predicted, plate.F, target_surface->V, target_surface->F);
    const ShapeDistance& d = fit.distance;
    predicted = fit.aligned;
    properties.set_vertex("deviation_mm", d.per_vertex_mm);
    run.target = *target_surface;
    run.predicted_deviation_mm = d.per_vertex_mm;
    metrics["gcode_dist_avg_pct"] = d.mean_percent;
    metrics["gcode_dist_max_pct"] = d.max_percent;
    if (!silent) {
      fmt::print(
          "distance to target by shape (closest points on its surface after the best rigid fit, "
          "no vertex correspondence): average {:.3f} % / max {:.3f} % of the diagonal ({:.3f} / "
          "{:.3f} mm, diagonal {:.1f} mm)\n",
          d.mean_percent, d.max_percent, d.mean_mm, d.max_mm, d.diagonal_mm);
    }
  } else if (!o.target_path.empty()) {
    const Eigen::MatrixXd full_target = read_shape_of(o.target_path, plate_mesh, "target");
    const Eigen::MatrixXd target = full_target(p.plate.kept_vertices, Eigen::all);
    predicted = rigidly_aligned(predicted, target);
    const ShapeDistance d = shape_distance(predicted, target);
    properties.set_vertex("deviation_mm", d.per_vertex_mm);
    run.target = Mesh{target, plate.F};
    run.predicted_deviation_mm = d.per_vertex_mm;
    metrics["gcode_dist_avg_pct"] = d.mean_percent;
    metrics["gcode_dist_max_pct"] = d.max_percent;
    if (!silent) {
      fmt::print(
          "distance to target: average {:.3f} % / max {:.3f} % of the diagonal ({:.3f} / "
          "{:.3f} mm, diagonal {:.1f} mm)\n",
          d.mean_percent, d.max_percent, d.mean_mm, d.max_mm, d.diagonal_mm);
    }
  }
  run.predicted = Mesh{predicted, plate.F};
  metrics["faces"] = plate.F.rows();
  metrics["layers"] = plate.stack.num_layers();
  metrics["beads"] = p.num_beads;
  metrics["unprinted_faces"] = p.plate.removed_faces - p.plate.loose_faces;
  metrics["loose_faces"] = p.plate.loose_faces;
  metrics["newton_iterations"] = p.result.iterations;
  metrics["converged"] = p.result.converged;
  metrics["t_read_s"] = p.read_seconds;
  metrics["t_rasterize_s"] = p.rasterize_seconds;
  metrics["t_sim_s"] = p.result.seconds;
  metrics["sim_stop_reason"] = stop_reason(p.result);
  nlohmann::ordered_json parameters;
  parameters["input"] = o.plate_path;
  parameters["plate"] = o.plate_mesh ? *o.plate_mesh : std::string("footprint");
  parameters["resolution_mm"] = o.resolution_mm;
  parameters["min_cover"] = o.min_cover;
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  for (const Material& m : materials) names.push_back(m.name);
  parameters["materials"] = names;
  parameters["plate_to_bed_mm"] = {p.plate_to_bed.x(), p.plate_to_bed.y()};
  if (!o.target_path.empty()) {
    parameters["target"] = o.target_path;
    parameters["target_comparison"] =
        target_surface ? "shape: closest points on the target's surface after the best rigid fit"
                       : "vertices: the plate's, after the best rigid fit";
  }
  run.parameters = parameters;
  run.metrics = metrics;
  run.metric_list = run_metric_list(metrics);
  write_ply(o.output, Mesh{predicted, plate.F}, properties);
  write_run_folder(run_dir, run, nullptr);
  if (o.json) fmt::print("{}\n", run_record(run).dump(2));
  if (!silent) fmt::print("wrote {} and {}/\n", o.output, run_dir.string());
  return 0;
}

int run_simulate(const SimulateOptions& o, const GlobalOptions& global) {
  if (std::filesystem::path(o.output).extension() != ".ply") {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("-o {}: the predicted shape is written as PLY; name it *.ply", o.output));
  }
  const SimulationOptions simulation = simulation_options(o);
  if (is_gcode_path(o.plate_path)) return run_simulate_gcode(o, simulation, global);
  if (o.printer || o.plate_mesh) {
    throw UserError(ErrorCategory::kOption,
                    "--printer and --plate apply to a G-code file; a flat.ply is its own plate");
  }
  std::string stack_warning;
  const PlateDesign plate = load_plate_input(o.plate_path, o.plate_input, stack_warning);

  PlateProblem problem;
  problem.plate = plate.plate;
  problem.F = plate.F;
  problem.rest_forms = laminate(plate.stack);

  Eigen::MatrixXd target;
  if (!o.target_path.empty()) target = read_shape(o.target_path, plate, "target");
  Eigen::MatrixXd start;
  if (o.from != "flat") start = read_shape(o.from, plate, "start shape");

  const bool silent = global.quiet || o.json;
  if (!silent) {
    fmt::print("plate: {} ({} vertices, {} faces), {}\n", o.plate_path, plate.plate.rows(),
               plate.F.rows(), describe_stack(plate.stack));
  }
  nlohmann::ordered_json record;
  record["input"] = o.plate_path;
  record["from"] = o.from;
  if (!o.target_path.empty()) record["target"] = o.target_path;
  record["max_seconds"] = o.max_seconds;
  nlohmann::ordered_json metrics;
  metrics["faces"] = plate.F.rows();
  metrics["layers"] = plate.stack.num_layers();
  SimulationResult result;
  std::optional<ForwardComparison> both;
  // With a 3D start, both starts are simulated so that several stable shapes can be reported.
  if (start.size() > 0) {
    both = simulate_from_start_and_flat(problem, start, simulation);
    const ForwardComparison& c = *both;
    result = c.from_start;
    if (!silent) {
      print_result("from start", c.from_start);
      print_result("from flat ", c.from_flat);
    }
    if (c.multistable) {
      fmt::print(stderr,
                 "flatmorph: warning: the plate has several stable shapes: started flat it ends "
                 "{:.3g} mm ({:.2f} % of its size) away from the shape reached from {} (paper "
                 "§6); the printed plate may take either\n",
                 c.max_difference_mm, c.max_difference_percent, o.from);
    }
  } else {
    result = simulate(problem, flat_start(problem), simulation);
    if (!silent) print_result("from flat", result);
  }
  warn_unless_converged(result);
  metrics["energy_mj"] = result.energy;
  metrics["newton_iterations"] = result.iterations;
  metrics["projected_iterations"] = result.projected_iterations;
  metrics["stimulus_steps"] = result.stimulus_steps;
  metrics["converged"] = result.converged;

  MeshProperties properties;
  // A shape simulated from flat has no reason to sit where the target does: align it rigidly
  // before measuring (a 3D start keeps the result registered to that start).
  if (target.size() > 0 && start.size() == 0) result.V = rigidly_aligned(result.V, target);
  if (target.size() > 0) {
    const ShapeDistance d = shape_distance(result.V, target);
    properties.set_vertex("deviation_mm", d.per_vertex_mm);
    metrics["dist_avg_pct"] = d.mean_percent;
    metrics["dist_max_pct"] = d.max_percent;
    if (!silent) {
      fmt::print(
          "distance to target: average {:.3f} % / max {:.3f} % of the diagonal ({:.3f} / "
          "{:.3f} mm, diagonal {:.1f} mm)\n",
          d.mean_percent, d.max_percent, d.mean_mm, d.max_mm, d.diagonal_mm);
    }
  }
  if (both) {
    metrics["multistable"] = both->multistable;
    metrics["flat_sim_stop_reason"] = stop_reason(both->from_flat);
  }
  metrics["t_sim_s"] = result.seconds;
  metrics["sim_stop_reason"] = stop_reason(result);
  record["metrics"] = metrics;
  write_ply(o.output, Mesh{result.V, plate.F}, properties);
  if (!stack_warning.empty()) fmt::print(stderr, "flatmorph: warning: {}\n", stack_warning);
  if (o.json) fmt::print("{}\n", record.dump(2));
  if (!silent) fmt::print("wrote {}\n", o.output);
  return 0;
}

}  // namespace

Command make_simulate_command(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand(
      "simulate",
      "Predict the shape a printed plate takes in hot water: the equilibrium of the "
      "non-Euclidean plate energy (Shrink & Morph §3.1) of the laminate of the layers stored in "
      "flat.ply and its stack file flat.stack.json (layer count, thicknesses, materials, "
      "directions; docs/plate.md), or of what a G-code file deposits (any slicer's or "
      "flatmorph's: docs/gcode.md, \"From G-code to a plate\").");
  sub->add_option("plate", o->plate_path,
                  "flat.ply written by 'flatmorph flatten' or 'design', or a G-code file "
                  "(.gcode, .gco, .g, .nc)")
      ->required();
  sub->add_option("--printer", o->printer,
                  "G-code only: the printer the file was sliced for (its filament diameter turns "
                  "E into volume when the file does not say)");
  sub->add_option("--plate", o->plate_mesh,
                  "G-code only: the plate mesh the file was printed from (the design's flat.ply; "
                  "placed by the file's plate_to_bed, else centred on the first layer); default: "
                  "the first layer's footprint");
  sub->add_option("--resolution", o->resolution_mm,
                  "G-code only: edge length (mm) of the plate mesh built from the first layer's "
                  "footprint, a lattice on the part's own axes (its principal axes), so that the "
                  "prediction does not depend on where or at what angle it lies on the bed")
      ->capture_default_str();
  sub->add_option("--min-cover", o->min_cover,
                  "G-code only: the share of a face a layer's beads must cover for the layer to "
                  "count there (less is stray material); lower it for sparse prints, e.g. w / (2 "
                  "s) for a lattice of lines w wide every s mm")
      ->capture_default_str();
  add_plate_input_options(sub, o->plate_input);
  sub->add_option("--from", o->from,
                  "Start state: 'flat' (the plate with a tiny bump following its rest curvature: "
                  "the honest forward prediction) or a mesh with the plate's vertex order, e.g. "
                  "target.ply (also simulates from flat and warns if the two end differently)")
      ->capture_default_str();
  sub->add_option("--target", o->target_path,
                  "Target shape to measure the predicted shape against (adds the per-vertex "
                  "property deviation_mm and prints the distances; a shape simulated from flat is "
                  "first moved rigidly onto the target). For flat.ply or a G-code with --plate: "
                  "the target.ply with the plate's vertices, compared vertex by vertex; for a "
                  "G-code on its footprint: any triangle mesh, compared by shape (each vertex to "
                  "the nearest point of the target's surface after the best rigid fit)");
  sub->add_option("--max-seconds", o->max_seconds,
                  "Wall-clock seconds each simulation may take before it stops and writes the "
                  "best state it reached, saying so (a last resort: no plate should need it; a "
                  "run that reaches it is not reproducible byte for byte)")
      ->capture_default_str();
  sub->add_flag("--json", o->json,
                "Print a JSON object on stdout at the end (the inputs, then \"metrics\": "
                "iterations, energy, whether it converged and sim_stop_reason, why not) instead "
                "of the human-readable lines; for a G-code file, the run folder's design.json");
  sub->add_option("-o,--output", o->output,
                  "Predicted shape (.ply), same vertex and face order; for a G-code file also a "
                  "run folder of the same name without .ply (flatmorph report shows it)")
      ->required();
  return {sub, [o, &global] { return run_simulate(*o, global); }};
}

}  // namespace flatmorph::cli
