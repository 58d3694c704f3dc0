// Issue 9, item 4 (Newton): non-convergence, NaN and an exploding energy stop the minimizer with a
// warning that says what to change, and the best finite state found is returned.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "numerics/newton.h"

namespace flatmorph::newton_safety_test {
namespace {

// A one-variable problem from the energy, its derivative and its second derivative.
template <typename E, typename G, typename H>
NewtonProblem scalar_problem(E energy, G grad, H hess) {
  NewtonProblem p;
  p.num_variables = 1;
  p.evaluate = [=](const Eigen::VectorXd& x, Eigen::VectorXd* g, Eigen::SparseMatrix<double>* h,
                   bool project) {
    if (g) (*g)(0) = grad(x(0));
    if (h) {
      h->resize(1, 1);
      h->insert(0, 0) = project ? std::abs(hess(x(0))) : hess(x(0));
      h->makeCompressed();
    }
    return energy(x(0));
  };
  return p;
}

TEST(NewtonSafety, ConvergedRunsHaveNoWarning) {
  const NewtonProblem p =
      scalar_problem([](double x) { return (x - 2) * (x - 2); },
                     [](double x) { return 2 * (x - 2); }, [](double) { return 2.0; });
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Constant(1, 7.0));
  EXPECT_EQ(r.status, NewtonStatus::kConverged);
  EXPECT_TRUE(r.warning.empty()) << r.warning;
}

TEST(NewtonSafety, AnEnergyUnboundedBelowStopsAsDiverged) {
  // -x^3 falls without bound for x > 0.
  const NewtonProblem p =
      scalar_problem([](double x) { return -x * x * x; }, [](double x) { return -3 * x * x; },
                     [](double x) { return -6 * x; });
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Constant(1, 1.0));
  EXPECT_EQ(r.status, NewtonStatus::kDiverged) << to_string(r.status);
  EXPECT_TRUE(r.x.allFinite());
  EXPECT_TRUE(std::isfinite(r.energy));
  EXPECT_LT(r.x(0), 1e9);
  EXPECT_NE(r.warning.find("finer mesh"), std::string::npos) << r.warning;
  EXPECT_NE(r.warning.find("exploded"), std::string::npos) << r.warning;
}

TEST(NewtonSafety, ANanGradientKeepsTheLastFiniteState) {
  // (x - 5)^2 with a gradient that turns NaN beyond x = 4: steps into that region back off to
  // finite states, and the minimizer never returns one beyond it.
  const NewtonProblem p = scalar_problem(
      [](double x) { return (x - 5) * (x - 5); },
      [](double x) { return x > 4 ? std::numeric_limits<double>::quiet_NaN() : 2 * (x - 5); },
      [](double) { return 0.2; });  // a poor Hessian: the steps overshoot into the NaN region
  NewtonOptions options;
  options.max_iterations = 50;
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Constant(1, 0.0), options);
  EXPECT_NE(r.status, NewtonStatus::kConverged) << to_string(r.status);
  EXPECT_TRUE(r.x.allFinite());
  EXPECT_TRUE(std::isfinite(r.energy));
  EXPECT_LE(r.x(0), 4.0);
  EXPECT_GT(r.x(0), 3.9);  // backed off toward the edge, not stopped at the first overshoot
  EXPECT_NE(r.warning.find("smaller plate"), std::string::npos) << r.warning;
}

TEST(NewtonSafety, ANanEverywhereButTheStartStopsAsNonFinite) {
  const NewtonProblem p = scalar_problem(
      [](double x) { return (x - 5) * (x - 5); },
      [](double x) { return x != 0 ? std::numeric_limits<double>::quiet_NaN() : 2 * (x - 5); },
      [](double) { return 2.0; });
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Constant(1, 0.0));
  EXPECT_EQ(r.status, NewtonStatus::kNonFinite) << to_string(r.status);
  EXPECT_EQ(r.x(0), 0.0);
  EXPECT_NE(r.warning.find("NaN"), std::string::npos) << r.warning;
}

TEST(NewtonSafety, ANanStartIsReportedNotPropagated) {
  const NewtonProblem p = scalar_problem(
      [](double x) { return x * x; }, [](double x) { return 2 * x; }, [](double) { return 2.0; });
  const NewtonResult r =
      newton_minimize(p, Eigen::VectorXd::Constant(1, std::numeric_limits<double>::quiet_NaN()));
  EXPECT_EQ(r.status, NewtonStatus::kNonFinite);
  EXPECT_FALSE(r.warning.empty());
}

TEST(NewtonSafety, TheIterationLimitSaysSoAndReturnsTheBestState) {
  // A slow valley: x^4 needs many Newton steps.
  const NewtonProblem p = scalar_problem([](double x) { return std::pow(x, 4); },
                                         [](double x) { return 4 * std::pow(x, 3); },
                                         [](double x) { return 12 * x * x; });
  NewtonOptions options;
  options.max_iterations = 3;
  options.tolerance = 1e-30;
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Constant(1, 10.0), options);
  EXPECT_EQ(r.status, NewtonStatus::kIterationLimit);
  EXPECT_EQ(r.iterations, 3);
  EXPECT_LT(r.energy, 1e4);  // below the start's energy
  EXPECT_NE(r.warning.find("did not converge in 3 iterations"), std::string::npos) << r.warning;
}

TEST(NewtonSafety, TheTimeBudgetSaysSoAndReturnsTheBestState) {
  const NewtonProblem p =
      scalar_problem([](double x) { return (x - 2) * (x - 2); },
                     [](double x) { return 2 * (x - 2); }, [](double) { return 2.0; });
  NewtonOptions options;
  options.max_seconds = 0;  // spent before the first iteration
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Constant(1, 7.0), options);
  EXPECT_EQ(r.status, NewtonStatus::kTimeLimit) << to_string(r.status);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.x(0), 7.0);
  EXPECT_NE(r.warning.find("time budget of 0 s"), std::string::npos) << r.warning;
}

// (x)^2 kept to x > 1: every Newton direction points past the feasible set, so each line search
// halves the step until it lands inside, and x creeps toward 1 while the gradient stays 2.
TEST(NewtonSafety, ACrawlAgainstTheFeasibleSetStopsAsStalled) {
  NewtonProblem p = scalar_problem([](double x) { return x * x; }, [](double x) { return 2 * x; },
                                   [](double) { return 2.0; });
  p.is_feasible = [](const Eigen::VectorXd& x) { return x(0) > 1; };
  NewtonOptions options;
  options.tolerance = 1e-3;
  options.stall_iterations = 5;
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Constant(1, 2.0), options);
  EXPECT_EQ(r.status, NewtonStatus::kStalled) << to_string(r.status);
  EXPECT_LT(r.iterations, 30);
  EXPECT_GT(r.x(0), 1.0);
  EXPECT_LT(r.x(0), 1.001);
  EXPECT_NE(r.warning.find("stalled: its last 5 of"), std::string::npos) << r.warning;
}

TEST(NewtonSafety, StopAtEndsAtTheFirstStateItNames) {
  NewtonProblem p =
      scalar_problem([](double x) { return (x - 3) * (x - 3); },
                     [](double x) { return 2 * (x - 3); }, [](double) { return 2.0; });
  p.stop_at = [](const Eigen::VectorXd& x) { return x(0) > 1; };
  const NewtonResult r = newton_minimize(p, Eigen::VectorXd::Zero(1));
  EXPECT_EQ(r.status, NewtonStatus::kStopped) << to_string(r.status);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_DOUBLE_EQ(r.x(0), 3.0);  // the state it moved to, not the start
}

}  // namespace
}  // namespace flatmorph::newton_safety_test
