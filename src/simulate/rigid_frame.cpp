#include "simulate/rigid_frame.h"

#include <fmt/core.h>

#include <Eigen/Geometry>
#include <limits>

#include "common/error.h"

namespace flatmorph {
namespace {

// The face whose rest centroid is nearest the mean vertex (ties: the lowest index).
int central_face(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F) {
  const Eigen::RowVector2d center = plate.colwise().mean();
  int best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector2d c = (plate.row(F(f, 0)) + plate.row(F(f, 1)) + plate.row(F(f, 2))) / 3;
    const double d = (c - center).squaredNorm();
    if (d < best_distance) {
      best_distance = d;
      best = f;
    }
  }
  return best;
}

}  // namespace

RigidFrame central_face_frame(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                              const Eigen::MatrixXd& shape, const char* what) {
  RigidFrame frame;
  frame.face = central_face(plate, F);
  const int v0 = F(frame.face, 0), v1 = F(frame.face, 1), v2 = F(frame.face, 2);
  frame.origin = shape.row(v0).transpose();
  const Eigen::Vector3d edge1 = shape.row(v1).transpose() - frame.origin;
  const Eigen::Vector3d edge2 = shape.row(v2).transpose() - frame.origin;
  const Eigen::Vector3d e1 = edge1.normalized();
  const Eigen::Vector3d e3 = edge1.cross(edge2).normalized();
  frame.rotation.row(0) = e1.transpose();
  frame.rotation.row(1) = e3.cross(e1).transpose();
  frame.rotation.row(2) = e3.transpose();
  if (!frame.rotation.allFinite()) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: face {} (the plate's central face) is degenerate; give a "
                                "shape without zero-area triangles (repair the mesh)",
                                what, frame.face));
  }
  frame.fixed_variables = {3 * v0, 3 * v0 + 1, 3 * v0 + 2, 3 * v1 + 1, 3 * v1 + 2, 3 * v2 + 2};
  return frame;
}

Eigen::VectorXd to_frame(const RigidFrame& frame, const Eigen::MatrixXd& V) {
  Eigen::VectorXd x(3 * V.rows());
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    x.segment<3>(3 * v) = frame.rotation * (V.row(v).transpose() - frame.origin);
  }
  for (int i : frame.fixed_variables) x(i) = 0;
  return x;
}

Eigen::MatrixXd from_frame(const RigidFrame& frame, const Eigen::VectorXd& x) {
  const Eigen::Index nv = x.size() / 3;
  Eigen::MatrixXd V(nv, 3);
  for (Eigen::Index v = 0; v < nv; ++v) {
    V.row(v) = (frame.rotation.transpose() * x.segment<3>(3 * v) + frame.origin).transpose();
  }
  return V;
}

}  // namespace flatmorph
