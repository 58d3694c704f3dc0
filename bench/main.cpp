// The benchmarks run with the CLI's process settings: the linear algebra threads chosen for this
// machine (numerics/linear_algebra_threads.h; FLATMORPH_THREADS overrides, as for the CLI).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "numerics/linear_algebra_threads.h"

int main(int argc, char** argv) {
  std::optional<int> threads;
  if (const char* env = std::getenv("FLATMORPH_THREADS"); env && *env) threads = std::atoi(env);
  flatmorph::set_linear_algebra_threads(
      flatmorph::choose_linear_algebra_threads(threads, flatmorph::threads_cache_path()).threads);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
