#include "mesh/topology.h"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <stdexcept>

namespace flatmorph {

EdgeTopology edge_topology(const Eigen::MatrixXi& F) {
  const int nf = static_cast<int>(F.rows());
  // (min, max, face, k) for every face edge, sorted so that the two sides of an edge are adjacent.
  std::vector<std::array<int, 4>> half(3 * nf);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      half[3 * f + k] = {std::min(a, b), std::max(a, b), f, k};
    }
  }
  std::sort(half.begin(), half.end());

  EdgeTopology t;
  t.face_edges.setConstant(nf, 3, -1);
  t.face_faces.setConstant(nf, 3, -1);
  t.face_faces_edge.setConstant(nf, 3, -1);
  std::vector<std::array<int, 4>> edges;  // a, b, f0, f1
  edges.reserve(half.size() / 2 + 1);
  for (size_t i = 0; i < half.size();) {
    size_t j = i + 1;
    while (j < half.size() && half[j][0] == half[i][0] && half[j][1] == half[i][1]) ++j;
    if (j - i > 2) {
      throw std::invalid_argument("edge_topology: non-manifold edge (more than two faces)");
    }
    const int e = static_cast<int>(edges.size());
    const int f0 = half[i][2], k0 = half[i][3];
    t.face_edges(f0, k0) = e;
    int f1 = -1;
    if (j - i == 2) {
      f1 = half[i + 1][2];
      const int k1 = half[i + 1][3];
      t.face_edges(f1, k1) = e;
      t.face_faces(f0, k0) = f1;
      t.face_faces_edge(f0, k0) = k1;
      t.face_faces(f1, k1) = f0;
      t.face_faces_edge(f1, k1) = k0;
    }
    edges.push_back({half[i][0], half[i][1], f0, f1});
    i = j;
  }
  t.edges.resize(static_cast<int>(edges.size()), 2);
  t.edge_faces.resize(static_cast<int>(edges.size()), 2);
  for (int e = 0; e < static_cast<int>(edges.size()); ++e) {
    t.edges.row(e) << edges[e][0], edges[e][1];
    t.edge_faces.row(e) << edges[e][2], edges[e][3];
  }
  return t;
}

std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixXi& F) {
  // Directed boundary edges: a face edge whose reverse is used by no face.
  std::map<std::pair<int, int>, int> directed_count;
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) ++directed_count[{F(f, k), F(f, (k + 1) % 3)}];
  }
  std::multimap<int, int> next;  // tail -> head of boundary edges
  for (const auto& [edge, count] : directed_count) {
    const auto reverse = directed_count.find({edge.second, edge.first});
    if (reverse == directed_count.end()) {
      for (int c = 0; c < count; ++c) next.emplace(edge.first, edge.second);
    }
  }
  std::vector<std::vector<int>> loops;
  while (!next.empty()) {
    auto it = next.begin();
    const int start = it->first;
    std::vector<int> loop{start};
    int current = it->second;
    next.erase(it);
    while (current != start) {
      loop.push_back(current);
      auto step = next.find(current);
      if (step == next.end()) break;  // open chain: only at non-manifold vertices
      current = step->second;
      next.erase(step);
    }
    loops.push_back(std::move(loop));
  }
  std::stable_sort(loops.begin(), loops.end(), [](const auto& a, const auto& b) {
    return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
  });
  return loops;
}

int face_components(const Eigen::MatrixXi& F, Eigen::VectorXi& component) {
  const int nf = static_cast<int>(F.rows());
  // Union-find over faces joined through shared (undirected) edges.
  std::vector<int> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::map<std::pair<int, int>, int> first_face;
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      auto [it, inserted] = first_face.emplace(std::make_pair(std::min(a, b), std::max(a, b)), f);
      if (!inserted) {
        const int r1 = find(it->second), r2 = find(f);
        if (r1 != r2) parent[std::max(r1, r2)] = std::min(r1, r2);
      }
    }
  }
  component.resize(nf);
  std::vector<int> id_of_root(nf, -1);
  int count = 0;
  for (int f = 0; f < nf; ++f) {
    const int r = find(f);
    if (id_of_root[r] < 0) id_of_root[r] = count++;
    component[f] = id_of_root[r];
  }
  return count;
}

int euler_characteristic(const Eigen::MatrixXi& F) {
  std::vector<int> used;
  used.reserve(3 * F.rows());
  std::vector<std::pair<int, int>> edges;
  edges.reserve(3 * F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      used.push_back(a);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(used.begin(), used.end());
  std::sort(edges.begin(), edges.end());
  const auto nv = std::unique(used.begin(), used.end()) - used.begin();
  const auto ne = std::unique(edges.begin(), edges.end()) - edges.begin();
  return static_cast<int>(nv - ne + F.rows());
}

std::vector<std::vector<int>> vertex_faces(const Eigen::MatrixXi& F, int num_vertices) {
  std::vector<std::vector<int>> result(num_vertices);
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) result[F(f, k)].push_back(f);
  }
  return result;
}

}  // namespace flatmorph
