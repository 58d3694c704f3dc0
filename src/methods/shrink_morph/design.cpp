#include "methods/shrink_morph/design.h"

#include <fmt/core.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/stopwatch.h"
#include "mesh/operators.h"
#include "mesh/prepare.h"
#include "mesh/topology.h"
#include "plate/laminate.h"
#include "simulate/simulate.h"

namespace flatmorph {
namespace {}  // namespace

double printed_side_agreement(const FlatPlate& flat, const Material& material,
                              double printed_thickness_mm) {
  const Eigen::MatrixXi& F = flat.target.F;
  const int nf = static_cast<int>(F.rows());
  const RestForms rest = shrink_morph_rest_forms(flat.theta1, Eigen::VectorXd::Zero(nf), material,
                                                 printed_thickness_mm);
  const std::vector<Eigen::Matrix3d> shape = shape_operators(flat.target.V, F, edge_topology(F));
  double cross = 0, target_norm = 0, rest_norm = 0;
  for (int f = 0; f < nf; ++f) {
    Eigen::Matrix2d plate_edges;
    plate_edges << (flat.plate.row(F(f, 1)) - flat.plate.row(F(f, 0))).transpose(),
        (flat.plate.row(F(f, 2)) - flat.plate.row(F(f, 0))).transpose();
    Eigen::Matrix<double, 3, 2> target_edges;
    target_edges << (flat.target.V.row(F(f, 1)) - flat.target.V.row(F(f, 0))).transpose(),
        (flat.target.V.row(F(f, 2)) - flat.target.V.row(F(f, 0))).transpose();
    const double area = 0.5 * std::abs(plate_edges.determinant());
    if (!(area > 0)) continue;
    // The differential of the map plate → target, and b pulled back to plate coordinates.
    const Eigen::Matrix<double, 3, 2> J = target_edges * plate_edges.inverse();
    const Eigen::Matrix2d b = J.transpose() * shape[f] * J;
    const Eigen::Matrix2d& b_bar = rest.rest_second_fundamental_form[f];
    cross += area * (b.array() * b_bar.array()).sum();
    target_norm += area * b.squaredNorm();
    rest_norm += area * b_bar.squaredNorm();
  }
  const double denominator = std::sqrt(target_norm * rest_norm);
  return denominator > 0 ? cross / denominator : 0.0;
}

Design design_shrink_morph(Mesh target, const std::string& source, const DesignOptions& options) {
  if (!(options.width_mm > 0) || !(options.w_D >= 0) || options.faces < 1 || options.layers < 2) {
    throw UserError(ErrorCategory::kOption,
                    "design: the width must be positive, w_D non-negative, the face count at least "
                    "1 and the layer count at least 2");
  }
  auto progress = [&](const std::string& stage, const std::string& detail) {
    report_progress(options.progress, {stage, 0, 0, NAN, detail});
  };
  Design out;
  DesignMetrics& m = out.metrics;

  auto t0 = Clock::now();
  target = prepare_target(std::move(target), source, options.faces).mesh;
  m.t_prepare_s = seconds_since(t0);
  m.faces = target.num_faces();
  m.vertices = target.num_vertices();
  progress("prepare", fmt::format("{} faces, {} vertices", m.faces, m.vertices));

  t0 = Clock::now();
  FlattenOptions flatten_options;
  flatten_options.lambda1 = options.material.lambda1;
  flatten_options.lambda2 = options.material.lambda2;
  flatten_options.width_mm = options.width_mm;
  flatten_options.w_D = options.w_D;
  const double printed_thickness = options.layers * options.material.layer_height;
  flatten_options.flip = options.side == PrintedSide::kNormalDown;
  flatten_options.progress = options.progress;
  out.flat = flatten(target, flatten_options);
  out.side_agreement = printed_side_agreement(out.flat, options.material, printed_thickness);
  m.t_param_s = seconds_since(t0);
  Eigen::MatrixXd equilibrium;  // with theta2 = 0, when found while choosing the side
  if (options.side == PrintedSide::kAutomatic) {
    const double kClearAgreement = 0.2;
    const int kSideChoiceIterations = 40;
    if (out.side_agreement <= -kClearAgreement) {
      // Flipping mirrors the plate and negates the agreement: the other side bends the right way.
      flatten_options.flip = true;
      out.flat = flatten(target, flatten_options);
      out.side_agreement = printed_side_agreement(out.flat, options.material, printed_thickness);
      m.t_param_s = seconds_since(t0);
    } else if (out.side_agreement < kClearAgreement) {
      // Not clear from the curvature alone (the stretch, not the bilayer, dominates the bending):
      // simulate both sides with theta2 = 0 and keep the one that lands closer to the target.
      flatten_options.flip = true;
      FlatPlate other = flatten(target, flatten_options);
      m.t_param_s = seconds_since(t0);
      const auto t_sim = Clock::now();
      auto equilibrium_of = [&](const FlatPlate& flat) {
        PlateProblem plate;
        plate.plate = flat.plate;
        plate.F = flat.target.F;
        plate.rest_forms =
            shrink_morph_rest_forms(flat.theta1, Eigen::VectorXd::Zero(flat.target.num_faces()),
                                    options.material, printed_thickness);
        plate.stiffness = stiffness_of(options.material);
        // The right side settles in a few tens of Newton iterations; the wrong one wanders (the
        // hat's takes 123 to a state of twice the energy), and need not be finished to lose.
        SimulationOptions capped = options.optimize.forward;
        capped.max_iterations = std::min(capped.max_iterations, kSideChoiceIterations);
        return simulate(plate, flat.target.V, capped);
      };
      progress("choose side", "simulating both sides with theta2 = 0");
      const SimulationResult up = equilibrium_of(out.flat);
      const SimulationResult down = equilibrium_of(other);
      const double up_distance = shape_distance(up.V, out.flat.target.V).mean_percent;
      const double down_distance = shape_distance(down.V, other.target.V).mean_percent;
      m.t_sim_s = seconds_since(t_sim);
      progress("choose side",
               fmt::format("theta2 = 0 lands {:.2f} % from the target with its normal side up{}, "
                           "{:.2f} % with it down{}",
                           up_distance, up.converged ? "" : " (still moving)", down_distance,
                           down.converged ? "" : " (still moving)"));
      // A side still moving after the cap is leaving the target's neighbourhood; an unfinished
      // state's distance says nothing yet.
      const bool down_wins =
          down.converged != up.converged ? down.converged : down_distance < up_distance;
      if (down_wins) {
        out.flat = std::move(other);
        out.side_agreement = printed_side_agreement(out.flat, options.material, printed_thickness);
        equilibrium = down.V;
      } else {
        flatten_options.flip = false;
        equilibrium = up.V;
      }
    }
  }
  out.flipped = flatten_options.flip;
  progress("flatten", fmt::format("the target's normal side {} (curvature agreement {:.2f})",
                                  out.flipped ? "down" : "up", out.side_agreement));

  Theta2Problem problem;
  problem.plate = out.flat.plate;
  problem.F = out.flat.target.F;
  problem.target = out.flat.target.V;
  problem.theta1 = out.flat.theta1;
  problem.material = options.material;
  problem.printed_thickness = printed_thickness;
  problem.start = equilibrium;

  OptimizeTheta2Options optimize = options.optimize;
  const auto t_optim = Clock::now();
  if (!optimize.progress && options.progress) {
    optimize.progress = [&](const Theta2Iteration& it) {
      report_progress(
          options.progress,
          {"optimize theta2", it.iteration + 1, 0, it.objective,
           fmt::format("step {:.3g} ({} trials, {} Newton iterations), {} CG iterations", it.step,
                       it.line_search_trials, it.forward_iterations, it.cg_iterations)});
    };
  }
  progress("simulate", "theta2 = 0, from the target");
  out.optimization = optimize_theta2(problem, {}, optimize);
  // The optimizer's first equilibrium is the theta2 = 0 simulation from the target (already found
  // when both sides were simulated).
  m.t_sim_s += out.optimization.initial_seconds;
  m.t_optim_s = seconds_since(t_optim) - out.optimization.initial_seconds;
  out.simulated = out.optimization.initial_V;
  out.optimized = out.optimization.V;
  out.theta2 = out.optimization.theta2;
  out.dist_to_sim = shape_distance(out.simulated, problem.target);
  out.dist_to_optim = shape_distance(out.optimized, problem.target);
  m.dist_to_sim_avg_pct = out.dist_to_sim.mean_percent;
  m.dist_to_sim_max_pct = out.dist_to_sim.max_percent;
  m.dist_to_optim_avg_pct = out.dist_to_optim.mean_percent;
  m.dist_to_optim_max_pct = out.dist_to_optim.max_percent;
  m.theta2_max_abs_rad = out.theta2.size() ? out.theta2.cwiseAbs().maxCoeff() : 0.0;
  m.theta2_dirichlet = out.theta2.dot(cotan_laplacian(problem.target, problem.F) * out.theta2);
  m.optim_iterations = out.optimization.iterations;
  m.optim_converged = out.optimization.converged;
  progress("optimize theta2",
           fmt::format("{} iterations ({}), distance to target {:.3f} % -> {:.3f} % average, "
                       "{:.3f} % -> {:.3f} % max; {:.1f} s in Gauss-Newton solves, {:.1f} s in "
                       "forward solves",
                       m.optim_iterations, out.optimization.stop_reason, m.dist_to_sim_avg_pct,
                       m.dist_to_optim_avg_pct, m.dist_to_sim_max_pct, m.dist_to_optim_max_pct,
                       out.optimization.cg_seconds, out.optimization.forward_seconds));
  return out;
}

}  // namespace flatmorph
