// Projection of small dense symmetric matrices onto the positive semi-definite cone, used to make
// per-element Hessians convex before assembly (projected Newton, Teran et al. 2005).
#pragma once

#include <Eigen/Core>

namespace flatmorph {

// Replaces the symmetric matrix `h` by the nearest (in the Frobenius norm) symmetric matrix whose
// eigenvalues are all >= min_eigenvalue: eigenvalues below the bound are raised to it, eigenvectors
// are kept. Matrices that are already diagonally dominant with a diagonal >= min_eigenvalue are
// left untouched without an eigen-decomposition (Gershgorin: they are already PSD). Returns true
// when `h` was changed. Instantiated for N = 9, 12, 18 and Eigen::Dynamic.
template <int N>
bool project_to_psd(Eigen::Matrix<double, N, N>& h, double min_eigenvalue = 0.0);

}  // namespace flatmorph
