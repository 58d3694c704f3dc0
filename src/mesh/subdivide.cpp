#include "mesh/subdivide.h"

#include <fmt/core.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "common/memory.h"
#include "mesh/topology.h"

namespace flatmorph {

Subdivision loop_subdivide(const Mesh& mesh) {
  const int nv = mesh.num_vertices();
  const int nf = mesh.num_faces();
  const EdgeTopology topo = edge_topology(mesh.F);
  const int ne = topo.num_edges();

  std::vector<int> valence(nv, 0), boundary_valence(nv, 0);
  for (int e = 0; e < ne; ++e) {
    for (int s = 0; s < 2; ++s) {
      ++valence[topo.edges(e, s)];
      boundary_valence[topo.edges(e, s)] += topo.is_boundary_edge(e);
    }
  }

  // Triplets in a fixed order (vertex rules by edge, then edge rules by edge), so that S and the
  // sums setFromTriplets forms are the same on every run.
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<size_t>(nv) + 2 * ne + 4 * ne);
  // Old vertices. Interior (Warren's form of Loop's rule): beta on each neighbour, 1 - n beta on
  // itself. Boundary (cubic B-spline along the boundary): 1/8 on each boundary neighbour, 3/4 on
  // itself; a vertex where several boundary pieces meet (not a disk) shares the 1/4 equally.
  std::vector<double> neighbour_weight(nv, 0.0);
  for (int v = 0; v < nv; ++v) {
    double self = 1.0;
    if (boundary_valence[v] > 0) {
      neighbour_weight[v] = 0.25 / boundary_valence[v];
      self = 0.75;
    } else if (valence[v] > 0) {
      const int n = valence[v];
      neighbour_weight[v] = n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n);
      self = 1.0 - n * neighbour_weight[v];
    }
    triplets.emplace_back(v, v, self);
  }
  for (int e = 0; e < ne; ++e) {
    const int a = topo.edges(e, 0), b = topo.edges(e, 1);
    const bool boundary = topo.is_boundary_edge(e);
    // A boundary vertex only listens to the boundary, so that the boundary curve is refined on its
    // own (the surface's outline does not depend on the interior).
    if (boundary || boundary_valence[a] == 0) triplets.emplace_back(a, b, neighbour_weight[a]);
    if (boundary || boundary_valence[b] == 0) triplets.emplace_back(b, a, neighbour_weight[b]);
  }
  // New edge vertices: midpoint on the boundary, 3/8 3/8 1/8 1/8 inside.
  for (int e = 0; e < ne; ++e) {
    const int row = nv + e;
    const int a = topo.edges(e, 0), b = topo.edges(e, 1);
    if (topo.is_boundary_edge(e)) {
      triplets.emplace_back(row, a, 0.5);
      triplets.emplace_back(row, b, 0.5);
      continue;
    }
    triplets.emplace_back(row, a, 3.0 / 8.0);
    triplets.emplace_back(row, b, 3.0 / 8.0);
    for (int s = 0; s < 2; ++s) {
      const int f = topo.edge_faces(e, s);
      // The corner opposite edge k of face f is corner (k+2)%3.
      for (int k = 0; k < 3; ++k) {
        if (topo.face_edges(f, k) == e) triplets.emplace_back(row, mesh.F(f, (k + 2) % 3), 0.125);
      }
    }
  }

  Subdivision result;
  result.S.resize(nv + ne, nv);
  result.S.setFromTriplets(triplets.begin(), triplets.end());
  result.mesh.V = result.S * mesh.V;
  result.mesh.F.resize(4 * nf, 3);
  for (int f = 0; f < nf; ++f) {
    const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    const int ab = nv + topo.face_edges(f, 0), bc = nv + topo.face_edges(f, 1),
              ca = nv + topo.face_edges(f, 2);
    result.mesh.F.row(4 * f + 0) << a, ab, ca;
    result.mesh.F.row(4 * f + 1) << b, bc, ab;
    result.mesh.F.row(4 * f + 2) << c, ca, bc;
    result.mesh.F.row(4 * f + 3) << ab, bc, ca;
  }
  return result;
}

Subdivision loop_subdivide_to(const Mesh& mesh, int min_faces) {
  Subdivision result;
  result.mesh = mesh;
  result.S.resize(mesh.num_vertices(), mesh.num_vertices());
  result.S.setIdentity();
  // Each step has 4 times the faces: refuse up front a count the machine cannot hold (the whole
  // design pipeline's memory, common/memory.h), rather than be killed by the kernel later.
  std::uint64_t faces = static_cast<std::uint64_t>(mesh.num_faces());
  while (faces > 0 && faces < static_cast<std::uint64_t>(std::max(min_faces, 0))) faces *= 4;
  if (faces > static_cast<std::uint64_t>(mesh.num_faces())) {
    require_memory(faces * kDesignBytesPerFace,
                   fmt::format("subdividing the target's {} faces to {} (at least {} asked for)",
                               mesh.num_faces(), faces, min_faces),
                   "ask for fewer faces (--faces) or close other programs");
  }
  // A mesh without faces cannot grow; return it as it is rather than loop forever.
  while (result.mesh.num_faces() > 0 && result.mesh.num_faces() < min_faces) {
    Subdivision step = loop_subdivide(result.mesh);
    result.mesh = std::move(step.mesh);
    result.S = step.S * result.S;
  }
  return result;
}

}  // namespace flatmorph
