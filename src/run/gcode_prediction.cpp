#include "run/gcode_prediction.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "common/stopwatch.h"
#include "plate/laminate.h"

namespace flatmorph {

GcodePrediction predict_from_gcode(std::string_view text, const std::string& source,
                                   const std::vector<Material>& tool_materials,
                                   const GcodePredictionOptions& options) {
  GcodePrediction out;
  auto t0 = Clock::now();
  const GcodeDeposition deposition = read_gcode_deposition(text, source, options.read);
  out.read_seconds = seconds_since(t0);
  out.num_beads = static_cast<int>(deposition.beads.size());

  t0 = Clock::now();
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  if (options.plate_V.rows() > 0) {
    V = options.plate_V.leftCols<2>();
    F = options.plate_F;
    if (deposition.header.plate_to_bed) {
      out.plate_to_bed = *deposition.header.plate_to_bed;
      out.placed_by_header = true;
    } else {
      const Eigen::Vector2d centre =
          (V.colwise().minCoeff() + V.colwise().maxCoeff()).transpose() / 2;
      out.plate_to_bed = first_layer_bounds(deposition, options.deposit).center() - centre;
    }
  } else {
    FootprintMesh footprint = footprint_plate(deposition, source, options.deposit);
    out.footprint_frame = footprint.frame;
    V = std::move(footprint.V);
    F = std::move(footprint.F);
  }
  const Eigen::MatrixXd on_bed = V.rowwise() + out.plate_to_bed.transpose();
  out.plate = deposited_plate(deposition, on_bed, F, tool_materials, source, options.deposit);
  out.plate.design.plate.rowwise() -= out.plate_to_bed.transpose();
  out.rasterize_seconds = seconds_since(t0);

  PlateProblem problem;
  problem.plate = out.plate.design.plate;
  problem.F = out.plate.design.F;
  problem.rest_forms = laminate(out.plate.design.stack);
  Eigen::MatrixXd start;
  if (options.start.rows() > 0) {
    if (options.start.rows() != options.plate_V.rows() || options.start.cols() != 3) {
      throw std::invalid_argument(
          "predict_from_gcode: the start needs one 3D row per plate vertex");
    }
    start = options.start(out.plate.kept_vertices, Eigen::all);
  } else {
    start = flat_start(problem);
  }
  out.result = simulate(problem, start, options.simulation);
  return out;
}

ClosedLoop close_the_loop(std::string_view gcode, const std::string& source,
                          const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                          const std::vector<Material>& tool_materials, const Eigen::MatrixXd& start,
                          const Eigen::MatrixXd& target, const Eigen::MatrixXd& fields_prediction,
                          const DepositedPlateOptions& deposit) {
  GcodePredictionOptions options;
  options.deposit = deposit;
  options.plate_V = plate;
  options.plate_F = F;
  options.start = start;
  ClosedLoop loop;
  loop.prediction = predict_from_gcode(gcode, source, tool_materials, options);
  const Eigen::VectorXi& kept = loop.prediction.plate.kept_vertices;
  const Eigen::MatrixXd& predicted = loop.prediction.result.V;
  const Eigen::MatrixXd kept_target = target(kept, Eigen::all);
  const Eigen::MatrixXd kept_fields = fields_prediction(kept, Eigen::all);
  loop.on_target = rigidly_aligned(predicted, kept_target);
  loop.to_target = shape_distance(loop.on_target, kept_target);
  // In % of the target's diagonal, as every other distance of a run.
  ShapeDistance to_fields = shape_distance(rigidly_aligned(predicted, kept_fields), kept_fields);
  const double diagonal = loop.to_target.diagonal_mm;
  to_fields.diagonal_mm = diagonal;
  to_fields.mean_percent = 100 * to_fields.mean_mm / diagonal;
  to_fields.max_percent = 100 * to_fields.max_mm / diagonal;
  loop.to_prediction = to_fields;
  return loop;
}

}  // namespace flatmorph
