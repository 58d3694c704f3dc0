#include "numerics/newton.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "numerics/psd_projection.h"

namespace flatmorph::newton_test {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// Adds the lower triangle of a 2x2 element Hessian over variables (i, j), i != j.
void add_element(Triplets& t, int i, int j, const Eigen::Matrix2d& h) {
  const int lo = std::min(i, j), hi = std::max(i, j);
  const bool swapped = i > j;
  t.emplace_back(lo, lo, swapped ? h(1, 1) : h(0, 0));
  t.emplace_back(hi, hi, swapped ? h(0, 0) : h(1, 1));
  t.emplace_back(hi, lo, h(0, 1));
}

// A chain of springs of rest length 0 with a pull b on each variable: E = sum_i k_i/2 (x_{i+1} -
// x_i)^2 - b.x, a quadratic whose Newton step is exact.
NewtonProblem spring_chain(int n, const Eigen::VectorXd& b) {
  NewtonProblem p;
  p.num_variables = n;
  p.evaluate = [n, b](const Eigen::VectorXd& x, Eigen::VectorXd* g, Eigen::SparseMatrix<double>* h,
                      bool) {
    double e = -b.dot(x);
    if (g) *g = -b;
    Triplets t;
    for (int i = 0; i + 1 < n; ++i) {
      const double k = 1.0 + 0.1 * i;
      const double d = x(i + 1) - x(i);
      e += 0.5 * k * d * d;
      if (g) {
        (*g)(i) -= k * d;
        (*g)(i + 1) += k * d;
      }
      Eigen::Matrix2d he;
      he << k, -k, -k, k;
      add_element(t, i, i + 1, he);
    }
    if (h) {
      h->resize(n, n);
      h->setFromTriplets(t.begin(), t.end());
    }
    return e;
  };
  return p;
}

TEST(Newton, QuadraticWithFixedEndsConvergesInOneStep) {
  const int n = 50;
  // No pull: the solution interpolates the two fixed ends, x_i with (x_{i+1} - x_i) k_i constant.
  NewtonProblem p = spring_chain(n, Eigen::VectorXd::Zero(n));
  p.fixed_variables = {n - 1, 0};
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(n);
  x0(n - 1) = 1.0;
  const NewtonResult r = newton_minimize(p, x0);
  ASSERT_TRUE(r.converged()) << to_string(r.status);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_EQ(r.projected_iterations, 0);
  EXPECT_EQ(r.x(0), 0.0);
  EXPECT_EQ(r.x(n - 1), 1.0);
  // Force balance: the spring tension k_i (x_{i+1} - x_i) is the same in every spring.
  const double tension = 1.0 * (r.x(1) - r.x(0));
  for (int i = 0; i + 1 < n; ++i) {
    EXPECT_NEAR((1.0 + 0.1 * i) * (r.x(i + 1) - r.x(i)), tension, 1e-12);
  }
  EXPECT_LT(r.gradient_norm, 1e-10);
}

TEST(Newton, WorkspaceKeepsTheConvergedFactorizationAndGivesTheSameResult) {
  const int n = 30;
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b(i) = std::sin(0.7 * i);
  NewtonProblem p = spring_chain(n, b);
  p.fixed_variables = {0, 17};
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(n);
  NewtonWorkspace workspace;
  EXPECT_FALSE(workspace.holds_exact_factorization());
  const NewtonResult alone = newton_minimize(p, x0);
  for (int call = 0; call < 2; ++call) {  // the second call reuses the symbolic analysis
    const NewtonResult r = newton_minimize(p, x0, {}, &workspace);
    ASSERT_TRUE(r.converged()) << to_string(r.status);
    EXPECT_EQ(r.x, alone.x);
    ASSERT_TRUE(workspace.holds_exact_factorization());
  }
  // The held factorization is the Hessian restricted to the free variables: check H^-1 c against
  // a dense solve, with c's fixed entries ignored and the result zero there.
  Eigen::SparseMatrix<double> lower;
  p.evaluate(alone.x, nullptr, &lower, false);
  const Eigen::MatrixXd full = Eigen::MatrixXd(lower).selfadjointView<Eigen::Lower>();
  std::vector<int> free;
  for (int i = 0; i < n; ++i) {
    if (i != 0 && i != 17) free.push_back(i);
  }
  const int m = static_cast<int>(free.size());
  Eigen::MatrixXd h(m, m);
  Eigen::VectorXd c_free(m);
  Eigen::VectorXd c = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  for (int i = 0; i < m; ++i) {
    c_free(i) = c(free[i]);
    for (int j = 0; j < m; ++j) h(i, j) = full(free[i], free[j]);
  }
  const Eigen::VectorXd expected = h.ldlt().solve(c_free);
  const Eigen::VectorXd solved = workspace.solve(c);
  EXPECT_EQ(solved(0), 0.0);
  EXPECT_EQ(solved(17), 0.0);
  for (int i = 0; i < m; ++i) EXPECT_NEAR(solved(free[i]), expected(i), 1e-9 * expected.norm());

  // A call that stops early leaves no exact factorization behind.
  NewtonOptions one_step;
  one_step.max_iterations = 1;
  NewtonProblem pulled = spring_chain(n, 3 * b);
  pulled.fixed_variables = {0};
  pulled.evaluate = [inner = pulled.evaluate](const Eigen::VectorXd& x, Eigen::VectorXd* g,
                                              Eigen::SparseMatrix<double>* hessian, bool proj) {
    // A quartic term makes Newton need more than one step.
    double e = inner(x, g, hessian, proj);
    e += 0.25 * x.array().pow(4).sum();
    if (g) *g += x.array().pow(3).matrix();
    if (hessian) {
      for (int i = 0; i < x.size(); ++i) hessian->coeffRef(i, i) += 3 * x(i) * x(i);
    }
    return e;
  };
  const NewtonResult early = newton_minimize(pulled, x0, one_step, &workspace);
  EXPECT_FALSE(early.converged());
  EXPECT_FALSE(workspace.holds_exact_factorization());
}

TEST(Newton, SingularHessianIsShiftedUntilItFactorizes) {
  // Without fixed variables the chain can translate freely: the Hessian is singular, and the
  // solver must still converge (the pull sums to zero so a minimum exists).
  const int n = 20;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  b(0) = -1.0;
  b(n - 1) = 1.0;
  const NewtonResult r = newton_minimize(spring_chain(n, b), Eigen::VectorXd::Zero(n));
  EXPECT_LT(r.gradient_norm, 1e-8) << to_string(r.status);
  // Every spring carries the unit pull.
  for (int i = 0; i + 1 < n; ++i) EXPECT_NEAR((1.0 + 0.1 * i) * (r.x(i + 1) - r.x(i)), 1.0, 1e-6);
}

// Chained Rosenbrock: sum_i 100 (x_{i+1} - x_i^2)^2 + (1 - x_i)^2, minimum at all ones; its
// element Hessians are indefinite away from the valley.
NewtonProblem rosenbrock(int n) {
  NewtonProblem p;
  p.num_variables = n;
  p.evaluate = [n](const Eigen::VectorXd& x, Eigen::VectorXd* g, Eigen::SparseMatrix<double>* h,
                   bool project) {
    double e = 0;
    if (g) g->setZero(n);
    Triplets t;
    for (int i = 0; i + 1 < n; ++i) {
      const double a = x(i), b = x(i + 1);
      const double r = b - a * a;
      e += 100 * r * r + (1 - a) * (1 - a);
      if (g) {
        (*g)(i) += -400 * r * a - 2 * (1 - a);
        (*g)(i + 1) += 200 * r;
      }
      Eigen::Matrix2d he;
      he << 1200 * a * a - 400 * b + 2, -400 * a, -400 * a, 200;
      if (project) {
        Eigen::MatrixXd projected = he;
        project_to_psd(projected);
        he = projected;
      }
      add_element(t, i, i + 1, he);
    }
    if (h) {
      h->resize(n, n);
      h->setFromTriplets(t.begin(), t.end());
    }
    return e;
  };
  return p;
}

TEST(Newton, NonConvexProblemFallsBackToProjectedHessianAndConverges) {
  const int n = 10;
  NewtonOptions options;
  options.tolerance = 1e-20;
  const NewtonResult r = newton_minimize(rosenbrock(n), Eigen::VectorXd::Constant(n, 0.1), options);
  ASSERT_TRUE(r.converged()) << to_string(r.status);
  EXPECT_GT(r.projected_iterations, 0);
  EXPECT_LT((r.x - Eigen::VectorXd::Ones(n)).norm(), 1e-9);
  // The energy never rises along the iterations (Armijo).
  for (size_t k = 1; k < r.history.size(); ++k) {
    EXPECT_LE(r.history[k].energy, r.history[k - 1].energy);
  }
  // Quadratic convergence at the end: the last exact decrements shrink super-linearly.
  ASSERT_GE(r.history.size(), 3u);
  const double d1 = r.history[r.history.size() - 3].decrement;
  const double d2 = r.history[r.history.size() - 2].decrement;
  EXPECT_LT(d2, d1 * d1 * 1e3 + 1e-12);
}

TEST(Newton, InfeasibleTrialStepsAreRejected) {
  // Minimize (x - 3)^2 while only x < 2 is feasible: every iterate must stay feasible.
  NewtonProblem p;
  p.num_variables = 1;
  p.evaluate = [](const Eigen::VectorXd& x, Eigen::VectorXd* g, Eigen::SparseMatrix<double>* h,
                  bool) {
    if (g) *g = Eigen::VectorXd::Constant(1, 2 * (x(0) - 3));
    if (h) {
      h->resize(1, 1);
      Triplets t{{0, 0, 2.0}};
      h->setFromTriplets(t.begin(), t.end());
    }
    return (x(0) - 3) * (x(0) - 3);
  };
  p.is_feasible = [](const Eigen::VectorXd& x) { return x(0) < 2.0; };
  NewtonOptions options;
  options.max_iterations = 30;
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Zero(1), options);
  EXPECT_LT(r.x(0), 2.0);
  EXPECT_GT(r.x(0), 1.9);
  EXPECT_FALSE(r.converged());
}

TEST(Newton, NonFiniteStartIsReported) {
  NewtonProblem p = rosenbrock(4);
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(4);
  x0(2) = std::nan("");
  const NewtonResult r = newton_minimize(p, x0);
  EXPECT_EQ(r.status, NewtonStatus::kNonFinite);
  EXPECT_EQ(r.iterations, 0);
}

TEST(Newton, NonFiniteTrialEnergiesAreBacktrackedOver) {
  // E = x^2 - log(1 - x), NaN for x > 1, minimum where 2x = -1/(1 - x): x = (1 - sqrt(3))/2. From
  // x = 0.99 the first full Newton steps land where E is NaN and must be backtracked.
  NewtonProblem p;
  p.num_variables = 1;
  p.evaluate = [](const Eigen::VectorXd& x, Eigen::VectorXd* g, Eigen::SparseMatrix<double>* h,
                  bool) {
    const double v = x(0);
    if (g) *g = Eigen::VectorXd::Constant(1, 2 * v + 1 / (1 - v));
    if (h) {
      h->resize(1, 1);
      Triplets t{{0, 0, 2 + 1 / ((1 - v) * (1 - v))}};
      h->setFromTriplets(t.begin(), t.end());
    }
    return v * v - std::log(1 - v);  // NaN for v > 1
  };
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Constant(1, 0.99));
  ASSERT_TRUE(r.converged()) << to_string(r.status);
  EXPECT_NEAR(r.x(0), (1 - std::sqrt(3.0)) / 2, 1e-6);
}

TEST(Newton, SameInputSameOutputBitForBit) {
  const NewtonResult a = newton_minimize(rosenbrock(30), Eigen::VectorXd::Constant(30, 0.1));
  const NewtonResult b = newton_minimize(rosenbrock(30), Eigen::VectorXd::Constant(30, 0.1));
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.energy, b.energy);
  EXPECT_TRUE((a.x.array() == b.x.array()).all());
}

}  // namespace
}  // namespace flatmorph::newton_test
