#include "mesh/operators.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace flatmorph {

namespace {

// Every operator accepts plate meshes (2 columns) as well as surfaces (3 columns); a plate vertex
// is read as lying in the z = 0 plane so that one code path serves both.
void require_2d_or_3d(const Eigen::MatrixXd& V, const char* who) {
  if (V.cols() != 2 && V.cols() != 3) {
    throw std::invalid_argument(std::string(who) + ": V must have 2 or 3 columns, got " +
                                std::to_string(V.cols()));
  }
}

Eigen::Vector3d point(const Eigen::MatrixXd& V, int i) {
  if (V.cols() == 3) return V.row(i).transpose();
  return {V(i, 0), V(i, 1), 0.0};
}

// (x_b - x_a) x (x_c - x_a) for face f: the normal by the right-hand rule, with length 2 A_f.
Eigen::Vector3d area_normal(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const Eigen::Vector3d a = point(V, F(f, 0));
  return (point(V, F(f, 1)) - a).cross(point(V, F(f, 2)) - a);
}

// The angle between u and v; atan2 stays accurate for angles near 0 and pi, where acos does not.
double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  require_2d_or_3d(V, "face_areas");
  Eigen::VectorXd areas(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d n = area_normal(V, F, f);
    // In the plane the z component keeps the orientation: negative for clockwise (flipped) faces.
    areas[f] = 0.5 * (V.cols() == 2 ? n.z() : n.norm());
  }
  return areas;
}

Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  require_2d_or_3d(V, "face_normals");
  Eigen::MatrixXd normals(F.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) normals.row(f) = area_normal(V, F, f).normalized().transpose();
  return normals;
}

Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  require_2d_or_3d(V, "cotan_laplacian");
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(12 * F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      // Corner k faces the edge between the two other corners.
      const int c = F(f, k), i = F(f, (k + 1) % 3), j = F(f, (k + 2) % 3);
      const Eigen::Vector3d u = point(V, i) - point(V, c);
      const Eigen::Vector3d v = point(V, j) - point(V, c);
      const double half_cot = 0.5 * u.dot(v) / u.cross(v).norm();
      triplets.emplace_back(i, j, -half_cot);
      triplets.emplace_back(j, i, -half_cot);
      triplets.emplace_back(i, i, half_cot);
      triplets.emplace_back(j, j, half_cot);
    }
  }
  Eigen::SparseMatrix<double> L(V.rows(), V.rows());
  // The triplets come in a fixed order and duplicates are summed in that order: deterministic.
  L.setFromTriplets(triplets.begin(), triplets.end());
  return L;
}

Eigen::VectorXd lumped_mass(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  require_2d_or_3d(V, "lumped_mass");
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(V.rows());
  for (int f = 0; f < F.rows(); ++f) {
    // Unsigned: a flipped plate triangle still carries material.
    const double third = area_normal(V, F, f).norm() / 6.0;
    for (int k = 0; k < 3; ++k) mass[F(f, k)] += third;
  }
  return mass;
}

Eigen::VectorXd signed_dihedral_angles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const EdgeTopology& topology) {
  require_2d_or_3d(V, "signed_dihedral_angles");
  Eigen::VectorXd angles = Eigen::VectorXd::Zero(topology.num_edges());
  for (int e = 0; e < topology.num_edges(); ++e) {
    if (topology.is_boundary_edge(e)) continue;
    const int f0 = topology.edge_faces(e, 0), f1 = topology.edge_faces(e, 1);
    int k0 = 0;
    while (topology.face_edges(f0, k0) != e) ++k0;
    // The edge as face f0 walks it; walking it as f1 does flips both the edge and the order of the
    // normals below, so the angle does not depend on which face comes first.
    const Eigen::Vector3d edge = point(V, F(f0, (k0 + 1) % 3)) - point(V, F(f0, k0));
    const Eigen::Vector3d n0 = area_normal(V, F, f0), n1 = area_normal(V, F, f1);
    // (n1 x n0) . edge > 0 when f1 turns toward n0: the side the normals point to is concave. This
    // is the opposite of the reference implementation's atan2((n0 x n1) . e, ...) (notes §3.4), as
    // our convention follows the paper's b = -dn^T dphi instead.
    angles[e] = std::atan2(n1.cross(n0).dot(edge), edge.norm() * n0.dot(n1));
  }
  return angles;
}

std::vector<Eigen::Matrix3d> shape_operators(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                             const EdgeTopology& topology) {
  const Eigen::VectorXd theta = signed_dihedral_angles(V, F, topology);
  std::vector<Eigen::Matrix3d> operators(F.rows(), Eigen::Matrix3d::Zero());
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d n = area_normal(V, F, f);
    const double two_area = n.norm();
    for (int k = 0; k < 3; ++k) {
      const int e = topology.face_edges(f, k);
      if (topology.is_boundary_edge(e)) continue;  // no neighbour, no bending measured there
      const Eigen::Vector3d edge = point(V, F(f, (k + 1) % 3)) - point(V, F(f, k));
      const Eigen::Vector3d t = n.cross(edge).normalized();
      // Shrink & Morph Eq. 10 with the normalization theta_e l_e / (2 A) (notes §3.4; the paper's
      // theta / (A l) tau tau^T with |tau| = l is twice too large): 1/R on a cylinder.
      operators[f] += theta[e] * edge.norm() / two_area * t * t.transpose();
    }
  }
  return operators;
}

void face_curvatures(const std::vector<Eigen::Matrix3d>& shape_operators,
                     const Eigen::MatrixXd& normals, Eigen::VectorXd& mean,
                     Eigen::VectorXd& gaussian) {
  const int nf = static_cast<int>(shape_operators.size());
  if (normals.rows() != nf || normals.cols() != 3) {
    throw std::invalid_argument("face_curvatures: need one 3D normal per shape operator");
  }
  mean.resize(nf);
  gaussian.resize(nf);
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d n = normals.row(f).transpose().normalized();
    // Any orthonormal tangent basis: mean and Gaussian curvature are invariant under its rotation.
    Eigen::Index axis = 0;
    n.cwiseAbs().minCoeff(&axis);
    const Eigen::Vector3d u = n.cross(Eigen::Vector3d::Unit(axis)).normalized();
    Eigen::Matrix<double, 3, 2> frame;
    frame << u, n.cross(u);
    const Eigen::Matrix2d s = frame.transpose() * shape_operators[f] * frame;
    mean[f] = 0.5 * s.trace();
    gaussian[f] = s.determinant();
  }
}

Eigen::VectorXd angle_defects(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  require_2d_or_3d(V, "angle_defects");
  const EdgeTopology topology = edge_topology(F);
  // 0: unused, 1: interior, 2: on a boundary edge.
  std::vector<int> kind(V.rows(), 0);
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) kind[F(f, k)] = 1;
  }
  for (int e = 0; e < topology.num_edges(); ++e) {
    if (topology.is_boundary_edge(e)) kind[topology.edges(e, 0)] = kind[topology.edges(e, 1)] = 2;
  }
  Eigen::VectorXd defects(V.rows());
  for (int i = 0; i < V.rows(); ++i) {
    // Unused vertices get 0 so that the sum still matches the Euler characteristic of F.
    defects[i] = kind[i] == 0 ? 0.0 : (kind[i] == 1 ? 2.0 : 1.0) * std::numbers::pi;
  }
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int c = F(f, k);
      defects[c] -= angle_between(point(V, F(f, (k + 1) % 3)) - point(V, c),
                                  point(V, F(f, (k + 2) % 3)) - point(V, c));
    }
  }
  return defects;
}

}  // namespace flatmorph
