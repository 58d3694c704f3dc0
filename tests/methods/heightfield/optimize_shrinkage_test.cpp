#include "methods/heightfield/optimize_shrinkage.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

#include "material/material.h"
#include "methods/heightfield/cap_printing_graph.h"
#include "methods/heightfield/rise_prediction.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"

namespace flatmorph::optimize_shrinkage_test {
namespace {

using testing::cap_material;
using testing::cap_printing_graph;
using testing::CapPrintingGraph;
using testing::kCapAngle;
using testing::kCapRadius;

ShrinkageProblem cap_problem(const CapPrintingGraph& cap, const Material& material) {
  ShrinkageProblem problem;
  problem.plate = cap.plate;
  problem.F = cap.mesh.F;
  problem.target = cap.mesh.V;
  problem.direction = deposition_directions(cap.mesh, cap.plate);
  problem.material = material;
  return problem;
}

// A stack exercising every term of the laminate: three layers of two materials, thicknesses,
// directions, λ1 and its gradient varying per face, the middle layer missing on one face.
LayerStack varied_stack(int num_faces) {
  Material a = load_material("pla-geodesy");
  Material b = a;
  b.young_modulus_along = 3.0;
  b.young_modulus_across = 2.0;
  b.poisson_ratio = 0.3;
  LayerStack stack;
  stack.materials = {a, b};
  for (int k = 0; k < 3; ++k) {
    Layer layer = uniform_layer(num_faces, k == 1 ? 1 : 0, k == 1 ? b : a, 0.1);
    for (int f = 0; f < num_faces; ++f) {
      layer.printed_thickness(f) = 0.08 + 0.03 * std::sin(1.3 * f + k);
      layer.theta(f) = 0.4 * f + 0.9 * k;
      layer.lambda1(f) = 0.7 + 0.1 * std::cos(0.7 * f + 2.0 * k);
      layer.delta_lambda1(f) = 0.02 * std::sin(f + 3.0 * k);
      layer.lambda2(f) = 0.9 + 0.05 * k;
      layer.lambda3(f) = 1.3 + 0.1 * k;
    }
    stack.layers.push_back(layer);
  }
  stack.layers[1].material(2) = Layer::kNotCovered;
  return stack;
}

TEST(LaminateShrinkDerivative, MatchesCentralDifferences) {
  const int nf = 5;
  const LayerStack stack = varied_stack(nf);
  LayerShrinkRates rates;
  for (int k = 0; k < stack.num_layers(); ++k) {
    Eigen::VectorXd l1(nf), h(nf);
    for (int f = 0; f < nf; ++f) {
      l1(f) = -1.0 + 0.3 * std::sin(2.0 * f + k);
      h(f) = -0.2 + 0.15 * std::cos(f + 2.0 * k);
    }
    rates.lambda1.push_back(l1);
    rates.printed_thickness.push_back(h);
  }
  LaminateDerivative derivative;
  const RestForms value = laminate(stack, rates, derivative);
  const RestForms reference = laminate(stack);
  const double step = 1e-5;
  auto moved = [&](double s) {
    LayerStack m = stack;
    for (int k = 0; k < m.num_layers(); ++k) {
      m.layers[k].lambda1 += s * rates.lambda1[k];
      m.layers[k].printed_thickness += s * rates.printed_thickness[k];
    }
    return laminate(m);
  };
  const RestForms plus = moved(step), minus = moved(-step);
  for (int f = 0; f < nf; ++f) {
    EXPECT_TRUE(value.stiffness[f].isApprox(reference.stiffness[f]));
    const Matrix6d dk = (plus.stiffness[f] - minus.stiffness[f]) / (2 * step);
    const Vector6d ds =
        (rest_vector(plus.rest_first_fundamental_form[f], plus.rest_second_fundamental_form[f]) -
         rest_vector(minus.rest_first_fundamental_form[f], minus.rest_second_fundamental_form[f])) /
        (2 * step);
    EXPECT_LT((derivative.stiffness[f] - dk).norm(), 1e-7 * dk.norm()) << "face " << f;
    EXPECT_LT((derivative.rest[f] - ds).norm(), 1e-7 * ds.norm()) << "face " << f;
    // Not trivially zero: both K and s̄ move.
    EXPECT_GT(dk.norm(), 1e-3 * value.stiffness[f].norm());
    EXPECT_GT(ds.norm(), 1e-3);
  }
}

TEST(LaminateShrinkDerivative, RefusesRatesOfTheWrongSize) {
  const LayerStack stack = varied_stack(4);
  LayerShrinkRates rates;
  rates.lambda1.assign(2, Eigen::VectorXd::Zero(4));
  rates.printed_thickness.assign(2, Eigen::VectorXd::Zero(4));
  LaminateDerivative derivative;
  EXPECT_THROW(laminate(stack, rates, derivative), std::invalid_argument);
}

// The adjoint gradient against central differences of E along a few directions (the equilibria
// solved from the same start to a tight tolerance, so that E is smooth in σ).
TEST(OptimizeShrinkage, AdjointGradientMatchesFiniteDifferences) {
  const CapPrintingGraph cap = cap_printing_graph(kCapRadius, kCapAngle, 4, 14.0, 0.85);
  const ShrinkageProblem problem = cap_problem(cap, cap_material());
  const int nv = static_cast<int>(cap.plate.rows());
  Eigen::VectorXd sigma(nv);
  for (int v = 0; v < nv; ++v) {
    sigma(v) = 0.17 + 0.03 * std::sin(1.7 * v) + 0.01 * cap.ring_angle(v);
  }
  OptimizeShrinkageOptions options;
  options.w_L = 0.01;
  options.forward.relative_tolerance = 1e-15;
  const ShrinkageEvaluation base =
      evaluate_shrinkage_objective(problem, sigma, problem.target, options);
  ASSERT_TRUE(base.forward_converged);
  ASSERT_EQ(base.gradient.size(), nv);
  std::vector<Eigen::VectorXd> directions;
  for (int v : {0, nv / 3, nv - 1}) directions.push_back(Eigen::VectorXd::Unit(nv, v));
  Eigen::VectorXd mixed(nv);
  for (int v = 0; v < nv; ++v) mixed(v) = std::cos(0.9 * v) + 0.5;
  directions.push_back(mixed.normalized());
  const double step = 1e-5;
  for (const Eigen::VectorXd& d : directions) {
    const double plus =
        evaluate_shrinkage_objective(problem, sigma + step * d, base.V, options, false).objective;
    const double minus =
        evaluate_shrinkage_objective(problem, sigma - step * d, base.V, options, false).objective;
    const double difference = (plus - minus) / (2 * step);
    const double adjoint = base.gradient.dot(d);
    EXPECT_NEAR(adjoint, difference, 1e-4 * std::abs(difference))
        << adjoint << " vs " << difference;
    EXPECT_GT(std::abs(difference), 1e-3 * base.gradient.norm());
  }
}

// E measures the distance after the best rigid motion: moving the target rigidly changes it only
// through the unit ℓ = 0.3 % of the (axis-aligned) bounding-box diagonal, which turns with it.
TEST(OptimizeShrinkage, ObjectiveDoesNotDependOnWhereTheTargetIs) {
  const CapPrintingGraph cap = cap_printing_graph(kCapRadius, kCapAngle, 4, 14.0, 0.85);
  ShrinkageProblem problem = cap_problem(cap, cap_material());
  const Eigen::VectorXd sigma =
      initial_vertex_shrinkage(cap.mesh, cap.plate, cap.edge_shrinkage, problem.material);
  OptimizeShrinkageOptions options;
  options.w_L = 0;
  auto diagonal2 = [](const Eigen::MatrixXd& V) {
    return (V.colwise().maxCoeff() - V.colwise().minCoeff()).squaredNorm();
  };
  const ShrinkageEvaluation here = evaluate_shrinkage_objective(problem, sigma, {}, options);
  const double here_scale = diagonal2(problem.target);
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  problem.target = (cap.mesh.V * turn.transpose()).rowwise() + Eigen::RowVector3d(5, -7, 11);
  const ShrinkageEvaluation there = evaluate_shrinkage_objective(problem, sigma, {}, options);
  const double there_scale = diagonal2(problem.target);
  ASSERT_TRUE(here.forward_converged && there.forward_converged);
  EXPECT_GT(std::abs(here_scale / there_scale - 1), 1e-3);  // the unit did change
  EXPECT_NEAR(here.objective * here_scale, there.objective * there_scale,
              1e-8 * here.objective * here_scale);
  EXPECT_LT((here.gradient * here_scale - there.gradient * there_scale).norm(),
            1e-6 * here.gradient.norm() * here_scale);
}

// From a uniform σ (a flat-ish dome far from the cap) the optimization finds a σ whose risen shape
// is at least as close to the cap as the exact flattening's, which the sheet's bending stiffness
// keeps some way off (rise_prediction_test.cpp), and stays within the curve's range.
TEST(OptimizeShrinkage, BringsAUniformShrinkToTheCap) {
  const CapPrintingGraph cap = cap_printing_graph(kCapRadius, kCapAngle, 6, 10.0, 0.85);
  const Material material = cap_material();
  const ShrinkageProblem problem = cap_problem(cap, material);
  const auto [least, most] = reachable_shrinkage(*material.thickness_curve);
  const int nv = static_cast<int>(cap.plate.rows());
  const Eigen::VectorXd uniform = Eigen::VectorXd::Constant(nv, 0.1);
  OptimizeShrinkageOptions options;
  options.max_iterations = 100;
  options.max_forward_iterations = 1000;
  int calls = 0;
  options.progress = [&calls](const ShrinkageIteration&) { ++calls; };
  const ShrinkageResult result = optimize_shrinkage(problem, uniform, options);
  EXPECT_TRUE(result.initial_forward_converged);
  EXPECT_GT(calls, 0);
  EXPECT_EQ(calls, static_cast<int>(result.history.size()));
  EXPECT_GE(result.vertex_shrinkage.minCoeff(), least);
  EXPECT_LE(result.vertex_shrinkage.maxCoeff(), most);
  EXPECT_LT(result.objective, 0.1 * result.initial_objective) << result.stop_reason;

  const ShapeDistance before = shape_distance(result.initial_V, cap.mesh.V);
  const ShapeDistance after = shape_distance(result.V, cap.mesh.V);
  const HeightFieldPlate exact =
      heightfield_plate(cap.mesh, cap.plate, cap.edge_shrinkage, material);
  RisePredictionOptions rise_options;
  rise_options.from_target = false;
  const RisePrediction paper = predict_rise(exact.design, cap.mesh.V, rise_options);
  EXPECT_LT(after.mean_percent, paper.distance.mean_percent) << after.max_percent << " % max";
  EXPECT_LT(after.mean_percent, 0.2 * before.mean_percent);
  // The optimum shrinks the rings more than the exact flattening, to pull the stiff sheet up.
  const Eigen::VectorXd exact_sigma =
      initial_vertex_shrinkage(cap.mesh, cap.plate, cap.edge_shrinkage, material);
  EXPECT_GT(result.vertex_shrinkage.mean(), exact_sigma.mean());
}

// The work budget bounds the line searches' Newton iterations, whatever the iteration limit.
TEST(OptimizeShrinkage, StopsAtTheBudgetOfForwardIterations) {
  const CapPrintingGraph cap = cap_printing_graph(kCapRadius, kCapAngle, 6, 10.0, 0.85);
  const Material material = cap_material();
  const ShrinkageProblem problem = cap_problem(cap, material);
  const Eigen::VectorXd uniform = Eigen::VectorXd::Constant(cap.plate.rows(), 0.1);
  OptimizeShrinkageOptions options;
  options.max_iterations = 100;
  options.max_forward_iterations = 8;
  const ShrinkageResult result = optimize_shrinkage(problem, uniform, options);
  int spent = 0;
  for (const ShrinkageIteration& it : result.history) spent += it.forward_iterations;
  EXPECT_GE(spent, options.max_forward_iterations);
  // The last trial may overrun it by at most its own iterations.
  EXPECT_LT(spent, options.max_forward_iterations + options.max_trial_forward_iterations);
  EXPECT_NE(result.stop_reason.find("budget"), std::string::npos) << result.stop_reason;
  EXPECT_FALSE(result.converged);
  EXPECT_LT(result.objective, result.initial_objective);
}

TEST(OptimizeShrinkage, StartsFromTheExactFlatteningAndImprovesOnIt) {
  const CapPrintingGraph cap = cap_printing_graph(kCapRadius, kCapAngle, 6, 10.0, 0.85);
  const Material material = cap_material();
  ShrinkageProblem problem = cap_problem(cap, material);
  const HeightFieldPlate exact =
      heightfield_plate(cap.mesh, cap.plate, cap.edge_shrinkage, material);
  RisePredictionOptions rise_options;
  rise_options.from_target = false;
  const RisePrediction paper = predict_rise(exact.design, cap.mesh.V, rise_options);
  problem.start = paper.from_flat.V;
  const ShrinkageResult result = optimize_shrinkage(
      problem, initial_vertex_shrinkage(cap.mesh, cap.plate, cap.edge_shrinkage, material));
  const ShapeDistance before = shape_distance(result.initial_V, cap.mesh.V);
  const ShapeDistance after = shape_distance(result.V, cap.mesh.V);
  // The first equilibrium is the one predicted from the flat sheet (the same σ up to the order of
  // clamping and averaging, which do not differ inside the range).
  EXPECT_NEAR(before.mean_percent, paper.distance.mean_percent, 1e-3);
  EXPECT_LT(result.objective, result.initial_objective);
  EXPECT_LT(after.max_percent, before.max_percent);
}

}  // namespace
}  // namespace flatmorph::optimize_shrinkage_test
