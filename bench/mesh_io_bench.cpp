// Mesh file reading and writing on the paper's hat (1409 vertices, 2752 faces).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "mesh/io.h"

namespace flatmorph {
namespace {

namespace fs = std::filesystem;

fs::path hat_obj() { return fs::path(FLATMORPH_SHARED_DIR) / "meshes" / "hat.obj"; }

// A file name in the temporary folder that no other running benchmark uses.
fs::path temporary(const std::string& name) {
  return fs::temp_directory_path() /
         ("flatmorph_bench_" + std::to_string(static_cast<long>(::getpid())) + "_" + name);
}

void BM_ReadObjHat(benchmark::State& state) {
  const fs::path path = hat_obj();
  for (auto _ : state) {
    MeshFile file = read_mesh(path);
    benchmark::DoNotOptimize(file.mesh.V.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fs::file_size(path)));
}
BENCHMARK(BM_ReadObjHat)->Unit(benchmark::kMicrosecond);

void BM_ReadPlyBinary(benchmark::State& state) {
  const fs::path path = temporary("hat.ply");
  write_ply(path, read_mesh(hat_obj()).mesh, {}, PlyEncoding::kBinaryLittleEndian);
  for (auto _ : state) {
    MeshFile file = read_mesh(path);
    benchmark::DoNotOptimize(file.mesh.V.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fs::file_size(path)));
  fs::remove(path);
}
BENCHMARK(BM_ReadPlyBinary)->Unit(benchmark::kMicrosecond);

void BM_WritePlyBinary(benchmark::State& state) {
  const Mesh mesh = read_mesh(hat_obj()).mesh;
  const fs::path path = temporary("hat_out.ply");
  for (auto _ : state) {
    write_ply(path, mesh, {}, PlyEncoding::kBinaryLittleEndian);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fs::file_size(path)));
  fs::remove(path);
}
BENCHMARK(BM_WritePlyBinary)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace flatmorph
