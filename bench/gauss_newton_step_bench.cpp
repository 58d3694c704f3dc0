// One Gauss–Newton step of the theta2 optimization by the reduced system (conjugate gradients,
// what optimize_theta2 uses) against the SGN KKT system (gauss_newton_step.h), on the paper's
// saddle and hat at the theta2 of two optimization iterations (so that the step is not the first
// one from zeros). BM_GaussNewtonStep/<model>/<system>: the step's seconds (manual time: the
// forward solve and what every system shares are not counted), CG iterations, the KKT matrix's
// size, the split of the direct solve, and rel_diff, |Δθ − Δθ*| / |Δθ*| with Δθ* the reduced
// system solved by CG to a relative residual of 1e-10.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <string>

#include "material/material.h"
#include "mesh/io.h"
#include "mesh/subdivide.h"
#include "methods/shrink_morph/flatten.h"
#include "methods/shrink_morph/gauss_newton_step.h"
#include "methods/shrink_morph/optimize_theta2.h"

namespace flatmorph {
namespace {

struct StepModel {
  const char* name;
  int faces;
  double width_mm;
  double w_D;
  bool flip;       // the printed side design_shrink_morph chooses (docs/design.md, Table 1)
  int iterations;  // of the benchmark (a KKT step takes 10-20 s on the hat)
};

constexpr StepModel kStepModels[] = {
    {"saddle", 2048, 100, 0.0, true, 3},
    {"hat", 11008, 100, 0.1, false, 1},
};

struct StepVariant {
  const char* name;
  GaussNewtonSystem system;
  KktSolver kkt_solver;
  double cg_tolerance;
  int max_cg_iterations;  // the default (200) for the production setting, no cap for the tight one
};

constexpr StepVariant kVariants[] = {
    {"reduced_cg_1e-2", GaussNewtonSystem::kReducedCG, KktSolver::kSparseLU, 1e-2, 200},
    {"reduced_cg_1e-6", GaussNewtonSystem::kReducedCG, KktSolver::kSparseLU, 1e-6, 100000},
    {"kkt_sparselu", GaussNewtonSystem::kKKT, KktSolver::kSparseLU, 0, 0},
    {"kkt_simplicial_ldlt", GaussNewtonSystem::kKKT, KktSolver::kSimplicialLDLT, 0, 0},
    {"kkt_cholmod_ldlt", GaussNewtonSystem::kKKT, KktSolver::kCholmodLDLT, 0, 0},
    {"kkt_simplicial_ldlt_by_vertex", GaussNewtonSystem::kKKT, KktSolver::kSimplicialLDLTByVertex,
     0, 0},
    {"kkt_cholmod_ldlt_by_vertex", GaussNewtonSystem::kKKT, KktSolver::kCholmodLDLTByVertex, 0, 0},
};

// The problem at the theta2 of two iterations, started from their equilibrium, and the reference
// direction there; built once per model.
struct Prepared {
  Theta2Problem problem;
  Eigen::VectorXd theta2, exact_direction;
  int exact_cg_iterations = 0;
};

const Prepared* prepare(const StepModel& model, benchmark::State& state) {
  static std::map<std::string, Prepared> cache;
  if (auto it = cache.find(model.name); it != cache.end()) return &it->second;
  const std::filesystem::path path =
      std::filesystem::path(FLATMORPH_SHARED_DIR) / "meshes" / (std::string(model.name) + ".obj");
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("../shared/meshes is not beside the project");
    return nullptr;
  }
  const Material material = load_material("pla-paper");
  const Mesh mesh = loop_subdivide_to(read_mesh(path).mesh, model.faces).mesh;
  FlattenOptions options = flatten_options(material, model.width_mm, model.w_D);
  options.flip = model.flip;
  const FlatPlate flat = flatten(mesh, options);
  Prepared p;
  p.problem = theta2_problem(flat, material, 10);
  OptimizeTheta2Options two;
  two.max_iterations = 2;
  const Theta2Result r = optimize_theta2(p.problem, {}, two);
  p.theta2 = r.theta2;
  p.problem.start = r.V;
  OptimizeTheta2Options exact;
  exact.cg_tolerance = 1e-10;
  exact.max_cg_iterations = 100000;
  const GaussNewtonStep reference =
      theta2_gauss_newton_step(p.problem, p.theta2, GaussNewtonSystem::kReducedCG, exact);
  p.exact_direction = reference.direction;
  p.exact_cg_iterations = reference.cg_iterations;
  return &cache.emplace(model.name, std::move(p)).first->second;
}

void BM_GaussNewtonStep(benchmark::State& state, const StepModel& model,
                        const StepVariant& variant) {
  const Prepared* p = prepare(model, state);
  if (!p) return;
  OptimizeTheta2Options options;
  if (variant.cg_tolerance > 0) {
    options.cg_tolerance = variant.cg_tolerance;
    options.max_cg_iterations = variant.max_cg_iterations;
  }
  // Sums over the iterations, reported as averages.
  std::map<std::string, double> sums;
  for (auto _ : state) {
    const GaussNewtonStep step = theta2_gauss_newton_step(p->problem, p->theta2, variant.system,
                                                          options, variant.kkt_solver);
    if (!step.solved) {
      state.SkipWithError("the factorization failed");
      return;
    }
    state.SetIterationTime(step.seconds);
    sums["step_s"] += step.seconds;
    sums["cg_it"] += step.cg_iterations;
    sums["assembly_s"] += step.assembly_seconds;
    sums["analysis_s"] += step.analysis_seconds;
    sums["factor_s"] += step.factorization_seconds;
    sums["solve_s"] += step.solve_seconds;
    sums["rel_diff"] += (step.direction - p->exact_direction).norm() / p->exact_direction.norm();
    sums["residual"] += step.reduced_residual;
    state.counters["kkt_rows"] = step.kkt_rows;
    state.counters["kkt_nnz"] = step.kkt_nonzeros;
    state.counters["factor_nnz"] = step.factor_nonzeros;
  }
  for (const auto& [name, sum] : sums) {
    state.counters[name] = benchmark::Counter(sum, benchmark::Counter::kAvgIterations);
  }
  state.counters["vertices"] = p->problem.plate.rows();
  state.counters["exact_cg_it"] = p->exact_cg_iterations;
}

[[maybe_unused]] const bool kRegistered = [] {
  for (const StepModel& model : kStepModels) {
    for (const StepVariant& variant : kVariants) {
      // Eigen's AMD on the scalar KKT matrix fills the factor 4 times more than CHOLMOD's ordering
      // (6.2M nonzeros for 7.6k rows): 4.8 s on the saddle, unfinished after 5 minutes on the hat.
      if (variant.system == GaussNewtonSystem::kKKT &&
          variant.kkt_solver == KktSolver::kSimplicialLDLT && model.faces > 4000) {
        continue;
      }
      benchmark::RegisterBenchmark(
          (std::string("BM_GaussNewtonStep/") + model.name + "/" + variant.name).c_str(),
          BM_GaussNewtonStep, model, variant)
          ->Unit(benchmark::kMillisecond)
          ->Iterations(model.iterations)
          ->UseManualTime();
    }
  }
  return true;
}();

}  // namespace
}  // namespace flatmorph
