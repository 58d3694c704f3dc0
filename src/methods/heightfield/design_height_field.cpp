#include "methods/heightfield/design_height_field.h"

#include <fmt/core.h>

#include <cmath>
#include <optional>

#include "common/error.h"
#include "common/stopwatch.h"
#include "methods/heightfield/shrinkage_field.h"

namespace flatmorph {
namespace {

// Per face, the mean of its corners' σ: what the optimization prints (optimize_shrinkage.h).
Eigen::VectorXd corner_mean(const Eigen::MatrixXi& F, const Eigen::VectorXd& vertex_values) {
  Eigen::VectorXd face_values(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    face_values(f) =
        (vertex_values(F(f, 0)) + vertex_values(F(f, 1)) + vertex_values(F(f, 2))) / 3.0;
  }
  return face_values;
}

}  // namespace

HeightFieldDesign design_height_field(const HeightField& field, const std::string& source,
                                      const HeightFieldDesignOptions& options) {
  const Material& material = options.material;
  const ThicknessCurve& curve = require_thickness_curve(material);
  if (options.num_layers < 0) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: {} layers requested: print at least 1 layer, or 0 for the "
                                "thickness curve's {}",
                                source, options.num_layers, curve.layers));
  }
  // One count for the stack simulated and the paths printed: they describe one plate.
  const std::optional<int> num_layers =
      options.num_layers > 0 ? std::optional<int>(options.num_layers) : std::nullopt;
  const auto start = Clock::now();
  const ProgressCallback& progress = options.progress;
  HeightFieldDesign design;

  report_progress(progress, {"mesh", 0, 0, NAN, "isolines and gradient lines"});
  auto t = Clock::now();
  design.mesh = isoline_mesh(field, options.meshing, source);
  design.times.meshing = seconds_since(t);
  const IsolineMesh& mesh = design.mesh;

  // The sheet is flattened for the growth the material has across the paths and for shrink from
  // 0 (SCF 2020 §8: only a path that must grow is invalid, besides one above the maximum) to the
  // most it gives; below the least shrink the curve reaches, paths print at that least one, and the
  // simulated shape (and the optimization) answers for it.
  SheetFlatteningOptions flattening = options.flattening;
  flattening.min_shrinkage = 0.0;
  flattening.max_shrinkage = reachable_shrinkage(curve).second;
  flattening.bridge_growth = material.lambda2;
  if (!flattening.progress && progress) {
    flattening.progress = [&](int step, double change, double max_height) {
      report_progress(progress, {"flatten", step, flattening.max_steps, change,
                                 fmt::format("height left {:.3g} mm", max_height)});
    };
  }
  report_progress(progress, {"flatten", 0, 0, NAN, "local/global steps with relocations"});
  t = Clock::now();
  design.sheet = flatten_sheet(mesh, flattening);
  design.times.flattening = seconds_since(t);
  const Eigen::MatrixXd& plate = design.sheet.plate;

  report_progress(progress,
                  {"simulate", 0, 0, NAN, "the flattening's shrink, from the flat sheet"});
  t = Clock::now();
  design.flattened_vertex_shrinkage =
      initial_vertex_shrinkage(mesh, plate, design.sheet.edge_shrinkage, material);
  const Eigen::VectorXd direction = deposition_directions(mesh, plate);
  design.flattened_plate = heightfield_plate(plate, mesh.F, direction,
                                             corner_mean(mesh.F, design.flattened_vertex_shrinkage),
                                             material, num_layers);
  // The simulation from the target (other stable shapes) is run once, on the design printed.
  RisePredictionOptions first_prediction = options.prediction;
  first_prediction.from_target = options.prediction.from_target && !options.optimize;
  design.flattened_prediction =
      predict_rise(design.flattened_plate.design, mesh.V, first_prediction);
  design.times.prediction = seconds_since(t);

  design.vertex_shrinkage = design.flattened_vertex_shrinkage;
  design.plate = design.flattened_plate;
  design.prediction = design.flattened_prediction;
  if (options.optimize) {
    report_progress(progress, {"optimize shrink", 0, 0, NAN, "adjoint Gauss-Newton"});
    t = Clock::now();
    ShrinkageProblem problem;
    problem.plate = plate;
    problem.F = mesh.F;
    problem.target = mesh.V;
    problem.direction = direction;
    problem.material = material;
    problem.num_layers = num_layers;
    // The equilibrium the flat sheet reaches: the optimization follows that branch.
    problem.start = design.flattened_prediction.from_flat.V;
    OptimizeShrinkageOptions optimization = options.optimization;
    if (!optimization.progress && progress) {
      optimization.progress = [&](const ShrinkageIteration& it) {
        report_progress(progress, {"optimize shrink", it.iteration + 1, optimization.max_iterations,
                                   it.objective, ""});
      };
    }
    design.optimization =
        optimize_shrinkage(problem, design.flattened_vertex_shrinkage, optimization);
    design.times.optimization = seconds_since(t);
    design.optimized = true;

    // The judge: the printed stack simulated from the flat sheet again, as it will rise.
    report_progress(progress, {"simulate", 0, 0, NAN, "the optimized shrink, from the flat sheet"});
    t = Clock::now();
    HeightFieldPlate optimized_plate = heightfield_plate(
        plate, mesh.F, direction, design.optimization.face_shrinkage, material, num_layers);
    RisePrediction optimized_prediction =
        predict_rise(optimized_plate.design, mesh.V, options.prediction);
    design.times.final_prediction = seconds_since(t);
    // Kept only when the sheet, risen from flat, comes closer than with the flattening's shrink:
    // the optimizer follows one equilibrium, and a sheet that snaps to another one is no better.
    if (optimized_prediction.distance.mean_mm <= design.flattened_prediction.distance.mean_mm) {
      design.vertex_shrinkage = design.optimization.vertex_shrinkage;
      design.plate = std::move(optimized_plate);
      design.prediction = std::move(optimized_prediction);
    }
  }

  if (options.paths) {
    report_progress(progress, {"trajectories", 0, 0, NAN, "continuous paths along the isolines"});
    t = Clock::now();
    ContinuousPathOptions path_options = options.path_options;
    path_options.num_layers = num_layers;
    design.paths = continuous_paths(mesh, plate, design.vertex_shrinkage, material, path_options);
    design.times.paths = seconds_since(t);
  }
  design.times.total = seconds_since(start);
  return design;
}

}  // namespace flatmorph
