#include "plate/laminate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "common/error.h"
#include "plate/layer_stack.h"
#include "plate/plate_fixtures.h"

namespace flatmorph::laminate_test {
namespace {

Material paper_material() { return Material{}; }  // the defaults are the paper's PLA

double max_abs(const Eigen::Matrix2d& m) { return m.cwiseAbs().maxCoeff(); }

// The Shrink & Morph continuous model's closed forms (Eq. 7, 15-17), first order in θ2 and Δλ1,
// over the post-heating thickness t = λ3 h:
//   ā = R(θ1) diag(λ1², λ2²) R(θ1)ᵀ
//   b̄ = θ2 (λ2² − λ1²)/(2t) R(θ1) [[0,1],[1,0]] R(θ1)ᵀ − (Δλ1 λ1 / t) R(θ1) [[1,0],[0,0]] R(θ1)ᵀ
struct ClosedForms {
  std::vector<Eigen::Matrix2d> rest_first_fundamental_form, rest_second_fundamental_form;
  Eigen::VectorXd thickness;
};
ClosedForms shrink_morph_rest_forms(const Eigen::VectorXd& theta1, const Eigen::VectorXd& theta2,
                                    const Material& m, double printed_thickness) {
  ClosedForms out;
  const double l1 = m.lambda1, l2 = m.lambda2, t = m.lambda3 * printed_thickness;
  out.thickness = Eigen::VectorXd::Constant(theta1.size(), t);
  Eigen::Matrix2d swap, along;
  swap << 0, 1, 1, 0;
  along << 1, 0, 0, 0;
  for (Eigen::Index f = 0; f < theta1.size(); ++f) {
    const Eigen::Matrix2d r = rotation(theta1(f));
    out.rest_first_fundamental_form.push_back(r * Eigen::Vector2d(l1 * l1, l2 * l2).asDiagonal() *
                                              r.transpose());
    out.rest_second_fundamental_form.push_back(
        r * (theta2(f) * (l2 * l2 - l1 * l1) / (2 * t) * swap - m.delta_lambda1 * l1 / t * along) *
        r.transpose());
  }
  return out;
}

// A stack whose layer k is printed at the continuous model's angle at the layer's mid-height,
// θ1 + s_k θ2 with s_k = (k - 1/2)/n - 1/2 (instead of the paper's printing rule).
LayerStack midpoint_stack(double theta1, double theta2, const Material& m, int n) {
  LayerStack s = shrink_morph_layer_stack(Eigen::VectorXd::Constant(1, theta1),
                                          Eigen::VectorXd::Zero(1), m, n, m.layer_height);
  for (int k = 1; k <= n; ++k) {
    s.layers[k - 1].theta(0) = theta1 + ((k - 0.5) / n - 0.5) * theta2;
  }
  return s;
}

TEST(Laminate, NoThetaVariationGivesTheClosedFormsExactly) {
  Material m = paper_material();
  const Eigen::VectorXd theta1 = (Eigen::VectorXd(3) << 0.0, 0.7, -2.1).finished();
  const Eigen::VectorXd theta2 = Eigen::VectorXd::Zero(3);
  for (int n : {1, 2, 10, 37}) {
    const RestForms lam = laminate(shrink_morph_layer_stack(theta1, theta2, m, n, 0.08));
    const ClosedForms closed = shrink_morph_rest_forms(theta1, theta2, m, n * 0.08);
    for (int f = 0; f < 3; ++f) {
      // ā gains the O(Δλ1²) term the first-order expansion drops: ⟨(z/h)²⟩ Δλ1² = Δλ1²/12
      // along the path.
      const Eigen::Matrix2d r = rotation(theta1(f));
      const Eigen::Matrix2d second_order =
          r * Eigen::Vector2d(m.delta_lambda1 * m.delta_lambda1 / 12, 0).asDiagonal() *
          r.transpose();
      // The fit is weighted by each layer's stiffness relative to its own rest metric (∝ 1/λ1⁴
      // along the path), which varies with z by O(Δλ1): it moves ā and b̄ at O(Δλ1²) relative.
      const double d2 = m.delta_lambda1 * m.delta_lambda1;
      EXPECT_LT(max_abs(lam.rest_first_fundamental_form[f] - closed.rest_first_fundamental_form[f] -
                        second_order),
                d2 * d2);
      // b̄ (Eq. 17) to first order in Δλ1.
      EXPECT_LT(
          max_abs(lam.rest_second_fundamental_form[f] - closed.rest_second_fundamental_form[f]),
          4 * d2 * closed.rest_second_fundamental_form[f].norm());
      EXPECT_NEAR(lam.thickness(f), m.lambda3 * n * 0.08, 1e-14);
      EXPECT_NEAR(closed.thickness(f), m.lambda3 * n * 0.08, 1e-14);
    }
  }
  // Without the bilayer term, ā is the closed form exactly.
  m.delta_lambda1 = 0;
  const RestForms lam = laminate(shrink_morph_layer_stack(theta1, theta2, m, 10, 0.08));
  const ClosedForms closed = shrink_morph_rest_forms(theta1, theta2, m, 0.8);
  for (int f = 0; f < 3; ++f) {
    EXPECT_LT(max_abs(lam.rest_first_fundamental_form[f] - closed.rest_first_fundamental_form[f]),
              1e-14);
  }
}

TEST(Laminate, BilayerCurvatureMatchesPaperNumbers) {
  // Eq. 17 with the paper's PLA: b̄ = −Δλ1 λ1 / t along the path, t = λ3 h = 1.216 mm for
  // 10 × 0.08 mm, i.e. 0.0226765 × 0.58 / 1.216 = 0.010816 /mm.
  const Material m = paper_material();
  const ClosedForms closed =
      shrink_morph_rest_forms(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), m, 0.8);
  EXPECT_NEAR(closed.rest_second_fundamental_form[0](0, 0), 0.0226764665509417 * 0.58 / 1.216,
              1e-12);
  EXPECT_GT(closed.rest_second_fundamental_form[0](0, 0), 0.0);  // the top shrinks more
  EXPECT_EQ(closed.rest_second_fundamental_form[0](1, 1), 0.0);
}

// The θ2 part of b̄ (Eq. 7) from a stack sampled at layer mid-heights converges to the closed form
// as 1 − 1/n² (the least-squares slope of a staircase) at small θ2, and to second order in θ2 with
// many layers (the layers' stiffness turns with them and weights the fit: the unweighted fit's
// θ2²/10 becomes about 0.75 θ2² for the paper's PLA).
TEST(Laminate, TwistConvergesToTheClosedFormAsPredicted) {
  Material m = paper_material();
  m.delta_lambda1 = 0;  // isolate the θ2 term
  const double theta1 = 0.4;
  auto relative_error = [&](double theta2, int n) {
    const RestForms lam = laminate(midpoint_stack(theta1, theta2, m, n));
    const ClosedForms closed =
        shrink_morph_rest_forms(Eigen::VectorXd::Constant(1, theta1),
                                Eigen::VectorXd::Constant(1, theta2), m, n * m.layer_height);
    const Eigen::Matrix2d& b = lam.rest_second_fundamental_form[0];
    const Eigen::Matrix2d& c = closed.rest_second_fundamental_form[0];
    return (b - c).norm() / c.norm();
  };
  // O(1/n²) at small θ2 (the weighting adds O(θ2) = 1e-6 here).
  for (int n : {4, 8, 16, 32}) {
    EXPECT_NEAR(relative_error(1e-3, n), 1.0 / (n * n), 1e-6) << "n=" << n;
  }
  // O(θ2²) with many layers: error / θ2² settles as θ2 -> 0.
  const double c1 = relative_error(0.0125, 1000) / (0.0125 * 0.0125);
  const double c2 = relative_error(0.025, 1000) / (0.025 * 0.025);
  const double c3 = relative_error(0.05, 1000) / (0.05 * 0.05);
  EXPECT_NEAR(c2, c1, 0.02 * c1);
  EXPECT_NEAR(c3, c1, 0.05 * c1);
  EXPECT_GT(c1, 0.1);
  EXPECT_LT(c1, 2.0);
}

// The paper's printing rule θ^k = θ1 + ((k−1)/(n−1) − 1/2) θ2 puts the outer layers at ±θ2/2 while
// their mid-heights are at ±(1/2 − 1/(2n)) h: the printed stack twists (n+1)/n times more than the
// continuous model (10 % for 10 layers).
TEST(Laminate, PaperPrintingRuleTwistsByNPlusOneOverN) {
  Material m = paper_material();
  m.delta_lambda1 = 0;
  const double theta2 = 1e-4;
  for (int n : {2, 5, 10}) {
    const LayerStack s = shrink_morph_layer_stack(Eigen::VectorXd::Constant(1, -1.1),
                                                  Eigen::VectorXd::Constant(1, theta2), m, n, 0.08);
    EXPECT_NEAR(s.layers.front().theta(0), -1.1 - theta2 / 2, 1e-15);
    EXPECT_NEAR(s.layers.back().theta(0), -1.1 + theta2 / 2, 1e-15);
    const RestForms lam = laminate(s);
    const ClosedForms closed = shrink_morph_rest_forms(
        Eigen::VectorXd::Constant(1, -1.1), Eigen::VectorXd::Constant(1, theta2), m, n * 0.08);
    const double ratio =
        lam.rest_second_fundamental_form[0].norm() / closed.rest_second_fundamental_form[0].norm();
    EXPECT_NEAR(ratio, (n + 1.0) / n, 1e-6) << "n=" << n;
  }
}

TEST(Laminate, HomogeneousSingleLayerHasNoRestCurvature) {
  Material m = paper_material();
  m.delta_lambda1 = 0;
  const LayerStack s = shrink_morph_layer_stack(Eigen::VectorXd::Constant(2, 0.3),
                                                Eigen::VectorXd::Constant(2, 0.5), m, 1, 0.2);
  const RestForms lam = laminate(s);
  for (int f = 0; f < 2; ++f) {
    EXPECT_LT(max_abs(lam.rest_second_fundamental_form[f]), 1e-15);
    EXPECT_NEAR(lam.thickness(f), m.lambda3 * 0.2, 1e-15);
  }
}

TEST(Laminate, FlippedStackFlipsTheRestCurvature) {
  const Material m = paper_material();
  const LayerStack s = shrink_morph_layer_stack(Eigen::VectorXd::Constant(1, 0.9),
                                                Eigen::VectorXd::Constant(1, 0.6), m, 7, 0.08);
  LayerStack flipped = s;
  std::reverse(flipped.layers.begin(), flipped.layers.end());
  for (Layer& l : flipped.layers) l.delta_lambda1 = -l.delta_lambda1;  // top and bottom swap
  const RestForms a = laminate(s), b = laminate(flipped);
  EXPECT_GT(a.rest_second_fundamental_form[0].norm(), 1e-3);
  EXPECT_LT(max_abs(a.rest_second_fundamental_form[0] + b.rest_second_fundamental_form[0]), 1e-14);
  EXPECT_LT(max_abs(a.rest_first_fundamental_form[0] - b.rest_first_fundamental_form[0]), 1e-14);
}

TEST(Laminate, UncoveredLayersAreLeftOutOfTheFace) {
  Material m = paper_material();
  m.delta_lambda1 = 0;
  LayerStack s =
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), m, 2, 0.1);
  s.layers[1].theta(0) = M_PI / 2;  // a 0/90 bilayer on face 0
  s.layers[1].theta(1) = M_PI / 2;
  s.layers[1].material(1) = Layer::kNotCovered;  // face 1 has only the bottom layer
  const RestForms lam = laminate(s);
  EXPECT_NEAR(lam.thickness(0), 2 * 0.1 * m.lambda3, 1e-15);
  EXPECT_NEAR(lam.thickness(1), 0.1 * m.lambda3, 1e-15);
  EXPECT_LT(max_abs(lam.rest_second_fundamental_form[1]), 1e-15);
  EXPECT_NEAR(lam.rest_first_fundamental_form[1](0, 0), m.lambda1 * m.lambda1, 1e-15);
  // The 0/90 bilayer: the top (90°) shrinks along y, the bottom along x, so the plate is concave
  // on top along y and convex along x, by the same amount (a quarter turn and a flip swap them).
  EXPECT_LT(lam.rest_second_fundamental_form[0](0, 0), 0.0);
  EXPECT_NEAR(lam.rest_second_fundamental_form[0](1, 1), -lam.rest_second_fundamental_form[0](0, 0),
              1e-12);
  // A face with no layer at all is a user error.
  s.layers[0].material(1) = Layer::kNotCovered;
  EXPECT_THROW(laminate(s), UserError);
}

// A face of two materials, random directions, thicknesses and λ's, one layer left out, one
// covering only part of the face (a lattice's lines).
LayerStack random_two_material_stack(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Material pla = paper_material(), tpu = paper_material();
  tpu.lambda1 = tpu.lambda2 = tpu.lambda3 = 1.0;
  tpu.delta_lambda1 = 0;
  tpu.young_modulus_along = tpu.young_modulus_across = 0.7;
  tpu.poisson_ratio = 0.45;
  LayerStack s;
  s.materials = {pla, tpu};
  for (int k = 0; k < 5; ++k) {
    Layer l = uniform_layer(1, k % 2, s.materials[k % 2], 0.1 + 0.05 * uni(rng));
    l.theta(0) = 3 * uni(rng);
    l.lambda1(0) *= 1 + 0.05 * uni(rng);
    l.delta_lambda1(0) = 0.02 * uni(rng);
    l.lambda2(0) *= 1 + 0.05 * uni(rng);
    l.lambda3(0) *= 1 + 0.05 * uni(rng);
    if (k == 2) l.material(0) = Layer::kNotCovered;
    if (k == 3) l.cover(0) = 0.3 + 0.2 * uni(rng);
    s.layers.push_back(l);
  }
  return s;
}

// The energy per unit area ¼ Σ_k ∫ ‖a − 2zb − C̄_k(z)‖²_{P_k} dz by brute-force quadrature, written
// from the definition (each layer's own rest metric and material norm), s = (a00, a11, a01, b00,
// b11, b01).
double integrated_energy(const LayerStack& stack, const Vector6d& s) {
  double t = 0;
  for (const Layer& l : stack.layers) {
    if (l.covers(0)) t += l.lambda3(0) * l.printed_thickness(0);
  }
  const Eigen::Vector3d a(s(0), s(1), s(2)), b(s(3), s(4), s(5));
  double energy = 0, bottom = -t / 2;
  for (const Layer& l : stack.layers) {
    if (!l.covers(0)) continue;
    const double tau = l.lambda3(0) * l.printed_thickness(0);
    const Eigen::Matrix2d r = rotation(l.theta(0));
    const Eigen::Matrix2d mid_metric =
        r * Eigen::Vector2d(l.lambda1(0) * l.lambda1(0), l.lambda2(0) * l.lambda2(0)).asDiagonal() *
        r.transpose();
    // Only the share of the area under the layer's beads stores energy.
    const Eigen::Matrix3d p =
        l.cover(0) *
        material_norm(mid_metric, l.theta(0), stiffness_of(stack.materials[l.material(0)]));
    const int samples = 4000;
    for (int i = 0; i < samples; ++i) {
      const double u = (i + 0.5) / samples;  // midpoint rule within the layer
      const double z = bottom + u * tau;
      const double lambda1 = l.lambda1(0) + l.delta_lambda1(0) * (u - 0.5);
      const Eigen::Matrix2d c =
          r * Eigen::Vector2d(lambda1 * lambda1, l.lambda2(0) * l.lambda2(0)).asDiagonal() *
          r.transpose();
      const Eigen::Vector3d e = a - 2 * z * b - Eigen::Vector3d(c(0, 0), c(1, 1), c(0, 1));
      energy += 0.25 * e.dot(p * e) * tau / samples;
    }
    bottom += tau;
  }
  return energy;
}

// Classical lamination theory as built: W(s) − W(s̄) = ¼ (s − s̄)ᵀ K (s − s̄) for the stiffness K and
// rest forms s̄ the laminate returns, checked against the integral itself.
TEST(Laminate, StiffnessAndRestFormsAreThoseOfTheIntegratedEnergy) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const LayerStack stack = random_two_material_stack(seed);
    const RestForms lam = laminate(stack);
    const Vector6d rest =
        rest_vector(lam.rest_first_fundamental_form[0], lam.rest_second_fundamental_form[0]);
    const Matrix6d& k = lam.stiffness[0];
    const double coupling = k.topRightCorner<3, 3>().norm();
    EXPECT_GT(coupling, 1e-3 * k.norm());  // membrane-bending coupling
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    const double at_rest = integrated_energy(stack, rest);
    for (int trial = 0; trial < 4; ++trial) {
      Vector6d d;
      for (int i = 0; i < 6; ++i) d(i) = 0.01 * uni(rng);
      const double expected = 0.25 * d.dot(k * d);
      EXPECT_NEAR(integrated_energy(stack, rest + d) - at_rest, expected, 1e-6 * expected)
          << "seed " << seed;
    }
  }
}

// The exact derivative of K and s̄ when the layers turn, against central differences.
TEST(Laminate, AngleDerivativeMatchesFiniteDifferences) {
  const LayerStack stack = random_two_material_stack(4);
  const std::vector<double> rates = {0.3, -1.0, 0.5, 2.0, -0.7};
  LaminateDerivative derivative;
  laminate(stack, rates, derivative);
  const double h = 1e-6;
  RestForms at[2];
  for (int side = 0; side < 2; ++side) {
    LayerStack moved = stack;
    for (int k = 0; k < moved.num_layers(); ++k)
      moved.layers[k].theta(0) += (side ? -h : h) * rates[k];
    at[side] = laminate(moved);
  }
  const Matrix6d dk = (at[0].stiffness[0] - at[1].stiffness[0]) / (2 * h);
  const Vector6d ds =
      (rest_vector(at[0].rest_first_fundamental_form[0], at[0].rest_second_fundamental_form[0]) -
       rest_vector(at[1].rest_first_fundamental_form[0], at[1].rest_second_fundamental_form[0])) /
      (2 * h);
  EXPECT_LT((dk - derivative.stiffness[0]).norm(), 1e-6 * dk.norm());
  EXPECT_LT((ds - derivative.rest[0]).norm(), 1e-6 * ds.norm());
  EXPECT_GT(ds.norm(), 1e-3);
}

// One PLA layer on one TPU layer, equally thick, PLA 14 times stiffer and shrinking isotropically
// by 1 %, TPU not at all: the free curvature is Timoshenko's bilayer formula (1925),
// κ = 6 Δε (1 + m)² / (h (3 (1 + m)² + (1 + m n)(m² + 1/(m n)))) with m = 1 the thickness ratio, n
// the stiffness ratio (the biaxial moduli E/(1 − ν) have the same ratio for equal ν), h the total
// thickness; the PLA on top shrinks, so the plate bends toward its top: b̄ = κ I.
TEST(Laminate, PlaOnTpuBilayerBendsAsTimoshenko) {
  const RestForms lam = laminate(testing::pla_on_tpu_bilayer(1, 0.99));
  const double kappa = testing::timoshenko_curvature(1, 14, 1.0, 0.01);
  const Eigen::Matrix2d& b = lam.rest_second_fundamental_form[0];
  EXPECT_NEAR(b(0, 0), kappa, 0.05 * kappa);
  EXPECT_NEAR(b(1, 1), kappa, 0.05 * kappa);
  EXPECT_NEAR(b(0, 1), 0.0, 1e-12);
  std::cout << "PLA on TPU: b = " << b(0, 0) << " /mm, Timoshenko " << kappa << " /mm\n";
}

// A layer covering a share s of the face is, to the laminate, the solid layer of a material s
// times as stiff (both moduli), at the same height: lines keep their height, not a plate s h thick.
TEST(Laminate, APartlyCoveredLayerIsTheSolidLayerOfAMaterialThatMuchSofter) {
  for (unsigned seed : {5u, 6u}) {
    LayerStack covered = random_two_material_stack(seed);
    LayerStack softer = covered;
    for (int k = 0; k < covered.num_layers(); ++k) {
      Layer& l = covered.layers[k];
      if (!l.covers(0)) continue;
      l.cover(0) = 0.2 + 0.15 * k;
      Material m = covered.materials[l.material(0)];
      m.young_modulus_along *= l.cover(0);
      m.young_modulus_across *= l.cover(0);
      softer.materials.push_back(m);
      softer.layers[k].material(0) = static_cast<int>(softer.materials.size()) - 1;
      softer.layers[k].cover(0) = 1;
    }
    const RestForms a = laminate(covered), b = laminate(softer);
    EXPECT_LT((a.stiffness[0] - b.stiffness[0]).norm(), 1e-12 * b.stiffness[0].norm());
    EXPECT_LT(max_abs(a.rest_first_fundamental_form[0] - b.rest_first_fundamental_form[0]), 1e-12);
    EXPECT_LT(max_abs(a.rest_second_fundamental_form[0] - b.rest_second_fundamental_form[0]),
              1e-10);
    EXPECT_NEAR(a.thickness(0), b.thickness(0), 1e-15);
    EXPECT_NEAR(a.energy_scale(0), b.energy_scale(0), 1e-12 * b.energy_scale(0));
  }
  // One layer alone: its share scales the stiffness, the rest forms stay.
  LayerStack one;
  one.materials = {paper_material()};
  one.layers = {uniform_layer(1, 0, one.materials[0], 0.2)};
  const RestForms solid = laminate(one);
  one.layers[0].cover(0) = 0.25;
  const RestForms lines = laminate(one);
  EXPECT_LT((lines.stiffness[0] - 0.25 * solid.stiffness[0]).norm(),
            1e-12 * solid.stiffness[0].norm());
  EXPECT_LT(max_abs(lines.rest_first_fundamental_form[0] - solid.rest_first_fundamental_form[0]),
            1e-14);
  EXPECT_DOUBLE_EQ(lines.thickness(0), solid.thickness(0));
}

TEST(Laminate, BadInputsAreUserErrors) {
  const Material m = paper_material();
  // Arrays of different sizes are the caller's bug, not the user's: exit status 1.
  EXPECT_THROW(
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(3), m, 10, 0.08),
      std::invalid_argument);
  EXPECT_THROW(
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), m, 0, 0.08),
      UserError);
  EXPECT_THROW(
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), m, 3, 0.0),
      UserError);
  LayerStack s =
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), m, 3, 0.08);
  for (const double cover : {0.0, 1.5, std::nan("")}) {
    LayerStack bad = s;
    bad.layers[1].cover(0) = cover;
    EXPECT_THROW(laminate(bad), UserError) << cover;
  }
  s.layers[1].lambda2.resize(1);
  EXPECT_THROW(laminate(s), UserError);
}

// The thinnest and thickest face: the sum over the layers that cover each face.
TEST(LayerStack, PrintedThicknessRangeSumsTheLayersCoveringEachFace) {
  const Material m = paper_material();
  LayerStack s =
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3), m, 4, 0.1);
  s.layers[3].material(1) = Layer::kNotCovered;  // face 1 lacks the top layer
  s.layers[2].printed_thickness(2) = 0.3;        // face 2 has a thicker third layer
  const auto [thinnest, thickest] = printed_thickness_range(s);
  EXPECT_NEAR(thinnest, 0.3, 1e-12);
  EXPECT_NEAR(thickest, 0.6, 1e-12);
}

TEST(LayerStack, PrintingRuleAndSignConvention) {
  // theta^k = theta1 + ((k-1)/(n-1) - 1/2) theta2; bed layer theta1 - theta2/2, top theta1 +
  // theta2/2 (z up from the bed).
  EXPECT_DOUBLE_EQ(shrink_morph_layer_weight(1, 10), -0.5);
  EXPECT_DOUBLE_EQ(shrink_morph_layer_weight(10, 10), 0.5);
  EXPECT_DOUBLE_EQ(shrink_morph_layer_weight(4, 10), 3.0 / 9 - 0.5);
  EXPECT_DOUBLE_EQ(shrink_morph_layer_weight(1, 1), 0.0);  // one layer prints theta1
  Eigen::VectorXd theta1(2), theta2(2);
  theta1 << 0.1, -0.3;
  theta2 << 0.4, 0.2;
  const LayerStack s = shrink_morph_layer_stack(theta1, theta2, paper_material(), 10, 0.08);
  EXPECT_TRUE(s.layers[9].theta.isApprox(theta1 + theta2 / 2));
  EXPECT_TRUE(s.layers[0].theta.isApprox(theta1 - theta2 / 2));
  EXPECT_EQ(s.materials.size(), 1u);
  EXPECT_TRUE((s.layers[4].material.array() == 0).all());
  EXPECT_TRUE((s.layers[4].printed_thickness.array() == 0.08).all());
}

TEST(LayerStack, VertexValuesAverageToFaces) {
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 2, 1, 3;
  const Eigen::VectorXd v = (Eigen::VectorXd(4) << 0.0, 3.0, 6.0, 9.0).finished();
  const Eigen::VectorXd f = vertex_to_face_average(F, v);
  EXPECT_DOUBLE_EQ(f(0), 3.0);
  EXPECT_DOUBLE_EQ(f(1), 6.0);
}

}  // namespace
}  // namespace flatmorph::laminate_test
