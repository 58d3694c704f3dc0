// flatmorph origami: Thermorph's self-folding sheets (CHI 2018) from a mesh, a drawn crease
// pattern or a built-in solid to a run folder: the nets with their actuators, the folded shape,
// the two-material G-code and what printing the solid would have cost.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>

#include "commands.h"
#include "common/error.h"
#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "mesh/io.h"
#include "methods/origami/crease_pattern_svg.h"
#include "methods/origami/design_origami.h"
#include "methods/origami/fold_file.h"
#include "methods/origami/net_svg.h"
#include "methods/origami/planar_faces.h"
#include "methods/origami/sheet_simulation.h"
#include "methods/origami/solid_estimate.h"
#include "plate/actuator_stack.h"
#include "print_summary.h"
#include "progress_display.h"
#include "run/gcode_prediction.h"
#include "run/print_plan.h"
#include "run/run_folder.h"

namespace flatmorph::cli {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

struct OrigamiCliOptions {
  std::string input;  // a mesh (.obj, .ply, .stl, .off) or a crease pattern (.svg)
  std::string example;
  int faces = 70;
  double size_mm = 0;
  std::string material = "pla-generic";
  std::string hinge_material = "tpu-generic";
  std::string printer = "prusa-xl-2t";
  double actuator_speed = 150;
  double actuator_width = 0;
  double flat_angle_deg = 1;
  bool case_b_hinges = false;
  bool simulate = false;
  double mesh_edge_mm = 1.5;
  int fit_hinges = 0;  // rounds
  bool slicer = true;
  bool gcode = true;
  bool json = false;
  std::string output;
};

void require(bool ok, const std::string& message) {
  if (!ok) throw UserError(ErrorCategory::kOption, message);
}

// Checked before anything is read or written, so that a bad value leaves no output behind.
void check(const OrigamiCliOptions& o) {
  require(o.input.empty() != o.example.empty(),
          o.input.empty()
              ? fmt::format("flatmorph origami needs a solid: a mesh (.obj, .ply, .stl, .off), a "
                            "crease pattern (.svg) or --example NAME ({})",
                            fmt::join(origami_example_names(), ", "))
              : "give either a file or --example, not both");
  require(!o.output.empty(), "flatmorph origami needs an output folder: -o DIR");
  require(o.faces >= 4 && o.faces <= 500,
          fmt::format("--faces {}: give 4 to 500 (the paper folds its bunny from 70)", o.faces));
  require(o.size_mm >= 0 && o.size_mm <= 2000 && std::isfinite(o.size_mm),
          fmt::format("--size {}: give the solid's longest side in mm (0: as given)", o.size_mm));
  require(o.actuator_speed > 0 && o.actuator_speed <= 1000,
          fmt::format("--actuator-speed {}: give the active PLA's print speed in mm/s (150 = "
                      "the paper's 9000 mm/min)",
                      o.actuator_speed));
  require(o.actuator_width >= 0 && o.actuator_width <= 100,
          fmt::format("--actuator-width {}: give a width in mm, or 0 to take it from the speed",
                      o.actuator_width));
  require(o.mesh_edge_mm >= 0.3 && o.mesh_edge_mm <= 10,
          fmt::format("--mesh-edge {}: give 0.3 to 10 mm", o.mesh_edge_mm));
  require(o.fit_hinges >= 0 && o.fit_hinges <= 20,
          fmt::format("--fit-hinges {}: give 0 to 20 rounds", o.fit_hinges));
  require(o.flat_angle_deg >= 0 && o.flat_angle_deg < 30,
          fmt::format("--flat-angle {}: give degrees in [0, 30)", o.flat_angle_deg));
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw UserError(ErrorCategory::kFile, fmt::format("{}: cannot open the file: check the path "
                                                      "and that it is readable",
                                                      path));
  }
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The solid as a Wavefront OBJ of its polygon faces (solid.obj: MeshLab and Blender keep the
// polygons).
std::string solid_obj(const Polyhedron& solid) {
  std::string out = "# flatmorph origami: the solid the sheets fold into, mm\n";
  for (Eigen::Index v = 0; v < solid.V.rows(); ++v) {
    out += fmt::format("v {} {} {}\n", solid.V(v, 0), solid.V(v, 1), solid.V(v, 2));
  }
  for (const std::vector<int>& face : solid.faces) {
    out += "f";
    for (int v : face) out += fmt::format(" {}", v + 1);
    out += "\n";
  }
  return out;
}

// --fit-hinges: how close every hinge must come, and the mesh its rounds simulate on.
constexpr double kHingeFitTolerance = 2 * kDegree;  // rad
constexpr double kHingeFitMeshEdge = 3;             // mm

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

int run_origami(const OrigamiCliOptions& o, const GlobalOptions& global) {
  check(o);
  OrigamiOptions options;
  options.pla = load_material(o.material);
  options.tpu = load_material(o.hinge_material);
  const PrinterProfile printer = load_printer(o.printer);
  require_run_folder_destination(o.output);
  const bool silent = global.quiet || o.json;
  options.progress = make_progress_display(silent);
  options.actuator_speed = o.actuator_speed;
  options.actuator_width = o.actuator_width;
  options.flat_angle = o.flat_angle_deg * kDegree;
  options.case_b_hinges = o.case_b_hinges;
  options.print.line_width = printer.nozzle_diameter;
  // The sheets go on the bed with a margin for the skirt and the primes.
  const double margin = 10;
  options.room = printer.bed_shape == BedShape::kCircular
                     ? Eigen::Vector2d::Constant(printer.bed_size.x() / std::sqrt(2.0) - margin)
                     : Eigen::Vector2d(printer.bed_size.array() - 2 * margin);

  std::vector<std::string> notes;
  OrigamiDesign design;
  const bool drawn = !o.input.empty() && std::filesystem::path(o.input).extension() == ".svg";
  if (drawn) {
    CreasePatternReadOptions read;
    read.flat_angle = options.flat_angle;
    read.name = std::filesystem::path(o.input).stem().string();
    const CreasePattern pattern =
        read_crease_pattern_svg(read_text(o.input), o.input, read, &notes);
    design = design_origami_pattern(pattern, options);
  } else {
    PlanarFacesOptions simplify;
    simplify.max_faces = o.faces;
    Polyhedron solid = o.example.empty()
                           ? planar_faces(read_mesh(o.input).mesh, o.input, simplify, &notes)
                           : origami_example(o.example, o.faces);
    if (o.size_mm > 0) solid = scaled_to_size(solid, o.size_mm);
    design = design_origami(solid, options);
  }
  // Each actuator's width corrected until the shared simulator folds the sheets as designed
  // (a coarse mesh: a few rounds of every sheet).
  std::optional<HingeFit> hinge_fit;
  double fit_seconds = 0;
  if (o.fit_hinges > 0) {
    const auto fit_start = std::chrono::steady_clock::now();
    const double design_seconds = design.times.total;
    hinge_fit = fit_hinges_to_simulation(design, options, o.fit_hinges, kHingeFitTolerance,
                                         kHingeFitMeshEdge);
    design = hinge_fit->design;
    fit_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
    design.times.total = design_seconds;
    if (!hinge_fit->stopped.empty()) {
      notes.push_back("the hinge fit stopped early: " + hinge_fit->stopped);
    }
    notes.push_back(fmt::format(
        "hinges fitted against the simulator: the worst hinge {:.1f}° off with the hinge curve's "
        "widths, {:.1f}° after round {} of {}",
        hinge_fit->worst_error.front() / kDegree,
        hinge_fit->worst_error[hinge_fit->best_round] / kDegree, hinge_fit->best_round + 1,
        hinge_fit->worst_error.size()));
  }
  for (const std::string& warning : design.warnings) notes.push_back(warning);
  const OrigamiPlate plate = origami_plate(design, options);

  // One print per bed: plate.gcode, then plate_2.gcode, ... when the sheets need several.
  std::vector<PrintPlan> plans;
  if (o.gcode) {
    const Eigen::VectorXd& sheet_of = *plate.plate.design_fields.find_face("sheet");
    for (int bed = 0; bed < design.num_beds; ++bed) {
      std::vector<int> rows;
      for (Eigen::Index t = 0; t < sheet_of.size(); ++t) {
        if (design.sheets[static_cast<int>(sheet_of(t))].bed == bed) rows.push_back(t);
      }
      plans.push_back(plan_toolpath_print(traced_layer_paths(design.bed_toolpaths[bed]),
                                          plate.plate.plate, plate.plate.F(rows, Eigen::all),
                                          {options.pla, options.tpu}, printer, {}));
    }
  }
  const auto gcode_name = [](int bed) {
    return bed == 0 ? std::string("plate") : fmt::format("plate_{}", bed + 1);
  };
  double print_time = 0, filament_mm = 0, filament_g = 0;
  int tool_changes = 0;
  for (const PrintPlan& plan : plans) {
    print_time += plan.gcode.print_time;
    filament_mm += plan.gcode.filament_length;
    filament_g += plan.gcode.filament_mass;
    tool_changes += plan.gcode.tool_changes;
  }
  std::optional<SolidPrintEstimate> solid_estimate, slicer_estimate;
  std::string slicer_why;
  if (design.solid) {
    solid_estimate = estimate_solid_print(*design.solid, options.pla, printer.filament_diameter);
    if (o.slicer) {
      slicer_estimate =
          slicer_solid_print(*design.solid, printer.filament_diameter, 300, &slicer_why);
    }
  }

  // The judge: each sheet meshed as one plate and folded by the shared simulator.
  std::vector<SheetSimulation> simulated;
  if (o.simulate) {
    for (size_t i = 0; i < design.sheets.size(); ++i) {
      report_progress(options.progress,
                      {"simulate", static_cast<int>(i) + 1, static_cast<int>(design.sheets.size()),
                       NAN, design.sheets[i].pattern.name});
      simulated.push_back(simulate_sheet(design, static_cast<int>(i), options, o.mesh_edge_mm));
    }
  }

  // ... and from what its own plate.gcode deposits (run/gcode_prediction.h), read back with the
  // PLA as the design models it (thermorph_pla), started from the same fold.
  std::vector<GcodePrediction> from_gcode;
  std::vector<std::vector<double>> gcode_angles;
  if (o.simulate && !plans.empty()) {
    const std::vector<Material> tool_materials = {thermorph_pla(options.pla, options.print.stack),
                                                  options.tpu};
    for (size_t i = 0; i < simulated.size(); ++i) {
      report_progress(options.progress,
                      {"simulate", static_cast<int>(i) + 1, static_cast<int>(simulated.size()), NAN,
                       design.sheets[i].pattern.name + " from plate.gcode"});
      GcodePredictionOptions predict;
      predict.plate_V = simulated[i].plate.plate;
      predict.plate_F = simulated[i].plate.F;
      predict.start = simulated[i].designed;
      from_gcode.push_back(predict_from_gcode(plans[design.sheets[i].bed].gcode.text,
                                              gcode_name(design.sheets[i].bed) + ".gcode",
                                              tool_materials, predict));
      const DepositedPlate& deposited = from_gcode.back().plate;
      gcode_angles.push_back(
          hinge_fold_angles(design.sheets[i].sheet, deposited.design.plate, deposited.design.F,
                            simulated[i].piece(deposited.kept_faces), from_gcode.back().result.V));
    }
  }

  std::vector<RunFile> files;
  nlohmann::ordered_json sheets = nlohmann::ordered_json::array();
  for (size_t i = 0; i < design.sheets.size(); ++i) {
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
    if (!plans.empty()) s["gcode"] = gcode_name(sheet.bed) + ".gcode";
    std::vector<int> order;
    for (int f : sheet.pattern.fold_order) order.push_back(f + 1);
    s["fold_order"] = order;
    if (!sheet.pattern.solid_face.empty() && sheet.pattern.solid_face[0] >= 0) {
      std::vector<int> solid_face;
      for (int f : sheet.pattern.solid_face) solid_face.push_back(f + 1);
      s["solid_face"] = solid_face;
    }
    s["hinges"] = hinges_json(sheet);
    if (!simulated.empty()) {
      const SheetSimulation& sim = simulated[i];
      for (size_t a = 0; a < sim.fold_angle.size(); ++a) {
        s["hinges"][a]["simulated_angle_deg"] = sim.fold_angle[a] / kDegree;
        if (!gcode_angles.empty()) {
          s["hinges"][a]["gcode_simulated_angle_deg"] = gcode_angles[i][a] / kDegree;
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
      if (!from_gcode.empty()) {
        const GcodePrediction& printed = from_gcode[i];
        s["gcode_simulated"] = {{"faces", printed.plate.design.F.rows()},
                                {"converged", printed.result.converged}};
        MeshProperties printed_piece;
        printed_piece.set_face("piece", sim.piece(printed.plate.kept_faces).cast<double>());
        files.push_back({"sheet_gcode_simulated" + stem + ".ply",
                         ply_bytes(Mesh{printed.result.V, printed.plate.design.F}, printed_piece)});
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
    sheets.push_back(s);
  }
  // A one-nozzle printer pauses for each swap; one file per material serves those that cannot
  // (the paper's F1-F5).
  for (int bed = 0; bed < static_cast<int>(plans.size()); ++bed) {
    if (bed > 0) files.push_back({gcode_name(bed) + ".gcode", plans[bed].gcode.text});
    if (printer.extruder_count > 1) continue;
    for (const MaterialFile& part :
         make_material_files(design.bed_toolpaths[bed], printer, {options.pla, options.tpu},
                             plans[bed].gcode_options)) {
      files.push_back({gcode_name(bed) + "-" + part.label + ".gcode", part.gcode.text});
    }
  }
  if (design.solid) files.push_back({"solid.obj", solid_obj(*design.solid)});
  // The folded sheet with each triangle's piece (face, then actuator) and sheet, numbered from 0.
  MeshProperties pieces;
  for (const char* name : {"piece", "sheet"}) {
    pieces.set_face(name, *plate.plate.design_fields.find_face(name));
  }
  files.push_back({"folded.ply", ply_bytes(plate.folded, pieces)});

  nlohmann::ordered_json j;
  j["input"] = o.example.empty() ? o.input : "example " + o.example;
  j["max_faces"] = o.faces;
  if (design.solid) {
    const Eigen::MatrixX3d& V = design.solid->V;
    j["size_mm"] = (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
  }
  j["material"] = options.pla.name;
  j["hinge_material"] = options.tpu.name;
  j["printer"] = printer.name;
  j["actuator_speed_mm_s"] = o.actuator_speed;
  j["actuator_width_mm"] = o.actuator_width;
  j["flat_angle_deg"] = o.flat_angle_deg;
  j["case_b_hinges"] = o.case_b_hinges;
  j["hinge_curve"] = design.curve.calibrated ? "calibrated" : "uncalibrated default";
  if (hinge_fit) {
    std::vector<double> worst;
    for (double e : hinge_fit->worst_error) worst.push_back(e / kDegree);
    j["hinge_fit"] = {{"mesh_edge_mm", kHingeFitMeshEdge},
                      {"seconds", fit_seconds},
                      {"worst_hinge_error_deg_per_round", worst},
                      {"kept_round", hinge_fit->best_round + 1}};
  }
  j["sheets"] = sheets;
  // The report shows the printed nets (report/run_folder.h).
  j["drawings"] = drawing_names(files, "net");
  if (!notes.empty()) j["notes"] = notes;

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
  if (!simulated.empty()) {
    double worst = 0, mean = 0;
    bool converged = true;
    for (size_t i = 0; i < simulated.size(); ++i) {
      for (size_t a = 0; a < simulated[i].fold_angle.size(); ++a) {
        worst = std::max(worst, std::abs(simulated[i].fold_angle[a] -
                                         design.sheets[i].sheet.actuators[a].hinge.fold_angle));
      }
      mean = std::max(mean, simulated[i].to_design.mean_percent);
      converged = converged && simulated[i].result.converged;
    }
    m["sim_hinge_error_max_rad"] = worst;
    if (!gcode_angles.empty()) {
      double gcode_worst = 0;
      for (size_t i = 0; i < gcode_angles.size(); ++i) {
        for (size_t a = 0; a < gcode_angles[i].size(); ++a) {
          gcode_worst = std::max(
              gcode_worst,
              std::abs(gcode_angles[i][a] - design.sheets[i].sheet.actuators[a].hinge.fold_angle));
        }
        converged = converged && from_gcode[i].result.converged;
      }
      m["sim_gcode_hinge_error_max_rad"] = gcode_worst;
    }
    m["sim_to_design_mean_pct"] = mean;
    m["sim_converged"] = converged;
  }
  m["t_unfold_s"] = design.times.unfold;
  m["t_actuate_s"] = design.times.actuate;
  m["t_fold_s"] = design.times.fold;
  m["t_toolpath_s"] = design.times.toolpath;
  m["t_design_s"] = design.times.total;
  if (!plans.empty()) {
    m["beds"] = plans.size();
    m["print_time_s"] = print_time;
    m["filament_g"] = filament_g;
    m["tool_changes"] = tool_changes;
  }
  const SolidPrintEstimate* solid_print = slicer_estimate  ? &*slicer_estimate
                                          : solid_estimate ? &*solid_estimate
                                                           : nullptr;
  if (solid_print) {
    m["solid_print_time_s"] = solid_print->time_s;
    m["solid_filament_mm"] = solid_print->filament_mm;
    j["solid_print_estimate"] = solid_print->source;
    if (!slicer_estimate && o.slicer) j["slicer"] = slicer_why;
    if (!plans.empty()) {
      m["time_saving_pct"] = 100 * (1 - print_time / solid_print->time_s);
      m["filament_saving_pct"] = 100 * (1 - filament_mm / solid_print->filament_mm);
    }
  }

  RunOutputs run;
  run.method = "origami";
  run.plate = plate.plate;
  run.predicted = plate.folded;
  if (!plans.empty()) run.print = std::move(plans[0]);
  run.files = std::move(files);
  run.parameters = j;
  run.metrics = m;
  run.metric_list = run_metric_list(m);
  write_run_folder(o.output, run, &printer, options.progress);
  const nlohmann::ordered_json record = run_record(run);

  finish_progress_line();
  for (const std::string& note : notes) fmt::print(stderr, "flatmorph: note: {}\n", note);
  if (o.json) fmt::print("{}\n", record.dump(2));
  if (silent) return 0;
  if (run.print) print_gcode_summary(*run.print, printer);
  if (run.print && design.num_beds > 1) {
    std::string names;
    for (int bed = 0; bed < design.num_beds; ++bed) {
      names += fmt::format("{}{}.gcode", bed ? ", " : "", gcode_name(bed));
    }
    fmt::print(
        "the sheets need {} beds, one print each ({}): {:.0f} min and {:.2f} m of filament in "
        "all\n",
        design.num_beds, names, print_time / 60, filament_mm / 1000);
  }
  for (const OrigamiSheet& sheet : design.sheets) {
    int mountains = 0;
    for (const Actuator& a : sheet.sheet.actuators) mountains += a.hinge.fold_angle < 0;
    fmt::print("{}: {} faces, {} hinges ({} mountains, case A; {} valleys, case B){}{}\n",
               sheet.pattern.name, sheet.pattern.num_faces(), sheet.sheet.actuators.size(),
               mountains, sheet.sheet.actuators.size() - mountains,
               sheet.turned_over ? ", printed inside up" : "",
               design.num_beds > 1 ? fmt::format(", in {}.gcode", gcode_name(sheet.bed)) : "");
  }
  if (design.solid) {
    fmt::print(
        "folded back: corners within {:.2g} % of the diagonal (sharp), faces within {:.2g} % "
        "of their planes (curved); hinge curve {}\n",
        design.sharp_error_pct, design.curved_plane_error_pct,
        design.curve.calibrated ? "calibrated" : "uncalibrated default");
  }
  if (!simulated.empty()) {
    const double worst = m["sim_hinge_error_max_rad"].get<double>() / kDegree;
    fmt::print(
        "simulated (the shared simulator, from the design's layers{}): the worst hinge "
        "{:.1f}° off its fold{}{}\n",
        gcode_angles.empty() ? "" : " and from the G-code", worst,
        gcode_angles.empty()
            ? std::string()
            : fmt::format(", {:.1f}° from the G-code",
                          m["sim_gcode_hinge_error_max_rad"].get<double>() / kDegree),
        worst > kHingeFitTolerance / kDegree && !hinge_fit
            ? "; --fit-hinges N corrects the widths against it"
            : "");
  }
  if (solid_print && run.print) {
    fmt::print(
        "the solid itself ({}): {:.0f} min, {:.0f} mm of filament; the sheet saves {:.0f} % "
        "of the time and {:.0f} % of the filament\n",
        solid_print->source, solid_print->time_s / 60, solid_print->filament_mm,
        m["time_saving_pct"].get<double>(), m["filament_saving_pct"].get<double>());
  }
  fmt::print("design time {:.2f} s{}\n", design.times.total,
             hinge_fit ? fmt::format(", fitting the hinges {:.1f} s", fit_seconds) : "");
  const std::string n = design.sheets.size() == 1 ? "" : "_N";
  fmt::print(
      "wrote {}: net{}.svg, crease_pattern{}.svg, pattern{}.fold, folded.ply, "
      "flat.ply{}, design.json, report.html\n",
      o.output, n, n, n,
      !run.print            ? ""
      : design.num_beds > 1 ? ", plate.gcode, plate_N.gcode, toolpath.json, layers/ (the first bed)"
                            : ", plate.gcode, toolpath.json, layers/");
  return 0;
}

}  // namespace

Command make_origami_command(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<OrigamiCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "origami",
      "Self-folding origami (Thermorph, CHI 2018): the solid simplified to planar faces, "
      "unfolded into nets, every fold given a curved actuator (active PLA lines across the hinge "
      "on a TPU layer) whose width bends it by the fold's angle, printed in two materials "
      "(two tools, or pauses to swap the filament). In 70 C water the sheet folds into the "
      "solid. Writes DIR/net.svg (the printed sheet), DIR/crease_pattern.svg and DIR/pattern.fold "
      "(Origami Simulator opens both), DIR/folded.ply (the folded sheet), DIR/flat.ply, "
      "DIR/plate.gcode (and DIR/plate_2.gcode, ... when the sheets need several beds), "
      "DIR/layers/, DIR/design.json and DIR/report.html. docs/origami.md explains each step.");
  sub->add_option("input", o->input,
                  "A mesh (.obj, .ply, .stl, .off: simplified to at most --faces planar faces) or "
                  "a crease pattern (.svg: outline black, mountains red, valleys blue, the angle "
                  "from data-fold-angle or the stroke opacity x 180 deg, as Origami Simulator)");
  sub->add_option("--example", o->example,
                  "A built-in solid: tetrahedron, cube, octahedron, dodecahedron, icosahedron, "
                  "pyramid or bunny");
  sub->add_option("--faces", o->faces, "At most this many faces (meshes and the bunny)")
      ->capture_default_str();
  sub->add_option("--size", o->size_mm,
                  "The solid's longest side, mm (0: as the file gives it; examples have their "
                  "own)")
      ->capture_default_str();
  sub->add_option("--material", o->material,
                  "The PLA of the faces and the actuators (see 'flatmorph materials'); its "
                  "hinge_curve, when calibrated, sets how far a hinge bends")
      ->capture_default_str();
  sub->add_option("--hinge-material", o->hinge_material, "The actuators' constraint layer (TPU)")
      ->capture_default_str();
  sub->add_option("--printer", o->printer,
                  "Printer preset or JSON file: two tools (T0 PLA, T1 TPU) or one with a "
                  "filament swap (see 'flatmorph printers')")
      ->capture_default_str();
  sub->add_option("--actuator-speed", o->actuator_speed,
                  "Print speed of the actuators' active PLA, mm/s: faster stores more stretch and "
                  "bends on a tighter arc (narrower actuators)")
      ->capture_default_str();
  sub->add_option("--actuator-width", o->actuator_width,
                  "Make every actuator this wide, mm, and solve each one's speed from its angle "
                  "(0: the width follows from --actuator-speed)")
      ->capture_default_str();
  sub->add_option("--flat-angle", o->flat_angle_deg,
                  "Folds of less than this many degrees print no actuator")
      ->capture_default_str();
  sub->add_flag("--case-b-hinges", o->case_b_hinges,
                "A mesh's valleys may print as case B hinges (TPU on the bed) though the hinge "
                "curve is uncalibrated: fewer nets, but such a hinge folds less than the curve "
                "promises once longer than wide, and each is named in a warning (default: they "
                "are cut, and every hinge is case A)");
  sub->add_flag("--simulate", o->simulate,
                "Fold each printed sheet with the shared simulator (faces and actuators meshed as "
                "one plate with the layers printed there, started from the design), once from the "
                "design's layers and once from what plate.gcode deposits: each hinge's simulated "
                "angles in design.json, DIR/sheet_simulated.ply and sheet_gcode_simulated.ply");
  sub->add_option("--fit-hinges", o->fit_hinges,
                  "Correct each actuator's width against the shared simulator, at most this many "
                  "rounds (each simulates every sheet on a 3 mm mesh and scales each width by "
                  "the square root of designed / simulated angle); the design whose worst hinge "
                  "came closest is printed. 0: the hinge curve's widths")
      ->capture_default_str();
  sub->add_option("--mesh-edge", o->mesh_edge_mm, "Longest edge of --simulate's mesh, mm")
      ->capture_default_str();
  sub->add_flag("!--no-slicer", o->slicer,
                "Do not run PrusaSlicer (when installed) for the solid's print time; use the "
                "volume estimate");
  sub->add_flag("!--no-gcode", o->gcode, "Skip the G-code");
  sub->add_flag("--json", o->json, "Print design.json on stdout at the end instead of the summary");
  sub->add_option("-o,--output", o->output, "Output folder (created if needed)")->required();
  return {sub, [o, &global] { return run_origami(*o, global); }};
}

}  // namespace flatmorph::cli
