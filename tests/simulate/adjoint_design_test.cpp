// Tests of the shared adjoint design solver (src/simulate/adjoint_design.h) on a design variable
// of neither method: the extra shrink p of the top layer of a bilayer strip. Its adjoint gradient
// against central finite differences of the objective (forward solves included), with and without
// the best rigid motion and with both regularizer terms; the optimization finding a target that is
// the equilibrium of a known p, and keeping p within its bounds.
#include "simulate/adjoint_design.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <functional>
#include <vector>

#include "material/material.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "plate/plate_fixtures.h"
#include "simulate/distance.h"
#include "simulate/simulate.h"

namespace flatmorph::adjoint_design_test {
namespace {

using testing::rectangle_plate;
using testing::TestPlate;

// Two 0.2 mm layers along x; the top one shrinks by p more (λ1 − p, per face).
LayerStack bilayer_stack(const Material& material, const Eigen::VectorXd& face_p) {
  const int nf = static_cast<int>(face_p.size());
  LayerStack stack;
  stack.materials = {material};
  stack.layers = {uniform_layer(nf, 0, material, 0.2), uniform_layer(nf, 0, material, 0.2)};
  stack.layers[1].lambda1 -= face_p;
  return stack;
}

AdjointDesignProblem bilayer_problem(const TestPlate& plate, const Eigen::MatrixXd& target) {
  const Material material;
  AdjointDesignProblem problem;
  problem.plate = plate.V;
  problem.F = plate.F;
  problem.target = target;
  problem.layer_stack = [material, F = plate.F](const Eigen::VectorXd& p) {
    return bilayer_stack(material, vertex_to_face_average(F, p));
  };
  problem.laminate_derivative = [](const LayerStack& stack) {
    const int nf = stack.num_faces();
    LayerShrinkRates rates;
    rates.lambda1 = {Eigen::VectorXd::Zero(nf), Eigen::VectorXd::Constant(nf, -1.0)};
    rates.printed_thickness = {Eigen::VectorXd::Zero(nf), Eigen::VectorXd::Zero(nf)};
    LaminateDerivative derivative;
    laminate(stack, rates, derivative);
    return derivative;
  };
  problem.reference_variables = Eigen::VectorXd::Zero(plate.V.rows());
  return problem;
}

// p rising along x: the strip bends more at one end.
Eigen::VectorXd ramp(const TestPlate& plate, double at_left, double at_right) {
  const double left = plate.V.col(0).minCoeff(), right = plate.V.col(0).maxCoeff();
  return (at_left + (at_right - at_left) * (plate.V.col(0).array() - left) / (right - left))
      .matrix();
}

PlateProblem strip_problem(const TestPlate& plate, const Eigen::VectorXd& p) {
  PlateProblem problem;
  problem.plate = plate.V;
  problem.F = plate.F;
  problem.rest_forms = laminate(bilayer_stack(Material{}, vertex_to_face_average(plate.F, p)));
  return problem;
}

// The shape the strip takes for p, from the flat plate.
Eigen::MatrixXd equilibrium(const TestPlate& plate, const Eigen::VectorXd& p) {
  const PlateProblem problem = strip_problem(plate, p);
  const SimulationResult r = simulate(problem, flat_start(problem));
  EXPECT_TRUE(r.converged);
  return r.V;
}

TEST(AdjointDesign, GradientMatchesCentralDifferencesOfTheObjective) {
  const TestPlate plate = rectangle_plate(40, 16, 8, 3);
  const int nv = static_cast<int>(plate.V.rows());
  const AdjointDesignProblem problem =
      bilayer_problem(plate, equilibrium(plate, ramp(plate, 0.002, 0.008)));
  Eigen::VectorXd p = ramp(plate, 0.006, 0.003);
  for (int v = 0; v < nv; ++v) p(v) += 0.001 * std::sin(1.7 * v);
  for (bool rigid : {false, true}) {
    AdjointDesignOptions options;
    // Both regularizer terms of the size of the distance term, so that their gradients count.
    options.mass_weight = 1e5;
    options.laplacian_weight = 1e5;
    options.best_rigid_motion = rigid;
    options.forward.relative_tolerance = 1e-20;  // converge the forward solves to round-off
    const AdjointEvaluation at = evaluate_adjoint_design(problem, p, problem.target, options);
    ASSERT_TRUE(at.forward_converged);
    ASSERT_EQ(at.gradient.size(), nv);
    EXPECT_GT(at.distance_term, 1);
    EXPECT_GT(at.objective, at.distance_term * 1.01);
    std::vector<Eigen::VectorXd> directions = {Eigen::VectorXd::Unit(nv, 0),
                                               Eigen::VectorXd::Unit(nv, nv / 2)};
    Eigen::VectorXd mixed(nv);
    for (int v = 0; v < nv; ++v) mixed(v) = std::cos(0.9 * v) + 0.5;
    directions.push_back(mixed);
    const double h = 1e-6;
    for (const Eigen::VectorXd& d : directions) {
      const double plus =
          evaluate_adjoint_design(problem, p + h * d, at.V, options, false).objective;
      const double minus =
          evaluate_adjoint_design(problem, p - h * d, at.V, options, false).objective;
      const double fd = (plus - minus) / (2 * h);
      const double adjoint = at.gradient.dot(d);
      EXPECT_NEAR(adjoint, fd, 1e-4 * std::abs(fd)) << "rigid " << rigid;
      EXPECT_GT(std::abs(fd), 1e-3 * at.gradient.norm()) << "rigid " << rigid;
    }
  }
}

// Printing errors (AdjointDesignProblem::perturbations): a top layer that shrinks 0.002 more, and
// one whose shrink varies along the strip. E's distance term is the mean of the three stacks'
// distances, each measured by a problem that prints that stack alone, and the gradient of that
// mean matches central differences.
TEST(AdjointDesign, AveragesTheDistanceOverPerturbedStacksWithItsGradient) {
  const TestPlate plate = rectangle_plate(40, 16, 8, 3);
  const int nv = static_cast<int>(plate.V.rows());
  const int nf = static_cast<int>(plate.F.rows());
  AdjointDesignProblem problem =
      bilayer_problem(plate, equilibrium(plate, ramp(plate, 0.002, 0.008)));
  Eigen::VectorXd wavy(nf);
  for (int f = 0; f < nf; ++f) wavy(f) = 0.0015 * std::sin(0.8 * f);
  const std::vector<std::function<void(LayerStack&)>> errors = {
      [](LayerStack& stack) { stack.layers[1].lambda1.array() -= 0.002; },
      [wavy](LayerStack& stack) { stack.layers[1].lambda1 += wavy; }};
  problem.perturbations = errors;
  const Eigen::VectorXd p = ramp(plate, 0.006, 0.003);
  AdjointDesignOptions options;
  options.laplacian_weight = 1e5;
  options.forward.relative_tolerance = 1e-20;
  const AdjointEvaluation at = evaluate_adjoint_design(problem, p, problem.target, options);
  ASSERT_TRUE(at.forward_converged);

  double mean = 0;
  for (int j = 0; j < 3; ++j) {
    AdjointDesignProblem alone = problem;
    alone.perturbations.clear();
    if (j > 0) {
      alone.layer_stack = [base = problem.layer_stack,
                           error = errors[j - 1]](const Eigen::VectorXd& q) {
        LayerStack stack = base(q);
        error(stack);
        return stack;
      };
    }
    mean += evaluate_adjoint_design(alone, p, problem.target, options, false).distance_term / 3;
  }
  EXPECT_NEAR(at.distance_term, mean, 1e-9 * mean);
  EXPECT_GT(at.distance_term, 1);

  Eigen::VectorXd mixed(nv);
  for (int v = 0; v < nv; ++v) mixed(v) = std::cos(0.9 * v) + 0.5;
  const double h = 1e-6;
  const double plus =
      evaluate_adjoint_design(problem, p + h * mixed, at.V, options, false).objective;
  const double minus =
      evaluate_adjoint_design(problem, p - h * mixed, at.V, options, false).objective;
  const double fd = (plus - minus) / (2 * h);
  EXPECT_NEAR(at.gradient.dot(mixed), fd, 1e-4 * std::abs(fd));
  EXPECT_GT(std::abs(fd), 1e-3 * at.gradient.norm());
}

// Steps of at most 0.004 in p, down to 1e-6, until the predicted decrease is below 1e-4: a few
// iterations from a uniform p.
AdjointDesignOptions short_steps() {
  AdjointDesignOptions options;
  options.laplacian_weight = 1e-2;
  options.max_step = 0.004;
  options.min_step = 1e-6;
  options.decrement_tolerance = 1e-4;
  options.relative_decrease = 0;
  return options;
}

// A perturbation that changes nothing leaves the optimization as it is, bit for bit: the mean of
// equal terms is the term.
TEST(AdjointDesign, AnErrorThatChangesNothingLeavesTheDesignAsItIs) {
  const TestPlate plate = rectangle_plate(40, 16, 8, 3);
  const int nv = static_cast<int>(plate.V.rows());
  AdjointDesignProblem problem =
      bilayer_problem(plate, equilibrium(plate, ramp(plate, 0.002, 0.008)));
  const AdjointDesignOptions options = short_steps();
  const Eigen::VectorXd start = Eigen::VectorXd::Constant(nv, 0.005);
  const AdjointDesignResult nominal = optimize_adjoint_design(problem, start, options);
  problem.perturbations = {[](LayerStack&) {}};
  const AdjointDesignResult twice = optimize_adjoint_design(problem, start, options);
  EXPECT_GT(nominal.iterations, 1);
  EXPECT_EQ(twice.iterations, nominal.iterations);
  EXPECT_EQ(twice.objective, nominal.objective);
  EXPECT_EQ(twice.variables, nominal.variables);
}

// The scenarios run side by side on the cores there are (each with its own solver): on one
// thread or on several the optimization takes the same steps, bit for bit.
TEST(AdjointDesign, ScenariosSideBySideGiveTheSameBitsAsOneAfterAnother) {
  const TestPlate plate = rectangle_plate(40, 16, 8, 3);
  const int nv = static_cast<int>(plate.V.rows());
  AdjointDesignProblem problem =
      bilayer_problem(plate, equilibrium(plate, ramp(plate, 0.002, 0.008)));
  problem.perturbations = {[](LayerStack& stack) { stack.layers[1].lambda1.array() -= 0.001; },
                           [](LayerStack& stack) { stack.layers[1].lambda1.array() += 0.001; }};
  const AdjointDesignOptions options = short_steps();
  const Eigen::VectorXd start = Eigen::VectorXd::Constant(nv, 0.005);
  const AdjointDesignResult side_by_side = optimize_adjoint_design(problem, start, options);
  AdjointDesignResult one_thread;
  {
    const tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
    one_thread = optimize_adjoint_design(problem, start, options);
  }
  EXPECT_GT(side_by_side.iterations, 1);
  EXPECT_EQ(one_thread.iterations, side_by_side.iterations);
  EXPECT_EQ(one_thread.objective, side_by_side.objective);
  EXPECT_EQ(one_thread.variables, side_by_side.variables);
  EXPECT_EQ(one_thread.V, side_by_side.V);
}

// The target is the equilibrium of a known p: from a uniform p the optimizer brings E down to a
// small fraction of where it starts, every accepted step lowering it, and reports every record.
TEST(AdjointDesign, FindsAReachableTarget) {
  const TestPlate plate = rectangle_plate(40, 16, 8, 3);
  const int nv = static_cast<int>(plate.V.rows());
  const Eigen::VectorXd wanted = ramp(plate, 0.002, 0.008);
  const AdjointDesignProblem problem = bilayer_problem(plate, equilibrium(plate, wanted));
  AdjointDesignOptions options = short_steps();
  int calls = 0;
  options.progress = [&calls](const AdjointIteration&) { ++calls; };
  const Eigen::VectorXd start = Eigen::VectorXd::Constant(nv, 0.005);
  const AdjointDesignResult r = optimize_adjoint_design(problem, start, options);
  EXPECT_TRUE(r.initial_forward_converged);
  EXPECT_TRUE(r.converged) << to_string(r.stop);
  EXPECT_EQ(calls, static_cast<int>(r.history.size()));
  EXPECT_EQ(r.history.back().stop, r.stop);
  EXPECT_LT(r.objective, 1e-3 * r.initial_objective)
      << r.initial_objective << " -> " << r.objective;
  for (size_t i = 1; i < r.history.size(); ++i) {
    EXPECT_LT(r.history[i].objective, r.history[i - 1].objective) << i;
  }
  // The shape lands on the target; p, weakly determined near the strip's free edges, comes closer.
  EXPECT_LT(shape_distance(r.V, problem.target).max_mm,
            0.02 * shape_distance(r.initial_V, problem.target).max_mm);
  EXPECT_LT((r.variables - wanted).cwiseAbs().mean(), 0.5 * (start - wanted).cwiseAbs().mean());
  // The result is the equilibrium of what it returns: simulating it again stays put.
  const SimulationResult again = simulate(strip_problem(plate, r.variables), r.V);
  EXPECT_LT((again.V - r.V).rowwise().norm().maxCoeff(), 1e-6);
}

// With an upper bound below what the target asks for, p ends on the bound where the target needs
// more, never past it, and the optimizer still lowers E.
TEST(AdjointDesign, KeepsTheVariablesWithinTheirBounds) {
  const TestPlate plate = rectangle_plate(40, 16, 8, 3);
  const int nv = static_cast<int>(plate.V.rows());
  AdjointDesignProblem problem =
      bilayer_problem(plate, equilibrium(plate, ramp(plate, 0.002, 0.008)));
  problem.bounds = {0.0, 0.005, 1e-12, 0.005 - 1e-12};
  AdjointDesignOptions options;
  options.max_step = 0.004;
  options.min_step = 1e-6;
  const AdjointDesignResult r =
      optimize_adjoint_design(problem, Eigen::VectorXd::Constant(nv, 0.009), options);
  EXPECT_LE(r.variables.maxCoeff(), 0.005);
  EXPECT_GE(r.variables.minCoeff(), 0.0);
  EXPECT_GT(r.vertices_at_bound, 0);
  EXPECT_LT(r.vertices_at_bound, nv);
  EXPECT_LT(r.objective, 0.5 * r.initial_objective);
}

}  // namespace
}  // namespace flatmorph::adjoint_design_test
