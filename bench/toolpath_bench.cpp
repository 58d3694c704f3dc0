// Print paths for the paper's Hat design (hat.obj Loop-subdivided to 11008 faces, flattened to a
// 100 mm plate): 10 layers of stripe-pattern trajectories and their order, with the time of each
// stage as counters (seconds per run). The reference implementation takes about a minute for this
// on a 2-core machine (notes §5).
#include <benchmark/benchmark.h>

#include <cmath>

#include "mesh/io.h"
#include "mesh/subdivide.h"
#include "methods/shrink_morph/design.h"
#include "methods/shrink_morph/flatten.h"
#include "toolpath/layer_paths.h"

namespace flatmorph {
namespace {

const FlatPlate& hat_plate() {
  static const FlatPlate plate = [] {
    const Mesh hat = read_mesh(std::string(FLATMORPH_SHARED_DIR) + "/meshes/hat.obj").mesh;
    FlattenOptions options;
    options.width_mm = 100;
    return flatten(loop_subdivide_to(hat, 11008).mesh, options);
  }();
  return plate;
}

void run_layers(benchmark::State& state, const Eigen::VectorXd& theta2) {
  const FlatPlate& flat = hat_plate();
  LayerPathOptions options;  // paths 0.4 mm apart
  const PlateDesign plate =
      shrink_morph_plate_design(flat, theta2, Material{}, 10);  // 10 layers of 0.08 mm
  LayerPaths result;
  LayerPathTimings total;
  for (auto _ : state) {
    result = stack_layer_paths(plate.plate, plate.F, plate.stack, options);
    total.refinement += result.timings.refinement;
    total.fields += result.timings.fields;
    total.eigenvector += result.timings.eigenvector;
    total.extraction += result.timings.extraction;
    total.ordering += result.timings.ordering;
  }
  const double runs = static_cast<double>(state.iterations());
  state.counters["refinement_s"] = total.refinement / runs;
  state.counters["fields_s"] = total.fields / runs;
  state.counters["eigenvector_s"] = total.eigenvector / runs;
  state.counters["extraction_s"] = total.extraction / runs;
  state.counters["ordering_s"] = total.ordering / runs;
  state.counters["refined_faces"] = result.refined_faces;
  double paths = 0, travel = 0, greedy = 0;
  for (const LayerPathReport& r : result.layers) {
    paths += r.paths;
    travel += r.travel_mm;
    greedy += r.travel_greedy_mm;
  }
  state.counters["paths_per_layer"] = paths / result.layers.size();
  state.counters["travel_mm"] = travel;
  state.counters["travel_vs_greedy"] = travel / greedy;
}

// The design as the acceptance test has it: theta2 = 0, so every layer has the same field and
// the stripes are computed once.
void BM_HatPaths10LayersTheta2Zero(benchmark::State& state) {
  run_layers(state, Eigen::VectorXd());
}
BENCHMARK(BM_HatPaths10LayersTheta2Zero)->Unit(benchmark::kSecond)->Iterations(2);

// A theta2 varying over the plate (up to 0.4 rad), so every layer has its own field: one stripe
// eigenvector per layer, as after the theta2 optimization.
void BM_HatPaths10LayersTheta2Varying(benchmark::State& state) {
  const FlatPlate& flat = hat_plate();
  Eigen::VectorXd theta2(flat.plate.rows());
  for (int v = 0; v < theta2.size(); ++v) {
    theta2(v) = 0.2 + 0.2 * std::sin(flat.plate(v, 0) / 20) * std::cos(flat.plate(v, 1) / 25);
  }
  run_layers(state, theta2);
}
BENCHMARK(BM_HatPaths10LayersTheta2Varying)->Unit(benchmark::kSecond)->Iterations(2);

}  // namespace
}  // namespace flatmorph
