// The benchmarks run with the CLI's process settings: the linear algebra threads chosen for this
// machine (numerics/linear_algebra_threads.h; FLATMORPH_THREADS overrides, as for the CLI).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <optional>

#include "numerics/linear_algebra_threads.h"

int main(int argc, char** argv) {
  try {
    flatmorph::configure_linear_algebra_threads(std::nullopt);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "flatmorph_bench: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
