// The benchmarks run with the CLI's process settings (numerics/sparse_cholesky.h).
#include <benchmark/benchmark.h>

#include "numerics/sparse_cholesky.h"

int main(int argc, char** argv) {
  flatmorph::use_single_threaded_blas();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
