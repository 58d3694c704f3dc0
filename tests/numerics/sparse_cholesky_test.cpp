// numerics/sparse_cholesky.h: the factorization solves, and leaves the caller's OpenMP setting as
// it found it; the programs' BLAS runs on one thread.
#include "numerics/sparse_cholesky.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <thread>
#include <vector>

namespace flatmorph::sparse_cholesky_test {
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
  analyze_pattern(solver, lower);
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

// The 5-point Laplacian of an n x n grid plus the identity, lower triangle: large and planar
// enough that CHOLMOD keeps METIS's nested dissection over AMD.
Eigen::SparseMatrix<double> grid_laplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const int v = i * n + j;
      t.emplace_back(v, v, 5.0);
      if (j + 1 < n) t.emplace_back(v + 1, v, -1.0);
      if (i + 1 < n) t.emplace_back(v + n, v, -1.0);
    }
  }
  Eigen::SparseMatrix<double> a(n * n, n * n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

Eigen::VectorXd solve_once(const Eigen::SparseMatrix<double>& lower, const Eigen::VectorXd& b) {
  SparseCholesky solver;
  configure_sparse_cholesky(solver);
  analyze_pattern(solver, lower);
  factorize(solver, lower);
  return solver.solve(b);
}

// The design runs independent problems on both cores. METIS's random generator is shared by the
// process, so analyses running at once ordered differently from run to run, and the rounding of
// every solve with them: the same problem must give the same bits, alone or beside another.
TEST(SparseCholesky, AnalysesBesideEachOtherGiveTheSameBits) {
  const Eigen::SparseMatrix<double> lower = grid_laplacian(120);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(lower.rows(), -1.0, 2.0).array().sin();
  const Eigen::VectorXd alone = solve_once(lower, b);
  for (int round = 0; round < 4; ++round) {
    Eigen::VectorXd first, second;
    std::thread other([&] { second = solve_once(lower, b); });
    first = solve_once(lower, b);
    other.join();
    EXPECT_TRUE(first == alone) << "round " << round;
    EXPECT_TRUE(second == alone) << "round " << round;
  }
}

}  // namespace
}  // namespace flatmorph::sparse_cholesky_test
