#include "plate/laminate.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "plate/layer_stack.h"

namespace flatmorph {
namespace {

Material paper_material() { return Material{}; }  // the defaults are the paper's PLA

double max_abs(const Eigen::Matrix2d& m) { return m.cwiseAbs().maxCoeff(); }

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
    const RestForms closed = shrink_morph_rest_forms(theta1, theta2, m, n * 0.08);
    for (int f = 0; f < 3; ++f) {
      // ā gains the O(Δλ1²) term the first-order expansion drops: ⟨(z/h)²⟩ Δλ1² = Δλ1²/12
      // along the path.
      const Eigen::Matrix2d r = rotation(theta1(f));
      const Eigen::Matrix2d second_order =
          r * Eigen::Vector2d(m.delta_lambda1 * m.delta_lambda1 / 12, 0).asDiagonal() *
          r.transpose();
      EXPECT_LT(max_abs(lam.rest_first_fundamental_form[f] - closed.rest_first_fundamental_form[f] -
                        second_order),
                1e-14);
      // b̄ (Eq. 17): exact, because λ1 is linear in z within each layer.
      EXPECT_LT(
          max_abs(lam.rest_second_fundamental_form[f] - closed.rest_second_fundamental_form[f]),
          1e-13);
      EXPECT_NEAR(lam.thickness(f), m.lambda3 * n * 0.08, 1e-14);
      EXPECT_NEAR(closed.thickness(f), m.lambda3 * n * 0.08, 1e-14);
      EXPECT_NEAR(std::remainder(lam.material_angle(f) - theta1(f), M_PI), 0.0, 1e-14);
    }
  }
  // Without the bilayer term, ā is the closed form exactly.
  m.delta_lambda1 = 0;
  const RestForms lam = laminate(shrink_morph_layer_stack(theta1, theta2, m, 10, 0.08));
  const RestForms closed = shrink_morph_rest_forms(theta1, theta2, m, 0.8);
  for (int f = 0; f < 3; ++f) {
    EXPECT_LT(max_abs(lam.rest_first_fundamental_form[f] - closed.rest_first_fundamental_form[f]),
              1e-15);
  }
}

TEST(Laminate, BilayerCurvatureMatchesPaperNumbers) {
  // Eq. 17 with the paper's PLA: b̄ = −Δλ1 λ1 / t along the path, t = λ3 h = 1.216 mm for
  // 10 × 0.08 mm, i.e. 0.0226765 × 0.58 / 1.216 = 0.010816 /mm.
  const Material m = paper_material();
  const RestForms closed =
      shrink_morph_rest_forms(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), m, 0.8);
  EXPECT_NEAR(closed.rest_second_fundamental_form[0](0, 0), 0.0226764665509417 * 0.58 / 1.216,
              1e-12);
  EXPECT_GT(closed.rest_second_fundamental_form[0](0, 0), 0.0);  // the top shrinks more
  EXPECT_EQ(closed.rest_second_fundamental_form[0](1, 1), 0.0);
}

// The θ2 part of b̄ (Eq. 7) from a stack sampled at layer mid-heights converges to the closed form
// as 1 − 1/n² (the least-squares slope of a staircase) and 1 − θ2²/10 (the next term of sin 2sθ2).
TEST(Laminate, TwistConvergesToTheClosedFormAsPredicted) {
  Material m = paper_material();
  m.delta_lambda1 = 0;  // isolate the θ2 term
  const double theta1 = 0.4;
  auto relative_error = [&](double theta2, int n) {
    const RestForms lam = laminate(midpoint_stack(theta1, theta2, m, n));
    const RestForms closed =
        shrink_morph_rest_forms(Eigen::VectorXd::Constant(1, theta1),
                                Eigen::VectorXd::Constant(1, theta2), m, n * m.layer_height);
    const Eigen::Matrix2d& b = lam.rest_second_fundamental_form[0];
    const Eigen::Matrix2d& c = closed.rest_second_fundamental_form[0];
    return (b - c).norm() / c.norm();
  };
  // O(1/n²) at small θ2: the error is 1/n² to within the θ2² term (1e-7).
  for (int n : {4, 8, 16, 32}) {
    EXPECT_NEAR(relative_error(1e-3, n), 1.0 / (n * n), 2e-7) << "n=" << n;
  }
  // O(θ2²) with many layers: the error is θ2²/10 (+ 1/n² = 1e-6).
  for (double theta2 : {0.05, 0.1, 0.2}) {
    EXPECT_NEAR(relative_error(theta2, 1000), theta2 * theta2 / 10, 2e-6 + 0.01 * theta2 * theta2)
        << "theta2=" << theta2;
  }
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
    const RestForms closed = shrink_morph_rest_forms(
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
  EXPECT_LT(max_abs(a.rest_second_fundamental_form[0] + b.rest_second_fundamental_form[0]), 1e-15);
  EXPECT_LT(max_abs(a.rest_first_fundamental_form[0] - b.rest_first_fundamental_form[0]), 1e-15);
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
  // on top along y and convex along x. C̄_xx steps from λ1² (bottom half) to λ2² (top half), so
  // b̄_xx = −(6/t³) ∫ z' C̄_xx dz' = −(3/(4t)) (λ2² − λ1²), and b̄_yy the opposite.
  const double t = lam.thickness(0);
  const double jump = m.lambda2 * m.lambda2 - m.lambda1 * m.lambda1;
  EXPECT_NEAR(lam.rest_second_fundamental_form[0](0, 0), -0.75 * jump / t, 1e-12);
  EXPECT_NEAR(lam.rest_second_fundamental_form[0](1, 1), 0.75 * jump / t, 1e-12);
  // A face with no layer at all is a user error.
  s.layers[0].material(1) = Layer::kNotCovered;
  EXPECT_THROW(laminate(s), UserError);
}

TEST(Laminate, BadInputsAreUserErrors) {
  const Material m = paper_material();
  EXPECT_THROW(
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(3), m, 10, 0.08),
      UserError);
  EXPECT_THROW(
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), m, 0, 0.08),
      UserError);
  EXPECT_THROW(
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), m, 3, 0.0),
      UserError);
  LayerStack s =
      shrink_morph_layer_stack(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), m, 3, 0.08);
  s.layers[1].lambda2.resize(1);
  EXPECT_THROW(laminate(s), UserError);
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
}  // namespace flatmorph
