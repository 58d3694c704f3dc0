// GCC 12 reports a false "may be used uninitialized" inside Eigen 3.4's tridiagonalization, which
// the eigen-decomposition below instantiates; the warning is about Eigen's code, not this file's.
#if !defined(__clang__)  // clang has no such warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "numerics/psd_projection.h"

#include <Eigen/Eigenvalues>

namespace flatmorph {
namespace {

template <int N>
bool is_diagonally_dominant(const Eigen::Matrix<double, N, N>& h, double min_eigenvalue) {
  for (int i = 0; i < h.rows(); ++i) {
    const double off = h.row(i).cwiseAbs().sum() - std::abs(h(i, i));
    if (h(i, i) - off < min_eigenvalue) return false;
  }
  return true;
}

}  // namespace

template <int N>
bool project_to_psd(Eigen::Matrix<double, N, N>& h, double min_eigenvalue) {
  if (is_diagonally_dominant(h, min_eigenvalue)) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(h);
  const auto& values = eig.eigenvalues();
  if (values.minCoeff() >= min_eigenvalue) return false;
  const auto clamped = values.cwiseMax(min_eigenvalue);
  h = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
  h = 0.5 * (h + h.transpose()).eval();  // exact symmetry, whatever the rounding above
  return true;
}

template bool project_to_psd<9>(Eigen::Matrix<double, 9, 9>&, double);
template bool project_to_psd<12>(Eigen::Matrix<double, 12, 12>&, double);
template bool project_to_psd<18>(Eigen::Matrix<double, 18, 18>&, double);
template bool project_to_psd<Eigen::Dynamic>(Eigen::MatrixXd&, double);

}  // namespace flatmorph
