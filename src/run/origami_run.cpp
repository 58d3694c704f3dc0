// Self-folding origami's steps of a run (method_steps.h, docs/origami.md): the solid from a mesh or
// an example, or a drawn crease pattern; the nets with their actuators (their widths fitted
// against the shared simulator when asked); one print per bed in two materials; the sheets judged
// by the shared simulator from their layers and from their own G-code (--simulate); the nets,
// crease patterns, FOLD files and what printing the solid would have cost.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "common/angles.h"
#include "common/error.h"
#include "common/file_text.h"
#include "common/stopwatch.h"
#include "examples/origami_examples.h"
#include "gcode/gcode_writer.h"
#include "mesh/io.h"
#include "methods/origami/crease_pattern_svg.h"
#include "methods/origami/fold_file.h"
#include "methods/origami/net_svg.h"
#include "methods/origami/planar_faces.h"
#include "methods/origami/solid_estimate.h"
#include "plate/actuator_stack.h"
#include "run/method_steps.h"

namespace flatmorph {
namespace {

// The sheets go on the bed with a margin for the skirt and the primes, mm.
constexpr double kBedMarginMm = 10;

// --fit-hinges: how close every hinge must come, and the mesh its rounds simulate on.
constexpr double kHingeFitTolerance = 2 * kDegree;  // rad
constexpr double kHingeFitMeshEdge = 3;             // mm

void check_options(const OrigamiRunOptions& o, const RunInput& input) {
  require_option(
      input.path.empty() != input.example.empty(),
      input.path.empty()
          ? fmt::format("flatmorph origami needs a solid: a mesh (.obj, .ply, .stl, .off), a "
                        "crease pattern (.svg) or --example NAME ({})",
                        fmt::join(origami_example_names(), ", "))
          : "give either a file or --example, not both");
  require_option(
      o.faces >= 4 && o.faces <= 500,
      fmt::format("--faces {}: give 4 to 500 (the paper folds its bunny from 70)", o.faces));
  require_option(
      o.size_mm >= 0 && o.size_mm <= 2000 && std::isfinite(o.size_mm),
      fmt::format("--size {}: give the solid's longest side in mm (0: as given)", o.size_mm));
  require_option(o.actuator_speed > 0 && o.actuator_speed <= 1000,
                 fmt::format("--actuator-speed {}: give the active PLA's print speed in mm/s "
                             "(150 = the paper's 9000 mm/min)",
                             o.actuator_speed));
  require_option(o.actuator_width >= 0 && o.actuator_width <= 100,
                 fmt::format("--actuator-width {}: give a width in mm, or 0 to take it from the "
                             "speed",
                             o.actuator_width));
  require_option(o.mesh_edge_mm >= 0.3 && o.mesh_edge_mm <= 10,
                 fmt::format("--mesh-edge {}: give 0.3 to 10 mm", o.mesh_edge_mm));
  require_option(o.fit_hinges >= 0 && o.fit_hinges <= 20,
                 fmt::format("--fit-hinges {}: give 0 to 20 rounds", o.fit_hinges));
  require_option(o.flat_angle_deg >= 0 && o.flat_angle_deg < 30,
                 fmt::format("--flat-angle {}: give degrees in [0, 30)", o.flat_angle_deg));
}

std::string gcode_name(int bed) {
  return bed == 0 ? std::string("plate") : fmt::format("plate_{}", bed + 1);
}

// The inverse flow (a solid) or the forward one (a drawn crease pattern).
OrigamiDesign design_sheets(const OrigamiSetup& setup, std::vector<std::string>& notes) {
  const OrigamiRunOptions& o = setup.options;
  const RunInput& input = setup.input;
  const OrigamiOptions& options = setup.design_options;
  if (!input.path.empty() && std::filesystem::path(input.path).extension() == ".svg") {
    CreasePatternReadOptions read;
    read.flat_angle = options.flat_angle;
    read.name = std::filesystem::path(input.path).stem().string();
    const CreasePattern pattern = read_crease_pattern_svg(
        read_file_text(input.path, "crease pattern"), input.path, read, &notes);
    return design_origami_pattern(pattern, options);
  }
  PlanarFacesOptions simplify;
  simplify.max_faces = o.faces;
  Polyhedron solid = input.example.empty()
                         ? planar_faces(read_mesh(input.path).mesh, input.path, simplify, &notes)
                         : origami_example(input.example, o.faces);
  if (o.size_mm > 0) solid = scaled_to_size(solid, o.size_mm);
  return design_origami(solid, options);
}

// Each actuator's width corrected until the shared simulator folds the sheets as designed (a
// coarse mesh: a few rounds of every sheet).
void fit_hinges(const OrigamiSetup& setup, OrigamiState& state) {
  OrigamiDesign& design = state.design;
  const auto start = Clock::now();
  const double design_seconds = design.times.total;
  state.hinge_fit = fit_hinges_to_simulation(design, setup.design_options, setup.options.fit_hinges,
                                             kHingeFitTolerance, kHingeFitMeshEdge);
  const HingeFit& fit = *state.hinge_fit;
  design = fit.design;
  state.fit_seconds = seconds_since(start);
  design.times.total = design_seconds;
  if (!fit.stopped.empty()) state.notes.push_back("the hinge fit stopped early: " + fit.stopped);
  state.notes.push_back(fmt::format(
      "hinges fitted against the simulator: the worst hinge {:.1f}° off with the hinge curve's "
      "widths, {:.1f}° after round {} of {}",
      fit.worst_error.front() / kDegree, fit.worst_error[fit.best_round] / kDegree,
      fit.best_round + 1, fit.worst_error.size()));
}

// The judge: each sheet meshed as one plate and folded by the shared simulator, from the design's
// layers and, when printed, from what its own plate.gcode deposits (read back with the PLA as the
// design models it, thermorph_pla), started from the same fold.
struct SheetJudgement {
  std::vector<SheetSimulation> from_layers;
  std::vector<GcodePrediction> from_gcode;
  std::vector<std::vector<double>> gcode_angles;  // per sheet, per actuator, rad
};

SheetJudgement judge_sheets(const OrigamiSetup& setup, const OrigamiState& state,
                            const PrintOutcome& print, const ProgressCallback& progress) {
  const OrigamiDesign& design = state.design;
  const OrigamiOptions& options = setup.design_options;
  SheetJudgement out;
  const int sheets = static_cast<int>(design.sheets.size());
  for (int i = 0; i < sheets; ++i) {
    report_progress(progress, {"simulate", i + 1, sheets, NAN, design.sheets[i].pattern.name});
    out.from_layers.push_back(simulate_sheet(design, i, options, setup.options.mesh_edge_mm));
  }
  if (print.plans.empty()) return out;
  const std::vector<Material> tool_materials = {thermorph_pla(options.pla, options.print.stack),
                                                options.tpu};
  for (int i = 0; i < sheets; ++i) {
    const SheetSimulation& simulated = out.from_layers[i];
    report_progress(progress, {"simulate", i + 1, sheets, NAN,
                               design.sheets[i].pattern.name + " from plate.gcode"});
    GcodePredictionOptions predict;
    predict.plate_V = simulated.plate.plate;
    predict.plate_F = simulated.plate.F;
    predict.start = simulated.designed;
    const int bed = design.sheets[i].bed;
    out.from_gcode.push_back(predict_from_gcode(
        print.plans[bed].gcode.text, gcode_name(bed) + ".gcode", tool_materials, predict));
    const DepositedPlate& deposited = out.from_gcode.back().plate;
    out.gcode_angles.push_back(
        hinge_fold_angles(design.sheets[i].sheet, deposited.design.plate, deposited.design.F,
                          simulated.piece(deposited.kept_faces), out.from_gcode.back().result.V));
  }
  return out;
}

nlohmann::ordered_json hinges_json(const OrigamiSheet& sheet) {
  nlohmann::ordered_json hinges = nlohmann::ordered_json::array();
  for (const Actuator& actuator : sheet.sheet.actuators) {
    const HingeDesign& h = actuator.hinge;
    nlohmann::ordered_json j;
    j["faces"] = {actuator.parent_face + 1, actuator.child_face + 1};
    j["fold_angle_deg"] = h.fold_angle / kDegree;
    j["kind"] = h.fold_angle < 0 ? "mountain" : "valley";
    j["case"] = h.pla_on_bed ? "A" : "B";
    j["radius_mm"] = h.radius;
    j["width_mm"] = h.width;
    j["cut_mm"] = h.cut;
    j["shift_mm"] = h.shift;
    j["pla_speed_mm_s"] = h.pla_speed;
    hinges.push_back(j);
  }
  return hinges;
}

// Sheet i in design.json, with its drawings and simulated shapes as files.
nlohmann::ordered_json sheet_json(const OrigamiState& state, const SheetJudgement& judged,
                                  bool printed, size_t i, std::vector<RunFile>& files) {
  const OrigamiDesign& design = state.design;
  const OrigamiSheet& sheet = design.sheets[i];
  const std::string stem = design.sheets.size() == 1 ? "" : fmt::format("_{}", i + 1);
  const std::vector<Eigen::MatrixX3d> sharp = fold_sharp(sheet.pattern, 1.0);
  files.push_back({"net" + stem + ".svg", net_svg(sheet.pattern, sheet.sheet)});
  files.push_back({"crease_pattern" + stem + ".svg", crease_pattern_svg(sheet.pattern)});
  files.push_back({"pattern" + stem + ".fold", fold_json(sheet.pattern, &sheet.hinges, &sharp)});
  nlohmann::ordered_json s;
  s["name"] = sheet.pattern.name;
  s["faces"] = sheet.pattern.num_faces();
  s["root_face"] = sheet.pattern.root + 1;
  s["turned_over"] = sheet.turned_over;
  s["bed"] = sheet.bed + 1;
  if (printed) s["gcode"] = gcode_name(sheet.bed) + ".gcode";
  std::vector<int> order;
  for (int f : sheet.pattern.fold_order) order.push_back(f + 1);
  s["fold_order"] = order;
  if (!sheet.pattern.solid_face.empty() && sheet.pattern.solid_face[0] >= 0) {
    std::vector<int> solid_face;
    for (int f : sheet.pattern.solid_face) solid_face.push_back(f + 1);
    s["solid_face"] = solid_face;
  }
  s["hinges"] = hinges_json(sheet);
  if (!judged.from_layers.empty()) {
    const SheetSimulation& sim = judged.from_layers[i];
    for (size_t a = 0; a < sim.fold_angle.size(); ++a) {
      s["hinges"][a]["simulated_angle_deg"] = sim.fold_angle[a] / kDegree;
      if (!judged.gcode_angles.empty()) {
        s["hinges"][a]["gcode_simulated_angle_deg"] = judged.gcode_angles[i][a] / kDegree;
      }
    }
    s["simulated"] = {{"faces", sim.plate.F.rows()},
                      {"converged", sim.result.converged},
                      {"to_design_mean_pct", sim.to_design.mean_percent},
                      {"to_design_max_pct", sim.to_design.max_percent}};
    MeshProperties piece;
    piece.set_face("piece", sim.piece.cast<double>());
    files.push_back(
        {"sheet_simulated" + stem + ".ply", ply_bytes(Mesh{sim.result.V, sim.plate.F}, piece)});
    if (!judged.from_gcode.empty()) {
      const GcodePrediction& printed_sheet = judged.from_gcode[i];
      s["gcode_simulated"] = {{"faces", printed_sheet.plate.design.F.rows()},
                              {"converged", printed_sheet.result.converged}};
      MeshProperties printed_piece;
      printed_piece.set_face("piece", sim.piece(printed_sheet.plate.kept_faces).cast<double>());
      files.push_back(
          {"sheet_gcode_simulated" + stem + ".ply",
           ply_bytes(Mesh{printed_sheet.result.V, printed_sheet.plate.design.F}, printed_piece)});
    }
  }
  s["corner_gap_mm"] = sheet.corner_gap;
  if (sheet.collision) {
    s["collision"] = {{"pieces",
                       {piece_name(sheet.sheet, sheet.collision->piece_a),
                        piece_name(sheet.sheet, sheet.collision->piece_b)}},
                      {"progress", sheet.collision->progress},
                      {"avoided_in_fold_order", !sheet.order_collision}};
  }
  return s;
}

// The G-code of every bed after the first, and on a one-nozzle printer one file per material
// too (the paper's F1-F5).
void add_bed_files(const OrigamiSetup& setup, const OrigamiState& state, const PrintOutcome& print,
                   std::vector<RunFile>& files) {
  const OrigamiOptions& options = setup.design_options;
  for (int bed = 0; bed < static_cast<int>(print.plans.size()); ++bed) {
    if (bed > 0) files.push_back({gcode_name(bed) + ".gcode", print.plans[bed].gcode.text});
    if (setup.printer.extruder_count > 1) continue;
    for (const MaterialFile& part :
         make_material_files(state.design.bed_toolpaths[bed], setup.printer,
                             {options.pla, options.tpu}, print.plans[bed].gcode_options)) {
      files.push_back({gcode_name(bed) + "-" + part.label + ".gcode", part.gcode.text});
    }
  }
}

struct PrintTotals {
  double time_s = 0, filament_mm = 0, filament_g = 0;
  int tool_changes = 0;
};

PrintTotals print_totals(const PrintOutcome& print) {
  PrintTotals totals;
  for (const PrintPlan& plan : print.plans) {
    totals.time_s += plan.gcode.print_time;
    totals.filament_mm += plan.gcode.filament_length;
    totals.filament_g += plan.gcode.filament_mass;
    totals.tool_changes += plan.gcode.tool_changes;
  }
  return totals;
}

nlohmann::ordered_json origami_parameters(const OrigamiSetup& setup, const OrigamiState& state) {
  const OrigamiRunOptions& o = setup.options;
  const OrigamiDesign& design = state.design;
  nlohmann::ordered_json j;
  j["input"] = describe(setup.input);
  j["max_faces"] = o.faces;
  if (design.solid) {
    const Eigen::MatrixX3d& V = design.solid->V;
    j["size_mm"] = (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
  }
  j["material"] = setup.design_options.pla.name;
  j["hinge_material"] = setup.design_options.tpu.name;
  j["printer"] = setup.printer.name;
  j["actuator_speed_mm_s"] = o.actuator_speed;
  j["actuator_width_mm"] = o.actuator_width;
  j["flat_angle_deg"] = o.flat_angle_deg;
  j["case_b_hinges"] = o.case_b_hinges;
  j["hinge_curve"] = design.curve.calibrated ? "calibrated" : "uncalibrated default";
  if (state.hinge_fit) {
    std::vector<double> worst;
    for (double e : state.hinge_fit->worst_error) worst.push_back(e / kDegree);
    j["hinge_fit"] = {{"mesh_edge_mm", kHingeFitMeshEdge},
                      {"seconds", state.fit_seconds},
                      {"worst_hinge_error_deg_per_round", worst},
                      {"kept_round", state.hinge_fit->best_round + 1}};
  }
  return j;
}

// The judge's figures: the worst hinge from the layers and from the G-code, the sheets' largest
// mean distance to the design, whether every simulation converged.
void add_judgement_metrics(const OrigamiDesign& design, const SheetJudgement& judged,
                           nlohmann::ordered_json& m) {
  std::vector<std::vector<double>> angles;
  double mean = 0;
  bool converged = true;
  for (const SheetSimulation& sim : judged.from_layers) {
    angles.push_back(sim.fold_angle);
    mean = std::max(mean, sim.to_design.mean_percent);
    converged = converged && sim.result.converged;
  }
  m["sim_hinge_error_max_rad"] = worst_hinge_error(design, angles);
  if (!judged.gcode_angles.empty()) {
    m["sim_gcode_hinge_error_max_rad"] = worst_hinge_error(design, judged.gcode_angles);
    for (const GcodePrediction& printed : judged.from_gcode) {
      converged = converged && printed.result.converged;
    }
  }
  m["sim_to_design_mean_pct"] = mean;
  m["sim_converged"] = converged;
}

// "converged" when every sheet's simulation did (from its layers and from its G-code), else why
// the first one that did not stopped.
std::string sheets_stop_reason(const SheetJudgement& judged) {
  for (size_t i = 0; i < judged.from_layers.size(); ++i) {
    const SimulationResult& r = judged.from_layers[i].result;
    if (!r.converged) return fmt::format("sheet {}: {}", i + 1, stop_reason(r));
  }
  for (size_t i = 0; i < judged.from_gcode.size(); ++i) {
    const SimulationResult& r = judged.from_gcode[i].result;
    if (!r.converged) return fmt::format("sheet {} from its G-code: {}", i + 1, stop_reason(r));
  }
  return "converged";
}

nlohmann::ordered_json origami_metrics(const OrigamiDesign& design, const SheetJudgement& judged,
                                       const PrintOutcome& print) {
  nlohmann::ordered_json m;
  int hinges = 0;
  for (const OrigamiSheet& sheet : design.sheets) hinges += sheet.sheet.actuators.size();
  m["sheets"] = design.sheets.size();
  m["hinges"] = hinges;
  if (design.solid) {
    m["faces"] = design.solid->faces.size();
    m["fold_angle_error_rad"] = design.fold_angle_error;
    m["sharp_fold_error_pct"] = design.sharp_error_pct;
    m["curved_plane_error_pct"] = design.curved_plane_error_pct;
  }
  bool collides = false;
  for (const OrigamiSheet& sheet : design.sheets) collides = collides || sheet.collision;
  m["collision"] = collides;
  if (!judged.from_layers.empty()) add_judgement_metrics(design, judged, m);
  m["t_unfold_s"] = design.times.unfold;
  m["t_actuate_s"] = design.times.actuate;
  m["t_fold_s"] = design.times.fold;
  m["t_toolpath_s"] = design.times.toolpath;
  m["t_design_s"] = design.times.total;
  if (!print.plans.empty()) {
    const PrintTotals totals = print_totals(print);
    m["beds"] = print.plans.size();
    m["print_time_s"] = totals.time_s;
    m["filament_g"] = totals.filament_g;
    m["tool_changes"] = totals.tool_changes;
  }
  if (!judged.from_layers.empty()) m["sim_stop_reason"] = sheets_stop_reason(judged);
  return m;
}

// The cost of printing the solid itself: PrusaSlicer's figures when it is installed (and not
// refused), else the volume estimate; and what the sheets save against it.
void add_solid_comparison(const OrigamiSetup& setup, const OrigamiDesign& design,
                          const PrintOutcome& print, MethodReport& report) {
  if (!design.solid) return;
  const double filament_diameter = setup.printer.filament_diameter;
  const SolidPrintEstimate estimate =
      estimate_solid_print(*design.solid, setup.design_options.pla, filament_diameter);
  std::optional<SolidPrintEstimate> sliced;
  std::string why;
  if (setup.options.slicer)
    sliced = slicer_solid_print(*design.solid, filament_diameter, 300, &why);
  const SolidPrintEstimate& solid = sliced ? *sliced : estimate;
  nlohmann::ordered_json& m = report.metrics;
  m["solid_print_time_s"] = solid.time_s;
  m["solid_filament_mm"] = solid.filament_mm;
  report.parameters["solid_print_estimate"] = solid.source;
  if (!sliced && setup.options.slicer) report.parameters["slicer"] = why;
  if (print.plans.empty()) return;
  const PrintTotals totals = print_totals(print);
  m["time_saving_pct"] = 100 * (1 - totals.time_s / solid.time_s);
  m["filament_saving_pct"] = 100 * (1 - totals.filament_mm / solid.filament_mm);
  report.summary.push_back(fmt::format(
      "the solid itself ({}): {:.0f} min, {:.0f} mm of filament; the sheet saves {:.0f} % of the "
      "time and {:.0f} % of the filament",
      solid.source, solid.time_s / 60, solid.filament_mm, m["time_saving_pct"].get<double>(),
      m["filament_saving_pct"].get<double>()));
}

std::vector<std::string> origami_summary(const OrigamiState& state, const PrintOutcome& print,
                                         const nlohmann::ordered_json& m) {
  const OrigamiDesign& design = state.design;
  std::vector<std::string> lines;
  if (!print.plans.empty() && design.num_beds > 1) {
    std::string names;
    for (int bed = 0; bed < design.num_beds; ++bed) {
      names += fmt::format("{}{}.gcode", bed ? ", " : "", gcode_name(bed));
    }
    const PrintTotals totals = print_totals(print);
    lines.push_back(fmt::format(
        "the sheets need {} beds, one print each ({}): {:.0f} min and {:.2f} m of filament in "
        "all",
        design.num_beds, names, totals.time_s / 60, totals.filament_mm / 1000));
  }
  for (const OrigamiSheet& sheet : design.sheets) {
    int mountains = 0;
    for (const Actuator& a : sheet.sheet.actuators) mountains += a.hinge.fold_angle < 0;
    lines.push_back(fmt::format(
        "{}: {} faces, {} hinges ({} mountains, case A; {} valleys, case B){}{}",
        sheet.pattern.name, sheet.pattern.num_faces(), sheet.sheet.actuators.size(), mountains,
        sheet.sheet.actuators.size() - mountains, sheet.turned_over ? ", printed inside up" : "",
        design.num_beds > 1 ? fmt::format(", in {}.gcode", gcode_name(sheet.bed)) : ""));
  }
  if (design.solid) {
    lines.push_back(fmt::format(
        "folded back: corners within {:.2g} % of the diagonal (sharp), faces within {:.2g} % of "
        "their planes (curved); hinge curve {}",
        design.sharp_error_pct, design.curved_plane_error_pct,
        design.curve.calibrated ? "calibrated" : "uncalibrated default"));
  }
  if (m.contains("sim_hinge_error_max_rad")) {
    const double worst = m["sim_hinge_error_max_rad"].get<double>() / kDegree;
    const bool from_gcode = m.contains("sim_gcode_hinge_error_max_rad");
    lines.push_back(fmt::format(
        "simulated (the shared simulator, from the design's layers{}): the worst hinge {:.1f}° "
        "off its fold{}{}",
        from_gcode ? " and from the G-code" : "", worst,
        from_gcode ? fmt::format(", {:.1f}° from the G-code",
                                 m["sim_gcode_hinge_error_max_rad"].get<double>() / kDegree)
                   : std::string(),
        worst > kHingeFitTolerance / kDegree && !state.hinge_fit
            ? "; --fit-hinges N corrects the widths against it"
            : ""));
  }
  return lines;
}

}  // namespace

OrigamiSetup prepare_run(const RunRequest& request, const OrigamiRunOptions& options) {
  check_options(options, request.input);
  OrigamiSetup setup;
  setup.input = request.input;
  setup.options = options;
  setup.gcode = request.gcode;
  OrigamiOptions& design = setup.design_options;
  design.pla = load_material(options.material);
  design.tpu = load_material(options.hinge_material);
  setup.printer = load_printer(options.printer);
  design.actuator_speed = options.actuator_speed;
  design.actuator_width = options.actuator_width;
  design.flat_angle = options.flat_angle_deg * kDegree;
  design.case_b_hinges = options.case_b_hinges;
  design.print.line_width = setup.printer.nozzle_diameter;
  design.room = usable_bed_area(setup.printer, kBedMarginMm);
  return setup;
}

OrigamiState design_run(const OrigamiSetup& setup, const ProgressCallback& progress) {
  OrigamiSetup with_progress = setup;
  with_progress.design_options.progress = progress;
  OrigamiState state;
  state.design = design_sheets(with_progress, state.notes);
  if (setup.options.fit_hinges > 0) fit_hinges(with_progress, state);
  for (const std::string& warning : state.design.warnings) state.notes.push_back(warning);
  state.plate = origami_plate(state.design, setup.design_options);

  MethodDesign& run = state.run;
  run.plate = state.plate.plate;
  run.predicted = state.plate.folded;
  if (!setup.gcode) return state;
  // One print per bed: plate.gcode, then plate_2.gcode, ... when the sheets need several.
  for (int bed = 0; bed < state.design.num_beds; ++bed) {
    run.beds.push_back({state.design.bed_toolpaths[bed],
                        bed_faces(state.plate, state.design, bed),
                        {setup.design_options.pla, setup.design_options.tpu},
                        0});
  }
  return state;
}

MethodReport report_run(const OrigamiSetup& setup, const OrigamiState& state,
                        const PrintOutcome& print, const ProgressCallback& progress) {
  const OrigamiDesign& design = state.design;
  MethodReport report;
  SheetJudgement judged;
  if (setup.options.simulate) judged = judge_sheets(setup, state, print, progress);

  nlohmann::ordered_json sheets = nlohmann::ordered_json::array();
  for (size_t i = 0; i < design.sheets.size(); ++i) {
    sheets.push_back(sheet_json(state, judged, !print.plans.empty(), i, report.files));
  }
  add_bed_files(setup, state, print, report.files);
  if (design.solid) report.files.push_back({"solid.obj", polyhedron_obj(*design.solid)});
  // The folded sheet with each triangle's piece (face, then actuator) and sheet, numbered from 0.
  MeshProperties pieces;
  for (const char* name : {"piece", "sheet"}) {
    pieces.set_face(name, *state.plate.plate.design_fields.find_face(name));
  }
  report.files.push_back({"folded.ply", ply_bytes(state.plate.folded, pieces)});

  report.parameters = origami_parameters(setup, state);
  report.parameters["sheets"] = sheets;
  // The report shows the printed nets (report/run_folder.h).
  report.parameters["drawings"] = drawing_names(report.files, "net");
  if (!state.notes.empty()) report.parameters["notes"] = state.notes;
  report.metrics = origami_metrics(design, judged, print);
  report.summary = origami_summary(state, print, report.metrics);
  add_solid_comparison(setup, design, print, report);
  report.summary.push_back(fmt::format(
      "design time {:.2f} s{}", design.times.total,
      state.hinge_fit ? fmt::format(", fitting the hinges {:.1f} s", state.fit_seconds) : ""));
  report.notes = state.notes;
  const std::string n = design.sheets.size() == 1 ? "" : "_N";
  report.written = fmt::format(
      "net{}.svg, crease_pattern{}.svg, pattern{}.fold, folded.ply, flat.ply{}, design.json, "
      "report.html",
      n, n, n,
      print.plans.empty()   ? ""
      : design.num_beds > 1 ? ", plate.gcode, plate_N.gcode, toolpath.json, layers/ (the first bed)"
                            : ", plate.gcode, toolpath.json, layers/");
  return report;
}

}  // namespace flatmorph
