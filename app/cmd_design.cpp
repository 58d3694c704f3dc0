// flatmorph design: the whole Shrink & Morph pipeline on one target (prepare, flatten, simulate
// with theta2 = 0, optimize theta2), writing the plate, the target, the predicted shape and a
// design.json with every parameter and the paper's Table 1 metrics.
#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.h"
#include "common/error.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "mesh/io.h"
#include "mesh_input.h"
#include "methods/shrink_morph/design.h"
#include "print_summary.h"
#include "progress_display.h"
#include "run/gcode_prediction.h"
#include "run/run_folder.h"

namespace flatmorph::cli {
namespace {

// Past this distance (average, % of the diagonal) between the shapes predicted from plate.gcode
// and from the fields, the design is not steady: the paths' small departures from the fields
// change its shape (issue 22's acceptance bar).
constexpr double kSteadyDesignPercent = 1.0;

constexpr int kMaxFaces = 2'000'000;
constexpr double kExampleWidthMm = 100.0;  // --width default for built-in examples

struct DesignCliOptions {
  MeshInput input;
  double width_mm = std::numeric_limits<double>::quiet_NaN();
  double w_D = 0.0;
  double w_M = 0.01;
  double w_L = 0.01;
  int faces = 10000;
  int layers = 10;
  std::string material = "pla-paper";
  std::string printer = "generic-marlin";
  std::string side = "auto";
  std::string stretch = "auto";
  bool gcode = true;
  bool json = false;
  std::string output;
};

void require(bool ok, const std::string& message) {
  if (!ok) throw UserError(ErrorCategory::kOption, message);
}

// --stretch: auto, all or an initial stretch index.
int parse_stretch(const std::string& stretch) {
  if (stretch == "auto") return kAutomaticStretch;
  if (stretch == "all") return kEveryStretch;
  for (int k = 0; k < kStretchCandidates; ++k) {
    if (stretch == std::to_string(k)) return k;
  }
  throw UserError(ErrorCategory::kOption,
                  fmt::format("--stretch {}: give auto, all or an initial stretch from 0 to {}",
                              stretch, kStretchCandidates - 1));
}

// Checked before anything is read or written, so that a bad value leaves no output behind.
void check(DesignCliOptions& o) {
  if (std::isnan(o.width_mm) && !o.input.example.empty()) o.width_mm = kExampleWidthMm;
  require(std::isfinite(o.width_mm) && o.width_mm > 0,
          std::isnan(o.width_mm)
              ? std::string("--width is needed for a mesh file: give the plate's largest extent "
                            "in mm (e.g. --width 150)")
              : fmt::format("--width {}: the plate width must be a positive number of mm (e.g. "
                            "--width 150)",
                            o.width_mm));
  require(std::isfinite(o.w_D) && o.w_D >= 0,
          fmt::format("--wD {}: the smoothing weight must be 0 (no smoothing) or positive (the "
                      "paper uses 0.1)",
                      o.w_D));
  require(std::isfinite(o.w_M) && o.w_M >= 0 && std::isfinite(o.w_L) && o.w_L >= 0,
          fmt::format("--wM {} / --wL {}: the theta2 regularization weights must be 0 or positive "
                      "(default 0.01)",
                      o.w_M, o.w_L));
  require(o.faces >= 1 && o.faces <= kMaxFaces,
          fmt::format("--faces {}: the face count must be between 1 and {}", o.faces, kMaxFaces));
  require(o.layers >= 2 && o.layers <= 1000,
          fmt::format("--layers {}: give 2 to 1000 layers (theta2 varies through them)", o.layers));
  require(!o.output.empty(), "flatmorph design needs an output folder: -o DIR");
}

PrintedSide parse_side(const std::string& side) {
  if (side == "auto") return PrintedSide::kAutomatic;
  if (side == "normal-up") return PrintedSide::kNormalUp;
  if (side == "normal-down") return PrintedSide::kNormalDown;
  throw UserError(ErrorCategory::kOption,
                  fmt::format("--side {}: give auto, normal-up or normal-down", side));
}

nlohmann::ordered_json metrics_json(const DesignMetrics& m) {
  nlohmann::ordered_json j;
  j["faces"] = m.faces;
  j["vertices"] = m.vertices;
  j["t_prepare_s"] = m.t_prepare_s;
  j["t_param_s"] = m.t_param_s;
  j["t_sim_s"] = m.t_sim_s;
  j["t_optim_s"] = m.t_optim_s;
  j["t_traj_s"] = m.t_traj_s;
  j["dist_to_sim_avg_pct"] = m.dist_to_sim_avg_pct;
  j["dist_to_sim_max_pct"] = m.dist_to_sim_max_pct;
  j["dist_to_optim_avg_pct"] = m.dist_to_optim_avg_pct;
  j["dist_to_optim_max_pct"] = m.dist_to_optim_max_pct;
  j["theta2_max_abs_rad"] = m.theta2_max_abs_rad;
  j["theta2_dirichlet"] = m.theta2_dirichlet;
  j["optim_iterations"] = m.optim_iterations;
  j["optim_objective"] = m.optim_objective;
  j["optim_converged"] = m.optim_converged;
  j["coarse_faces"] = m.coarse_faces;
  j["first_pass_iterations"] = m.first_pass_iterations;
  return j;
}

int run_design(DesignCliOptions& o, const GlobalOptions& global) {
  check(o);
  const PrintedSide side = parse_side(o.side);
  const int stretch = parse_stretch(o.stretch);
  const Material material = load_material(o.material);
  // A bad printer fails before any work.
  const PrinterProfile printer = load_printer(o.printer);
  // The plate's largest extent is --width: one larger than the bed cannot be printed, which is
  // better said before minutes of optimization (the exact check comes with the G-code).
  if (o.gcode && o.width_mm > printer.bed_size.maxCoeff()) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("--width {} mm: the plate would not fit the {} x {} mm bed of {}; "
                    "give a smaller --width, another --printer, or --no-gcode",
                    o.width_mm, printer.bed_size.x(), printer.bed_size.y(), printer.name));
  }
  const std::string source = describe(o.input);
  require_run_folder_destination(o.output);

  const auto start = std::chrono::steady_clock::now();
  Mesh mesh = load_mesh_input(o.input).mesh;
  const double load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  DesignOptions options;
  options.width_mm = o.width_mm;
  options.w_D = o.w_D;
  options.side = side;
  options.stretch_candidate = stretch;
  options.faces = o.faces;
  options.layers = o.layers;
  options.material = material;
  options.optimize.w_M = o.w_M;
  options.optimize.w_L = o.w_L;
  const bool silent = global.quiet || o.json;
  options.progress = make_progress_display(silent);
  Design design = design_shrink_morph(std::move(mesh), source, options);
  design.metrics.t_prepare_s += load_seconds;

  const PlateDesign plate =
      shrink_morph_plate_design(design.flat, design.theta2, material, o.layers);

  // Trajectories and G-code are planned (and a plate too large for the bed refused) before
  // anything is written.
  std::optional<PrintPlan> plan;
  double loop_seconds = 0;
  if (o.gcode) {
    PrintFilesOptions print_options;
    print_options.progress = options.progress;
    plan = plan_print(plate, printer, print_options);
    design.metrics.t_traj_s = plan->seconds;
  }
  // The loop closed: what plate.gcode deposits, simulated from the target as the fields were.
  std::optional<ClosedLoop> loop;
  if (plan) {
    report_progress(options.progress,
                    {"simulate", 0, 0, NAN, "the plate as plate.gcode prints it"});
    const auto t = std::chrono::steady_clock::now();
    loop = close_the_loop(plan->gcode.text, "plate.gcode", plate.plate, plate.F, {material},
                          design.flat.target.V, design.flat.target.V, design.optimized);
    loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  }

  nlohmann::ordered_json j;
  j["input"] = source;
  j["width_mm"] = o.width_mm;
  j["w_D"] = o.w_D;
  j["w_M"] = o.w_M;
  j["w_L"] = o.w_L;
  j["faces_requested"] = o.faces;
  j["layers"] = o.layers;
  j["layer_height_mm"] = material.layer_height;
  j["side"] = o.side;
  j["stretch"] = o.stretch;
  j["normal_side_down"] = design.flipped;
  j["side_agreement"] = design.side_agreement;
  j["stretch_candidate"] = design.flat.stretch_candidate;
  if (!design.explored.empty()) {
    nlohmann::ordered_json explored = nlohmann::ordered_json::array();
    for (const StretchOutcome& e : design.explored) {
      explored.push_back({{"stretch_candidate", e.stretch_candidate},
                          {"normal_side_down", e.flipped},
                          {"optim_objective", e.objective},
                          {"dist_to_optim_avg_pct", e.dist_to_optim_avg_pct},
                          {"dist_to_optim_max_pct", e.dist_to_optim_max_pct},
                          {"optim_iterations", e.optim_iterations}});
    }
    j["explored_stretches"] = explored;
  }
  j["material"] = {{"name", material.name},
                   {"lambda1", material.lambda1},
                   {"lambda2", material.lambda2},
                   {"lambda3", material.lambda3},
                   {"delta_lambda1", material.delta_lambda1},
                   {"young_modulus_along", material.young_modulus_along},
                   {"young_modulus_across", material.young_modulus_across},
                   {"poisson_ratio", material.poisson_ratio},
                   {"nozzle_temperature", material.nozzle_temperature}};
  j["printer"] = printer.name;
  j["optim_stop_reason"] = design.optimization.stop_reason;
  nlohmann::ordered_json metrics = metrics_json(design.metrics);
  metrics["infeasible_area_pct"] = 100 * design.flat.feasibility.infeasible_area_fraction;
  metrics["sv_deviation_mean_pct"] = 100 * design.flat.feasibility.mean_deviation;
  if (plan) {
    metrics["print_time_s"] = plan->gcode.print_time;
    metrics["filament_mm"] = plan->gcode.filament_length;
    metrics["filament_g"] = plan->gcode.filament_mass;
    // The shape plate.gcode makes (gcode_prediction.h: rigidly fitted, over the vertices it
    // prints) against the target and against the shape predicted from the design's fields.
    metrics["gcode_dist_avg_pct"] = loop->to_target.mean_percent;
    metrics["gcode_dist_max_pct"] = loop->to_target.max_percent;
    metrics["gcode_vs_fields_avg_pct"] = loop->to_prediction.mean_percent;
    metrics["gcode_vs_fields_max_pct"] = loop->to_prediction.max_percent;
    metrics["gcode_unprinted_faces"] = loop->prediction.plate.removed_faces;
    metrics["gcode_converged"] = loop->prediction.result.converged;
    metrics["t_gcode_sim_s"] = loop_seconds;
  }
  const std::filesystem::path dir = o.output;
  RunOutputs run;
  run.method = plate.method;
  run.plate = plate;
  run.target = design.flat.target;
  run.predicted = Mesh{design.optimized, plate.F};
  run.predicted_deviation_mm = design.dist_to_optim.per_vertex_mm;
  if (loop) {
    // Rigidly fitted to the target, as its distances are measured.
    run.gcode_predicted = Mesh{loop->on_target, loop->prediction.plate.design.F};
    run.gcode_predicted_deviation_mm = loop->to_target.per_vertex_mm;
  }
  run.print = std::move(plan);
  run.parameters = j;
  run.metrics = metrics;
  run.metric_list = run_metric_list(metrics);
  write_run_folder(dir, run, &printer, options.progress);
  const nlohmann::ordered_json record = run_record(run);
  const std::optional<PrintPlan>& plan_written = run.print;

  finish_progress_line();
  for (const std::string& warning : design.flat.warnings) {
    fmt::print(stderr, "flatmorph: warning: flatten: {}\n", warning);
  }
  if (design.flat.feasibility.infeasible_area_fraction > 0) {
    fmt::print(stderr,
               "flatmorph: warning: {:.1f} % of the target's area needs more shrink than the "
               "material gives (singular values more than 5 % from 1/lambda): expect larger "
               "deviations there; a smaller or less curved target, or a material that shrinks "
               "more (flatmorph calibrate), helps\n",
               100 * design.flat.feasibility.infeasible_area_fraction);
  }
  if (!design.optimization.initial_forward_converged) {
    fmt::print(stderr,
               "flatmorph: warning: the theta2 = 0 simulation did not converge; the design starts "
               "from the best state reached (a finer mesh, a smaller --width or another material "
               "usually helps)\n");
  }
  if (!design.optimization.converged) {
    // The reason says why and what to change, in one sentence.
    fmt::print(stderr, "flatmorph: warning: the theta2 optimization did not converge: {}\n",
               design.optimization.stop_reason);
  }
  if (loop && loop->to_prediction.mean_percent > kSteadyDesignPercent) {
    fmt::print(stderr,
               "flatmorph: warning: the shape plate.gcode prints lies {:.2f} % / {:.2f} % (avg / "
               "max of the diagonal) from the fields' prediction: the design sits at a fold of "
               "its equilibria, where paths a degree off make the plate snap to another shape; "
               "expect the G-code's shape ({:.2f} % / {:.2f} % from the target, "
               "gcode_simulated.ply) rather than simulated.ply. Another --stretch (or --stretch "
               "all) may give a steadier design\n",
               loop->to_prediction.mean_percent, loop->to_prediction.max_percent,
               loop->to_target.mean_percent, loop->to_target.max_percent);
  }
  if (o.json) fmt::print("{}\n", record.dump(2));
  if (silent) return 0;
  const DesignMetrics& m = design.metrics;
  if (plan_written) print_plan_summary(*plan_written, printer);
  fmt::print(
      "distance to target: {:.3f} % / {:.3f} % (avg / max of the diagonal) with theta2 = 0, "
      "{:.3f} % / {:.3f} % optimized; max |theta2| {:.4f} rad\n",
      m.dist_to_sim_avg_pct, m.dist_to_sim_max_pct, m.dist_to_optim_avg_pct,
      m.dist_to_optim_max_pct, m.theta2_max_abs_rad);
  if (loop) {
    fmt::print(
        "as plate.gcode prints it: {:.3f} % / {:.3f} % from the target, {:.3f} % / {:.3f} % from "
        "the fields' prediction\n",
        loop->to_target.mean_percent, loop->to_target.max_percent, loop->to_prediction.mean_percent,
        loop->to_prediction.max_percent);
  }
  fmt::print(
      "wrote {}: flat.ply, target.ply, simulated.ply, design.json{}, report.html and "
      "pictures (*.png)\n",
      dir.string(), plan_written ? ", plate.gcode, toolpath.json, layers/" : "");
  return 0;
}

}  // namespace

Command make_design_command(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<DesignCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "design",
      "The whole Shrink & Morph design of a target surface: flatten it (plate and theta1), "
      "simulate the plate, optimize the through-thickness variation theta2 so that the predicted "
      "shape matches the target (paper 3.2.2), then trace the print paths of every layer. Writes "
      "DIR/flat.ply (per-face theta1, per-vertex theta2, radians), DIR/target.ply, "
      "DIR/simulated.ply (the predicted shape, per-vertex deviation_mm), DIR/design.json "
      "(parameters and metrics), DIR/plate.gcode, DIR/layers/ (previews) and DIR/report.html "
      "(open it in a browser: 3D view, plate, layers, metrics).");
  add_mesh_input(sub, o->input);
  sub->add_option("--width", o->width_mm,
                  fmt::format("Largest extent of the plate, in mm (default {} for --example; "
                              "needed for a mesh file)",
                              kExampleWidthMm));
  sub->add_option("--wD", o->w_D, "Smoothing weight of the print directions (Eq. 12)")
      ->capture_default_str();
  sub->add_option("--wM", o->w_M, "Weight of the theta2 magnitude term (Eq. 13)")
      ->capture_default_str();
  sub->add_option("--wL", o->w_L, "Weight of the theta2 smoothness term (Eq. 13)")
      ->capture_default_str();
  sub->add_option("--faces", o->faces,
                  "Loop-subdivide the target until it has at least this many faces")
      ->capture_default_str();
  sub->add_option("--layers", o->layers, "Number of printed layers")->capture_default_str();
  sub->add_option("--material", o->material, "Material preset name or material JSON file")
      ->capture_default_str();
  sub->add_option("--printer", o->printer,
                  "Printer preset name or JSON file for the G-code (see 'flatmorph printers')")
      ->capture_default_str();
  sub->add_option("--side", o->side,
                  "Which side of the target is printed on top: auto (the side the plate naturally "
                  "curls toward; when the curvature does not tell, both sides are designed one "
                  "subdivision level coarser and the closer one is kept), normal-up or "
                  "normal-down")
      ->capture_default_str();
  sub->add_option("--stretch", o->stretch,
                  "Which of the 4 initial stretches (45 degrees apart) the flattening starts from: "
                  "auto (the one whose print directions follow the target's curvature, see "
                  "docs/design.md), 0 to 3, or all: design from each, side by side on the cores "
                  "there are, and keep the one with the lowest final objective (about twice the "
                  "time on 2 cores). The flattening has several local minima, and the theta2 "
                  "design can land closer from another one; design.json records the one used as "
                  "stretch_candidate (and with all, each one's result as explored_stretches)")
      ->capture_default_str();
  sub->add_flag("!--no-gcode", o->gcode, "Skip trajectories and G-code");
  sub->add_flag("--json", o->json,
                "Print design.json (parameters and metrics) on stdout at the end instead of the "
                "human-readable summary and progress");
  sub->add_option("-o,--output", o->output, "Output folder (created if needed)")->required();
  return {sub, [o, &global] { return run_design(*o, global); }};
}

}  // namespace flatmorph::cli
