// flatmorph simulate: predict the shape a printed plate takes in hot water.
#include <fmt/core.h>

#include <cmath>
#include <filesystem>

#include "commands.h"
#include "common/error.h"
#include "material/material.h"
#include "mesh/io.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "plate/plate_design.h"
#include "plate_input.h"
#include "simulate/distance.h"
#include "simulate/simulate.h"

namespace flatmorph::cli {
namespace {

struct SimulateOptions {
  std::string plate_path;
  PlateInputOptions plate_input;
  std::string from = "flat";
  std::string target_path;
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

void print_result(const char* label, const SimulationResult& r) {
  fmt::print(
      "{}: energy {:.6g} mJ (membrane {:.4g}, bending {:.4g}), {} Newton iterations ({} "
      "projected), {}, {:.2f} s\n",
      label, r.energy, r.membrane_energy, r.bending_energy, r.iterations, r.projected_iterations,
      to_string(r.status), r.seconds);
}

int run_simulate(const SimulateOptions& o, const GlobalOptions& global) {
  if (std::filesystem::path(o.output).extension() != ".ply") {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("-o {}: the predicted shape is written as PLY; name it *.ply", o.output));
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

  if (!global.quiet) {
    fmt::print("plate: {} ({} vertices, {} faces), {}\n", o.plate_path, plate.plate.rows(),
               plate.F.rows(), describe_stack(plate.stack));
  }
  SimulationResult result;
  // With a 3D start, both starts are simulated so that several stable shapes can be reported.
  if (start.size() > 0) {
    const ForwardComparison c = simulate_from_start_and_flat(problem, start);
    result = c.from_start;
    if (!global.quiet) {
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
    result = simulate(problem, flat_start(problem));
    if (!global.quiet) print_result("from flat", result);
  }
  if (!result.converged) {
    fmt::print(stderr, "flatmorph: warning: simulation: {}\n",
               result.warning.empty() ? std::string(to_string(result.status)) : result.warning);
  }

  MeshProperties properties;
  // A shape simulated from flat has no reason to sit where the target does: align it rigidly
  // before measuring (a 3D start keeps the result registered to that start).
  if (target.size() > 0 && start.size() == 0) result.V = rigidly_aligned(result.V, target);
  if (target.size() > 0) {
    const ShapeDistance d = shape_distance(result.V, target);
    properties.set_vertex("deviation_mm", d.per_vertex_mm);
    if (!global.quiet) {
      fmt::print(
          "distance to target: average {:.3f} % / max {:.3f} % of the diagonal ({:.3f} / "
          "{:.3f} mm, diagonal {:.1f} mm)\n",
          d.mean_percent, d.max_percent, d.mean_mm, d.max_mm, d.diagonal_mm);
    }
  }
  write_ply(o.output, Mesh{result.V, plate.F}, properties);
  if (!stack_warning.empty()) fmt::print(stderr, "flatmorph: warning: {}\n", stack_warning);
  if (!global.quiet) fmt::print("wrote {}\n", o.output);
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
      "directions; docs/plate.md).");
  sub->add_option("plate", o->plate_path, "flat.ply written by 'flatmorph flatten' or 'design'")
      ->required();
  add_plate_input_options(sub, o->plate_input);
  sub->add_option("--from", o->from,
                  "Start state: 'flat' (the plate with a tiny bump following its rest curvature: "
                  "the honest forward prediction) or a mesh with the plate's vertex order, e.g. "
                  "target.ply (also simulates from flat and warns if the two end differently)")
      ->capture_default_str();
  sub->add_option("--target", o->target_path,
                  "Target shape (target.ply) to measure the predicted shape against: adds the "
                  "per-vertex property deviation_mm and prints the distances (a shape simulated "
                  "from flat is first moved rigidly onto the target)");
  sub->add_option("-o,--output", o->output, "Predicted shape (.ply), same vertex and face order")
      ->required();
  return {sub, [o, &global] { return run_simulate(*o, global); }};
}

}  // namespace flatmorph::cli
