// Tutte start and the local/global iterations of the Shrink & Morph flattening (Eq. 11).
#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "common/error.h"
#include "mesh/topology.h"
#include "methods/shrink_morph/flatten_internal.h"

namespace flatmorph::shrink_morph_internal {
namespace {

// Below this RMS singular-value error (dimensionless) a plate counts as exact: the stopping rule
// then asks for changes below tolerance * 1e-9, near double precision.
constexpr double kResidualFloor = 1e-9;

}  // namespace

RestFrames rest_frames(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  RestFrames frames;
  const int nf = static_cast<int>(F.rows());
  frames.area.resize(nf);
  frames.inverse.resize(nf);
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d e1 = V.row(F(f, 1)) - V.row(F(f, 0));
    const Eigen::Vector3d e2 = V.row(F(f, 2)) - V.row(F(f, 0));
    const double l1 = e1.norm();
    const double twice_area = e1.cross(e2).norm();
    // Relative to the edge lengths, so that the test does not depend on the target's units.
    if (!(twice_area > 1e-14 * (e1.squaredNorm() + e2.squaredNorm()))) {
      throw UserError(ErrorCategory::kGeometry,
                      fmt::format("target: face {} has zero area; run it through repair (flatmorph "
                                  "removes degenerate faces when it reads a mesh)",
                                  f));
    }
    Eigen::Matrix2d X;
    X << l1, e1.dot(e2) / l1, 0.0, twice_area / l1;
    frames.area(f) = 0.5 * twice_area;
    frames.inverse[f] = X.inverse();
  }
  return frames;
}

Eigen::MatrixXd tutte_embedding(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                const std::vector<int>& loop, double radius) {
  const int nv = static_cast<int>(V.rows());
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(nv, 2);
  std::vector<int> unknown(nv, -1);  // interior index, or -1 on the boundary
  std::vector<bool> on_boundary(nv, false);
  for (int v : loop) on_boundary[v] = true;

  const int n = static_cast<int>(loop.size());
  std::vector<double> arc(n + 1, 0.0);
  for (int k = 0; k < n; ++k) {
    arc[k + 1] = arc[k] + (V.row(loop[(k + 1) % n]) - V.row(loop[k])).norm();
  }
  for (int k = 0; k < n; ++k) {
    const double angle = 2.0 * std::numbers::pi * arc[k] / arc[n];
    P(loop[k], 0) = radius * std::cos(angle);
    P(loop[k], 1) = radius * std::sin(angle);
  }
  int num_unknowns = 0;
  for (int v = 0; v < nv; ++v) {
    if (!on_boundary[v]) unknown[v] = num_unknowns++;
  }
  if (num_unknowns == 0) return P;

  // Uniform graph Laplacian: each undirected edge once.
  const EdgeTopology topology = edge_topology(F);
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(num_unknowns, 2);
  for (int e = 0; e < topology.num_edges(); ++e) {
    const int a = topology.edges(e, 0), b = topology.edges(e, 1);
    for (auto [i, j] : {std::pair{a, b}, std::pair{b, a}}) {
      if (unknown[i] < 0) continue;
      triplets.emplace_back(unknown[i], unknown[i], 1.0);
      if (unknown[j] >= 0) {
        triplets.emplace_back(unknown[i], unknown[j], -1.0);
      } else {
        rhs.row(unknown[i]) += P.row(j);
      }
    }
  }
  Eigen::SparseMatrix<double> L(num_unknowns, num_unknowns);
  L.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::CholmodSimplicialLLT<Eigen::SparseMatrix<double>> solver(L);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error("Tutte embedding: the graph Laplacian is not positive definite");
  }
  const Eigen::MatrixXd interior = solver.solve(rhs);
  for (int v = 0; v < nv; ++v) {
    if (unknown[v] >= 0) P.row(v) = interior.row(unknown[v]);
  }
  return P;
}

LocalGlobal::LocalGlobal(const Eigen::MatrixXi& F, const RestFrames& frames, int num_vertices)
    : F_(F), frames_(frames) {
  const int nf = static_cast<int>(F.rows());
  Eigen::Matrix<double, 3, 2> E;
  E << -1, -1, 1, 0, 0, 1;
  gradient_.resize(nf);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(9 * nf);
  // Vertex 0 is pinned at the origin: the energy only sees edge vectors, so this removes the
  // translation without distorting anything.
  const int pinned = 0;
  for (int f = 0; f < nf; ++f) {
    const Eigen::Matrix<double, 3, 2> D = E * frames.inverse[f];
    gradient_[f] = frames.area(f) * D;
    const Eigen::Matrix3d K = frames.area(f) * D * D.transpose();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (F(f, i) == pinned || F(f, j) == pinned) continue;
        triplets.emplace_back(F(f, i), F(f, j), K(i, j));
      }
    }
  }
  triplets.emplace_back(pinned, pinned, 1.0);
  Eigen::SparseMatrix<double> K(num_vertices, num_vertices);
  K.setFromTriplets(triplets.begin(), triplets.end());
  solver_.compute(K);
  if (solver_.info() != Eigen::Success) {
    throw std::runtime_error("local/global: the global matrix is not positive definite");
  }
}

LocalGlobalStats LocalGlobal::solve(Eigen::MatrixXd& P, double s1, double s2, double tolerance,
                                    int max_iterations) const {
  const int nf = static_cast<int>(F_.rows());
  const double total_area = frames_.area.sum();
  std::vector<Eigen::Matrix2d> targets(nf);
  Eigen::VectorXd face_energy(nf);
  Eigen::MatrixX2d sigma(nf, 2), previous_sigma(nf, 2);
  LocalGlobalStats stats;
  for (int iteration = 0;; ++iteration) {
    // Local step: per face the closest admissible differential (faces are independent, so the
    // parallel loop is deterministic).
    tbb::parallel_for(tbb::blocked_range<int>(0, nf), [&](const tbb::blocked_range<int>& range) {
      for (int f = range.begin(); f != range.end(); ++f) {
        const Eigen::Matrix2d J = plate_differential(P, F_, frames_, f);
        const ConformalSplit split = conformal_split(J);
        sigma(f, 0) = split.sigma1();
        sigma(f, 1) = split.sigma2();
        targets[f] = closest_with_singular_values(split, s1, s2);
        face_energy(f) = frames_.area(f) * (J - targets[f]).squaredNorm();
      }
    });
    stats.energy = face_energy.sum() / total_area;
    if (iteration > 0) {
      // Relative to how far the singular values still are from their targets (the RMS of which
      // is sqrt(energy)): a surface that can be met exactly (a plane, a developable surface with
      // lambda1 = lambda2) is iterated until it is, one that cannot stops once its remaining
      // error has settled.
      const double change = std::sqrt(
          ((sigma - previous_sigma).rowwise().squaredNorm().array() * frames_.area.array()).sum() /
          total_area);
      if (change < tolerance * std::max(std::sqrt(stats.energy), kResidualFloor)) {
        stats.converged = true;
        return stats;
      }
    }
    if (iteration == max_iterations) return stats;
    previous_sigma = sigma;

    // Global step: the gradient of sum_f A_f ||J_f - T_f||^2 in the positions is K P - b.
    Eigen::MatrixX2d b = Eigen::MatrixX2d::Zero(P.rows(), 2);
    for (int f = 0; f < nf; ++f) {
      const Eigen::Matrix<double, 3, 2> g = gradient_[f] * targets[f].transpose();
      for (int k = 0; k < 3; ++k) b.row(F_(f, k)) += g.row(k);
    }
    b.row(0).setZero();
    P = solver_.solve(b);
    ++stats.iterations;
  }
}

DualEdges dual_edges(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const RestFrames& frames) {
  const EdgeTopology topology = edge_topology(F);
  DualEdges edges;
  for (int e = 0; e < topology.num_edges(); ++e) {
    if (topology.is_boundary_edge(e)) continue;
    const int f = topology.edge_faces(e, 0), g = topology.edge_faces(e, 1);
    const double length2 =
        (V.row(topology.edges(e, 0)) - V.row(topology.edges(e, 1))).squaredNorm();
    edges.face_f.push_back(f);
    edges.face_g.push_back(g);
    // l_e over the distance between the two centroids measured across the edge (each centroid is
    // 2 A / (3 l) from the edge line).
    edges.weight.push_back(3.0 * length2 / (2.0 * (frames.area(f) + frames.area(g))));
  }
  return edges;
}

}  // namespace flatmorph::shrink_morph_internal
