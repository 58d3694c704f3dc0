// GCC 12 reports a false "may be used uninitialized" inside Eigen 3.4's tridiagonalization (the
// eigen-decompositions below); the warning is about Eigen's code, not this file's.
#if !defined(__clang__)  // clang has no such warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "simulate/plate_energy.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

#include "common/error.h"
#include "mesh/topology.h"
#include "plate/laminate.h"
#include "plate/plate_fixtures.h"

namespace flatmorph::plate_energy_test {
namespace {

using testing::embed;
using testing::flatten_positions;
using testing::rectangle_plate;
using testing::TestPlate;

// Rest forms of one material along one direction per face: the orthotropic energy of Eq. 8, the
// special case of a laminate (single_material_rest_forms).
struct OrthotropicRest {
  std::vector<Eigen::Matrix2d> rest_first_fundamental_form, rest_second_fundamental_form;
  Eigen::VectorXd thickness, material_angle;
  int num_faces() const { return static_cast<int>(thickness.size()); }
};

PlateEnergy make_plate_energy(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                              const OrthotropicRest& rest, const Stiffness& stiffness) {
  return flatmorph::make_plate_energy(
      plate, F,
      single_material_rest_forms(rest.rest_first_fundamental_form,
                                 rest.rest_second_fundamental_form, rest.thickness,
                                 rest.material_angle, stiffness));
}

// A small rectangle with jittered vertices, random per-face rest forms (SPD ā, any b̄), random
// material angles and thicknesses.
struct RandomCase {
  TestPlate plate;
  OrthotropicRest rest;
  Stiffness stiffness;
  Eigen::VectorXd x;  // a random 3D state near the plate
};

RandomCase random_case(unsigned seed, int cells_x, int cells_y) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  RandomCase c;
  c.plate = rectangle_plate(3.0 * cells_x, 2.5 * cells_y, cells_x, cells_y);
  for (Eigen::Index v = 0; v < c.plate.V.rows(); ++v) {
    c.plate.V.row(v) += 0.4 * Eigen::RowVector2d(uni(rng), uni(rng));
  }
  const int nf = static_cast<int>(c.plate.F.rows());
  c.rest.rest_first_fundamental_form.resize(nf);
  c.rest.rest_second_fundamental_form.resize(nf);
  c.rest.thickness.resize(nf);
  c.rest.material_angle.resize(nf);
  for (int f = 0; f < nf; ++f) {
    Eigen::Matrix2d m;
    m << uni(rng), uni(rng), uni(rng), uni(rng);
    c.rest.rest_first_fundamental_form[f] = m * m.transpose() + 0.5 * Eigen::Matrix2d::Identity();
    Eigen::Matrix2d b;
    b << uni(rng), uni(rng), uni(rng), uni(rng);
    c.rest.rest_second_fundamental_form[f] = 0.2 * (b + b.transpose());
    c.rest.thickness(f) = 1.0 + 0.5 * uni(rng);
    c.rest.material_angle(f) = 3.0 * uni(rng);
  }
  c.stiffness = {7.0, 1.5, 0.3};
  Eigen::MatrixXd X = embed(c.plate.V);
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    X.row(v) += Eigen::RowVector3d(0.3 * uni(rng), 0.3 * uni(rng), 0.8 * uni(rng));
  }
  c.x = flatten_positions(X);
  return c;
}

Eigen::MatrixXd dense_symmetric(const Eigen::SparseMatrix<double>& lower) {
  const Eigen::SparseMatrix<double> full = lower.selfadjointView<Eigen::Lower>();
  return Eigen::MatrixXd(full);
}

// Central differences: gradient from energies, Hessian columns from gradients.
void check_derivatives(const PlateEnergy& energy, const Eigen::VectorXd& x, double tolerance) {
  Eigen::VectorXd g;
  Eigen::SparseMatrix<double> h;
  evaluate_plate_energy(energy, x, &g, &h, false);
  const Eigen::MatrixXd hess = dense_symmetric(h);
  const int n = static_cast<int>(x.size());
  const double step = 1e-5;
  Eigen::VectorXd g_fd(n);
  Eigen::MatrixXd h_fd(n, n);
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp(i) += step;
    xm(i) -= step;
    Eigen::VectorXd gp, gm;
    const double ep = evaluate_plate_energy(energy, xp, &gp, nullptr, false);
    const double em = evaluate_plate_energy(energy, xm, &gm, nullptr, false);
    g_fd(i) = (ep - em) / (2 * step);
    h_fd.col(i) = (gp - gm) / (2 * step);
  }
  EXPECT_LT((g - g_fd).norm() / g.norm(), tolerance);
  EXPECT_LT((hess - h_fd).norm() / hess.norm(), tolerance);
  // Entry by entry too, so that a small wrong block cannot hide in the norm.
  const double scale = hess.cwiseAbs().maxCoeff();
  EXPECT_LT((hess - h_fd).cwiseAbs().maxCoeff() / scale, tolerance);
  EXPECT_LT((g - g_fd).cwiseAbs().maxCoeff() / g.cwiseAbs().maxCoeff(), tolerance);
}

TEST(PlateEnergy, GradientAndHessianMatchFiniteDifferences) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const RandomCase c = random_case(seed, 3, 2);
    const PlateEnergy energy = make_plate_energy(c.plate.V, c.plate.F, c.rest, c.stiffness);
    SCOPED_TRACE(seed);
    check_derivatives(energy, c.x, 1e-6);
  }
}

// A laminate of two materials with random layer directions, thicknesses and coverage: its stiffness
// couples membrane and bending (B != 0), which the orthotropic cases above never exercise.
TEST(PlateEnergy, LaminateWithCouplingMatchesFiniteDifferences) {
  const RandomCase c = random_case(11, 3, 2);
  const int nf = c.rest.num_faces();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Material pla, tpu;
  tpu.lambda1 = tpu.lambda2 = tpu.lambda3 = 1.0;
  tpu.delta_lambda1 = 0;
  tpu.young_modulus_along = tpu.young_modulus_across = 0.7;
  LayerStack stack;
  stack.materials = {pla, tpu};
  for (int k = 0; k < 4; ++k) {
    Layer layer = uniform_layer(nf, k % 2, stack.materials[k % 2], 0.1);
    for (int f = 0; f < nf; ++f) {
      layer.theta(f) = 3 * uni(rng);
      layer.printed_thickness(f) = 0.1 + 0.05 * uni(rng);
      if (k == 3 && f % 3 == 0) layer.material(f) = Layer::kNotCovered;
    }
    stack.layers.push_back(layer);
  }
  const RestForms rest = laminate(stack);
  const Eigen::Matrix3d coupling = rest.stiffness[0].topRightCorner<3, 3>();
  ASSERT_GT(coupling.norm(), 1e-3 * rest.stiffness[0].norm());
  const PlateEnergy energy = flatmorph::make_plate_energy(c.plate.V, c.plate.F, rest);
  check_derivatives(energy, c.x, 1e-6);
}

TEST(PlateEnergy, BendingDerivativesAloneMatchFiniteDifferences) {
  // Thick plate, ā = I: the membrane term is small and the bending derivatives dominate the check.
  RandomCase c = random_case(9, 3, 3);
  for (int f = 0; f < c.rest.num_faces(); ++f) c.rest.thickness(f) = 20.0;
  const PlateEnergy energy = make_plate_energy(c.plate.V, c.plate.F, c.rest, c.stiffness);
  check_derivatives(energy, c.x, 1e-6);
}

TEST(PlateEnergy, HingeMeasureIsSignedDihedralAngleTimesHeight) {
  // Face (i, j, k) in the xy plane with normal +z; the hinge across edge (i, j) folded by angle α.
  const Eigen::Vector3d xi(0, 0, 0), xj(2, 0, 0), xk(0.5, 1.5, 0);
  for (double alpha : {0.3, -0.7, 1.2}) {
    // The neighbour's vertex: across the edge (y < 0), rotated about the x axis by α, so that
    // α > 0 lifts it to z > 0, the side the normal points to: the hinge bends toward the normal.
    const Eigen::Vector3d xl(1.0, -std::cos(alpha), std::sin(alpha));
    const double phi = hinge_bending_measure(xi, xj, xk, xl);
    EXPECT_NEAR(phi, alpha * 1.5, 1e-14) << alpha;  // 2A/ℓ = the height over the edge = 1.5
  }
}

// The derivation behind the fast bending term: b = FᵀΛF with Λ = Σ_e θ_e ℓ_e/(2A) t̂_e t̂_eᵀ (Eq. 10
// normalized as in notes §3.4) equals Σ_e φ_e K_e with K_e = m̂ m̂ᵀ ℓ̂²/(2Â)² from the rest triangle.
TEST(PlateEnergy, PulledBackShapeOperatorEqualsSumOfConstantTensors) {
  const RandomCase c = random_case(5, 3, 3);
  const EdgeTopology topo = edge_topology(c.plate.F);
  const Eigen::MatrixXd X = testing::unflatten_positions(c.x);
  for (int f = 0; f < c.plate.F.rows(); ++f) {
    Eigen::Vector2d p[3];
    Eigen::Vector3d x[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = c.plate.V.row(c.plate.F(f, k)).transpose();
      x[k] = X.row(c.plate.F(f, k)).transpose();
    }
    Eigen::Matrix2d rest_edges;
    rest_edges << p[1] - p[0], p[2] - p[0];
    Eigen::Matrix<double, 3, 2> edges;
    edges << x[1] - x[0], x[2] - x[0];
    const Eigen::Matrix<double, 3, 2> deformation = edges * rest_edges.inverse();  // Eq. 9
    const Eigen::Vector3d n = (x[1] - x[0]).cross(x[2] - x[0]);
    const double area = 0.5 * n.norm(), rest_area = 0.5 * rest_edges.determinant();
    Eigen::Matrix3d shape = Eigen::Matrix3d::Zero();
    Eigen::Matrix2d b_fast = Eigen::Matrix2d::Zero();
    for (int k = 0; k < 3; ++k) {
      const int g = topo.face_faces(f, k);
      if (g < 0) continue;
      const Eigen::Vector3d xl =
          X.row(c.plate.F(g, (topo.face_faces_edge(f, k) + 2) % 3)).transpose();
      const Eigen::Vector3d e = x[(k + 1) % 3] - x[k];
      const double phi = hinge_bending_measure(x[k], x[(k + 1) % 3], x[(k + 2) % 3], xl);
      const double theta = phi * e.norm() / (2 * area);
      const Eigen::Vector3d tau = n.cross(e).normalized();
      shape += theta * e.norm() / (2 * area) * tau * tau.transpose();
      const Eigen::Vector2d rest_edge = p[(k + 1) % 3] - p[k];
      const Eigen::Vector2d m = Eigen::Vector2d(rest_edge.y(), -rest_edge.x()).normalized();
      b_fast += phi * m * m.transpose() * rest_edge.squaredNorm() / (4 * rest_area * rest_area);
    }
    const Eigen::Matrix2d b_direct = deformation.transpose() * shape * deformation;
    EXPECT_LT((b_direct - b_fast).norm(), 1e-12 * (1 + b_direct.norm())) << "face " << f;
  }
}

// A 10 x 6 mm plate at rest when flat: ā = I, b̄ = 0, 1.2 mm thick.
OrthotropicRest flat_unstimulated_rest(int nf) {
  OrthotropicRest rest;
  rest.rest_first_fundamental_form.assign(nf, Eigen::Matrix2d::Identity());
  rest.rest_second_fundamental_form.assign(nf, Eigen::Matrix2d::Zero());
  rest.thickness = Eigen::VectorXd::Constant(nf, 1.2);
  rest.material_angle = Eigen::VectorXd::Constant(nf, 0.4);
  return rest;
}

TEST(PlateEnergy, ZeroAtTheRestStateOfAFlatUnstimulatedPlate) {
  const TestPlate plate = rectangle_plate(10, 6, 5, 3);
  const OrthotropicRest rest = flat_unstimulated_rest(static_cast<int>(plate.F.rows()));
  const PlateEnergy energy = make_plate_energy(plate.V, plate.F, rest, {});
  Eigen::VectorXd g;
  const double e =
      evaluate_plate_energy(energy, flatten_positions(embed(plate.V)), &g, nullptr, false);
  EXPECT_LT(e, 1e-25);
  EXPECT_LT(g.norm(), 1e-12);
}

TEST(PlateEnergy, MembraneNormMatchesEquationThreeForAUniformStretch) {
  // One triangle stretched by s along the material direction (θ = 0), ā = I: a − ā = diag(s² − 1,
  // 0), ε_M = (s² − 1, 0, 0), W = Â (t/4) C00 (s² − 1)² with C00 = E1/(1 − ν²).
  Eigen::MatrixXd V(3, 2);
  V << 0, 0, 2, 0, 0, 1;
  Eigen::MatrixXi F(1, 3);
  F << 0, 1, 2;
  OrthotropicRest rest;
  rest.rest_first_fundamental_form = {Eigen::Matrix2d::Identity()};
  rest.rest_second_fundamental_form = {Eigen::Matrix2d::Zero()};
  rest.thickness = Eigen::VectorXd::Constant(1, 0.8);
  rest.material_angle = Eigen::VectorXd::Zero(1);
  const Stiffness stiffness{10, 1, 0.4};
  const PlateEnergy energy = make_plate_energy(V, F, rest, stiffness);
  const double s = 1.3;
  Eigen::MatrixXd X = embed(V);
  X.col(0) *= s;
  const double w = evaluate_plate_energy(energy, flatten_positions(X), nullptr, nullptr, false);
  EXPECT_NEAR(w, 1.0 * 0.8 / 4 * 10 / (1 - 0.16) * std::pow(s * s - 1, 2), 1e-12);
  // Across the material direction the modulus is E2.
  rest.material_angle(0) = M_PI / 2;
  const PlateEnergy across = make_plate_energy(V, F, rest, stiffness);
  EXPECT_NEAR(evaluate_plate_energy(across, flatten_positions(X), nullptr, nullptr, false),
              1.0 * 0.8 / 4 * 1 / (1 - 0.16) * std::pow(s * s - 1, 2), 1e-12);
}

// A shape's own forms are rest forms at which it has zero energy and no force (the simulator's
// stimulus in steps starts there), and the most squeezed direction is read relative to ā.
TEST(PlateEnergy, AShapesOwnFormsAreItsRestAndTheSqueezeIsRelativeToThem) {
  RandomCase c = random_case(11, 4, 3);
  PlateEnergy energy = make_plate_energy(c.plate.V, c.plate.F, c.rest, c.stiffness);
  RestForms own = single_material_rest_forms(c.rest.rest_first_fundamental_form,
                                             c.rest.rest_second_fundamental_form, c.rest.thickness,
                                             c.rest.material_angle, c.stiffness);
  const std::vector<Vector6d> forms = plate_forms(energy, c.x);
  for (size_t f = 0; f < forms.size(); ++f) {
    own.rest_first_fundamental_form[f] << forms[f](0), forms[f](2), forms[f](2), forms[f](1);
    own.rest_second_fundamental_form[f] << forms[f](3), forms[f](5), forms[f](5), forms[f](4);
  }
  set_rest_forms(energy, own);
  Eigen::VectorXd g;
  EXPECT_LT(evaluate_plate_energy(energy, c.x, &g, nullptr, false), 1e-20);
  EXPECT_LT(g.norm(), 1e-9);
  EXPECT_NEAR(smallest_metric_ratio(energy, c.x), 1.0, 1e-12);
  // The flat plate squeezed to half its length along x and stretched by 2 along y, against ā = I:
  // the squared stretches are 1/4 and 4.
  const TestPlate plate = rectangle_plate(10, 6, 5, 3);
  const int nf = static_cast<int>(plate.F.rows());
  OrthotropicRest rest = flat_unstimulated_rest(nf);
  Eigen::MatrixXd X = embed(plate.V);
  X.col(0) *= 0.5;
  X.col(1) *= 2;
  const PlateEnergy flat = make_plate_energy(plate.V, plate.F, rest, {});
  EXPECT_NEAR(smallest_metric_ratio(flat, flatten_positions(X)), 0.25, 1e-12);
  // ā = diag(1/4, 1): the same shape is at rest along x.
  rest.rest_first_fundamental_form.assign(nf, Eigen::Vector2d(0.25, 1).asDiagonal());
  const PlateEnergy shrunk = make_plate_energy(plate.V, plate.F, rest, {});
  EXPECT_NEAR(smallest_metric_ratio(shrunk, flatten_positions(X)), 1.0, 1e-12);
}

TEST(PlateEnergy, ProjectedHessianIsPositiveSemiDefinite) {
  const RandomCase c = random_case(4, 3, 2);
  const PlateEnergy energy = make_plate_energy(c.plate.V, c.plate.F, c.rest, c.stiffness);
  Eigen::SparseMatrix<double> exact, projected;
  evaluate_plate_energy(energy, c.x, nullptr, &exact, false);
  evaluate_plate_energy(energy, c.x, nullptr, &projected, true);
  const Eigen::MatrixXd he = dense_symmetric(exact);
  const Eigen::MatrixXd hp = dense_symmetric(projected);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ee(he), ep(hp);
  EXPECT_LT(ee.eigenvalues().minCoeff(), -1e-3);  // the random state is far from equilibrium
  EXPECT_GE(ep.eigenvalues().minCoeff(), -1e-9 * ep.eigenvalues().maxCoeff());
}

TEST(PlateEnergy, DeterministicBitForBit) {
  const RandomCase c = random_case(6, 12, 10);
  const PlateEnergy energy = make_plate_energy(c.plate.V, c.plate.F, c.rest, c.stiffness);
  Eigen::VectorXd g1, g2;
  Eigen::SparseMatrix<double> h1, h2;
  const double e1 = evaluate_plate_energy(energy, c.x, &g1, &h1, false);
  const double e2 = evaluate_plate_energy(energy, c.x, &g2, &h2, false);
  EXPECT_EQ(e1, e2);
  EXPECT_TRUE((g1.array() == g2.array()).all());
  EXPECT_TRUE(std::equal(h1.valuePtr(), h1.valuePtr() + h1.nonZeros(), h2.valuePtr()));
}

TEST(PlateEnergy, ClockwisePlateFacesAreUserErrors) {
  TestPlate plate = rectangle_plate(4, 4, 2, 2);
  OrthotropicRest rest;
  const int nf = static_cast<int>(plate.F.rows());
  rest.rest_first_fundamental_form.assign(nf, Eigen::Matrix2d::Identity());
  rest.rest_second_fundamental_form.assign(nf, Eigen::Matrix2d::Zero());
  rest.thickness = Eigen::VectorXd::Constant(nf, 1.0);
  rest.material_angle = Eigen::VectorXd::Zero(nf);
  EXPECT_NO_THROW(make_plate_energy(plate.V, plate.F, rest, {}));
  plate.V.col(0) *= -1;  // mirrored: every face is clockwise
  EXPECT_THROW(make_plate_energy(plate.V, plate.F, rest, {}), UserError);
}

}  // namespace
}  // namespace flatmorph::plate_energy_test
