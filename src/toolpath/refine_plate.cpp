#include "toolpath/refine_plate.h"

#include <cmath>
#include <string>
#include <vector>

#include "common/error.h"
#include "mesh/topology.h"

namespace flatmorph {

RefinedPlate midpoint_subdivide(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const EdgeTopology topology = edge_topology(F);
  const int nv = static_cast<int>(V.rows()), nf = static_cast<int>(F.rows());
  const int ne = topology.num_edges();
  RefinedPlate out;
  out.levels = 1;
  out.V.resize(nv + ne, 2);
  out.V.topRows(nv) = V.leftCols<2>();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(nv + 2 * ne);
  for (int v = 0; v < nv; ++v) triplets.emplace_back(v, v, 1.0);
  for (int e = 0; e < ne; ++e) {
    const int a = topology.edges(e, 0), b = topology.edges(e, 1);
    out.V.row(nv + e) = 0.5 * (V.row(a).head<2>() + V.row(b).head<2>());
    triplets.emplace_back(nv + e, a, 0.5);
    triplets.emplace_back(nv + e, b, 0.5);
  }
  out.S.resize(nv + ne, nv);
  out.S.setFromTriplets(triplets.begin(), triplets.end());
  out.F.resize(4 * nf, 3);
  out.face_parent.resize(4 * nf);
  for (int f = 0; f < nf; ++f) {
    // Edge k of f runs from corner k to corner k+1 (topology.h), so m[k] is the midpoint opposite
    // corner k+2.
    int m[3];
    for (int k = 0; k < 3; ++k) m[k] = nv + topology.face_edges(f, k);
    out.F.row(4 * f + 0) << F(f, 0), m[0], m[2];
    out.F.row(4 * f + 1) << m[0], F(f, 1), m[1];
    out.F.row(4 * f + 2) << m[2], m[1], F(f, 2);
    out.F.row(4 * f + 3) << m[0], m[1], m[2];
    out.face_parent.segment<4>(4 * f).setConstant(f);
  }
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
  // Every split halves every edge exactly, so the number of levels is known in advance.
  const double mean = mean_edge(V, F);
  int levels = 0;
  double faces = static_cast<double>(F.rows());
  while (mean * std::ldexp(1.0, -levels) > mean_edge_mm) {
    ++levels;
    faces *= 4;
  }
  if (faces > max_faces) {
    throw UserError(ErrorCategory::kResource,
                    "plate refinement: edges of " + std::to_string(mean_edge_mm) + " mm need " +
                        std::to_string(static_cast<long long>(faces)) + " faces (more than " +
                        std::to_string(max_faces) +
                        "); use a smaller plate or a larger path spacing");
  }
  RefinedPlate out;
  out.V = V.leftCols<2>();
  out.F = F;
  out.S.resize(V.rows(), V.rows());
  out.S.setIdentity();
  out.face_parent = Eigen::VectorXi::LinSpaced(F.rows(), 0, static_cast<int>(F.rows()) - 1);
  for (int level = 0; level < levels; ++level) {
    RefinedPlate step = midpoint_subdivide(out.V, out.F);
    step.S = (step.S * out.S).pruned();
    Eigen::VectorXi parent(step.F.rows());
    for (int f = 0; f < step.F.rows(); ++f) parent(f) = out.face_parent(step.face_parent(f));
    step.face_parent = parent;
    step.levels = out.levels + 1;
    out = std::move(step);
  }
  return out;
}

}  // namespace flatmorph
