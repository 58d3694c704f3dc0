// The plate simulator: one full equilibrium solve at the paper's hat size (11008 faces), from the
// target and from the flat plate, and its two costs separately (Hessian assembly, Cholesky
// factorization); disks printed along their radii, 20 to 80 mm across, from flat. Counters give
// Newton iterations and where the time went (seconds).
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

#include "../tests/plate/plate_fixtures.h"
#include "mesh/io.h"
#include "mesh/subdivide.h"
#include "methods/shrink_morph/flatten.h"
#include "numerics/sparse_cholesky.h"
#include "plate/laminate.h"
#include "simulate/distance.h"
#include "simulate/plate_energy.h"
#include "simulate/simulate.h"

namespace flatmorph {
namespace {

struct Case {
  PlateProblem problem;
  Eigen::MatrixXd target;  // a 3D start shape
};

// The paper's hat (Table 1: 2752 faces Loop-subdivided once to 11008, 100 mm wide, w_D = 0.1),
// flattened, θ2 = 0, 10 layers of 0.08 mm of the paper's PLA. Its face normals point to the convex
// side, so it is flattened with flip: the concave side is printed on top, where the bilayer term
// (the top shrinks more) bends it the right way.
const Case* hat_case() {
  static const Case* c = [] {
    const std::filesystem::path path =
        std::filesystem::path(FLATMORPH_SHARED_DIR) / "meshes/hat.obj";
    if (!std::filesystem::exists(path)) return static_cast<Case*>(nullptr);
    const Mesh mesh = loop_subdivide_to(read_mesh(path).mesh, 10000).mesh;
    FlattenOptions options;
    options.width_mm = 100;
    options.w_D = 0.1;
    options.flip = true;
    const FlatPlate flat = flatten(mesh, options);
    const Material m;
    auto* out = new Case;
    out->problem.plate = flat.plate;
    out->problem.F = flat.target.F;
    out->problem.rest_forms = laminate(shrink_morph_layer_stack(
        flat.theta1, Eigen::VectorXd::Zero(flat.theta1.size()), m, 10, m.layer_height));
    out->target = flat.target.V;
    return out;
  }();
  return c;
}

// A procedural plate of the same size: a 100 mm disk of 11094 faces printed in concentric circles,
// which rises into a cone-like dome; its "target" is its own equilibrium, smoothly perturbed by up
// to 1 mm (a target is a smooth surface near, not at, the equilibrium).
const Case* disk_case() {
  static const Case* c = [] {
    const testing::TestPlate plate = testing::disk_plate(50, 43);
    const int nf = static_cast<int>(plate.F.rows());
    Eigen::VectorXd theta1(nf);
    for (int f = 0; f < nf; ++f) {
      const Eigen::RowVector2d centroid =
          (plate.V.row(plate.F(f, 0)) + plate.V.row(plate.F(f, 1)) + plate.V.row(plate.F(f, 2))) /
          3;
      theta1(f) = std::atan2(centroid.y(), centroid.x()) + M_PI / 2;
    }
    const Material m;
    auto* out = new Case;
    out->problem.plate = plate.V;
    out->problem.F = plate.F;
    out->problem.rest_forms = laminate(
        shrink_morph_layer_stack(theta1, Eigen::VectorXd::Zero(nf), m, 10, m.layer_height));
    out->target = simulate(out->problem, flat_start(out->problem)).V;
    for (Eigen::Index v = 0; v < out->target.rows(); ++v) {
      const double x = plate.V(v, 0), y = plate.V(v, 1);
      out->target.row(v) += Eigen::RowVector3d(0.3 * std::sin(y / 10), 0.3 * std::cos(x / 12),
                                               std::sin(x / 15) * std::cos(y / 20));
    }
    return out;
  }();
  return c;
}

void report(benchmark::State& state, const SimulationResult& r, const Case& c) {
  state.counters["faces"] = static_cast<double>(c.problem.F.rows());
  state.counters["newton_iterations"] = r.iterations;
  state.counters["projected_iterations"] = r.projected_iterations;
  state.counters["stimulus_steps"] = r.stimulus_steps;
  state.counters["converged"] = r.converged;
  state.counters["assembly_s"] = r.assembly_seconds;
  state.counters["factorization_s"] = r.factorization_seconds;
  state.counters["solve_s"] = r.solve_seconds;
  state.counters["line_search_s"] = r.line_search_seconds;
  const ShapeDistance d = shape_distance(rigidly_aligned(r.V, c.target), c.target);
  state.counters["dist_avg_percent"] = d.mean_percent;
  state.counters["dist_max_percent"] = d.max_percent;
}

void solve(benchmark::State& state, const Case* c, bool from_flat) {
  if (c == nullptr) {
    state.SkipWithError("shared/meshes/hat.obj not found");
    return;
  }
  SimulationResult r;
  const Eigen::MatrixXd start = from_flat ? flat_start(c->problem) : c->target;
  for (auto _ : state) {
    r = simulate(c->problem, start);
    benchmark::DoNotOptimize(r.energy);
  }
  report(state, r, *c);
}

void BM_SimulateHatFromTarget(benchmark::State& state) { solve(state, hat_case(), false); }
void BM_SimulateHatFromFlat(benchmark::State& state) { solve(state, hat_case(), true); }
void BM_SimulateDiskFromPerturbedEquilibrium(benchmark::State& state) {
  solve(state, disk_case(), false);
}
void BM_SimulateDiskFromFlat(benchmark::State& state) { solve(state, disk_case(), true); }

// A disk printed along its radii, Arg mm across (the paper's PLA, 10 layers, rings 1 mm apart),
// from flat: the rest metric is a cone with an angle excess, which the plate takes by buckling into
// a saddle (docs/simulation.md). Before the stimulus was applied in steps, the 80 mm disk crawled
// for 1000 Newton iterations (over 8 minutes). The label is the stop reason.
void BM_SimulateRadialDiskFromFlat(benchmark::State& state) {
  const double radius = static_cast<double>(state.range(0)) / 2;
  const testing::TestPlate plate = testing::disk_plate(radius, static_cast<int>(radius));
  const int nf = static_cast<int>(plate.F.rows());
  Eigen::VectorXd theta1(nf);
  for (int f = 0; f < nf; ++f) {
    const Eigen::RowVector2d centroid =
        (plate.V.row(plate.F(f, 0)) + plate.V.row(plate.F(f, 1)) + plate.V.row(plate.F(f, 2))) / 3;
    theta1(f) = std::atan2(centroid.y(), centroid.x());
  }
  const Material m;
  PlateProblem problem;
  problem.plate = plate.V;
  problem.F = plate.F;
  problem.rest_forms =
      laminate(shrink_morph_layer_stack(theta1, Eigen::VectorXd::Zero(nf), m, 10, m.layer_height));
  SimulationResult r;
  for (auto _ : state) {
    r = simulate(problem, flat_start(problem));
    benchmark::DoNotOptimize(r.energy);
  }
  // The total Gaussian curvature: the angle defects of the interior vertices (the boundary ring
  // lies at the radius).
  Eigen::VectorXd angles = Eigen::VectorXd::Zero(plate.V.rows());
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = r.V.row(plate.F(f, k)), b = r.V.row(plate.F(f, (k + 1) % 3)),
                            c = r.V.row(plate.F(f, (k + 2) % 3));
      angles(plate.F(f, k)) += std::acos((b - a).normalized().dot((c - a).normalized()));
    }
  }
  double curvature = 0;
  for (Eigen::Index v = 0; v < plate.V.rows(); ++v) {
    if (plate.V.row(v).norm() < radius - 0.5) curvature += 2 * M_PI - angles(v);
  }
  state.counters["faces"] = nf;
  state.counters["newton_iterations"] = r.iterations;
  state.counters["projected_iterations"] = r.projected_iterations;
  state.counters["stimulus_steps"] = r.stimulus_steps;
  state.counters["converged"] = r.converged;
  state.counters["gaussian_curvature"] = curvature;
  state.counters["cone_excess"] = 2 * M_PI * (1 - m.lambda2 / m.lambda1);
  state.SetLabel(stop_reason(r));
}

// One energy + gradient + Hessian evaluation (exact, or with per-face PSD projection) on the hat.
void BM_PlateEnergyHessian(benchmark::State& state) {
  const Case* c = hat_case();
  if (c == nullptr) {
    state.SkipWithError("shared/meshes/hat.obj not found");
    return;
  }
  const PlateEnergy energy =
      make_plate_energy(c->problem.plate, c->problem.F, c->problem.rest_forms);
  Eigen::VectorXd x(c->target.size());
  for (Eigen::Index v = 0; v < c->target.rows(); ++v)
    x.segment<3>(3 * v) = c->target.row(v).transpose();
  Eigen::VectorXd g;
  Eigen::SparseMatrix<double> h;
  const bool project = state.range(0) != 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(evaluate_plate_energy(energy, x, &g, &h, project));
  }
  state.counters["nonzeros"] = static_cast<double>(h.nonZeros());
}

// One numeric Cholesky factorization (CHOLMOD supernodal, symbolic analysis done once) of the
// hat's projected Hessian at the target, as Newton does every iteration.
void BM_PlateHessianFactorization(benchmark::State& state) {
  const Case* c = hat_case();
  if (c == nullptr) {
    state.SkipWithError("shared/meshes/hat.obj not found");
    return;
  }
  const PlateEnergy energy =
      make_plate_energy(c->problem.plate, c->problem.F, c->problem.rest_forms);
  Eigen::VectorXd x(c->target.size());
  for (Eigen::Index v = 0; v < c->target.rows(); ++v)
    x.segment<3>(3 * v) = c->target.row(v).transpose();
  Eigen::SparseMatrix<double> h;
  evaluate_plate_energy(energy, x, nullptr, &h, true);
  // Remove the rigid null space the way a small shift does, so the matrix is positive definite.
  for (int k = 0; k < h.outerSize(); ++k) h.coeffRef(k, k) += 1e-8 * h.coeff(k, k);
  SparseCholesky solver;
  solver.cholmod().print = 0;
  analyze_pattern(solver, h);
  for (auto _ : state) {
    factorize(solver, h);
    benchmark::DoNotOptimize(solver.info());
  }
  state.counters["factor_nonzeros"] = solver.cholmod().lnz;
  state.counters["factor_gflop"] = solver.cholmod().fl * 1e-9;
}

BENCHMARK(BM_SimulateHatFromTarget)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_SimulateHatFromFlat)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_SimulateDiskFromPerturbedEquilibrium)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();
BENCHMARK(BM_SimulateDiskFromFlat)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_SimulateRadialDiskFromFlat)
    ->Arg(20)
    ->Arg(40)
    ->Arg(80)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();
BENCHMARK(BM_PlateEnergyHessian)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PlateHessianFactorization)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace flatmorph
