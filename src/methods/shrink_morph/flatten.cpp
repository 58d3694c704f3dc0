// The Shrink & Morph flattening pipeline (§3.2.1) and the measures of its result.
#include "methods/shrink_morph/flatten.h"

#include <fmt/core.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "common/error.h"
#include "common/stopwatch.h"
#include "mesh/topology.h"
#include "methods/shrink_morph/flatten_internal.h"

namespace flatmorph {
namespace {

using namespace shrink_morph_internal;

void check_options(const FlattenOptions& o) {
  require_option(std::isfinite(o.lambda1) && std::isfinite(o.lambda2) && o.lambda1 > 0 &&
                     o.lambda2 > 0 && o.lambda1 <= o.lambda2,
                 fmt::format("material: shrink ratios lambda1 = {}, lambda2 = {} are not usable; "
                             "they must be positive with lambda1 (along the path) <= lambda2",
                             o.lambda1, o.lambda2));
  require_option(
      std::isfinite(o.width_mm) && o.width_mm > 0,
      fmt::format("--width {}: the plate width must be a positive number of mm", o.width_mm));
  require_option(o.stretch_candidate >= -1 && o.stretch_candidate < kStretchCandidates,
                 fmt::format("flatten: stretch candidate {} must be -1 (automatic) or 0 to {}",
                             o.stretch_candidate, kStretchCandidates - 1));
  require_option(std::isfinite(o.w_D) && o.w_D >= 0,
                 fmt::format("--wD {}: the smoothing weight must be 0 (none) or positive", o.w_D));
  require_option(std::isfinite(o.tolerance) && o.tolerance > 0 && o.max_iterations >= 1 &&
                     std::isfinite(o.newton_tolerance) && o.newton_tolerance > 0 &&
                     o.max_newton_iterations >= 1,
                 "flatten: tolerances must be positive and iteration caps at least 1");
  require_option(o.w_D == 0 || o.lambda1 < o.lambda2,
                 fmt::format("--wD {}: smoothing needs a material that shrinks anisotropically "
                             "(lambda1 < lambda2, got {} and {}); use --wD 0",
                             o.w_D, o.lambda1, o.lambda2));
}

int count_flipped(const Eigen::MatrixXd& P, const Eigen::MatrixXi& F) {
  int flipped = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector2d ab = (P.row(F(f, 1)) - P.row(F(f, 0))).transpose();
    const Eigen::Vector2d ac = (P.row(F(f, 2)) - P.row(F(f, 0))).transpose();
    if (!(ab(0) * ac(1) - ab(1) * ac(0) > 0)) ++flipped;
  }
  return flipped;
}

// Directions tried for the initial stretch (evenly spread over the half turn), and how many
// local/global iterations each gets before the best is chosen: enough for the energies to rank the
// local minima they lead to on the paper's meshes.
constexpr int kCandidateIterations = 50;

// Rotation of the ARAP plate that the anisotropic stretch diag(s1, s2) fits best: the angle phi in
// [0, pi) minimizing sum_f A_f min_T ||S_phi J_f - T||^2 over T with singular values (s1, s2), with
// S_phi = R(phi) diag(s1, s2) R(phi)^T. It depends only on the plate (not on how the target sits
// in space). Sampled every degree, then refined by a parabola through the best sample and its
// neighbours, so that a rotated plate gives the rotated angle rather than the nearest sample.
double best_stretch_angle(const Eigen::MatrixXd& P, const Eigen::MatrixXi& F,
                          const RestFrames& frames, double s1, double s2) {
  const int nf = static_cast<int>(F.rows());
  std::vector<Eigen::Matrix2d> J(nf);
  for (int f = 0; f < nf; ++f) J[f] = plate_differential(P, F, frames, f);
  auto energy = [&](double phi) {
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(phi).toRotationMatrix();
    const Eigen::Matrix2d S = R * Eigen::Vector2d(s1, s2).asDiagonal() * R.transpose();
    double sum = 0;
    for (int f = 0; f < nf; ++f) {
      const Eigen::Matrix2d M = S * J[f];
      const ConformalSplit split = conformal_split(M);
      sum += frames.area(f) * (M.squaredNorm() + s1 * s1 + s2 * s2 -
                               2 * (split.sigma1() * s1 + split.sigma2() * s2));
    }
    return sum;
  };
  constexpr int kSamples = 180;
  constexpr double kStep = std::numbers::pi / kSamples;
  Eigen::VectorXd samples(kSamples);
  for (int k = 0; k < kSamples; ++k) samples(k) = energy(k * kStep);
  Eigen::Index best = 0;
  samples.minCoeff(&best);
  // E has period pi, so the neighbours wrap around.
  const double left = samples((best + kSamples - 1) % kSamples);
  const double right = samples((best + 1) % kSamples);
  const double curvature = left - 2 * samples(best) + right;
  const double offset = curvature > 0 ? 0.5 * (left - right) / curvature : 0.0;
  return (static_cast<double>(best) + offset) * kStep;
}

}  // namespace

FlattenOptions flatten_options(const Material& material, double width_mm, double w_D) {
  FlattenOptions options;
  options.lambda1 = material.lambda1;
  options.lambda2 = material.lambda2;
  options.width_mm = width_mm;
  options.w_D = w_D;
  return options;
}

FlatPlate flatten(const Mesh& input, const FlattenOptions& options) {
  check_options(options);
  FlatPlate result;
  result.target = input;
  Mesh& target = result.target;
  // Reversing every face swaps which side the plate's +z (top) is; the vertex order is kept.
  if (options.flip) target.F.col(1).swap(target.F.col(2));
  const Eigen::MatrixXd& V = target.V;
  const Eigen::MatrixXi& F = target.F;
  int phase = 0;
  const int phases = options.w_D > 0 ? 4 : 3;
  auto add_step = [&](FlattenStep step) {
    report_progress(options.progress,
                    {"flatten", ++phase, phases, NAN,
                     fmt::format("{}, {} iterations{}", step.name, step.iterations,
                                 step.converged ? "" : " (not converged)")});
    result.steps.push_back(std::move(step));
  };

  Eigen::VectorXi component;
  const std::vector<std::vector<int>> loops = boundary_loops(F);
  const int pieces = F.rows() > 0 ? face_components(F, component) : 0;
  const int euler = euler_characteristic(F);
  if (pieces != 1 || loops.size() != 1 || euler != 1) {
    throw UserError(ErrorCategory::kTopology,
                    fmt::format("target: flattening needs a disk (one piece, one boundary loop, no "
                                "handles), got {} piece(s), {} boundary loop(s), Euler "
                                "characteristic {}; cut the surface open or fill its holes in a "
                                "mesh editor",
                                pieces, loops.size(), euler));
  }
  std::vector<bool> used(target.num_vertices(), false);
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) used[F(f, k)] = true;
  }
  const auto unused = std::find(used.begin(), used.end(), false);
  if (unused != used.end()) {
    throw UserError(ErrorCategory::kTopology,
                    fmt::format("target: vertex {} belongs to no face; remove unreferenced "
                                "vertices (flatmorph's repair does when it reads a mesh)",
                                unused - used.begin()));
  }
  const RestFrames frames = rest_frames(V, F);
  const double total_area = frames.area.sum();
  const double s1 = 1.0 / options.lambda1, s2 = 1.0 / options.lambda2;  // Eq. 11 targets

  // Tutte on a circle of the target's area (the right scale for ARAP). The boundary loop has the
  // surface on its left and runs counter-clockwise, so every triangle starts positive.
  auto start = Clock::now();
  const Eigen::MatrixXd tutte =
      tutte_embedding(V, F, loops[0], std::sqrt(total_area / std::numbers::pi));
  add_step({"tutte", 1, seconds_since(start), true});

  auto warn_cap = [&](const char* name) {
    result.warnings.push_back(
        fmt::format("{} local/global stopped at the iteration cap ({}) before converging; raise "
                    "the cap or loosen the tolerance",
                    name, options.max_iterations));
  };

  start = Clock::now();
  const LocalGlobal solver(F, frames, target.num_vertices());
  Eigen::MatrixXd P = tutte;
  const LocalGlobalStats arap =
      solver.solve(P, 1.0, 1.0, options.tolerance, options.max_iterations);
  add_step({"arap", arap.iterations, seconds_since(start), arap.converged});
  if (!arap.converged) warn_cap("ARAP");

  // The paper's start for Eq. 11: the ARAP plate stretched by (1/lambda1, 1/lambda2). Which plate
  // direction gets 1/lambda1 decides which local minimum the iterations reach, and the best
  // direction is not known beforehand (the reference uses the target's x axis, which a rotated
  // input would change). So several directions are tried for a few iterations each, and the one
  // with the lowest Eq. 11 energy is carried on to convergence (unless the caller names one:
  // FlattenOptions::stretch_candidate).
  start = Clock::now();
  const double phi0 = best_stretch_angle(P, F, frames, s1, s2);
  const bool chosen = options.stretch_candidate >= 0;
  Eigen::MatrixXd best;
  LocalGlobalStats best_stats;
  int anisotropic_iterations = 0;
  for (int k = chosen ? options.stretch_candidate : 0;
       k < (chosen ? options.stretch_candidate + 1 : kStretchCandidates); ++k) {
    // Clockwise on a flipped target, whose ARAP plate is the mirror image.
    const double phi = phi0 + (options.flip ? -1 : 1) * std::numbers::pi * k / kStretchCandidates;
    Eigen::MatrixXd candidate = P * Eigen::Rotation2Dd(phi).toRotationMatrix();  // rows by -phi
    candidate.col(0) *= s1;
    candidate.col(1) *= s2;
    const LocalGlobalStats stats =
        solver.solve(candidate, s1, s2, options.tolerance,
                     std::min(kCandidateIterations, options.max_iterations));
    anisotropic_iterations += stats.iterations;
    if (best.size() == 0 || stats.energy < best_stats.energy) {
      best = std::move(candidate);
      best_stats = stats;
      result.stretch_candidate = k;
    }
  }
  P = std::move(best);
  if (!best_stats.converged && options.max_iterations > best_stats.iterations) {
    const LocalGlobalStats stats =
        solver.solve(P, s1, s2, options.tolerance, options.max_iterations - best_stats.iterations);
    anisotropic_iterations += stats.iterations;
    best_stats.converged = stats.converged;
  }
  add_step({"anisotropic", anisotropic_iterations, seconds_since(start), best_stats.converged});
  if (!best_stats.converged) warn_cap("anisotropic");

  // Local/global does not guarantee positive triangles, even with the orientation-preserving local
  // step. Should it leave a flipped one (not seen on the paper's meshes or the examples), Eq. 12 is
  // solved by Newton from the flip-free Tutte embedding instead: its line search rejects any step
  // that flips a triangle, so the plate stays flip-free all the way.
  const int flipped = count_flipped(P, F);
  const bool restart = flipped > 0;
  if (restart) {
    result.warnings.push_back(fmt::format(
        "local/global left {} flipped triangle(s); the plate was re-solved by Newton from the "
        "Tutte embedding",
        flipped));
    P = tutte;
  }
  if (options.w_D > 0 || restart) {
    start = Clock::now();
    const SmoothingStats stats =
        smooth_directions(P, F, frames, dual_edges(V, F, frames), s1, s2, options.w_D,
                          options.newton_tolerance, options.max_newton_iterations);
    add_step({"smoothing", stats.iterations, seconds_since(start), stats.converged});
    if (!stats.converged) {
      result.warnings.push_back(
          fmt::format("Eq. 12 Newton stopped after {} iterations before converging (cap {})",
                      stats.iterations, options.max_newton_iterations));
    }
  }

  // Centre the bounding box on the origin and scale to the requested width; the target follows,
  // scaled about its own bounding-box centre.
  const Eigen::RowVector2d low = P.colwise().minCoeff(), high = P.colwise().maxCoeff();
  const double scale = options.width_mm / (high - low).maxCoeff();
  P = (P.rowwise() - 0.5 * (low + high)) * scale;
  const Eigen::RowVector3d centre = 0.5 * (V.colwise().minCoeff() + V.colwise().maxCoeff());
  target.V = ((V.rowwise() - centre) * scale).rowwise() + centre;

  result.plate = std::move(P);
  result.singular_values = plate_singular_values(target.V, F, result.plate);
  result.theta1 = theta1_per_face(target.V, F, result.plate);
  result.sv_deviation = shrink_deviation(result.singular_values, options.lambda1, options.lambda2);
  result.feasibility = shrink_feasibility(result.sv_deviation, frames.area);
  result.direction_dirichlet = direction_dirichlet_energy(target.V, F, result.theta1);
  return result;
}

Eigen::MatrixXd plate_singular_values(const Eigen::MatrixXd& target_V, const Eigen::MatrixXi& F,
                                      const Eigen::MatrixXd& plate) {
  const RestFrames frames = rest_frames(target_V, F);
  const Eigen::MatrixXd P = plate.leftCols(2);
  Eigen::MatrixXd sigma(F.rows(), 2);
  for (int f = 0; f < F.rows(); ++f) {
    const ConformalSplit split = conformal_split(plate_differential(P, F, frames, f));
    sigma(f, 0) = split.sigma1();
    sigma(f, 1) = split.sigma2();
  }
  return sigma;
}

Eigen::VectorXd theta1_per_face(const Eigen::MatrixXd& target_V, const Eigen::MatrixXi& F,
                                const Eigen::MatrixXd& plate) {
  Eigen::VectorXd theta1(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Matrix<double, 3, 2> X;
    Eigen::Matrix2d Q;
    for (int k = 0; k < 2; ++k) {
      X.col(k) = (target_V.row(F(f, k + 1)) - target_V.row(F(f, 0))).transpose();
      Q.col(k) = (plate.row(F(f, k + 1)).head<2>() - plate.row(F(f, 0)).head<2>()).transpose();
    }
    const Eigen::Matrix<double, 3, 2> D = X * Q.inverse();  // plate -> target
    const Eigen::Matrix2d I = D.transpose() * D;
    // atan2 gives twice the angle of the major eigenvector; the minor one is a quarter turn away.
    const double twice_major = std::atan2(2 * I(0, 1), I(0, 0) - I(1, 1));
    theta1(f) = twice_major < 0 ? 0.5 * (twice_major + std::numbers::pi)
                                : 0.5 * (twice_major - std::numbers::pi);
  }
  return theta1;
}

Eigen::VectorXd shrink_deviation(const Eigen::MatrixXd& singular_values, double lambda1,
                                 double lambda2) {
  return (singular_values.col(0).array() * lambda1 - 1.0)
      .abs()
      .max((singular_values.col(1).array() * lambda2 - 1.0).abs());
}

ShrinkFeasibility shrink_feasibility(const Eigen::VectorXd& deviation,
                                     const Eigen::VectorXd& face_areas, double tolerance) {
  ShrinkFeasibility feasibility;
  const double total = face_areas.sum();
  if (deviation.size() == 0 || !(total > 0)) return feasibility;
  feasibility.mean_deviation = deviation.dot(face_areas) / total;
  feasibility.max_deviation = deviation.maxCoeff();
  feasibility.infeasible_area_fraction =
      (deviation.array() > tolerance).select(face_areas.array(), 0.0).sum() / total;
  return feasibility;
}

double direction_dirichlet_energy(const Eigen::MatrixXd& target_V, const Eigen::MatrixXi& F,
                                  const Eigen::VectorXd& theta1) {
  const DualEdges edges = dual_edges(target_V, F, rest_frames(target_V, F));
  double energy = 0;
  for (size_t e = 0; e < edges.weight.size(); ++e) {
    const double s = std::sin(theta1(edges.face_f[e]) - theta1(edges.face_g[e]));
    energy += edges.weight[e] * 4.0 * s * s;
  }
  return energy;
}

}  // namespace flatmorph
