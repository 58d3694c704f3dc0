#include "methods/origami/sheet_simulation.h"

#include <fmt/core.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.h"
#include "mesh/sheet_mesh.h"
#include "plate/laminate.h"

namespace flatmorph {
namespace {

constexpr int kArcSteps = 64;  // the curved model's arcs, fine enough to start the simulator on

// The designed (curved) position of flat point p of actuator a: across the strip along its arc,
// along it between its two end polylines.
Eigen::Vector3d on_strip(const Actuator& actuator, const ActuatorStrip& strip,
                         const Eigen::Vector2d& p) {
  const Eigen::Vector2d q0 = actuator.quad.row(0).transpose();
  const Eigen::Vector2d q1 = actuator.quad.row(1).transpose();
  const double across = std::clamp((p - q0).dot(actuator.across) / actuator.hinge.width, 0.0, 1.0);
  const Eigen::Vector2d along = q1 - q0;
  const double t = std::clamp((p - q0).dot(along) / along.squaredNorm(), 0.0, 1.0);
  const double x = across * kArcSteps;
  const int i = std::min(static_cast<int>(x), kArcSteps - 1);
  const double u = x - i;
  const Eigen::Vector3d a = (1 - u) * strip.side0.row(i) + u * strip.side0.row(i + 1);
  const Eigen::Vector3d b = (1 - u) * strip.side1.row(i) + u * strip.side1.row(i + 1);
  return a + t * (b - a);
}

}  // namespace

std::vector<double> hinge_fold_angles(const ActuatedSheet& sheet, const Eigen::MatrixXd& flat,
                                      const Eigen::MatrixXi& F, const Eigen::VectorXi& piece,
                                      const Eigen::MatrixXd& V) {
  // The triangles within kBand of the actuator's ends: the actuator's own bend, apart from how
  // the faces themselves warp.
  constexpr double kBand = 3;  // mm
  std::vector<double> angles;
  for (const Actuator& actuator : sheet.actuators) {
    Eigen::Vector3d side_normal[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    for (Eigen::Index t = 0; t < F.rows(); ++t) {
      const int f = piece(t);
      const int side = f == actuator.parent_face ? 0 : f == actuator.child_face ? 1 : -1;
      if (side < 0) continue;
      const Eigen::Vector2d centroid =
          (flat.row(F(t, 0)) + flat.row(F(t, 1)) + flat.row(F(t, 2))).leftCols<2>().transpose() / 3;
      const Eigen::Vector2d end = actuator.quad.row(side == 0 ? 0 : 3).transpose();
      if (std::abs((centroid - end).dot(actuator.across)) > kBand) continue;
      const Eigen::Vector3d a = V.row(F(t, 0)).transpose();
      const Eigen::Vector3d b = V.row(F(t, 1)).transpose();
      const Eigen::Vector3d c = V.row(F(t, 2)).transpose();
      side_normal[side] += (b - a).cross(c - a);
    }
    const double cosine =
        std::clamp(side_normal[0].normalized().dot(side_normal[1].normalized()), -1.0, 1.0);
    angles.push_back(std::copysign(std::acos(cosine), actuator.hinge.fold_angle));
  }
  return angles;
}

SheetSimulation simulate_sheet(const OrigamiDesign& design, int index,
                               const OrigamiOptions& options, double max_edge) {
  const OrigamiSheet& sheet = design.sheets.at(index);
  const ActuatedSheet& printed = sheet.sheet;
  const int num_faces = static_cast<int>(printed.faces.size());
  std::vector<PlaneRegion> regions;
  for (int f = 0; f < num_faces; ++f) {
    regions.push_back({printed.faces[f], {}, "face " + std::to_string(f + 1)});
  }
  for (size_t a = 0; a < printed.actuators.size(); ++a) {
    regions.push_back({printed.actuators[a].quad, {}, "actuator " + std::to_string(a + 1)});
  }
  SheetMeshOptions mesh_options;
  mesh_options.max_edge = max_edge;
  const SheetMesh mesh = sheet_mesh(regions, mesh_options);

  SheetSimulation out;
  out.piece = mesh.face_region;
  out.plate.method = "origami";
  out.plate.plate = mesh.V;
  out.plate.F = mesh.F;
  out.plate.stack =
      printed_sheet_stack({sheet}, Eigen::VectorXi::Zero(mesh.F.rows()), mesh.face_region, options);

  // The start: each vertex where the curved model puts it, through the first triangle met.
  const FoldedSheet folded = fold_curved(sheet.pattern, printed, 1.0, kArcSteps);
  std::vector<RigidFit> face_motion(num_faces);
  for (int f = 0; f < num_faces; ++f) {
    Eigen::MatrixXd flat = Eigen::MatrixXd::Zero(printed.faces[f].rows(), 3);
    flat.leftCols(2) = printed.faces[f];
    face_motion[f] = best_rigid_fit(flat, folded.faces[f]);
  }
  out.designed = Eigen::MatrixXd::Zero(mesh.V.rows(), 3);
  std::vector<bool> placed(mesh.V.rows(), false);
  for (Eigen::Index t = 0; t < mesh.F.rows(); ++t) {
    const int piece = mesh.face_region(t);
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(t, k);
      if (placed[v]) continue;
      placed[v] = true;
      const Eigen::Vector2d p = mesh.V.row(v).transpose();
      if (piece < num_faces) {
        out.designed.row(v) = (face_motion[piece].rotation * Eigen::Vector3d(p.x(), p.y(), 0) +
                               face_motion[piece].translation)
                                  .transpose();
      } else {
        out.designed.row(v) =
            on_strip(printed.actuators[piece - num_faces], folded.actuators[piece - num_faces], p)
                .transpose();
      }
    }
  }

  PlateProblem problem;
  problem.plate = mesh.V;
  problem.F = mesh.F;
  problem.rest_forms = laminate(out.plate.stack);
  out.result = simulate(problem, out.designed);
  out.to_design = shape_distance(rigidly_aligned(out.result.V, out.designed), out.designed);

  out.fold_angle = hinge_fold_angles(printed, mesh.V, mesh.F, mesh.face_region, out.result.V);
  return out;
}

double worst_hinge_error(const OrigamiDesign& design,
                         const std::vector<std::vector<double>>& angles) {
  double worst = 0;
  for (size_t i = 0; i < angles.size(); ++i) {
    for (size_t a = 0; a < angles[i].size(); ++a) {
      worst = std::max(
          worst, std::abs(angles[i][a] - design.sheets[i].sheet.actuators[a].hinge.fold_angle));
    }
  }
  return worst;
}

HingeFit fit_hinges_to_simulation(const OrigamiDesign& design, const OrigamiOptions& options,
                                  int max_rounds, double tolerance, double max_edge) {
  if (max_rounds < 1) throw std::invalid_argument("fit_hinges_to_simulation: at least one round");
  HingeFit fit;
  OrigamiDesign current = design;
  double best = INFINITY;
  for (int round = 0; round < max_rounds; ++round) {
    double worst = 0;
    std::vector<std::vector<double>> scale(current.sheets.size());
    for (size_t s = 0; s < current.sheets.size(); ++s) {
      report_progress(options.progress,
                      {"fit hinges", round + 1, max_rounds, NAN,
                       fmt::format("{}, round {}", current.sheets[s].pattern.name, round + 1)});
      const SheetSimulation simulated =
          simulate_sheet(current, static_cast<int>(s), options, max_edge);
      const std::vector<Actuator>& actuators = current.sheets[s].sheet.actuators;
      for (size_t a = 0; a < actuators.size(); ++a) {
        const double designed = actuators[a].hinge.fold_angle;
        const double reached = simulated.fold_angle[a];
        worst = std::max(worst, std::abs(reached - designed));
        // The fold grows about in proportion to the strip's width (θ = κ W); half the step, as
        // the hinges of a face pull on each other.
        const double ratio = reached * designed > 0 ? std::sqrt(designed / reached) : 1.5;
        scale[s].push_back(std::clamp(ratio, 2.0 / 3, 1.5));
      }
    }
    fit.worst_error.push_back(worst);
    if (worst < best) {
      best = worst;
      fit.best_round = round;
      fit.design = current;
    }
    if (worst <= tolerance || round + 1 == max_rounds) break;
    try {
      current = with_hinges_widened(current, scale, options);
    } catch (const UserError& e) {
      fit.stopped = e.what();  // the widths that would not print: the best so far stays
      break;
    }
  }
  return fit;
}

}  // namespace flatmorph
