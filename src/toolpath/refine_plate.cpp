#include "toolpath/refine_plate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/error.h"
#include "mesh/topology.h"

namespace flatmorph {

RefinedPlate regular_subdivide(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int n) {
  if (n < 1) throw std::invalid_argument("regular_subdivide: n must be at least 1");
  const EdgeTopology topology = edge_topology(F);
  const int nv = static_cast<int>(V.rows()), nf = static_cast<int>(F.rows());
  const int ne = topology.num_edges();
  const int per_edge = n - 1, per_face = (n - 1) * (n - 2) / 2;
  const int total = nv + ne * per_edge + nf * per_face;
  RefinedPlate out;
  out.splits = n;
  out.V.resize(total, 2);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(nv + 2 * ne * per_edge + 3 * nf * per_face);
  const auto add_point = [&](int index, int a, double wa, int b, double wb, int c, double wc) {
    out.V.row(index) = wa * V.row(a).head<2>() + wb * V.row(b).head<2>() + wc * V.row(c).head<2>();
    if (wa > 0) triplets.emplace_back(index, a, wa);
    if (wb > 0) triplets.emplace_back(index, b, wb);
    if (wc > 0) triplets.emplace_back(index, c, wc);
  };
  for (int v = 0; v < nv; ++v) add_point(v, v, 1.0, v, 0.0, v, 0.0);
  // Edge e holds its points in order from edges(e, 0) to edges(e, 1).
  for (int e = 0; e < ne; ++e) {
    const int a = topology.edges(e, 0), b = topology.edges(e, 1);
    for (int i = 1; i < n; ++i) {
      add_point(nv + e * per_edge + i - 1, a, static_cast<double>(n - i) / n, b,
                static_cast<double>(i) / n, a, 0.0);
    }
  }
  out.F.resize(static_cast<Eigen::Index>(nf) * n * n, 3);
  out.face_parent.resize(out.F.rows());
  // Lattice point (i, j) of face f is corner0 + i/n (corner1 - corner0) + j/n (corner2 - corner0).
  std::vector<int> lattice((n + 1) * (n + 1));
  const auto at = [&](int i, int j) -> int& { return lattice[i * (n + 1) + j]; };
  int next_interior = nv + ne * per_edge;
  int next_face = 0;
  for (int f = 0; f < nf; ++f) {
    const int c[3] = {F(f, 0), F(f, 1), F(f, 2)};
    // The point at distance t (in 1/n) along edge k of f from its corner k.
    const auto on_edge = [&](int k, int t) {
      const int e = topology.face_edges(f, k);
      const int from_start = topology.edges(e, 0) == c[k] ? t : n - t;
      return nv + e * per_edge + from_start - 1;
    };
    at(0, 0) = c[0];
    at(n, 0) = c[1];
    at(0, n) = c[2];
    for (int t = 1; t < n; ++t) {
      at(t, 0) = on_edge(0, t);
      at(n - t, t) = on_edge(1, t);
      at(0, n - t) = on_edge(2, t);
    }
    for (int i = 1; i < n; ++i) {
      for (int j = 1; i + j < n; ++j) {
        at(i, j) = next_interior;
        add_point(next_interior++, c[0], static_cast<double>(n - i - j) / n, c[1],
                  static_cast<double>(i) / n, c[2], static_cast<double>(j) / n);
      }
    }
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        out.face_parent(next_face) = f;
        out.F.row(next_face++) << at(i, j), at(i + 1, j), at(i, j + 1);
        if (i + j + 2 <= n) {
          out.face_parent(next_face) = f;
          out.F.row(next_face++) << at(i + 1, j), at(i + 1, j + 1), at(i, j + 1);
        }
      }
    }
  }
  out.S.resize(total, nv);
  out.S.setFromTriplets(triplets.begin(), triplets.end());
  return out;
}

double longest_edge(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double longest = 0;
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const double l = (V.row(F(f, k)).head<2>() - V.row(F(f, (k + 1) % 3)).head<2>()).norm();
      longest = std::max(longest, l);
    }
  }
  return longest;
}

double mean_edge(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double total = 0;
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      total += (V.row(F(f, k)).head<2>() - V.row(F(f, (k + 1) % 3)).head<2>()).norm();
    }
  }
  return F.rows() ? total / (3.0 * F.rows()) : 0.0;
}

RefinedPlate refine_plate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double mean_edge_mm,
                          int max_faces) {
  if (!(mean_edge_mm > 0)) {
    throw UserError(ErrorCategory::kOption,
                    "plate refinement: the target edge length must be positive (got " +
                        std::to_string(mean_edge_mm) + " mm); use a positive path spacing");
  }
  // Every edge is cut into the same number of equal parts, so the mean edge is known in advance.
  const double mean = mean_edge(V, F);
  const int n = std::max(1, static_cast<int>(std::ceil(mean / mean_edge_mm - 1e-9)));
  const double faces = static_cast<double>(F.rows()) * n * n;
  if (faces > max_faces) {
    throw UserError(ErrorCategory::kResource,
                    "plate refinement: edges of " + std::to_string(mean_edge_mm) + " mm need " +
                        std::to_string(static_cast<long long>(faces)) + " faces (more than " +
                        std::to_string(max_faces) +
                        "); use a smaller plate or a larger path spacing");
  }
  return regular_subdivide(V, F, n);
}

}  // namespace flatmorph
