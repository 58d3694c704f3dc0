// GCC 12 reports a false "may be used uninitialized" inside Eigen 3.4's tridiagonalization (the
// eigen-decompositions below); the warning is about Eigen's code, not this file's.
#if !defined(__clang__)  // clang has no such warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "simulate/simulate.h"

#include <gtest/gtest.h>

#include <iostream>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/QR>
#include <cmath>

#include "common/error.h"
#include "plate/laminate.h"
#include "plate/layer_stack.h"
#include "plate/plate_fixtures.h"
#include "simulate/distance.h"
#include "simulate/shape_fits.h"

namespace flatmorph::simulate_test {
namespace {

using testing::disk_plate;
using testing::embed;
using testing::rectangle_plate;
using testing::TestPlate;

constexpr int kLayers = 10;  // the paper's 10 x 0.08 mm plates

PlateProblem shrink_morph_problem(const TestPlate& plate, const Eigen::VectorXd& theta1,
                                  const Eigen::VectorXd& theta2, const Material& m) {
  PlateProblem p;
  p.plate = plate.V;
  p.F = plate.F;
  p.rest_forms = laminate(shrink_morph_layer_stack(theta1, theta2, m, kLayers, m.layer_height));
  return p;
}

Eigen::MatrixXd face_centroids(const TestPlate& plate) {
  Eigen::MatrixXd c(plate.F.rows(), 2);
  for (int f = 0; f < plate.F.rows(); ++f) {
    c.row(f) =
        (plate.V.row(plate.F(f, 0)) + plate.V.row(plate.F(f, 1)) + plate.V.row(plate.F(f, 2))) / 3;
  }
  return c;
}

Eigen::Vector3d face_normal(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, int f) {
  const Eigen::Vector3d a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
  return (b - a).cross(c - a).normalized();
}

using testing::fitted_circle_curvature;

// The second fundamental form at a point of a shape, from a least-squares quadric fit of the
// height over the tangent plane (normal n) of the vertices within `radius` of `origin`:
// h ≈ c + g·p + ½ pᵀ H p, with p in the basis (t1, t2) of the plane. H > 0 along a direction where
// the surface bends toward n.
Eigen::Matrix2d height_hessian(const Eigen::MatrixXd& X, const Eigen::Vector3d& origin,
                               const Eigen::Vector3d& n, const Eigen::Vector3d& t1, double radius) {
  const Eigen::Vector3d t2 = n.cross(t1);
  std::vector<Eigen::Matrix<double, 1, 6>> rows;
  std::vector<double> heights;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    const Eigen::Vector3d d = X.row(v).transpose() - origin;
    const double x = d.dot(t1), y = d.dot(t2);
    if (x * x + y * y > radius * radius) continue;
    rows.push_back(
        (Eigen::Matrix<double, 1, 6>() << 1, x, y, 0.5 * x * x, x * y, 0.5 * y * y).finished());
    heights.push_back(d.dot(n));
  }
  Eigen::MatrixXd A(rows.size(), 6);
  Eigen::VectorXd h(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    A.row(i) = rows[i];
    h(i) = heights[i];
  }
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(h);
  Eigen::Matrix2d H;
  H << c(3), c(4), c(4), c(5);
  return H;
}

// Σ (2π − Σ corner angles) over the interior vertices within `radius` of the plate's origin: the
// integrated Gaussian curvature there.
double central_angle_defect(const Eigen::MatrixXd& X, const TestPlate& plate, double radius) {
  Eigen::VectorXd angle_sum = Eigen::VectorXd::Zero(X.rows());
  for (int f = 0; f < plate.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = X.row(plate.F(f, k)), b = X.row(plate.F(f, (k + 1) % 3)),
                            c = X.row(plate.F(f, (k + 2) % 3));
      angle_sum(plate.F(f, k)) += std::acos((b - a).normalized().dot((c - a).normalized()));
    }
  }
  double defect = 0;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    if (plate.V.row(v).norm() <= radius) defect += 2 * M_PI - angle_sum(v);
  }
  return defect;
}

// The second fundamental form of a shape at the plate's origin (a vertex there), in the frame of
// the plate's x direction and the mean normal of the faces around it.
Eigen::Matrix2d hessian_at_origin(const Eigen::MatrixXd& X, const TestPlate& plate, double radius) {
  int centre = 0;
  for (Eigen::Index v = 0; v < plate.V.rows(); ++v) {
    if (plate.V.row(v).norm() < plate.V.row(centre).norm()) centre = static_cast<int>(v);
  }
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (int f = 0; f < plate.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (plate.F(f, k) == centre) n += face_normal(X, plate.F, f);
    }
  }
  n.normalize();
  const Eigen::Vector3d t1 = (Eigen::Vector3d::UnitX() - n.x() * n).normalized();
  return height_hessian(X, X.row(centre).transpose(), n, t1, radius);
}

Material no_bilayer(Material m) {
  m.delta_lambda1 = 0;
  return m;
}

TEST(Simulate, NoStimulusStaysFlatWithZeroEnergy) {
  Material m;
  m.lambda1 = m.lambda2 = 1.0;
  m.delta_lambda1 = 0;
  const TestPlate plate = rectangle_plate(30, 20, 15, 10);
  const int nf = static_cast<int>(plate.F.rows());
  const PlateProblem problem =
      shrink_morph_problem(plate, Eigen::VectorXd::Constant(nf, 0.3), Eigen::VectorXd::Zero(nf), m);
  const SimulationResult flat = simulate(problem, flat_start(problem));
  ASSERT_TRUE(flat.converged) << to_string(flat.status);
  EXPECT_LT(flat.energy, 1e-20);
  EXPECT_LT((flat.V - embed(plate.V)).cwiseAbs().maxCoeff(), 1e-12);
  // From a bumpy start it relaxes back to a flat, undistorted plate (up to a rigid motion).
  Eigen::MatrixXd bumpy = embed(plate.V);
  for (Eigen::Index v = 0; v < bumpy.rows(); ++v) {
    bumpy(v, 2) = 0.5 * std::sin(plate.V(v, 0) / 5) * std::cos(plate.V(v, 1) / 7);
  }
  const SimulationResult relaxed = simulate(problem, bumpy);
  ASSERT_TRUE(relaxed.converged) << to_string(relaxed.status);
  EXPECT_LT(relaxed.energy, 1e-9);  // from about 10 at the start
  const ShapeDistance d =
      shape_distance(rigidly_aligned(relaxed.V, embed(plate.V)), embed(plate.V));
  EXPECT_LT(d.max_mm, 1e-5);
}

TEST(Simulate, UniformIsotropicShrinkStaysFlatAndScales) {
  Material m;
  m.lambda1 = m.lambda2 = 0.8;
  m.delta_lambda1 = 0;
  const TestPlate plate = disk_plate(15, 8);
  const int nf = static_cast<int>(plate.F.rows());
  const Eigen::VectorXd theta1 = face_centroids(plate).col(1) * 0.1;  // any directions
  const PlateProblem problem = shrink_morph_problem(plate, theta1, Eigen::VectorXd::Zero(nf), m);
  const SimulationResult r = simulate(problem, flat_start(problem));
  ASSERT_TRUE(r.converged) << to_string(r.status);
  EXPECT_LT(r.energy, 1e-10);  // from about 4000 at the start
  const Eigen::MatrixXd expected = 0.8 * embed(plate.V);
  const ShapeDistance d = shape_distance(rigidly_aligned(r.V, expected), expected);
  EXPECT_LT(d.max_mm, 1e-6);
  EXPECT_LT(r.V.col(2).cwiseAbs().maxCoeff(), 1e-6);  // still in the plate's plane
}

// The paper's calibration strips (§4.2): 80 x 20 mm, paths along the length, bilayer term only.
// Eq. 17-18: b = b̄ gives κ = −Δλ1/(h λ3 λ1), h the printed thickness.
TEST(Simulate, BilayerStripCurlsIntoTheCalibratedArc) {
  const Material m;  // paper PLA, Δλ1 < 0: the top shrinks more
  const TestPlate plate = rectangle_plate(80, 20, 80, 20);
  const int nf = static_cast<int>(plate.F.rows());
  const PlateProblem problem =
      shrink_morph_problem(plate, Eigen::VectorXd::Zero(nf), Eigen::VectorXd::Zero(nf), m);
  const SimulationResult r = simulate(problem, flat_start(problem));
  ASSERT_TRUE(r.converged) << to_string(r.status);
  const double h = kLayers * m.layer_height;
  const double expected = -m.delta_lambda1 / (h * m.lambda3 * m.lambda1);
  // The centreline y = 0, away from the ends where the boundary faces have no hinge.
  std::vector<int> centre;
  for (Eigen::Index v = 0; v < plate.V.rows(); ++v) {
    if (std::abs(plate.V(v, 1)) < 1e-9 && std::abs(plate.V(v, 0)) < 35) centre.push_back(v);
  }
  Eigen::MatrixXd P(centre.size(), 3);
  for (size_t i = 0; i < centre.size(); ++i) P.row(i) = r.V.row(centre[i]);
  Eigen::Vector3d circle_center;
  const double kappa = fitted_circle_curvature(P, circle_center);
  RecordProperty("strip_curvature", std::to_string(kappa));
  EXPECT_NEAR(kappa, expected, 0.03 * expected) << "expected " << expected;
  // Concave on the top (+n) side: the centre of the circle is on the side the normals point to.
  int middle_face = -1;
  for (int f = 0; f < nf && middle_face < 0; ++f) {
    for (int k = 0; k < 3; ++k) {
      if (plate.V.row(plate.F(f, k)).norm() < 1e-9) middle_face = f;
    }
  }
  const Eigen::Vector3d n = face_normal(r.V, plate.F, middle_face);
  const Eigen::Vector3d mid = r.V.row(plate.F(middle_face, 0)).transpose();
  EXPECT_GT((circle_center - mid).dot(n), 0.9 / kappa);
  // Reversing the gradient (the bed side shrinks more) curls it the other way.
  Material flipped = m;
  flipped.delta_lambda1 = -m.delta_lambda1;
  const PlateProblem down =
      shrink_morph_problem(plate, Eigen::VectorXd::Zero(nf), Eigen::VectorXd::Zero(nf), flipped);
  const SimulationResult rd = simulate(down, flat_start(down));
  for (size_t i = 0; i < centre.size(); ++i) P.row(i) = rd.V.row(centre[i]);
  EXPECT_NEAR(fitted_circle_curvature(P, circle_center), expected, 0.03 * expected);
  const Eigen::Vector3d nd = face_normal(rd.V, plate.F, middle_face);
  EXPECT_LT((circle_center - rd.V.row(plate.F(middle_face, 0)).transpose()).dot(nd), 0.0);
}

// The curvature of the centreline y = 0 of a simulated rectangle plate, over |x - centre| < half.
double centreline_curvature(const TestPlate& plate, const Eigen::MatrixXd& V, double centre,
                            double half) {
  std::vector<int> line;
  for (Eigen::Index v = 0; v < plate.V.rows(); ++v) {
    if (std::abs(plate.V(v, 1)) < 1e-9 && std::abs(plate.V(v, 0) - centre) < half) {
      line.push_back(static_cast<int>(v));
    }
  }
  Eigen::MatrixXd P(line.size(), 3);
  for (size_t i = 0; i < line.size(); ++i) P.row(i) = V.row(line[i]);
  Eigen::Vector3d circle_center;
  return fitted_circle_curvature(P, circle_center);
}

// One PLA layer on one TPU layer (the acceptance check of the laminate's stiffness): PLA 14 times
// stiffer, shrinking isotropically by 0.1 %, TPU not at all, equally thick. Small against its
// curvature radius, the plate takes the free bilayer curvature of Timoshenko (1925),
// κ = 6 Δε (1 + m)² / (h (3 (1 + m)² + (1 + m n)(m² + 1/(m n)))), m = 1, n = 14.
TEST(Simulate, PlaOnTpuBilayerBendsToTimoshenkosCurvature) {
  const TestPlate plate = rectangle_plate(20, 20, 20, 20);
  const int nf = static_cast<int>(plate.F.rows());
  LayerStack stack = testing::pla_on_tpu_bilayer(nf, 0.999);
  PlateProblem p;
  p.plate = plate.V;
  p.F = plate.F;
  p.rest_forms = laminate(stack);
  const SimulationResult r = simulate(p, flat_start(p));
  ASSERT_TRUE(r.converged) << to_string(r.status);
  const double strain = 0.001, h = 1.0;
  const double expected = testing::timoshenko_curvature(1, 14, h, strain);
  const double kappa = centreline_curvature(plate, r.V, 0, 8);
  RecordProperty("bilayer_curvature", std::to_string(kappa));
  EXPECT_NEAR(kappa, expected, 0.05 * expected) << "Timoshenko " << expected;
  // With equal stiffness the same mismatch bends it 1.5 / 0.855 times more (n = 1): the stiffness
  // ratio is what the laminate reads.
  stack.materials[1] = stack.materials[0];
  stack.materials[1].lambda1 = stack.materials[1].lambda2 = 1.0;
  stack.layers[0] = uniform_layer(nf, 1, stack.materials[1], 0.5);
  p.rest_forms = laminate(stack);
  const SimulationResult equal = simulate(p, flat_start(p));
  const double kappa_equal = centreline_curvature(plate, equal.V, 0, 8);
  EXPECT_NEAR(kappa_equal, 1.5 * strain / h, 0.05 * 1.5 * strain / h);
}

// A plate whose left half has 6 layers and right half 10 (the top 4 layers cover only x > 0) is
// an ordinary stack: each half curls into its own laminate's curvature.
TEST(Simulate, PlateOfSixLayersOnTheLeftAndTenOnTheRight) {
  const Material m;  // paper PLA: the top shrinks more
  const TestPlate plate = rectangle_plate(120, 10, 120, 10);
  const int nf = static_cast<int>(plate.F.rows());
  LayerStack stack = shrink_morph_layer_stack(Eigen::VectorXd::Zero(nf), Eigen::VectorXd::Zero(nf),
                                              m, 10, m.layer_height);
  int left_face = -1, right_face = -1;
  for (int f = 0; f < nf; ++f) {
    const double x =
        (plate.V(plate.F(f, 0), 0) + plate.V(plate.F(f, 1), 0) + plate.V(plate.F(f, 2), 0)) / 3;
    if (x > 0) {
      right_face = f;
      continue;
    }
    left_face = f;
    for (int k = 6; k < 10; ++k) stack.layers[k].material(f) = Layer::kNotCovered;
  }
  PlateProblem p;
  p.plate = plate.V;
  p.F = plate.F;
  p.rest_forms = laminate(stack);
  EXPECT_NEAR(p.rest_forms.thickness(left_face), 0.6 * p.rest_forms.thickness(right_face), 1e-12);
  const SimulationResult r = simulate(p, flat_start(p));
  ASSERT_TRUE(r.converged) << to_string(r.status);
  const double left = centreline_curvature(plate, r.V, -30, 20);
  const double right = centreline_curvature(plate, r.V, 30, 20);
  // b̄ is pulled back to the plate: the 3D curvature along x is b̄_xx / ā_xx.
  auto rest_curvature = [&](int f) {
    return p.rest_forms.rest_second_fundamental_form[f](0, 0) /
           p.rest_forms.rest_first_fundamental_form[f](0, 0);
  };
  const double left_rest = rest_curvature(left_face), right_rest = rest_curvature(right_face);
  EXPECT_NEAR(left, left_rest, 0.05 * left_rest);
  EXPECT_NEAR(right, right_rest, 0.05 * right_rest);
  std::cout << "6 | 10 layers: curvature " << left << " | " << right << " /mm (rest " << left_rest
            << " | " << right_rest << ")\n";
}

TEST(Simulate, TangentialPathsMakeADomeRadialPathsDoNot) {
  const Material m;
  const TestPlate plate = disk_plate(30, 15);
  const Eigen::MatrixXd c = face_centroids(plate);
  const int nf = static_cast<int>(plate.F.rows());
  Eigen::VectorXd radial(nf), tangential(nf);
  for (int f = 0; f < nf; ++f) {
    radial(f) = std::atan2(c(f, 1), c(f, 0));
    tangential(f) = radial(f) + M_PI / 2;
  }
  const PlateProblem dome = shrink_morph_problem(plate, tangential, Eigen::VectorXd::Zero(nf), m);
  const PlateProblem cone = shrink_morph_problem(plate, radial, Eigen::VectorXd::Zero(nf), m);
  const SimulationResult rd = simulate(dome, flat_start(dome));
  const SimulationResult rc = simulate(cone, flat_start(cone));
  EXPECT_TRUE(rd.converged) << to_string(rd.status);
  EXPECT_TRUE(rc.converged) << to_string(rc.status);
  // Integrated Gaussian curvature (angle defect) within 6 mm of the centre.
  const double k_dome = central_angle_defect(rd.V, plate, 6.0);
  const double k_cone = central_angle_defect(rc.V, plate, 6.0);
  RecordProperty("dome_central_angle_defect", std::to_string(k_dome));
  RecordProperty("radial_central_angle_defect", std::to_string(k_cone));
  EXPECT_GT(k_dome, 0.1);
  EXPECT_LT(k_cone, 0.0);
  // The dome's principal curvatures at the centre are both positive (concave on top, Δλ1 < 0).
  const Eigen::Vector3d n = face_normal(rd.V, plate.F, 0);
  const Eigen::Vector3d t1 = (Eigen::Vector3d::UnitX() - n.x() * n).normalized();
  const Eigen::Matrix2d H = height_hessian(rd.V, rd.V.row(0).transpose(), n, t1, 6.0);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(H);
  EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
}

// A disk of the paper's PLA (10 layers) printed along its radii, on a mesh of 1 mm edges: the
// paths shrink (λ1) and the circles across them grow (λ2), so the rest metric is a cone of angle
// 2π λ2/λ1 at the centre, 2π (λ2/λ1 − 1) more than the plane has. The plate takes that excess by
// buckling into a wavy saddle: its total Gaussian curvature, the angle defects of the interior
// vertices, is the cone's 2π (1 − λ2/λ1) = −5.42 (a dome would be positive, a flat plate 0).
// Solved at once from flat, the first in-plane steps squeeze the circles past the point where the
// membrane energy softens, the faces collapse and the plate creases (the 80 mm disk crawled for
// 1000 iterations): the stimulus goes on in steps.
void expect_radial_disk_saddle(double diameter) {
  const double radius = diameter / 2;
  const TestPlate plate = disk_plate(radius, static_cast<int>(radius));
  const Eigen::MatrixXd c = face_centroids(plate);
  const int nf = static_cast<int>(plate.F.rows());
  Eigen::VectorXd radial(nf);
  for (int f = 0; f < nf; ++f) radial(f) = std::atan2(c(f, 1), c(f, 0));
  const Material m;
  const PlateProblem p = shrink_morph_problem(plate, radial, Eigen::VectorXd::Zero(nf), m);
  const SimulationResult r = simulate(p, flat_start(p));
  ASSERT_TRUE(r.converged) << r.warning;
  EXPECT_EQ(stop_reason(r), "converged");
  EXPECT_GT(r.stimulus_steps, 1);
  const double curvature = central_angle_defect(r.V, plate, radius - 0.5);  // interior vertices
  const double cone = 2 * M_PI * (1 - m.lambda2 / m.lambda1);
  ::testing::Test::RecordProperty("total_gaussian_curvature", std::to_string(curvature));
  ::testing::Test::RecordProperty("newton_iterations", std::to_string(r.iterations));
  EXPECT_NEAR(curvature, cone, 0.1 * std::abs(cone));
}

TEST(Simulate, RadialDiskOf20MmBucklesIntoNegativeCurvature) { expect_radial_disk_saddle(20); }
TEST(Simulate, RadialDiskOf40MmBucklesIntoNegativeCurvature) { expect_radial_disk_saddle(40); }

// The budgets: a solve stopped by either returns the best finite state it reached and says why.
TEST(Simulate, ABudgetStopReturnsTheBestFiniteStateAndSaysWhy) {
  const TestPlate plate = disk_plate(10, 10);
  const Eigen::MatrixXd c = face_centroids(plate);
  const int nf = static_cast<int>(plate.F.rows());
  Eigen::VectorXd radial(nf);
  for (int f = 0; f < nf; ++f) radial(f) = std::atan2(c(f, 1), c(f, 0));
  const PlateProblem p = shrink_morph_problem(plate, radial, Eigen::VectorXd::Zero(nf), Material{});
  SimulationOptions none;
  none.max_iterations = 0;
  const double start_energy = simulate(p, flat_start(p), none).energy;
  SimulationOptions two;
  two.max_iterations = 2;
  const SimulationResult r = simulate(p, flat_start(p), two);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.status, NewtonStatus::kIterationLimit);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_TRUE(r.V.allFinite());
  EXPECT_LT(r.energy, 0.1 * start_energy);
  EXPECT_NE(r.warning.find("did not converge in 2 iterations"), std::string::npos) << r.warning;
  EXPECT_EQ(stop_reason(r), r.warning);
  SimulationOptions no_time;
  no_time.max_seconds = 0;
  const SimulationResult t = simulate(p, flat_start(p), no_time);
  EXPECT_EQ(t.status, NewtonStatus::kTimeLimit);
  EXPECT_LT((t.V - flat_start(p)).cwiseAbs().maxCoeff(), 1e-9);  // the start: nothing better
  EXPECT_NE(t.warning.find("time budget of 0 s"), std::string::npos) << t.warning;
}

// θ1 = 0 and a uniform θ2 > 0: the top layer runs at +θ2/2, the bottom one at −θ2/2. Along the
// diagonal (1, 1) the top's rest metric is the smaller (it shrinks more), along (1, −1) the
// bottom's: the top must be concave along (1, 1) and convex along (1, −1). Small plate, small θ2:
// the linear regime where the twist is the only stable shape.
TEST(Simulate, ThetaTwoTwistsTheWayTheShrinkingLayerSays) {
  const Material m = no_bilayer(Material{});
  const TestPlate plate = rectangle_plate(10, 10, 16, 16);
  const int nf = static_cast<int>(plate.F.rows());
  auto run = [&](double theta2) {
    const PlateProblem p = shrink_morph_problem(plate, Eigen::VectorXd::Zero(nf),
                                                Eigen::VectorXd::Constant(nf, theta2), m);
    const SimulationResult r = simulate(p, flat_start(p));
    EXPECT_TRUE(r.converged) << to_string(r.status);
    return r;
  };
  const SimulationResult up = run(0.05), down = run(-0.05);
  for (const auto& [r, sign] : {std::pair{&up, 1.0}, std::pair{&down, -1.0}}) {
    const Eigen::Matrix2d H = hessian_at_origin(r->V, plate, 3.0);
    const Eigen::Vector2d d1(1, 1), d2(1, -1);
    const double along_11 = d1.dot(H * d1) / 2, along_1m1 = d2.dot(H * d2) / 2;
    EXPECT_GT(sign * along_11, 0.0);
    EXPECT_LT(sign * along_1m1, 0.0);
    EXPECT_GT(std::abs(H(0, 1)), 5 * std::max(std::abs(H(0, 0)), std::abs(H(1, 1))));
  }
  // Flipping θ2 gives the mirror image (z → −z, i.e. b → −b).
  Eigen::MatrixXd mirrored = up.V;
  mirrored.col(2) *= -1;
  const ShapeDistance d = shape_distance(rigidly_aligned(down.V, mirrored), mirrored);
  EXPECT_LT(d.max_percent, 1e-4);
}

// Paper Fig. 12: a plate shaped like an ellipse squished at its poles, printed in concentric
// paths, deploys into a pinched hemisphere with E1/E2 = 10 and a near-constant-curvature dome with
// E1 = E2. The plate: the unit disk mapped by (u, v) -> (a u, b v (1 − s u²)), paths along the
// images of the concentric circles.
TEST(Simulate, OrthotropyChangesTheShapeOfTheSquishedEllipse) {
  const double a = 40, b = 32, s = 0.3;
  TestPlate plate = disk_plate(1.0, 14);
  const Eigen::MatrixXd uv = plate.V;
  for (Eigen::Index v = 0; v < plate.V.rows(); ++v) {
    const double u = uv(v, 0), w = uv(v, 1);
    plate.V.row(v) << a * u, b * w * (1 - s * u * u);
  }
  const int nf = static_cast<int>(plate.F.rows());
  Eigen::VectorXd theta1(nf);
  for (int f = 0; f < nf; ++f) {
    const Eigen::RowVector2d c =
        (uv.row(plate.F(f, 0)) + uv.row(plate.F(f, 1)) + uv.row(plate.F(f, 2))) / 3;
    Eigen::Matrix2d jacobian;
    jacobian << a, 0, -2 * b * s * c(0) * c(1), b * (1 - s * c(0) * c(0));
    const Eigen::Vector2d tangent = jacobian * Eigen::Vector2d(-c(1), c(0));
    theta1(f) = std::atan2(tangent.y(), tangent.x());
  }
  // Principal curvatures from a quadric fit over the central 15 mm (the dome, not just its apex).
  auto simulate_with = [&](double e1_over_e2, Eigen::Vector2d& curvatures) {
    Material m;
    m.young_modulus_along = e1_over_e2;
    m.young_modulus_across = 1;
    const PlateProblem p = shrink_morph_problem(plate, theta1, Eigen::VectorXd::Zero(nf), m);
    const SimulationResult r = simulate(p, flat_start(p));
    EXPECT_TRUE(r.converged) << to_string(r.status);
    const Eigen::Vector3d n = face_normal(r.V, plate.F, 0);
    const Eigen::Vector3d t1 = (Eigen::Vector3d::UnitX() - n.x() * n).normalized();
    const Eigen::Matrix2d H = height_hessian(r.V, r.V.row(0).transpose(), n, t1, 15.0);
    curvatures = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(H).eigenvalues();
    return r.V;
  };
  Eigen::Vector2d iso, ortho;
  const Eigen::MatrixXd shape_iso = simulate_with(1, iso);
  const Eigen::MatrixXd shape_ortho = simulate_with(10, ortho);
  const double ratio_iso = iso(1) / iso(0), ratio_ortho = ortho(1) / ortho(0);
  const ShapeDistance apart = shape_distance(rigidly_aligned(shape_ortho, shape_iso), shape_iso);
  RecordProperty("principal_curvature_ratio_E1_E2_1", std::to_string(ratio_iso));
  RecordProperty("principal_curvature_ratio_E1_E2_10", std::to_string(ratio_ortho));
  std::printf(
      "Fig. 12 ellipse, principal curvatures over the central 15 mm (1/mm): E1/E2 = 1: "
      "%.4f %.4f (ratio %.3f); E1/E2 = 10: %.4f %.4f (ratio %.3f); shapes %.1f %% of the "
      "diagonal apart\n",
      iso(0), iso(1), ratio_iso, ortho(0), ortho(1), ratio_ortho, apart.max_percent);
  EXPECT_GT(iso(0), 0.0);  // both domes
  EXPECT_GT(ortho(0), 0.0);
  EXPECT_GT(std::abs(ratio_ortho - ratio_iso), 0.1 * ratio_iso);
  EXPECT_GT(apart.max_percent, 2.0);
}

// Invariances hold to the solver's accuracy: solve tightly so that they show at 1e-4 % of the size.
SimulationOptions tight() {
  SimulationOptions o;
  o.relative_tolerance = 1e-16;
  return o;
}

// A design that is neither symmetric nor uniform, for the invariance tests: θ1, θ2 per face.
void asymmetric_design(const TestPlate& plate, Eigen::VectorXd& theta1, Eigen::VectorXd& theta2) {
  const Eigen::MatrixXd c = face_centroids(plate);
  const int nf = static_cast<int>(plate.F.rows());
  theta1.resize(nf);
  theta2.resize(nf);
  for (int f = 0; f < nf; ++f) {
    theta1(f) = 0.4 + 0.03 * c(f, 0) - 0.02 * c(f, 1);
    theta2(f) = 0.3 * std::sin(0.2 * c(f, 0) + 0.1 * c(f, 1));
  }
}

PlateProblem asymmetric_problem(const TestPlate& plate) {
  Eigen::VectorXd theta1, theta2;
  asymmetric_design(plate, theta1, theta2);
  return shrink_morph_problem(plate, theta1, theta2, Material{});
}

// The rest forms are rebuilt from θ1 + α (not rotated as tensors), so this also checks that the
// rest curvature lives in the plate frame (docs/conventions.md: no extra rotation by θ1).
TEST(Simulate, RotatingTheDesignRotatesTheShape) {
  const TestPlate plate = rectangle_plate(24, 16, 12, 8);
  Eigen::VectorXd theta1, theta2;
  asymmetric_design(plate, theta1, theta2);
  const double alpha = 0.7;
  const Eigen::Matrix2d rot = rotation(alpha);
  TestPlate rotated = plate;
  rotated.V = plate.V * rot.transpose();
  const PlateProblem p = shrink_morph_problem(plate, theta1, theta2, Material{});
  const PlateProblem q =
      shrink_morph_problem(rotated, (theta1.array() + alpha).matrix(), theta2, Material{});
  const SimulationResult rp = simulate(p, flat_start(p), tight());
  const SimulationResult rq = simulate(q, flat_start(q), tight());
  ASSERT_TRUE(rp.converged && rq.converged);
  Eigen::Matrix3d rot3 = Eigen::Matrix3d::Identity();
  rot3.topLeftCorner<2, 2>() = rot;
  const Eigen::MatrixXd expected = rp.V * rot3.transpose();
  const ShapeDistance d = shape_distance(rq.V, expected);
  EXPECT_LT(d.max_percent, 1e-4) << d.max_mm << " mm";
  EXPECT_NEAR(rp.energy, rq.energy, 1e-9 * rp.energy);
}

TEST(Simulate, MirroringTheDesignMirrorsTheShape) {
  const TestPlate plate = rectangle_plate(24, 16, 12, 8);
  Eigen::VectorXd theta1, theta2;
  asymmetric_design(plate, theta1, theta2);
  // x -> −x, faces reversed to stay counter-clockwise, θ1 -> π − θ1, θ2 -> −θ2: the face at the
  // mirrored centroid carries the mirrored design.
  TestPlate mirror = plate;
  mirror.V.col(0) *= -1;
  mirror.F.col(1).swap(mirror.F.col(2));
  const Material m;
  const PlateProblem p = shrink_morph_problem(plate, theta1, theta2, m);
  const PlateProblem q = shrink_morph_problem(mirror, (M_PI - theta1.array()).matrix(), -theta2, m);
  const SimulationResult rp = simulate(p, flat_start(p), tight());
  const SimulationResult rq = simulate(q, flat_start(q), tight());
  ASSERT_TRUE(rp.converged && rq.converged);
  Eigen::MatrixXd expected = rp.V;
  expected.col(0) *= -1;
  const ShapeDistance d = shape_distance(rigidly_aligned(rq.V, expected), expected);
  EXPECT_LT(d.max_percent, 1e-4) << d.max_mm << " mm";
  EXPECT_NEAR(rp.energy, rq.energy, 1e-9 * rp.energy);
  // The mirror is not a rotation: the shape is chiral (θ2 twists), so without mirroring it differs.
  const ShapeDistance unmirrored = shape_distance(rigidly_aligned(rq.V, rp.V), rp.V);
  EXPECT_GT(unmirrored.max_percent, 0.1);
}

TEST(Simulate, StartingFromTheEquilibriumStaysThere) {
  const TestPlate plate = rectangle_plate(24, 16, 12, 8);
  const PlateProblem p = asymmetric_problem(plate);
  const SimulationResult first = simulate(p, flat_start(p), tight());
  ASSERT_TRUE(first.converged);
  // Started on the equilibrium, it stays there, registered to the start (no rigid drift).
  const SimulationResult again = simulate(p, first.V, tight());
  EXPECT_TRUE(again.converged);
  EXPECT_LE(again.iterations, 1);
  EXPECT_LT(shape_distance(again.V, first.V).max_percent, 1e-6);
  // Started near it (as from a target), it finds it again: same shape as from flat.
  Eigen::MatrixXd perturbed = first.V;
  for (Eigen::Index v = 0; v < perturbed.rows(); ++v) {
    perturbed.row(v) +=
        0.05 * Eigen::RowVector3d(std::sin(v), std::cos(3.0 * v), std::sin(7.0 * v));
  }
  const ForwardComparison both = simulate_from_start_and_flat(p, perturbed, tight());
  EXPECT_TRUE(both.from_start.converged);
  EXPECT_TRUE(both.from_flat.converged);
  EXPECT_FALSE(both.multistable);
  EXPECT_LT(both.max_difference_percent, 1e-4);
}

// A cross-ply plate (5 layers along x on the bed, 5 along y on top) wants a saddle: b̄_xx < 0 <
// b̄_yy. Large and thin, it cannot take both curvatures and snaps into one of two cylinders (the
// classic bistable laminate): concave on top along y, or convex on top along x. Built through the
// layer stack and the laminate.
TEST(Simulate, CrossPlyPlateIsBistableAndTheComparisonSaysSo) {
  Material m;
  m.lambda1 = 0.98;  // a weak stimulus keeps the curvature radius (41 mm) near the plate's size
  m.lambda2 = 1.0;
  m.delta_lambda1 = 0;
  m.young_modulus_along = m.young_modulus_across = 1.0;  // isotropic
  const TestPlate plate = rectangle_plate(100, 100, 20, 20);
  const int nf = static_cast<int>(plate.F.rows());
  LayerStack stack = shrink_morph_layer_stack(Eigen::VectorXd::Zero(nf), Eigen::VectorXd::Zero(nf),
                                              m, 10, m.layer_height);
  for (int k = 5; k < 10; ++k) stack.layers[k].theta.setConstant(M_PI / 2);
  PlateProblem p;
  p.plate = plate.V;
  p.F = plate.F;
  p.rest_forms = laminate(stack);
  ASSERT_LT(p.rest_forms.rest_second_fundamental_form[0](0, 0), 0.0);
  ASSERT_GT(p.rest_forms.rest_second_fundamental_form[0](1, 1), 0.0);
  auto cylinder = [&](int axis, double curvature) {
    Eigen::MatrixXd start = embed(plate.V);
    for (Eigen::Index v = 0; v < start.rows(); ++v) {
      start(v, 2) = 0.5 * curvature * plate.V(v, axis) * plate.V(v, axis);
    }
    return start;
  };
  const ForwardComparison along_x = simulate_from_start_and_flat(p, cylinder(0, -0.01));
  const ForwardComparison along_y = simulate_from_start_and_flat(p, cylinder(1, 0.01));
  ASSERT_TRUE(along_x.from_start.converged && along_y.from_start.converged);
  ASSERT_TRUE(along_x.from_flat.converged);
  // Two different stable shapes of the same energy (mirror images of each other).
  const ShapeDistance apart = shape_distance(
      rigidly_aligned(along_x.from_start.V, along_y.from_start.V), along_y.from_start.V);
  EXPECT_GT(apart.max_percent, 5.0);
  EXPECT_NEAR(along_x.from_start.energy, along_y.from_start.energy,
              1e-6 * along_y.from_start.energy);
  // Each is a cylinder with the sign the layers ask for.
  for (const auto& [r, axis] :
       {std::pair{&along_x.from_start, 0}, std::pair{&along_y.from_start, 1}}) {
    const Eigen::Matrix2d H = hessian_at_origin(r->V, plate, 20.0);
    const double along = H(axis, axis), across = H(1 - axis, 1 - axis);
    EXPECT_GT(std::abs(along), 5 * std::abs(across)) << "axis " << axis;
    EXPECT_GT(axis == 0 ? -along : along, 0.0) << "axis " << axis;
  }
  // The flat start ends in one of them, so one of the two comparisons reports multistability.
  EXPECT_NE(along_x.multistable, along_y.multistable);
}

TEST(Simulate, SameInputSameOutputBitForBit) {
  const TestPlate plate = rectangle_plate(24, 16, 12, 8);
  const PlateProblem p = asymmetric_problem(plate);
  const SimulationResult a = simulate(p, flat_start(p));
  const SimulationResult b = simulate(p, flat_start(p));
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.energy, b.energy);
  EXPECT_TRUE((a.V.array() == b.V.array()).all());
}

TEST(Simulate, BadStartShapesAreUserErrors) {
  const TestPlate plate = rectangle_plate(4, 4, 2, 2);
  const int nf = static_cast<int>(plate.F.rows());
  const PlateProblem p =
      shrink_morph_problem(plate, Eigen::VectorXd::Zero(nf), Eigen::VectorXd::Zero(nf), Material{});
  EXPECT_THROW(simulate(p, Eigen::MatrixXd::Zero(3, 3)), UserError);
  Eigen::MatrixXd nan_start = embed(plate.V);
  nan_start(2, 1) = std::nan("");
  EXPECT_THROW(simulate(p, nan_start), UserError);
}

TEST(ShapeDistance, MatchesHandComputedValues) {
  Eigen::MatrixXd target(3, 3), shape(3, 3);
  target << 0, 0, 0, 3, 0, 0, 0, 4, 0;  // bounding-box diagonal 5
  shape = target;
  shape(1, 2) = 1.0;
  shape(2, 0) = 0.5;
  const ShapeDistance d = shape_distance(shape, target);
  EXPECT_DOUBLE_EQ(d.diagonal_mm, 5.0);
  EXPECT_DOUBLE_EQ(d.max_mm, 1.0);
  EXPECT_DOUBLE_EQ(d.mean_mm, 0.5);
  EXPECT_DOUBLE_EQ(d.max_percent, 20.0);
  EXPECT_DOUBLE_EQ(d.mean_percent, 10.0);
  EXPECT_THROW(shape_distance(shape.topRows(2), target), UserError);
  // A rigidly moved copy aligns back onto the original.
  const Eigen::Matrix3d rot =
      Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  const Eigen::MatrixXd moved = (shape * rot.transpose()).rowwise() + Eigen::RowVector3d(5, -2, 1);
  EXPECT_LT(shape_distance(rigidly_aligned(moved, shape), shape).max_mm, 1e-12);
}

}  // namespace
}  // namespace flatmorph::simulate_test
