// GCC 12 reports a false "may be used uninitialized" inside Eigen 3.4's tridiagonalization (the
// eigen-decompositions below); the warning is about Eigen's code, not this file's.
#if !defined(__clang__)  // clang has no such warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "numerics/psd_projection.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

namespace flatmorph::psd_projection_test {
namespace {

template <int N>
Eigen::Matrix<double, N, N> random_symmetric(std::mt19937& rng, int n = N) {
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, N, N> a(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) a(i, j) = normal(rng);
  }
  return a + a.transpose();
}

TEST(PsdProjection, ClampsNegativeEigenvaluesAndKeepsEigenvectors) {
  std::mt19937 rng(7);
  const Eigen::Matrix<double, 12, 12> h = random_symmetric<12>(rng);
  Eigen::Matrix<double, 12, 12> p = h;
  EXPECT_TRUE(project_to_psd(p));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> before(h), after(p);
  ASSERT_LT(before.eigenvalues().minCoeff(), 0.0);
  EXPECT_GE(after.eigenvalues().minCoeff(), -1e-12);
  // Same spectrum with negatives replaced by 0, and p - h is PSD (only negatives were raised).
  Eigen::VectorXd expected = before.eigenvalues().cwiseMax(0.0);
  std::sort(expected.data(), expected.data() + expected.size());
  EXPECT_TRUE(after.eigenvalues().isApprox(expected, 1e-10) ||
              (after.eigenvalues() - expected).norm() < 1e-10);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> diff(p - h);
  EXPECT_GE(diff.eigenvalues().minCoeff(), -1e-10);
  // p - h lives in the span of the negative eigenvectors: p v = h v for positive eigenvectors.
  for (int i = 0; i < 12; ++i) {
    if (before.eigenvalues()(i) > 0) {
      const auto v = before.eigenvectors().col(i);
      EXPECT_LT((p * v - h * v).norm(), 1e-10);
    }
  }
  EXPECT_EQ(p, p.transpose());
}

TEST(PsdProjection, LeavesPositiveDefiniteMatricesUnchanged) {
  std::mt19937 rng(3);
  Eigen::Matrix<double, 9, 9> a = random_symmetric<9>(rng);
  Eigen::Matrix<double, 9, 9> spd = a * a.transpose() + Eigen::Matrix<double, 9, 9>::Identity();
  const Eigen::Matrix<double, 9, 9> copy = spd;
  EXPECT_FALSE(project_to_psd(spd));
  EXPECT_EQ(spd, copy);
}

TEST(PsdProjection, MinimumEigenvalueIsHonoured) {
  std::mt19937 rng(11);
  Eigen::MatrixXd h = random_symmetric<Eigen::Dynamic>(rng, 5);
  EXPECT_TRUE(project_to_psd(h, 0.25));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(h);
  EXPECT_GE(eig.eigenvalues().minCoeff(), 0.25 - 1e-12);
}

TEST(PsdProjection, DiagonallyDominantShortcutIsExact) {
  // Diagonally dominant with a small negative off-diagonal: PSD, must not be touched.
  Eigen::Matrix<double, 18, 18> h = Eigen::Matrix<double, 18, 18>::Identity() * 2.0;
  h(0, 1) = h(1, 0) = -1.0;
  const Eigen::Matrix<double, 18, 18> copy = h;
  EXPECT_FALSE(project_to_psd(h));
  EXPECT_EQ(h, copy);
  // Not dominant and indefinite: must change.
  h(0, 1) = h(1, 0) = -3.0;
  EXPECT_TRUE(project_to_psd(h));
}

}  // namespace
}  // namespace flatmorph::psd_projection_test
