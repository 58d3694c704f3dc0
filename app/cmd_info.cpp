// flatmorph info: what a mesh file holds and whether flatmorph can use it as a target.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "mesh/operators.h"
#include "mesh/prepare.h"
#include "mesh/topology.h"
#include "mesh/validate.h"
#include "mesh_input.h"

namespace flatmorph::cli {
namespace {

struct InfoOptions {
  RunInput input;
  bool json = false;
};

int run_info(const InfoOptions& options) {
  const std::string source = describe(options.input);
  MeshFile file;
  try {
    file = read_target_mesh(options.input);
  } catch (const MeshReadError& e) {
    if (options.json) {
      nlohmann::json j = {{"file", source},
                          {"valid", false},
                          {"vertices_read", e.vertices_read},
                          {"faces_read", e.faces_read},
                          {"error", e.what()},
                          {"error_category", to_string(e.category())}};
      fmt::print("{}\n", j.dump(2));
    } else {
      fmt::print(
          "file:            {}\nread before the error: {} vertices, {} faces\nvalid:       "
          "     no\n",
          source, e.vertices_read, e.faces_read);
    }
    fmt::print(stderr, "flatmorph: error [{}]: {}\n", to_string(e.category()), e.what());
    return 2;
  }

  Mesh mesh = file.mesh;
  const int vertices_read = mesh.num_vertices(), faces_read = mesh.num_faces();
  const RepairReport repair = repair_mesh(mesh);
  const MeshDiagnosis diagnosis = diagnose_mesh(mesh);

  nlohmann::json j;
  j["file"] = source;
  j["vertices"] = vertices_read;
  j["faces"] = faces_read;
  j["repair"] = {{"welded_vertices", repair.welded_vertices},
                 {"unreferenced_vertices", repair.unreferenced_vertices},
                 {"degenerate_faces", repair.degenerate_faces},
                 {"duplicate_faces", repair.duplicate_faces},
                 {"flipped_faces", repair.flipped_faces}};
  j["edges"] = diagnosis.num_edges;
  j["boundary_loops"] = diagnosis.num_boundary_loops;
  j["components"] = diagnosis.num_components;
  j["euler_characteristic"] = diagnosis.euler_characteristic;

  bool finite = mesh.num_vertices() > 0 && mesh.V.allFinite();
  if (finite) {
    const BoundingBox box = bounding_box(mesh.V);
    j["bounding_box"] = {{"min", {box.min.x(), box.min.y(), box.min.z()}},
                         {"max", {box.max.x(), box.max.y(), box.max.z()}},
                         {"diagonal", box.diagonal()}};
    j["area"] = mesh.num_faces() ? face_areas(mesh.V, mesh.F).sum() : 0.0;
  }
  // Curvature needs a manifold, finite mesh; skip it otherwise rather than guess.
  const bool curvature_ok =
      finite && mesh.num_faces() > 0 &&
      std::none_of(diagnosis.problems.begin(), diagnosis.problems.end(), [](const MeshProblem& p) {
        return p.category == ErrorCategory::kGeometry ||
               p.what.find("non-manifold") != std::string::npos;
      });
  if (curvature_ok) {
    const EdgeTopology topology = edge_topology(mesh.F);
    Eigen::VectorXd mean, gaussian;
    face_curvatures(shape_operators(mesh.V, mesh.F, topology), face_normals(mesh.V, mesh.F), mean,
                    gaussian);
    j["mean_curvature"] = {mean.minCoeff(), mean.maxCoeff()};
    j["gaussian_curvature"] = {gaussian.minCoeff(), gaussian.maxCoeff()};
  }
  j["valid"] = diagnosis.is_disk();
  if (!diagnosis.is_disk()) {
    j["problems"] = nlohmann::json::array();
    for (const MeshProblem& p : diagnosis.problems) {
      j["problems"].push_back({{"category", to_string(p.category)},
                               {"what", p.what},
                               {"count", p.count},
                               {"first", p.first},
                               {"fix", p.fix}});
    }
  }

  if (options.json) {
    fmt::print("{}\n", j.dump(2));
  } else {
    fmt::print("file:                 {}\n", source);
    fmt::print("vertices:             {}\n", vertices_read);
    fmt::print("faces:                {}\n", faces_read);
    if (repair.welded_vertices || repair.unreferenced_vertices || repair.degenerate_faces ||
        repair.duplicate_faces || repair.flipped_faces) {
      fmt::print(
          "repair:               {} welded, {} unreferenced vertices; {} degenerate, {} "
          "duplicate faces removed; {} faces flipped -> {} vertices, {} faces\n",
          repair.welded_vertices, repair.unreferenced_vertices, repair.degenerate_faces,
          repair.duplicate_faces, repair.flipped_faces, mesh.num_vertices(), mesh.num_faces());
    }
    if (finite) {
      const BoundingBox box = bounding_box(mesh.V);
      fmt::print("bounding box:         [{:.4g}, {:.4g}] x [{:.4g}, {:.4g}] x [{:.4g}, {:.4g}]\n",
                 box.min.x(), box.max.x(), box.min.y(), box.max.y(), box.min.z(), box.max.z());
      fmt::print("size:                 {:.4g} x {:.4g} x {:.4g} (diagonal {:.4g})\n",
                 box.extent().x(), box.extent().y(), box.extent().z(), box.diagonal());
      fmt::print("area:                 {:.6g}\n", j["area"].get<double>());
    }
    fmt::print("edges:                {}\n", diagnosis.num_edges);
    fmt::print("components:           {}\n", diagnosis.num_components);
    fmt::print("boundary loops:       {}\n", diagnosis.num_boundary_loops);
    fmt::print("euler characteristic: {}\n", diagnosis.euler_characteristic);
    if (curvature_ok) {
      fmt::print(
          "mean curvature:       [{:.4g}, {:.4g}] (1/length; > 0 where the surface bends "
          "toward its normals)\n",
          j["mean_curvature"][0].get<double>(), j["mean_curvature"][1].get<double>());
      fmt::print("gaussian curvature:   [{:.4g}, {:.4g}] (1/length^2)\n",
                 j["gaussian_curvature"][0].get<double>(),
                 j["gaussian_curvature"][1].get<double>());
    }
    fmt::print("valid:                {}\n",
               diagnosis.is_disk() ? "yes (a disk-like surface flatmorph can use)" : "no");
    for (const MeshProblem& p : diagnosis.problems) {
      fmt::print("problem:              {}\n", problem_line(source, p));
    }
  }
  if (!diagnosis.is_disk()) {
    fmt::print(stderr, "flatmorph: error [{}]: {}\n",
               to_string(diagnosis.problems.front().category),
               problem_line(source, diagnosis.problems.front()));
    return 2;
  }
  return 0;
}

}  // namespace

Command make_info_command(CLI::App& app, const GlobalOptions&) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* sub = app.add_subcommand(
      "info",
      "Show what a mesh holds (vertices, faces, bounding box, area, boundary loops, Euler "
      "characteristic, curvature ranges) and whether it is a disk-like surface flatmorph can "
      "use. Exits with status 2, after printing what it could read, when it is not.");
  add_mesh_input(sub, options->input);
  sub->add_flag("--json", options->json, "Print a JSON object instead of text");
  return {sub, [options] { return run_info(*options); }};
}

}  // namespace flatmorph::cli
