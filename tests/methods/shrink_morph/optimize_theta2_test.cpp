// Tests of the theta2 inverse design (src/methods/shrink_morph/optimize_theta2.h): the mixed
// derivative of the plate energy against finite differences of its gradient, the adjoint gradient
// of Eq. 14 against central finite differences of the full objective (forward solves included),
// that the optimization lowers the distance to the target, its stop on the Gauss–Newton
// decrement, and that the SGN KKT system gives the reduced system's step.
#include "methods/shrink_morph/optimize_theta2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "material/material.h"
#include "mesh/mesh_fixtures.h"
#include "methods/shrink_morph/flatten.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "simulate/distance.h"
#include "simulate/plate_energy.h"
#include "simulate/simulate.h"

namespace flatmorph::optimize_theta2_test {
namespace {

// A spherical cap of radius `radius` mm over an n x n grid of the square [-1, 1]^2 * half_width.
Mesh cap_mesh(int n, double half_width, double radius) {
  return testing::grid_mesh(n, n, [&](double u, double v) {
    const double x = half_width * (2 * u - 1), y = half_width * (2 * v - 1);
    return Eigen::Vector3d(x, y, std::sqrt(radius * radius - x * x - y * y) - radius);
  });
}

Theta2Problem cap_problem(int n) {
  const Mesh mesh = cap_mesh(n, 20, 60);
  FlattenOptions options;
  options.width_mm = 60;
  const Material material = load_material("pla-paper");
  return theta2_problem(flatten(mesh, options), material, 10);
}

// ∂²W/∂x∂θ2_f through the exact laminate of the printed layers (ā, b̄ and the stiffness all move
// with θ2), at θ2 up to 1.5 rad where the first-order model is far off.
TEST(RestFormsMixedDerivative, MatchesFiniteDifferencesOfTheGradient) {
  const Theta2Problem problem = cap_problem(4);
  const int nf = static_cast<int>(problem.F.rows());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.5, 1.5);
  Eigen::VectorXd theta2(nf);
  for (int f = 0; f < nf; ++f) theta2(f) = uniform(rng);
  auto stack = [&](const Eigen::VectorXd& face_theta2) {
    return shrink_morph_layer_stack(problem.theta1, face_theta2, problem.material,
                                    problem.num_layers, problem.material.layer_height);
  };
  std::vector<double> rates;
  for (int k = 1; k <= problem.num_layers; ++k) {
    rates.push_back(shrink_morph_layer_weight(k, problem.num_layers));
  }
  LaminateDerivative derivative;
  const RestForms base = laminate(stack(theta2), rates, derivative);
  PlateEnergy energy = make_plate_energy(problem.plate, problem.F, base);
  Eigen::VectorXd x(3 * problem.plate.rows());
  for (int v = 0; v < problem.plate.rows(); ++v) {
    x.segment<3>(3 * v) = problem.target.row(v).transpose();
    x(3 * v + 2) += 0.1 * uniform(rng);
  }
  const Eigen::MatrixXd mixed = rest_forms_mixed_derivative(energy, x, derivative);
  const double h = 1e-5;
  for (int f : {0, nf / 2, nf - 1}) {
    Eigen::VectorXd grad[2];
    for (int side = 0; side < 2; ++side) {
      Eigen::VectorXd moved = theta2;
      moved(f) += side == 0 ? h : -h;
      set_rest_forms(energy, laminate(stack(moved)));
      evaluate_plate_energy(energy, x, &grad[side], nullptr, false);
    }
    const Eigen::VectorXd fd = (grad[0] - grad[1]) / (2 * h);
    EXPECT_LT((fd - mixed.col(f)).norm(), 1e-6 * (1 + fd.norm())) << "face " << f;
    EXPECT_GT(fd.norm(), 0);
  }
}

TEST(OptimizeTheta2, AdjointGradientMatchesFiniteDifferencesOfTheObjective) {
  const Theta2Problem problem = cap_problem(5);
  const int nv = static_cast<int>(problem.plate.rows());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-0.05, 0.05);
  Eigen::VectorXd theta2(nv);
  for (int v = 0; v < nv; ++v) theta2(v) = uniform(rng);
  OptimizeTheta2Options options;
  options.forward.relative_tolerance = 1e-20;  // converge the forward solves to round-off
  const Theta2Evaluation at = evaluate_theta2_objective(problem, theta2, problem.target, options);
  ASSERT_TRUE(at.forward_converged);
  ASSERT_EQ(at.gradient.size(), nv);
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd direction(nv);
    for (int v = 0; v < nv; ++v) direction(v) = uniform(rng);
    const double h = 1e-4;
    const double plus =
        evaluate_theta2_objective(problem, theta2 + h * direction, at.V, options).objective;
    const double minus =
        evaluate_theta2_objective(problem, theta2 - h * direction, at.V, options).objective;
    const double fd = (plus - minus) / (2 * h);
    const double adjoint = at.gradient.dot(direction);
    EXPECT_NEAR(adjoint, fd, 1e-4 * std::abs(fd) + 1e-9) << "direction " << trial;
    EXPECT_GT(std::abs(fd), 1e-3) << "the direction should change the objective";
  }
}

TEST(OptimizeTheta2, LowersTheDistanceToTheTarget) {
  const Theta2Problem problem = cap_problem(8);
  const Theta2Result r = optimize_theta2(problem, {});
  const ShapeDistance before = shape_distance(r.initial_V, problem.target);
  const ShapeDistance after = shape_distance(r.V, problem.target);
  EXPECT_LT(r.objective, r.initial_objective);
  // The printed laminate cannot twist without bound as the first-order model (Eq. 7, linear in θ2)
  // could: on this cap it stops near 3.2 % (3.5 % on the first-order model; docs/design.md).
  EXPECT_LT(after.mean_percent * 2, before.mean_percent)
      << before.mean_percent << " -> " << after.mean_percent;
  EXPECT_GT(r.iterations, 0);
  std::cout << "cap: " << before.mean_percent << " -> " << after.mean_percent << " % in "
            << r.iterations << " iterations (" << r.stop_reason << ")\n";
}

// θ2 stays within its bound: with a bound well below what the cap asks for, the result sits on it
// somewhere, never beyond, and still lowers E; by default the bound is the printed stack's.
// What the optimizer returns is an equilibrium no farther from the target than θ2 = 0's, on caps
// curved enough that the plate is multistable (θ2 = 0 lands 7-12 % from them). Line-search trials
// solved to a 1000x looser tolerance let it accept states that were not equilibria, and the
// returned θ2's equilibrium ended up farther than the start (E 1822 -> 2417 on the 50 mm cap).
TEST(OptimizeTheta2, EndsCloserThanItStartsOnStronglyCurvedCaps) {
  for (double radius : {50.0, 70.0, 100.0}) {
    FlattenOptions flatten_options;
    flatten_options.width_mm = 60;
    const Theta2Problem problem = theta2_problem(flatten(cap_mesh(8, 20, radius), flatten_options),
                                                 load_material("pla-paper"), 10);
    const Theta2Result r = optimize_theta2(problem, {});
    const double before = shape_distance(r.initial_V, problem.target).mean_percent;
    const double after = shape_distance(r.V, problem.target).mean_percent;
    EXPECT_LT(r.objective, 0.5 * r.initial_objective) << radius;
    EXPECT_LT(after * 2, before) << radius;
    // The returned shape is the equilibrium of the returned θ2: simulating it again stays put.
    const SimulationResult again =
        simulate(theta2_plate_problem(problem, r.theta2), r.V, OptimizeTheta2Options{}.forward);
    EXPECT_LT((again.V - r.V).rowwise().norm().maxCoeff(), 1e-3) << radius;
    std::cout << "cap of radius " << radius << " mm: " << before << " -> " << after << " % ("
              << r.stop_reason << ")\n";
  }
}

TEST(OptimizeTheta2, KeepsTheta2WithinItsBound) {
  const Theta2Problem problem = cap_problem(8);
  OptimizeTheta2Options options;
  options.max_abs_theta2 = 0.05;
  const Theta2Result r =
      optimize_theta2(problem, Eigen::VectorXd::Constant(problem.plate.rows(), 0.3), options);
  EXPECT_LE(r.theta2.cwiseAbs().maxCoeff(), 0.05);
  EXPECT_DOUBLE_EQ(r.theta2_bound, 0.05);
  EXPECT_GT(r.vertices_at_bound, 0);
  EXPECT_LT(r.objective, r.initial_objective);
  const Theta2Result unbounded = optimize_theta2(problem, {});
  EXPECT_DOUBLE_EQ(unbounded.theta2_bound, kShrinkMorphTheta2Bound);
  EXPECT_LT(unbounded.objective, r.objective);
}

// The stop on the Gauss–Newton decrement: every iteration but the last predicted at least the
// tolerance, the last less. The prediction is the model's: the model E + gᵀd + ½ dᵀ(Sᵀ2DS + R)d is
// a sum of squares, so it cannot predict a decrease larger than E.
TEST(OptimizeTheta2, StopsWhenTheGaussNewtonModelPredictsLessThanTheTolerance) {
  const Theta2Problem problem = cap_problem(8);
  OptimizeTheta2Options options;
  options.relative_decrease = 0;
  // E starts at about 1300 on this cap and stalls near 300 on the printed laminate.
  options.decrement_tolerance = 300;
  std::vector<Theta2Iteration> reported;
  options.progress = [&](const Theta2Iteration& it) { reported.push_back(it); };
  const Theta2Result r = optimize_theta2(problem, {}, options);
  ASSERT_EQ(r.stop_reason, "predicted decrease below tolerance");
  // Progress sees every record, the stopping one (no trial) included.
  ASSERT_EQ(reported.size(), r.history.size());
  EXPECT_EQ(reported.back().decrement, r.history.back().decrement);
  EXPECT_EQ(reported.back().line_search_trials, 0);
  ASSERT_GE(r.history.size(), 2u);
  EXPECT_LT(r.history.back().decrement, options.decrement_tolerance);
  EXPECT_EQ(r.iterations + 1, static_cast<int>(r.history.size()));
  for (size_t i = 0; i < r.history.size(); ++i) {
    const Theta2Iteration& it = r.history[i];
    if (i + 1 < r.history.size()) {
      EXPECT_GE(it.decrement, options.decrement_tolerance) << i;
    }
    EXPECT_GT(it.decrement, 0) << i;
    EXPECT_LE(it.decrement, it.objective) << i;
  }
}

}  // namespace
}  // namespace flatmorph::optimize_theta2_test
