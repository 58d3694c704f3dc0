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
#include "plate/plate_file.h"
#include "simulate/distance.h"
#include "simulate/simulate.h"

namespace flatmorph::cli {
namespace {

struct SimulateOptions {
  std::string plate_path;
  std::string material = "pla-paper";
  int layers = 10;
  std::string from = "flat";
  std::string target_path;
  std::string output;
};

Eigen::MatrixXd read_shape(const std::string& path, const PlateFile& plate, const char* role) {
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
  if (o.layers < 1 || o.layers > 1000) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--layers {} is out of range: give 1 to 1000 layers", o.layers));
  }
  if (std::filesystem::path(o.output).extension() != ".ply") {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("-o {}: the predicted shape is written as PLY; name it *.ply", o.output));
  }
  const Material material = load_material(o.material);
  const PlateFile plate = read_plate_file(o.plate_path);

  PlateProblem problem;
  problem.plate = plate.plate;
  problem.F = plate.F;
  problem.rest_forms =
      laminate(shrink_morph_layer_stack(plate.theta1, vertex_to_face_average(plate.F, plate.theta2),
                                        material, o.layers, material.layer_height));

  Eigen::MatrixXd target;
  if (!o.target_path.empty()) target = read_shape(o.target_path, plate, "target");
  Eigen::MatrixXd start;
  if (o.from != "flat") start = read_shape(o.from, plate, "start shape");

  if (!global.quiet) {
    fmt::print("plate: {} ({} vertices, {} faces), material {}, {} layers of {} mm\n", o.plate_path,
               plate.plate.rows(), plate.F.rows(), material.name, o.layers, material.layer_height);
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
  if (!global.quiet) fmt::print("wrote {}\n", o.output);
  return 0;
}

}  // namespace

Command make_simulate_command(CLI::App& app, const GlobalOptions& global) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand(
      "simulate",
      "Predict the shape a printed plate takes in hot water: the equilibrium of the orthotropic "
      "non-Euclidean plate energy (Shrink & Morph §3.1) of the layers printed along theta1 "
      "(per face) and theta2 (per vertex) stored in flat.ply.");
  sub->add_option("plate", o->plate_path, "flat.ply written by 'flatmorph flatten' or 'design'")
      ->required();
  sub->add_option("--material", o->material, "Material preset name or JSON file")
      ->capture_default_str();
  sub->add_option("--layers", o->layers,
                  "Number of printed layers (each of the material's layer "
                  "height)")
      ->capture_default_str();
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
