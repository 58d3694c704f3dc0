#include "numerics/autodiff.h"

#include <gtest/gtest.h>

#include <functional>

namespace flatmorph::autodiff_test {
namespace {

constexpr int kN = 3;
using D = Dual<kN>;
using Vec = Eigen::Vector3d;

// Central finite differences of a double-valued function for the gradient, and of the Dual's own
// gradient for the Hessian (so the Hessian check does not compound two truncation errors).
template <typename F>
void expect_derivatives_match(F f, const Vec& x, double tolerance = 1e-7) {
  auto eval = [&](const Vec& p) {
    std::array<D, kN> v;
    for (int i = 0; i < kN; ++i) v[i] = D::variable(p(i), i);
    return f(v);
  };
  const D at = eval(x);
  const double h = 1e-6;
  for (int i = 0; i < kN; ++i) {
    Vec xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    const D fp = eval(xp), fm = eval(xm);
    const double fd_gradient = (fp.value - fm.value) / (2 * h);
    EXPECT_NEAR(at.gradient(i), fd_gradient, tolerance * (1 + std::abs(fd_gradient))) << "i=" << i;
    const Vec fd_hessian_column = (fp.gradient - fm.gradient) / (2 * h);
    for (int j = 0; j < kN; ++j) {
      EXPECT_NEAR(at.hessian(j, i), fd_hessian_column(j),
                  tolerance * (1 + std::abs(fd_hessian_column(j))))
          << "i=" << i << " j=" << j;
    }
  }
  EXPECT_TRUE(at.hessian.isApprox(at.hessian.transpose(), 1e-14) || at.hessian.norm() < 1e-14);
}

const Vec kPoint(0.7, -1.3, 2.1);

TEST(Autodiff, ValueOfVariableAndConstant) {
  const D x = D::variable(2.5, 1);
  EXPECT_EQ(x.value, 2.5);
  EXPECT_EQ(x.gradient, Vec(0, 1, 0));
  EXPECT_EQ(x.hessian.norm(), 0.0);
  const D c = 4.0;
  EXPECT_EQ(c.gradient.norm(), 0.0);
}

TEST(Autodiff, ArithmeticMatchesFiniteDifferences) {
  expect_derivatives_match([](auto& v) { return v[0] + v[1] - v[2]; }, kPoint);
  expect_derivatives_match([](auto& v) { return v[0] * v[1] * v[2]; }, kPoint);
  expect_derivatives_match([](auto& v) { return v[0] / (v[1] * v[2]); }, kPoint);
  expect_derivatives_match([](auto& v) { return -v[0] * 3.0 + 2.0 / v[2] - v[1] / 5.0; }, kPoint);
  expect_derivatives_match([](auto& v) { return 1.5 - v[0] + (v[1] - 0.5) + 2.0 * v[2]; }, kPoint);
  expect_derivatives_match(
      [](auto& v) {
        D a = v[0];
        a += v[1];
        a *= v[2];
        a -= v[0] * v[0];
        a /= v[1];
        return a;
      },
      kPoint);
}

TEST(Autodiff, ElementaryFunctionsMatchFiniteDifferences) {
  expect_derivatives_match([](auto& v) { return sqrt(v[0] * v[0] + v[2]); }, kPoint);
  expect_derivatives_match([](auto& v) { return sin(v[0] * v[1]); }, kPoint);
  expect_derivatives_match([](auto& v) { return cos(v[1] + v[2] * v[0]); }, kPoint);
  expect_derivatives_match([](auto& v) { return exp(v[0] - 0.3 * v[2]); }, kPoint);
  expect_derivatives_match([](auto& v) { return log(v[2] * v[0]); }, kPoint);
  expect_derivatives_match([](auto& v) { return hypot(v[0] * v[2], v[1]); }, kPoint);
}

TEST(Autodiff, Atan2MatchesFiniteDifferencesInEveryQuadrant) {
  for (const Vec& p :
       {Vec(0.7, 1.3, 0), Vec(-0.7, 1.3, 0), Vec(-0.7, -1.3, 0), Vec(0.7, -1.3, 0)}) {
    expect_derivatives_match([](auto& v) { return atan2(v[1] * v[2] + v[1], v[0] - v[2]); },
                             p + Vec(0, 0, 0.2));
  }
}

TEST(Autodiff, IntegerPowersMatchFiniteDifferences) {
  for (int n : {-3, -1, 0, 1, 2, 3, 5}) {
    expect_derivatives_match([n](auto& v) { return pow(v[0] * v[2], n); }, kPoint);
  }
  // pow(x, 2) at x = 0: derivatives 0 and 2, no NaN from negative powers of zero.
  const D zero = D::variable(0.0, 0);
  const D sq = pow(zero, 2);
  EXPECT_EQ(sq.value, 0.0);
  EXPECT_EQ(sq.gradient(0), 0.0);
  EXPECT_EQ(sq.hessian(0, 0), 2.0);
}

TEST(Autodiff, ComparisonsUseValues) {
  const D a = D::variable(1.0, 0), b = D::variable(2.0, 1);
  EXPECT_TRUE(a < b);
  EXPECT_TRUE(b > a);
  EXPECT_TRUE(a <= a);
  EXPECT_TRUE(a >= a);
  EXPECT_FALSE(a == b);
  EXPECT_TRUE(a != b);
}

}  // namespace
}  // namespace flatmorph::autodiff_test
