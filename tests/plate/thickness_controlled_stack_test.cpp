// The thickness-controlled stack (SCF 2020 §6, Geodesy §3): the builder's per-face layer height
// and shrink against the material's thickness curve, its clamping and its refusals; the laminate of
// faces of different thickness; and the physics through laminate + simulate against known shapes:
// a strip shrinks to 1 − σ of its length and stays flat, concentric rings rise into the surface of
// revolution the geometric calculation of Geodesy (§7, Sh(k) = 1 − F(G(w k)) / (w k)) gives.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <functional>
#include <iostream>
#include <numbers>
#include <stdexcept>

#include "common/angles.h"
#include "common/error.h"
#include "mesh/operators.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "plate/plate_fixtures.h"
#include "simulate/simulate.h"

namespace flatmorph::thickness_controlled_stack_test {
namespace {

using testing::disk_plate;
using testing::embed;
using testing::rectangle_plate;
using testing::TestPlate;

Material geodesy() { return load_material("pla-geodesy"); }

// pla-geodesy growing 8 % across its paths, as Shrink & Morph's PLA does (pla-paper): the rings
// below then rise into steeper cones, whose parallels lie well off the apex's rounding.
Material growing_geodesy() {
  Material m = geodesy();
  m.lambda2 = 1.08;
  return m;
}

TEST(ThicknessControlledStack, PerFaceHeightAndShrinkFollowTheCurve) {
  const Material m = geodesy();
  const ThicknessCurve& curve = *m.thickness_curve;
  const Eigen::VectorXd sigma = (Eigen::VectorXd(5) << 0.10, 0.15, 0.24, 0.30, 0.36).finished();
  const Eigen::VectorXd direction = (Eigen::VectorXd(5) << 0.0, 0.3, -1.2, kPi / 2, 2.5).finished();
  const ThicknessControlledStack out = thickness_controlled_layer_stack(direction, sigma, m);
  EXPECT_EQ(out.num_clamped(), 0);
  ASSERT_EQ(out.stack.num_layers(), 6) << "the curve's 6 calibration layers";
  ASSERT_EQ(out.stack.num_faces(), 5);
  EXPECT_NO_THROW(check_layer_stack(out.stack));
  for (const Layer& l : out.stack.layers) {
    for (int f = 0; f < 5; ++f) {
      EXPECT_EQ(l.material(f), 0);
      EXPECT_EQ(l.theta(f), direction(f));
      EXPECT_DOUBLE_EQ(l.printed_thickness(f), layer_height_for_shrinkage(curve, sigma(f)));
      EXPECT_NEAR(l.lambda1(f), 1 - sigma(f), 1e-12);
      EXPECT_EQ(l.lambda1(f), lambda1_at_layer_height(curve, l.printed_thickness(f)));
      EXPECT_EQ(l.delta_lambda1(f), 0);
      EXPECT_EQ(l.lambda2(f), m.lambda2);
      EXPECT_EQ(l.lambda3(f), m.lambda3);
    }
    // More shrink, thinner layers (SCF 2020 §3).
    for (int f = 1; f < 5; ++f) {
      EXPECT_LT(l.printed_thickness(f), l.printed_thickness(f - 1));
    }
  }
  // Geodesy's table: 24 % of shrink is printed at 0.10 mm layers (up to the fit's residual).
  EXPECT_NEAR(out.stack.layers[0].printed_thickness(2), 0.10, 0.01);

  // Another count when asked; the default follows a user's curve measured on 8 layers.
  EXPECT_EQ(thickness_controlled_layer_stack(direction, sigma, m, 4).stack.num_layers(), 4);
  Material eight = m;
  eight.thickness_curve->layers = 8;
  EXPECT_EQ(thickness_controlled_layer_stack(direction, sigma, eight).stack.num_layers(), 8);
}

TEST(ThicknessControlledStack, ShrinkOutsideTheCurveIsClampedAndCounted) {
  const Material m = geodesy();
  const ThicknessCurve& curve = *m.thickness_curve;
  const auto [least, most] = reachable_shrinkage(curve);
  // A path asked to grow, one asked for less than the thickest layer gives, one reachable, one
  // asked for more than the thinnest gives, and the two ends exactly.
  const Eigen::VectorXd sigma =
      (Eigen::VectorXd(6) << -0.05, least - 0.01, 0.2, most + 0.1, least, most).finished();
  ThicknessControlledStack out;
  ASSERT_NO_THROW(out = thickness_controlled_layer_stack(Eigen::VectorXd::Zero(6), sigma, m));
  EXPECT_EQ(out.clamped, (Eigen::VectorXi(6) << -1, -1, 0, 1, 0, 0).finished());
  EXPECT_EQ(out.num_clamped(), 3);
  const Layer& l = out.stack.layers[0];
  for (int f : {0, 1, 4}) {
    EXPECT_NEAR(l.printed_thickness(f), curve.max_layer_height, 1e-12) << f;
    EXPECT_NEAR(1 - l.lambda1(f), least, 1e-12) << f;
  }
  for (int f : {3, 5}) {
    EXPECT_NEAR(l.printed_thickness(f), curve.min_layer_height, 1e-12) << f;
    EXPECT_NEAR(1 - l.lambda1(f), most, 1e-12) << f;
  }
  EXPECT_NO_THROW(check_layer_stack(out.stack));
}

TEST(ThicknessControlledStack, RefusesAMaterialWithoutACurveAndBadInput) {
  const Eigen::VectorXd one = Eigen::VectorXd::Constant(1, 0.2);
  try {
    thickness_controlled_layer_stack(one, one, load_material("pla-paper"));
    ADD_FAILURE() << "a material without a thickness curve was accepted";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
    const std::string message = e.what();
    for (const char* words : {"pla-paper", "thickness curve", "pla-geodesy", "calibrate"}) {
      EXPECT_NE(message.find(words), std::string::npos) << message;
    }
  }
  EXPECT_THROW(thickness_controlled_layer_stack(one, one, geodesy(), 0), UserError);
  EXPECT_THROW(thickness_controlled_layer_stack(one, Eigen::VectorXd::Zero(2), geodesy()),
               std::invalid_argument);
  EXPECT_THROW(thickness_controlled_layer_stack(one, Eigen::VectorXd::Constant(1, NAN), geodesy()),
               std::invalid_argument);
}

// A material's own Δλ1 varies λ1 through each face's whole thickness (Shrink & Morph Eq. 15) about
// the curve's value: the layers' mean is still 1 − σ, the top shrinks more when Δλ1 < 0.
TEST(ThicknessControlledStack, TheMaterialsBilayerGradientSpansTheWholeThickness) {
  Material m = geodesy();
  m.delta_lambda1 = -0.03;
  const ThicknessControlledStack out = thickness_controlled_layer_stack(
      Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 0.2), m);
  double mean = 0;
  for (const Layer& l : out.stack.layers) {
    mean += l.lambda1(0) / out.stack.num_layers();
    EXPECT_DOUBLE_EQ(l.delta_lambda1(0), -0.03 / 6);
  }
  EXPECT_NEAR(mean, 0.8, 1e-12);
  EXPECT_NEAR(out.stack.layers.back().lambda1(0) - out.stack.layers.front().lambda1(0),
              -0.03 * 5 / 6, 1e-12);
  EXPECT_GT(laminate(out.stack).rest_second_fundamental_form[0](0, 0), 0)
      << "the top shrinks more: the plate bends toward its top";
}

// Faces of different thickness are each their own laminate: per face the single-material,
// single-direction forms of thickness t = 6 h λ3, ā = R diag(λ1², λ2²) Rᵀ, b̄ = 0 (symmetric).
TEST(ThicknessControlledStack, EachFaceLaminatesAtItsOwnThickness) {
  const Material m = geodesy();
  const Eigen::VectorXd sigma = (Eigen::VectorXd(3) << 0.09, 0.2, 0.35).finished();
  const Eigen::VectorXd direction = (Eigen::VectorXd(3) << 0.4, -1.0, 2.0).finished();
  const ThicknessControlledStack out = thickness_controlled_layer_stack(direction, sigma, m);
  const RestForms forms = laminate(out.stack);
  std::vector<Eigen::Matrix2d> a_bar, b_bar(3, Eigen::Matrix2d::Zero());
  Eigen::VectorXd t(3);
  for (int f = 0; f < 3; ++f) {
    const double l1 = 1 - sigma(f);
    a_bar.push_back(rotation(direction(f)) *
                    Eigen::Vector2d(l1 * l1, m.lambda2 * m.lambda2).asDiagonal() *
                    rotation(direction(f)).transpose());
    t(f) = 6 * out.stack.layers[0].printed_thickness(f) * m.lambda3;
  }
  const RestForms expected =
      single_material_rest_forms(a_bar, b_bar, t, direction, stiffness_of(m));
  for (int f = 0; f < 3; ++f) {
    EXPECT_NEAR(forms.thickness(f), t(f), 1e-12);
    EXPECT_LT((forms.rest_first_fundamental_form[f] - a_bar[f]).norm(), 1e-10) << f;
    EXPECT_LT(forms.rest_second_fundamental_form[f].norm(), 1e-10) << f;
    EXPECT_LT((forms.stiffness[f] - expected.stiffness[f]).norm(),
              1e-10 * expected.stiffness[f].norm())
        << f;
  }
  // The thinnest face (most shrink) bends t³ times more easily.
  EXPECT_LT(forms.thickness(2), forms.thickness(0));
}

// Per face of `plate`: the print direction and wanted shrinkage at the face's centroid.
PlateProblem thickness_problem(const TestPlate& plate,
                               const std::function<double(const Eigen::Vector2d&)>& direction,
                               const std::function<double(const Eigen::Vector2d&)>& shrinkage) {
  const Eigen::Index nf = plate.F.rows();
  Eigen::VectorXd theta(nf), sigma(nf);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector2d c =
        (plate.V.row(plate.F(f, 0)) + plate.V.row(plate.F(f, 1)) + plate.V.row(plate.F(f, 2)))
            .transpose() /
        3;
    theta(f) = direction(c);
    sigma(f) = shrinkage(c);
  }
  const ThicknessControlledStack out =
      thickness_controlled_layer_stack(theta, sigma, growing_geodesy());
  EXPECT_EQ(out.num_clamped(), 0);
  return {plate.V, plate.F, laminate(out.stack)};
}

// The mean of the result's vertices whose plate x is within `tolerance` of `x`.
Eigen::Vector3d mean_at_plate_x(const TestPlate& plate, const Eigen::MatrixXd& X, double x) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (Eigen::Index v = 0; v < plate.V.rows(); ++v) {
    if (std::abs(plate.V(v, 0) - x) < 1e-9) {
      sum += X.row(v).transpose();
      ++n;
    }
  }
  EXPECT_GT(n, 0);
  return sum / n;
}

// (a) A strip printed along its length with one shrink σ everywhere: its rest metric diag((1−σ)²,
// λ2²) is flat, so it shrinks to exactly (1 − σ) of its length and grows to λ2 of its width; the
// stack is symmetric (Δλ1 = 0), so it stays flat. Then a strip whose halves ask 10 % and 30 %:
// layers of 0.22 and 0.07 mm side by side, still flat, its length the sum of the halves'.
TEST(ThicknessControlledStack, AStripShrinksAlongItsPathsAndStaysFlat) {
  const double length = 80, width = 10;
  const TestPlate plate = rectangle_plate(length, width, 64, 8);
  auto along = [](const Eigen::Vector2d&) { return 0.0; };
  for (double sigma : {0.10, 0.24, 0.35}) {
    const PlateProblem p =
        thickness_problem(plate, along, [&](const Eigen::Vector2d&) { return sigma; });
    const SimulationResult r = simulate(p, flat_start(p));
    ASSERT_TRUE(r.converged) << r.warning;
    const double shrunk =
        (mean_at_plate_x(plate, r.V, length / 2) - mean_at_plate_x(plate, r.V, -length / 2)).norm();
    const double error = shrunk / length / (1 - sigma) - 1;
    std::cout << fmt::format(
        "strip σ = {:.2f}: length ratio {:.6f} (1 − σ = {:.2f}), error {:.2e}, "
        "max |z| {:.1e} mm\n",
        sigma, shrunk / length, 1 - sigma, error, r.V.col(2).cwiseAbs().maxCoeff());
    EXPECT_LT(std::abs(error), 0.01);
    EXPECT_LT(r.V.col(2).cwiseAbs().maxCoeff(), 1e-6 * length) << "a symmetric stack stays flat";
  }
  const PlateProblem halves = thickness_problem(
      plate, along, [](const Eigen::Vector2d& c) { return c.x() < 0 ? 0.10 : 0.30; });
  const SimulationResult r = simulate(halves, flat_start(halves));
  ASSERT_TRUE(r.converged) << r.warning;
  const double shrunk =
      (mean_at_plate_x(plate, r.V, length / 2) - mean_at_plate_x(plate, r.V, -length / 2)).norm();
  const double expected = length / 2 * (0.90 + 0.70);
  std::cout << fmt::format("strip of halves 10 % | 30 %: length {:.4f} mm, expected {:.4f} mm\n",
                           shrunk, expected);
  EXPECT_NEAR(shrunk, expected, 0.01 * expected);
  // The halves' widths differ by nothing (both grow by λ2): the joint is compatible and flat.
  EXPECT_LT(r.V.col(2).cwiseAbs().maxCoeff(), 1e-3);
}

// A disk printed along concentric circles, shrinking by σ(r) around and growing by λ2 across, wants
// the metric λ2² dr² + (r λ1(r))² dφ²: the surface of revolution whose parallel at plate radius r
// has radius ρ(r) = r λ1(r) and whose meridian has arc length λ2 r (Geodesy §7: Sh(k) = 1 −
// F(G(w k)) / (w k), one minus the ring's radius in 3D over its flat one, there with λ2 = 1). The
// parallel at r lies ∫_r^R √(λ2² − ρ'²) dr above the rim, and by Gauss–Bonnet the Gaussian
// curvature within plate radius r integrates to 2π (1 − ρ'(r)/λ2) (the apex's cone deficit 2π (1 −
// λ1(0)/λ2) included). A plate of thickness t reaches this isometric limit only away from the apex:
// there it rounds the cone's tip over a core several times t wide, stretching rather than bend so
// sharply, which lowers the apex by a few mm whatever the disk's size (about 4.2 mm for the 1.4 mm
// thick cone below, at radius 20, 40 and 80 mm alike).
struct RingShrink {
  double centre;  // σ at r = 0
  double rim;     // σ at r = radius, linear in between

  double sigma(double r, double radius) const { return centre + (rim - centre) * r / radius; }
  // ρ' = d(r (1 − σ(r)))/dr.
  double rho_prime(double r, double radius) const {
    return 1 - centre - 2 * (rim - centre) * r / radius;
  }
  double height_above_rim(double r, double radius, double lambda2) const {
    const int n = 2000;
    double h = 0;
    for (int i = 0; i < n; ++i) {
      const double x = rho_prime(r + (i + 0.5) * (radius - r) / n, radius);
      h += std::sqrt(lambda2 * lambda2 - x * x) * (radius - r) / n;
    }
    return h;
  }
  double curvature_within(double r, double radius, double lambda2) const {
    return 2 * kPi * (1 - rho_prime(r, radius) / lambda2);
  }
};

struct DiskShape {
  std::vector<double> height;     // mm, mean of the parallel at each radius above the rim's plane
  std::vector<double> curvature;  // integrated Gaussian curvature within each radius
};

DiskShape measure_disk(const TestPlate& plate, const Eigen::MatrixXd& X, double radius,
                       const std::vector<double>& radii) {
  auto on_circle = [&](double r) {
    std::vector<int> out;
    for (Eigen::Index v = 0; v < plate.V.rows(); ++v) {
      if (std::abs(plate.V.row(v).norm() - r) < 1e-9) out.push_back(static_cast<int>(v));
    }
    return out;
  };
  const std::vector<int> rim = on_circle(radius);
  Eigen::MatrixXd P(rim.size(), 3);
  for (size_t i = 0; i < rim.size(); ++i) P.row(i) = X.row(rim[i]);
  const Eigen::RowVector3d mean = P.colwise().mean();
  const Eigen::MatrixXd Q = P.rowwise() - mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Q.transpose() * Q);
  Eigen::Vector3d normal = eig.eigenvectors().col(0);
  if (normal.z() < 0) normal = -normal;
  const Eigen::VectorXd defects = angle_defects(X, plate.F);
  DiskShape s;
  for (double r : radii) {
    double height = 0;
    const std::vector<int> circle = on_circle(r);
    EXPECT_FALSE(circle.empty()) << "no ring of vertices at " << r << " mm";
    for (int v : circle) height += (X.row(v) - mean).dot(normal) / circle.size();
    s.height.push_back(height);
    double k = 0;
    for (Eigen::Index v = 0; v < plate.V.rows(); ++v) {
      if (plate.V.row(v).norm() < r + 1e-9) k += defects(v);
    }
    s.curvature.push_back(k);
  }
  return s;
}

// (b), (c): rings shrinking 30 % at the centre down to 15 % at the rim (thinner layers inside), and
// 15 % everywhere, on a disk of 40 mm radius. The symmetric sheet (Δλ1 = 0) has no preferred side:
// flat, it is an equilibrium (the in-plane shrink pushes nothing out of the plane, and flat_start's
// bump follows b̄, which is 0), so the simulation starts from a bump of 0.2 mm, the paper's "small
// initial out-of-plane bias" (in water the sheet pops to one side, SCF 2020 §8). Both follow the
// geometric surface of revolution off the apex: the heights of the parallels at 10 and 20 mm and
// the Gaussian curvature within them and within 32 mm. Constant σ gives a cone (SCF 2020 Fig. 3a):
// all its curvature is at the apex, none on the flanks. More shrink inside puts more curvature at
// the centre and negative curvature on the flanks, whose outer half is flatter than the cone's.
TEST(ThicknessControlledStack, ConcentricRingsRiseIntoTheSurfaceOfRevolutionOfTheirShrink) {
  const double radius = 40;
  const int rings = 30;
  const TestPlate plate = disk_plate(radius, rings);
  const double lambda2 = growing_geodesy().lambda2;
  const double spacing = radius / rings;
  // On rings of vertices (multiples of the spacing): 10.67, 20 and 32 mm.
  const std::vector<double> radii = {8 * spacing, 15 * spacing, 24 * spacing};
  Eigen::MatrixXd start = embed(plate.V);
  for (Eigen::Index v = 0; v < start.rows(); ++v) {
    start(v, 2) = 0.2 * (1 - plate.V.row(v).squaredNorm() / (radius * radius));
  }
  auto around = [](const Eigen::Vector2d& c) { return std::atan2(c.y(), c.x()) + kPi / 2; };
  std::vector<DiskShape> shapes;
  for (const RingShrink rule : {RingShrink{0.30, 0.15}, RingShrink{0.15, 0.15}}) {
    const PlateProblem p = thickness_problem(
        plate, around, [&](const Eigen::Vector2d& c) { return rule.sigma(c.norm(), radius); });
    const SimulationResult r = simulate(p, start);
    ASSERT_TRUE(r.converged) << r.warning;
    const DiskShape s = measure_disk(plate, r.V, radius, {0.0, radii[0], radii[1], radii[2]});
    std::cout << fmt::format(
        "rings σ {:.2f} → {:.2f}: apex {:.2f} mm above the rim (geometric "
        "{:.2f})",
        rule.centre, rule.rim, s.height[0], rule.height_above_rim(0, radius, lambda2));
    for (size_t i = 0; i < radii.size(); ++i) {
      const double height = rule.height_above_rim(radii[i], radius, lambda2);
      // The vertices within r bound a region reaching half a ring beyond r.
      const double k = rule.curvature_within(radii[i] + spacing / 2, radius, lambda2);
      std::cout << fmt::format("; at {:.1f} mm: height {:.2f} ({:.2f}), K within {:.3f} ({:.3f})",
                               radii[i], s.height[i + 1], height, s.curvature[i + 1], k);
      // Measured: heights 1.5-2.6 % low (the free rim bends a little out of the surface, which
      // moves the plane heights are measured from), curvatures at most 0.052 rad off (the thick
      // cone's rounded tip reaches 10 mm). Near the rim the heights are small: left out.
      if (i < 2) {
        EXPECT_NEAR(s.height[i + 1], height, 0.03 * height) << radii[i];
      }
      EXPECT_NEAR(s.curvature[i + 1], k, 0.06) << radii[i];
    }
    std::cout << "\n";
    // The apex is lower than the isometric limit by the rounding of its tip, but not higher.
    EXPECT_LT(s.height[0], rule.height_above_rim(0, radius, lambda2));
    EXPECT_GT(s.height[0], s.height[1]);
    shapes.push_back(s);
  }
  const DiskShape& graded = shapes[0];
  const DiskShape& cone = shapes[1];
  EXPECT_GT(graded.curvature[1], 0) << "positive Gaussian curvature at the centre";
  EXPECT_GT(graded.curvature[1], cone.curvature[1] + 0.3) << "more of it than the cone";
  EXPECT_LT(graded.curvature[3], graded.curvature[1] - 0.5) << "negative curvature on the flanks";
  EXPECT_NEAR(cone.curvature[3], cone.curvature[1], 0.06) << "a cone is flat off its apex";
  EXPECT_LT(graded.height[2], cone.height[2]) << "a flatter outer half";
}

}  // namespace
}  // namespace flatmorph::thickness_controlled_stack_test
