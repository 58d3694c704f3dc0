// numerics/sparse_cholesky.h: the factorization solves, and leaves the caller's OpenMP setting as
// it found it; the programs' BLAS runs on one thread.
#include "numerics/sparse_cholesky.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <vector>

namespace flatmorph {
namespace {

// The 1D Laplacian plus the identity on n unknowns (SPD), lower triangle only.
Eigen::SparseMatrix<double> laplacian_plus_identity(int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 3.0);
    if (i + 1 < n) t.emplace_back(i + 1, i, -1.0);
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

TEST(SparseCholesky, FactorizesAndRestoresTheCallersOpenMpSetting) {
  const int n = 2000;
  const Eigen::SparseMatrix<double> lower = laplacian_plus_identity(n);
  const Eigen::SparseMatrix<double> full =
      Eigen::SparseMatrix<double>(lower.selfadjointView<Eigen::Lower>());
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  const Eigen::VectorXd b = full * x;

  const int before = omp_get_max_active_levels();
  omp_set_max_active_levels(3);
  SparseCholesky solver;
  configure_sparse_cholesky(solver);
  solver.analyzePattern(lower);
  factorize(solver, lower);
  EXPECT_EQ(omp_get_max_active_levels(), 3);
  omp_set_max_active_levels(before);
  ASSERT_EQ(solver.info(), Eigen::Success);
  EXPECT_LT((solver.solve(b) - x).cwiseAbs().maxCoeff(), 1e-10);

  // Not positive definite: the failure is reported, and the setting restored all the same.
  Eigen::SparseMatrix<double> indefinite = lower;
  indefinite.coeffRef(n / 2, n / 2) = -3.0;
  factorize(solver, indefinite);
  EXPECT_NE(solver.info(), Eigen::Success);
  EXPECT_EQ(omp_get_max_active_levels(), before);
}

}  // namespace
}  // namespace flatmorph
