#include "methods/heightfield/shrinkage_field.h"

#include <stdexcept>

namespace flatmorph {

Eigen::VectorXd vertex_shrinkage(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                 const Eigen::VectorXd& edge_shrinkage) {
  const Eigen::Index num_vertices = mesh.V.rows();
  if (plate.rows() != num_vertices || plate.cols() < 2 || edge_shrinkage.size() != mesh.E.rows() ||
      static_cast<Eigen::Index>(mesh.edge_kind.size()) != mesh.E.rows())
    throw std::invalid_argument("vertex_shrinkage: sizes of the mesh, plate and shrinkage differ");
  auto flat_length = [&](int a, int b) {
    return (plate.row(a).head<2>() - plate.row(b).head<2>()).norm();
  };
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(num_vertices);
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(num_vertices);
  // The printing and boundary edges at their ends.
  for (Eigen::Index e = 0; e < mesh.E.rows(); ++e) {
    if (mesh.edge_kind[e] == EdgeKind::kBridge) continue;
    const int a = mesh.E(e, 0), b = mesh.E(e, 1);
    const double length = flat_length(a, b);
    for (int v : {a, b}) {
      sum(v) += length * edge_shrinkage(e);
      weight(v) += length;
    }
  }
  Eigen::VectorXd sigma(num_vertices);
  for (Eigen::Index v = 0; v < num_vertices; ++v)
    sigma(v) = weight(v) > 0 ? sum(v) / weight(v) : 0.0;
  // Vertices without a printing edge: the mean over the opposite edges of their faces, whose ends
  // have a value (the rim of a fan), weighted by those edges' flat lengths.
  Eigen::VectorXd rim_sum = Eigen::VectorXd::Zero(num_vertices);
  Eigen::VectorXd rim_weight = Eigen::VectorXd::Zero(num_vertices);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    for (int corner = 0; corner < 3; ++corner) {
      const int v = mesh.F(f, corner);
      if (weight(v) > 0) continue;
      const int a = mesh.F(f, (corner + 1) % 3), b = mesh.F(f, (corner + 2) % 3);
      if (weight(a) <= 0 || weight(b) <= 0) continue;
      const double length = flat_length(a, b);
      rim_sum(v) += length * 0.5 * (sigma(a) + sigma(b));
      rim_weight(v) += length;
    }
  }
  for (Eigen::Index v = 0; v < num_vertices; ++v)
    if (weight(v) <= 0 && rim_weight(v) > 0) sigma(v) = rim_sum(v) / rim_weight(v);
  return sigma;
}

Eigen::VectorXd face_shrinkage(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                               const Eigen::VectorXd& edge_shrinkage) {
  const Eigen::VectorXd sigma = vertex_shrinkage(mesh, plate, edge_shrinkage);
  Eigen::VectorXd face_sigma(mesh.F.rows());
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    face_sigma(f) = (sigma(mesh.F(f, 0)) + sigma(mesh.F(f, 1)) + sigma(mesh.F(f, 2))) / 3.0;
  return face_sigma;
}

}  // namespace flatmorph
