#include "toolpath/line_field.h"

#include <cmath>
#include <complex>
#include <numbers>

#include "common/angles.h"
#include "mesh/operators.h"

namespace flatmorph {

Eigen::VectorXcd face_to_vertex_line_field(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                           const Eigen::VectorXd& theta_face) {
  const Eigen::VectorXd area = face_areas(V.leftCols<2>(), F).cwiseAbs();
  Eigen::VectorXcd sum = Eigen::VectorXcd::Zero(V.rows());
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(V.rows());
  for (int f = 0; f < F.rows(); ++f) {
    const std::complex<double> u = std::polar(area(f), 2 * theta_face(f));
    for (int k = 0; k < 3; ++k) {
      sum(F(f, k)) += u;
      weight(F(f, k)) += area(f);
    }
  }
  for (int v = 0; v < sum.size(); ++v) {
    if (weight(v) > 0) sum(v) /= weight(v);
  }
  return sum;
}

Eigen::VectorXd line_field_angle(const Eigen::VectorXcd& u) {
  Eigen::VectorXd theta(u.size());
  for (int i = 0; i < u.size(); ++i) theta(i) = 0.5 * std::arg(u(i));
  return theta;
}

Eigen::VectorXi line_field_doubled_index(const Eigen::MatrixXi& F,
                                         const Eigen::VectorXd& theta_vertex) {
  Eigen::VectorXi index(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    double total = 0;
    for (int k = 0; k < 3; ++k) {
      total += wrap_angle(2 * theta_vertex(F(f, (k + 1) % 3)) - 2 * theta_vertex(F(f, k)));
    }
    index(f) = static_cast<int>(std::lround(total / (2 * std::numbers::pi)));
  }
  return index;
}

double interpolate_line_field(double theta_a, double theta_b, double theta_c,
                              const Eigen::Vector3d& barycentric) {
  const std::complex<double> u = barycentric(0) * std::polar(1.0, 2 * theta_a) +
                                 barycentric(1) * std::polar(1.0, 2 * theta_b) +
                                 barycentric(2) * std::polar(1.0, 2 * theta_c);
  return 0.5 * std::arg(u);
}

double line_angle_difference(double theta_a, double theta_b) {
  return 0.5 * std::abs(wrap_angle(2 * (theta_a - theta_b)));
}

}  // namespace flatmorph
