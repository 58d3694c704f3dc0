#include "methods/heightfield/rise_prediction.h"

#include <fmt/core.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/error.h"
#include "common/stopwatch.h"
#include "mesh/topology.h"
#include "methods/heightfield/shrinkage_field.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"

namespace flatmorph {
namespace {

// The angle of the segment a -> b in the plate, folded to [0, π): a path has no sign.
double line_angle(const Eigen::MatrixXd& plate, int a, int b) {
  const double angle = std::atan2(plate(b, 1) - plate(a, 1), plate(b, 0) - plate(a, 0));
  double folded = std::fmod(angle, std::numbers::pi);
  if (folded < 0) folded += std::numbers::pi;
  return folded >= std::numbers::pi ? 0.0 : folded;
}

}  // namespace

Eigen::VectorXd deposition_directions(const IsolineMesh& mesh, const Eigen::MatrixXd& plate) {
  if (plate.rows() != mesh.V.rows() || plate.cols() < 2 ||
      mesh.vertex_level.size() != mesh.V.rows()) {
    throw std::invalid_argument(
        fmt::format("deposition directions: a plate of {} vertices and {} levels for a mesh of {} "
                    "vertices: give one flat position and one level per vertex",
                    plate.rows(), mesh.vertex_level.size(), mesh.V.rows()));
  }
  Eigen::VectorXd direction(mesh.F.rows());
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    int base = -1;  // the corner the base edge starts at (corner -> corner + 1)
    int centre = -1;
    for (int k = 0; k < 3; ++k) {
      if (mesh.vertex_level(mesh.F(f, k)) < 0) centre = k;
    }
    if (centre >= 0) {
      base = (centre + 1) % 3;  // the rim edge: the two corners after the centre
    } else {
      for (int k = 0; k < 3; ++k) {
        if (mesh.vertex_level(mesh.F(f, k)) == mesh.vertex_level(mesh.F(f, (k + 1) % 3))) {
          base = k;
          break;
        }
      }
    }
    if (base < 0) {
      throw std::invalid_argument(fmt::format(
          "face {} of the printing graph has no edge along a level (levels {}, {}, {}): the "
          "isoline mesh breaks its contract (isoline_mesh.h)",
          f, mesh.vertex_level(mesh.F(f, 0)), mesh.vertex_level(mesh.F(f, 1)),
          mesh.vertex_level(mesh.F(f, 2))));
    }
    direction(f) = line_angle(plate, mesh.F(f, base), mesh.F(f, (base + 1) % 3));
  }
  return direction;
}

HeightFieldPlate heightfield_plate(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                                   const Eigen::VectorXd& direction,
                                   const Eigen::VectorXd& face_shrinkage, const Material& material,
                                   std::optional<int> num_layers) {
  if (direction.size() != F.rows() || face_shrinkage.size() != F.rows() || plate.cols() != 2) {
    throw std::invalid_argument(
        fmt::format("height-field plate: {} directions and {} shrinkages for {} faces (plate of {} "
                    "columns): give one of each per face and a 2D plate",
                    direction.size(), face_shrinkage.size(), F.rows(), plate.cols()));
  }
  ThicknessControlledStack printed =
      thickness_controlled_layer_stack(direction, face_shrinkage, material, num_layers);
  HeightFieldPlate out;
  out.direction = direction;
  out.wanted_shrinkage = face_shrinkage;
  out.clamped = printed.clamped;
  out.shrinkage = printed.shrinkage;
  const Layer& first = printed.stack.layers.front();
  out.design.plate = plate;
  out.design.F = F;
  out.design.method = "heightfield";
  out.design.design_fields.set_face("shrinkage", out.shrinkage);
  out.design.design_fields.set_face("wanted_shrinkage", face_shrinkage);
  out.design.design_fields.set_face("layer_height", first.printed_thickness);
  out.design.design_fields.set_face("direction", direction);
  out.design.design_fields.set_face("shrinkage_clamped", out.clamped.cast<double>());
  out.design.stack = std::move(printed.stack);
  return out;
}

HeightFieldPlate heightfield_plate(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                   const Eigen::VectorXd& edge_shrinkage, const Material& material,
                                   std::optional<int> num_layers) {
  return heightfield_plate(plate.leftCols(2), mesh.F, deposition_directions(mesh, plate),
                           face_shrinkage(mesh, plate, edge_shrinkage), material, num_layers);
}

Eigen::MatrixXd biased_flat_start(const Eigen::MatrixXd& plate, double bias) {
  Eigen::MatrixXd start = Eigen::MatrixXd::Zero(plate.rows(), 3);
  if (plate.rows() == 0) return start;
  start.leftCols(2) = plate.leftCols(2);
  const Eigen::RowVector2d center = plate.leftCols(2).colwise().mean();
  const double diagonal =
      (plate.leftCols(2).colwise().maxCoeff() - plate.leftCols(2).colwise().minCoeff()).norm();
  const double radius2 = (plate.leftCols(2).rowwise() - center).rowwise().squaredNorm().maxCoeff();
  if (!(radius2 > 0)) return start;
  for (Eigen::Index v = 0; v < plate.rows(); ++v) {
    const double r2 = (plate.row(v).head<2>() - center).squaredNorm();
    start(v, 2) = bias * (1 - r2 / radius2) * diagonal;
  }
  return start;
}

double height_above_boundary_plane(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<int> boundary;
  for (const std::vector<int>& loop : boundary_loops(F)) {
    boundary.insert(boundary.end(), loop.begin(), loop.end());
  }
  if (boundary.size() < 3 || V.rows() == 0) return 0;
  Eigen::RowVector3d center = Eigen::RowVector3d::Zero();
  for (int v : boundary) center += V.row(v);
  center /= static_cast<double>(boundary.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int v : boundary) {
    const Eigen::Vector3d d = (V.row(v) - center).transpose();
    scatter += d * d.transpose();
  }
  // The plane's normal: the direction in which the boundary spreads least.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  if (normal.z() < 0) normal = -normal;
  return ((V.rowwise() - center) * normal).mean();
}

RisePrediction predict_rise(const PlateDesign& design, const Eigen::MatrixXd& target,
                            const RisePredictionOptions& options) {
  const auto t0 = Clock::now();
  if (target.rows() != design.plate.rows() || target.cols() != 3) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("the target has {} x {} coordinates for a plate of {} vertices: "
                                "give one 3D position per plate vertex, in order",
                                target.rows(), target.cols(), design.plate.rows()));
  }
  PlateProblem problem;
  problem.plate = design.plate;
  problem.F = design.F;
  problem.rest_forms = laminate(design.stack);
  RisePrediction out;
  out.from_flat =
      simulate(problem, biased_flat_start(design.plate, options.bias), options.simulation);
  out.rise_mm = height_above_boundary_plane(out.from_flat.V, design.F);
  const double diagonal = (target.colwise().maxCoeff() - target.colwise().minCoeff()).norm();
  // A rise below a millionth of the size is the flat state (no buckling).
  out.side = std::abs(out.rise_mm) <= 1e-6 * diagonal ? 0 : (out.rise_mm > 0 ? 1 : -1);
  out.aligned = rigidly_aligned(out.from_flat.V, target);
  out.distance = shape_distance(out.aligned, target);
  if (options.from_target) {
    out.has_from_target = true;
    SimulationOptions check = options.simulation;
    check.max_iterations = options.from_target_max_iterations;
    out.from_target = simulate(problem, target, check);
    out.from_target_distance = shape_distance(rigidly_aligned(out.from_target.V, target), target);
    const Eigen::MatrixXd other = rigidly_aligned(out.from_target.V, out.aligned);
    const ShapeDistance difference = shape_distance(other, out.aligned);
    out.starts_difference_mm = difference.max_mm;
    out.starts_difference_percent = diagonal > 0 ? 100 * difference.max_mm / diagonal : 0;
    // Unconverged states prove nothing either way: not agreeing, then.
    out.starts_agree = out.from_flat.converged && out.from_target.converged &&
                       out.starts_difference_percent <= options.agreement_percent;
  }
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace flatmorph
