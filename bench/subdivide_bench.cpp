// Preparing a target surface: Loop subdivision to the paper's face counts, and repair of an
// STL-like triangle soup. Meshes are built here so that the numbers do not depend on files.
#include <benchmark/benchmark.h>

#include <cmath>

#include "mesh/subdivide.h"
#include "mesh/validate.h"

namespace flatmorph {
namespace {

// nx x ny squares, two triangles each, bent onto a sphere of radius 2 (a cap like the paper's
// hemisphere, so that the geometry is not degenerate).
Mesh curved_grid(int nx, int ny) {
  Mesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  const double size = std::max(nx, ny);
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double x = (i - 0.5 * nx) / size, y = (j - 0.5 * ny) / size;
      m.V.row(j * (nx + 1) + i) << x, y, std::sqrt(4.0 - x * x - y * y);
    }
  }
  m.F.resize(2 * nx * ny, 3);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int v00 = j * (nx + 1) + i, v10 = v00 + 1, v01 = v00 + nx + 1, v11 = v01 + 1;
      m.F.row(2 * (j * nx + i)) << v00, v10, v11;
      m.F.row(2 * (j * nx + i) + 1) << v00, v11, v01;
    }
  }
  return m;
}

void subdivide_to(benchmark::State& state, const Mesh& mesh, int min_faces) {
  int faces = 0;
  for (auto _ : state) {
    const Subdivision s = loop_subdivide_to(mesh, min_faces);
    faces = s.mesh.num_faces();
    benchmark::DoNotOptimize(s.S.nonZeros());
  }
  state.counters["faces_in"] = mesh.num_faces();
  state.counters["faces_out"] = faces;
}

// The hat model's size: 2752 faces, one step to 11008.
void BM_LoopSubdivideTo11008(benchmark::State& state) {
  subdivide_to(state, curved_grid(32, 43), 11008);
}
BENCHMARK(BM_LoopSubdivideTo11008)->Unit(benchmark::kMillisecond);

// The big hemisphere's size: 1072 faces, two steps to 17152.
void BM_LoopSubdivideTo17152(benchmark::State& state) {
  subdivide_to(state, curved_grid(8, 67), 17152);
}
BENCHMARK(BM_LoopSubdivideTo17152)->Unit(benchmark::kMillisecond);

// An STL file of the 11008-face mesh: every face with its own three corners, welded back.
void BM_RepairSoup(benchmark::State& state) {
  const Mesh indexed = loop_subdivide(curved_grid(32, 43)).mesh;
  Mesh soup;
  soup.V.resize(3 * indexed.num_faces(), 3);
  soup.F.resize(indexed.num_faces(), 3);
  for (int f = 0; f < indexed.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      soup.V.row(3 * f + k) = indexed.V.row(indexed.F(f, k));
      soup.F(f, k) = 3 * f + k;
    }
  }
  int vertices = 0;
  for (auto _ : state) {
    Mesh m = soup;
    repair_mesh(m);
    vertices = m.num_vertices();
  }
  state.counters["faces"] = soup.num_faces();
  state.counters["vertices_out"] = vertices;
}
BENCHMARK(BM_RepairSoup)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace flatmorph
