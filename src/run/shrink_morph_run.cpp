// Shrink & Morph's steps of a run (method_steps.h): the whole design (docs/design.md), its plate's
// layers traced by the pipeline, the loop closed from the target as the fields' prediction was.
#include <fmt/core.h>

#include <cmath>
#include <numbers>

#include "common/error.h"
#include "common/stopwatch.h"
#include "run/method_steps.h"

namespace flatmorph {
namespace {

// Past this distance (average, % of the diagonal) between the shapes predicted from plate.gcode
// and from the fields, the design is not steady: the paths' small departures from the fields
// change its shape.
constexpr double kSteadyDesignPercent = 1.0;

constexpr int kMaxFaces = 2'000'000;

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

PrintedSide parse_side(const std::string& side) {
  if (side == "auto") return PrintedSide::kAutomatic;
  if (side == "normal-up") return PrintedSide::kNormalUp;
  if (side == "normal-down") return PrintedSide::kNormalDown;
  throw UserError(ErrorCategory::kOption,
                  fmt::format("--side {}: give auto, normal-up or normal-down", side));
}

void check_options(ShrinkMorphRunOptions& o, const RunInput& input) {
  if (std::isnan(o.width_mm) && !input.example.empty()) o.width_mm = kExamplePlateWidthMm;
  require_option(std::isfinite(o.width_mm) && o.width_mm > 0,
                 std::isnan(o.width_mm)
                     ? std::string("--width is needed for a mesh file: give the plate's largest "
                                   "extent in mm (e.g. --width 150)")
                     : fmt::format("--width {}: the plate width must be a positive number of mm "
                                   "(e.g. --width 150)",
                                   o.width_mm));
  require_option(std::isfinite(o.w_D) && o.w_D >= 0,
                 fmt::format("--wD {}: the smoothing weight must be 0 (no smoothing) or positive "
                             "(the paper uses 0.1)",
                             o.w_D));
  require_option(std::isfinite(o.w_M) && o.w_M >= 0 && std::isfinite(o.w_L) && o.w_L >= 0,
                 fmt::format("--wM {} / --wL {}: the theta2 regularization weights must be 0 or "
                             "positive (default 0.01)",
                             o.w_M, o.w_L));
  require_option(std::isfinite(o.path_error_deg) && o.path_error_deg >= 0 && o.path_error_deg <= 45,
                 fmt::format("--path-error {}: give the paths' angle error in degrees, 0 (off) to "
                             "45 (default 2.3)",
                             o.path_error_deg));
  require_option(
      o.faces >= 1 && o.faces <= kMaxFaces,
      fmt::format("--faces {}: the face count must be between 1 and {}", o.faces, kMaxFaces));
  require_option(
      o.layers >= 2 && o.layers <= 1000,
      fmt::format("--layers {}: give 2 to 1000 layers (theta2 varies through them)", o.layers));
}

nlohmann::ordered_json design_metrics(const DesignMetrics& m) {
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
  j["path_error_dist_avg_pct"] = m.path_error_dist_avg_pct;
  j["path_error_dist_max_pct"] = m.path_error_dist_max_pct;
  j["path_error_redesigned"] = m.path_error_redesigned;
  j["path_error_redesign_avg_pct"] = m.path_error_redesign_avg_pct;
  j["path_error_redesign_max_pct"] = m.path_error_redesign_max_pct;
  return j;
}

nlohmann::ordered_json design_parameters(const ShrinkMorphSetup& setup, const Design& design) {
  const ShrinkMorphRunOptions& o = setup.options;
  const Material& material = setup.material;
  nlohmann::ordered_json j;
  j["input"] = describe(setup.input);
  j["width_mm"] = o.width_mm;
  j["w_D"] = o.w_D;
  j["w_M"] = o.w_M;
  j["w_L"] = o.w_L;
  j["path_error_deg"] = o.path_error_deg;
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
  j["printer"] = setup.printer.name;
  j["optim_stop_reason"] = design.optimization.stop_reason;
  return j;
}

std::vector<std::string> design_warnings(const Design& design, const PrintOutcome& print) {
  std::vector<std::string> warnings;
  for (const std::string& warning : design.flat.warnings) warnings.push_back("flatten: " + warning);
  if (design.flat.feasibility.infeasible_area_fraction > 0) {
    warnings.push_back(fmt::format(
        "{:.1f} % of the target's area needs more shrink than the material gives (singular "
        "values more than 5 % from 1/lambda): expect larger deviations there; a smaller or less "
        "curved target, or a material that shrinks more (flatmorph calibrate), helps",
        100 * design.flat.feasibility.infeasible_area_fraction));
  }
  if (!design.optimization.initial_forward_converged) {
    warnings.push_back(
        "the theta2 = 0 simulation did not converge; the design starts from the best state "
        "reached (a finer mesh, a smaller --width or another material usually helps)");
  }
  if (!design.optimization.converged) {
    // The reason says why and what to change, in one sentence.
    warnings.push_back("the theta2 optimization did not converge: " +
                       design.optimization.stop_reason);
  }
  const std::optional<ClosedLoop>& loop = print.loop;
  if (loop && loop->to_prediction.mean_percent > kSteadyDesignPercent) {
    warnings.push_back(fmt::format(
        "the shape plate.gcode prints lies {:.2f} % / {:.2f} % (avg / max of the diagonal) from "
        "the fields' prediction: the design sits at a fold of its equilibria, where paths a "
        "degree off make the plate snap to another shape; expect the G-code's shape ({:.2f} % / "
        "{:.2f} % from the target, gcode_simulated.ply) rather than simulated.ply. Another "
        "--stretch (or --stretch all) may give a steadier design",
        loop->to_prediction.mean_percent, loop->to_prediction.max_percent,
        loop->to_target.mean_percent, loop->to_target.max_percent));
  }
  return warnings;
}

}  // namespace

ShrinkMorphSetup prepare_run(const RunRequest& request, const ShrinkMorphRunOptions& options) {
  ShrinkMorphSetup setup;
  setup.input = request.input;
  setup.options = options;
  setup.gcode = request.gcode;
  check_options(setup.options, request.input);
  setup.side = parse_side(options.side);
  setup.stretch = parse_stretch(options.stretch);
  setup.material = load_material(options.material);
  // A bad printer fails before any work.
  setup.printer = load_printer(options.printer);
  // The plate's largest extent is --width: one larger than the bed cannot be printed, which is
  // better said before minutes of optimization (the exact check comes with the G-code).
  const double width = setup.options.width_mm;
  const PrinterProfile& printer = setup.printer;
  if (request.gcode && width > printer.bed_size.maxCoeff()) {
    throw UserError(ErrorCategory::kInfeasible,
                    fmt::format("--width {} mm: the plate would not fit the {} x {} mm bed of {}; "
                                "give a smaller --width, another --printer, or --no-gcode",
                                width, printer.bed_size.x(), printer.bed_size.y(), printer.name));
  }
  return setup;
}

ShrinkMorphState design_run(const ShrinkMorphSetup& setup, const ProgressCallback& progress) {
  const ShrinkMorphRunOptions& o = setup.options;
  const auto start = Clock::now();
  Mesh mesh = read_target_mesh(setup.input).mesh;
  const double load_seconds = seconds_since(start);

  DesignOptions options;
  options.width_mm = o.width_mm;
  options.w_D = o.w_D;
  options.side = setup.side;
  options.stretch_candidate = setup.stretch;
  options.faces = o.faces;
  options.layers = o.layers;
  options.material = setup.material;
  options.optimize.w_M = o.w_M;
  options.optimize.w_L = o.w_L;
  options.optimize.path_error_rad = o.path_error_deg * std::numbers::pi / 180;
  options.progress = progress;
  ShrinkMorphState state;
  state.design = design_shrink_morph(std::move(mesh), describe(setup.input), options);
  Design& design = state.design;
  design.metrics.t_prepare_s += load_seconds;

  MethodDesign& run = state.run;
  run.plate = shrink_morph_plate_design(design.flat, design.theta2, setup.material, o.layers);
  run.target = design.flat.target;
  run.predicted = Mesh{design.optimized, run.plate.F};
  run.predicted_deviation_mm = design.dist_to_optim.per_vertex_mm;
  if (setup.gcode) {
    run.beds.push_back({});  // the plate's layers, traced by the pipeline
    // What plate.gcode deposits, simulated from the target as the fields were.
    run.loop = LoopClosure{
        {setup.material}, design.flat.target.V, design.flat.target.V, design.optimized, {},
        "plate"};
  }
  return state;
}

MethodReport report_run(const ShrinkMorphSetup& setup, const ShrinkMorphState& state,
                        const PrintOutcome& print, const ProgressCallback&) {
  const Design& design = state.design;
  MethodReport report;
  report.parameters = design_parameters(setup, design);
  DesignMetrics metrics = design.metrics;
  if (!print.plans.empty()) metrics.t_traj_s = print.plans.front().seconds;
  nlohmann::ordered_json& m = report.metrics;
  m = design_metrics(metrics);
  m["infeasible_area_pct"] = 100 * design.flat.feasibility.infeasible_area_fraction;
  m["sv_deviation_mean_pct"] = 100 * design.flat.feasibility.mean_deviation;
  if (!print.plans.empty()) {
    const PrintPlan& plan = print.plans.front();
    const ClosedLoop& loop = *print.loop;
    m["print_time_s"] = plan.gcode.print_time;
    m["filament_mm"] = plan.gcode.filament_length;
    m["filament_g"] = plan.gcode.filament_mass;
    // The shape plate.gcode makes (gcode_prediction.h: rigidly fitted, over the vertices it
    // prints) against the target and against the shape predicted from the design's fields.
    m["gcode_dist_avg_pct"] = loop.to_target.mean_percent;
    m["gcode_dist_max_pct"] = loop.to_target.max_percent;
    m["gcode_vs_fields_avg_pct"] = loop.to_prediction.mean_percent;
    m["gcode_vs_fields_max_pct"] = loop.to_prediction.max_percent;
    m["gcode_unprinted_faces"] = loop.prediction.plate.removed_faces;
    m["gcode_converged"] = loop.prediction.result.converged;
    m["t_gcode_sim_s"] = print.loop_seconds;
  }
  m["sim_stop_reason"] = design.simulated_stop_reason;
  if (print.loop) m["gcode_sim_stop_reason"] = stop_reason(print.loop->prediction.result);
  report.warnings = design_warnings(design, print);
  report.layer_table = true;
  const DesignMetrics& d = design.metrics;
  report.summary.push_back(fmt::format(
      "distance to target: {:.3f} % / {:.3f} % (avg / max of the diagonal) with theta2 = 0, "
      "{:.3f} % / {:.3f} % optimized; max |theta2| {:.4f} rad",
      d.dist_to_sim_avg_pct, d.dist_to_sim_max_pct, d.dist_to_optim_avg_pct,
      d.dist_to_optim_max_pct, d.theta2_max_abs_rad));
  if (print.loop) {
    report.summary.push_back(fmt::format(
        "as plate.gcode prints it: {:.3f} % / {:.3f} % from the target, {:.3f} % / {:.3f} % from "
        "the fields' prediction",
        print.loop->to_target.mean_percent, print.loop->to_target.max_percent,
        print.loop->to_prediction.mean_percent, print.loop->to_prediction.max_percent));
  }
  report.written = fmt::format(
      "flat.ply, target.ply, simulated.ply, design.json{}, report.html and pictures (*.png)",
      print.plans.empty() ? "" : ", plate.gcode, toolpath.json, layers/");
  return report;
}

}  // namespace flatmorph
