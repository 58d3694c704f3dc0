// Tests of the Shrink & Morph flattening (src/methods/shrink_morph/flatten.h): analytic cases
// (a developable cylinder, a plane), the paper's meshes and the built-in examples, derivatives of
// the Eq. 12 energy, invariants (rotation, flip = mirror) and the CLI (determinism, bad options).
#include "methods/shrink_morph/flatten.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

#include "common/error.h"
#include "examples/examples.h"
#include "mesh/io.h"
#include "mesh/mesh_fixtures.h"
#include "mesh/operators.h"
#include "mesh/subdivide.h"
#include "mesh/topology.h"
#include "mesh/validate.h"
#include "methods/shrink_morph/flatten_internal.h"
#include "test_support.h"

namespace flatmorph::flatten_test {
namespace {

namespace fs = std::filesystem;
using namespace shrink_morph_internal;

using testing::grid_mesh;

// Part of a cylinder of radius 40 mm: 120 degrees around, 60 mm along the axis (developable).
Mesh cylinder_patch() {
  return grid_mesh(24, 12, [](double u, double v) {
    const double angle = (u - 0.5) * 2 * kPi / 3;
    return Eigen::Vector3d(40 * std::sin(angle), 60 * v, 40 * std::cos(angle));
  });
}

// A planar patch, tilted in space, with an irregular outline and uneven triangles.
Mesh plane_patch() {
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())).toRotationMatrix();
  return grid_mesh(16, 10, [&](double u, double v) {
    const double x = 80 * u + 7 * std::sin(3 * v), y = 50 * v + 5 * u * u;
    return Eigen::Vector3d(R * Eigen::Vector3d(x, y, 0));
  });
}

Eigen::VectorXd signed_areas(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F) {
  return face_areas(plate.leftCols(2), F);
}

// A paper mesh prepared like the CLI does: repaired, checked, Loop-subdivided to `faces`.
Mesh paper_mesh(const std::string& name, int faces) {
  Mesh mesh = read_mesh(testing::shared_dir() / "meshes" / (name + ".obj")).mesh;
  repair_mesh(mesh);
  require_disk(mesh, name);
  return loop_subdivide_to(mesh, faces).mesh;
}

// The rotation angle and translation that best map `from` onto `to` (2D Kabsch, no reflection),
// and the largest remaining vertex distance.
struct RigidFit {
  double angle;
  double max_distance;
};
RigidFit rigid_fit(const Eigen::MatrixXd& from, const Eigen::MatrixXd& to) {
  const Eigen::RowVector2d cf = from.colwise().mean(), ct = to.colwise().mean();
  const Eigen::MatrixXd a = from.rowwise() - cf, b = to.rowwise() - ct;
  const Eigen::Matrix2d H = a.transpose() * b;
  const double angle = std::atan2(H(0, 1) - H(1, 0), H(0, 0) + H(1, 1));
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(angle).toRotationMatrix();
  const Eigen::MatrixXd moved = a * R.transpose();
  return {angle, (moved - b).rowwise().norm().maxCoeff()};
}

// Largest |sin(a_f - b_f - shift)|: 0 when the line fields agree up to a rotation by `shift`.
double line_field_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double shift) {
  return (a.array() - b.array() - shift).sin().abs().maxCoeff();
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The 2x2 algebra of the local step.

TEST(FlattenLocalStep, ConformalSplitGivesSignedSingularValuesAndMajorDirection) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> entry(-2, 2);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix2d J;
    J << entry(random), entry(random), entry(random), entry(random);
    const ConformalSplit split = conformal_split(J);
    const Eigen::Vector2d sv = Eigen::JacobiSVD<Eigen::Matrix2d>(J).singularValues();
    EXPECT_NEAR(split.sigma1(), sv(0), 1e-12);
    EXPECT_NEAR(std::abs(split.sigma2()), sv(1), 1e-12);
    EXPECT_EQ(split.sigma2() < 0, J.determinant() < 0);
    // beta = (arg z1 + arg z2)/2 is the plate direction J stretches most: J J^T u = sigma1^2 u.
    const double beta = 0.5 * (std::atan2(split.anticonformal_sin, split.anticonformal_cos) +
                               std::atan2(split.conformal_sin, split.conformal_cos));
    const Eigen::Vector2d u(std::cos(beta), std::sin(beta));
    EXPECT_LT((J * J.transpose() * u - sv(0) * sv(0) * u).norm(), 1e-10);
  }
}

TEST(FlattenLocalStep, TargetIsTheClosestOrientationPreservingMatrix) {
  const double s1 = 1 / 0.58, s2 = 1 / 1.08;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> entry(-2, 2);
  for (int trial = 0; trial < 40; ++trial) {
    Eigen::Matrix2d J;
    J << entry(random), entry(random), entry(random), entry(random);
    const Eigen::Matrix2d T = closest_with_singular_values(conformal_split(J), s1, s2);
    const Eigen::Vector2d sv = Eigen::JacobiSVD<Eigen::Matrix2d>(T).singularValues();
    EXPECT_NEAR(sv(0), s1, 1e-12);
    EXPECT_NEAR(sv(1), s2, 1e-12);
    EXPECT_GT(T.determinant(), 0);  // also when det J < 0: no reflection is ever asked for
    // No rotation-stretch-rotation with these singular values is closer (brute force).
    double closest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 360; ++i) {
      for (int k = 0; k < 360; ++k) {
        const Eigen::Matrix2d candidate = Eigen::Rotation2Dd(i * kPi / 180).toRotationMatrix() *
                                          Eigen::Vector2d(s1, s2).asDiagonal() *
                                          Eigen::Rotation2Dd(k * kPi / 180).toRotationMatrix();
        closest = std::min(closest, (J - candidate).norm());
      }
    }
    EXPECT_LE((J - T).norm(), closest + 1e-12);
  }
}

// Measures on known plates.

TEST(FlattenMeasures, Theta1AndSingularValuesOfAKnownLinearPlate) {
  // A plate made from a planar target by a linear map with singular values (1/lambda1,
  // 1/lambda2) whose 1/lambda1 direction is at `theta` in the plate: theta1 is that direction.
  const Mesh target = plane_patch();
  const Eigen::Vector3d e1 = (target.V.row(1) - target.V.row(0)).transpose().normalized();
  const Eigen::Vector3d n =
      e1.cross(Eigen::Vector3d((target.V.row(17) - target.V.row(0)).transpose())).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  Eigen::MatrixXd flat(target.V.rows(), 2);
  flat.col(0) = target.V * e1;
  flat.col(1) = target.V * e2;
  for (double theta : {-1.2, 0.0, 0.3, 1.5}) {
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(theta).toRotationMatrix();
    const Eigen::Matrix2d A = R * Eigen::Vector2d(1 / 0.58, 1 / 1.08).asDiagonal();
    const Eigen::MatrixXd plate = flat * A.transpose();
    const Eigen::MatrixXd sigma = plate_singular_values(target.V, target.F, plate);
    EXPECT_LT((sigma.col(0).array() - 1 / 0.58).abs().maxCoeff(), 1e-12);
    EXPECT_LT((sigma.col(1).array() - 1 / 1.08).abs().maxCoeff(), 1e-12);
    const Eigen::VectorXd theta1 = theta1_per_face(target.V, target.F, plate);
    EXPECT_LT(line_field_difference(theta1, Eigen::VectorXd::Zero(theta1.size()), theta), 1e-9);
    EXPECT_GE(theta1.minCoeff(), -kPi / 2);
    EXPECT_LT(theta1.maxCoeff(), kPi / 2);
    EXPECT_LT(shrink_deviation(sigma, 0.58, 1.08).maxCoeff(), 1e-12);
    // Off by 6 % along the path on every face: every face is out of the 5 % tolerance.
    const Eigen::VectorXd deviation = shrink_deviation(sigma, 0.58 * 1.06, 1.08);
    EXPECT_NEAR(deviation.maxCoeff(), 0.06, 1e-12);
    const ShrinkFeasibility feasibility =
        shrink_feasibility(deviation, face_areas(target.V, target.F));
    EXPECT_NEAR(feasibility.mean_deviation, 0.06, 1e-12);
    EXPECT_DOUBLE_EQ(feasibility.infeasible_area_fraction, 1.0);
  }
}

TEST(FlattenMeasures, DirichletEnergyIsResolutionIndependent) {
  // u = e^{2 i theta} with theta = k x on a 100 x 60 mm rectangle: int |grad u|^2 = 4 k^2 area.
  // The two-point (centroid) discretization is exact on equilateral triangles and overestimates
  // by a fixed factor (here about 1.27) on these right triangles, whatever the resolution.
  const double k = 0.02;
  auto rectangle = [](int n) {
    return grid_mesh(n, n, [](double u, double v) { return Eigen::Vector3d(100 * u, 60 * v, 0); });
  };
  const double exact = 4 * k * k * 100 * 60;
  double previous = 0;
  for (int n : {10, 20, 40}) {
    const Mesh mesh = rectangle(n);
    Eigen::VectorXd theta(mesh.num_faces());
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const double x =
          (mesh.V(mesh.F(f, 0), 0) + mesh.V(mesh.F(f, 1), 0) + mesh.V(mesh.F(f, 2), 0));
      theta(f) = k * x / 3;
    }
    const double energy = direction_dirichlet_energy(mesh.V, mesh.F, theta);
    EXPECT_NEAR(energy / exact, 1.0, 0.3) << n;
    if (previous > 0) {
      EXPECT_NEAR(energy / previous, 1.0, 0.05) << n;
    }
    previous = energy;
  }
}

// The Eq. 12 energy.

TEST(FlattenSmoothingEnergy, DerivativesMatchFiniteDifferencesAndProjectionIsPsd) {
  const Mesh target = grid_mesh(5, 4, [](double u, double v) {
    return Eigen::Vector3d(40 * u, 30 * v, 6 * std::sin(2 * u + v) + 4 * u * v);
  });
  const RestFrames frames = rest_frames(target.V, target.F);
  const DualEdges edges = dual_edges(target.V, target.F, frames);
  const double s1 = 1 / 0.58, s2 = 1 / 1.08, weight = 1e-2;
  // A plate with varied, positive triangles: the target's (x, y) squeezed unevenly.
  Eigen::VectorXd x(2 * target.num_vertices());
  for (int v = 0; v < target.num_vertices(); ++v) {
    x(2 * v) = 1.5 * target.V(v, 0) + 0.01 * target.V(v, 1) * target.V(v, 1);
    x(2 * v + 1) = 0.95 * target.V(v, 1) + 2 * std::sin(0.1 * target.V(v, 0));
  }
  Eigen::VectorXd gradient;
  Eigen::SparseMatrix<double> hessian;
  const double energy =
      smoothing_energy(target.F, frames, edges, s1, s2, weight, x, &gradient, &hessian, false);
  EXPECT_GT(energy, 0);
  const Eigen::MatrixXd H = Eigen::MatrixXd(hessian).selfadjointView<Eigen::Lower>();
  const double h = 1e-6;
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd plus = x, minus = x;
    plus(i) += h;
    minus(i) -= h;
    Eigen::VectorXd g_plus, g_minus;
    const double e_plus =
        smoothing_energy(target.F, frames, edges, s1, s2, weight, plus, &g_plus, nullptr, false);
    const double e_minus =
        smoothing_energy(target.F, frames, edges, s1, s2, weight, minus, &g_minus, nullptr, false);
    EXPECT_NEAR(gradient(i), (e_plus - e_minus) / (2 * h),
                1e-7 * (1 + gradient.cwiseAbs().maxCoeff()));
    const Eigen::VectorXd column = (g_plus - g_minus) / (2 * h);
    EXPECT_LT((H.col(i) - column).cwiseAbs().maxCoeff(), 1e-5 * H.cwiseAbs().maxCoeff()) << i;
  }
  // The exact Hessian is indefinite here; the filtered one is PSD.
  Eigen::SparseMatrix<double> projected;
  smoothing_energy(target.F, frames, edges, s1, s2, weight, x, nullptr, &projected, true);
  const Eigen::MatrixXd Hp = Eigen::MatrixXd(projected).selfadjointView<Eigen::Lower>();
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues().minCoeff(), 0);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hp).eigenvalues().minCoeff(),
            -1e-12 * Hp.cwiseAbs().maxCoeff());
}

// Analytic flattenings.

TEST(Flatten, DevelopableCylinderFlattensIsometrically) {
  const Mesh target = cylinder_patch();
  FlattenOptions options;
  options.lambda1 = options.lambda2 = 1.0;
  options.width_mm = 100;
  const FlatPlate plate = flatten(target, options);
  EXPECT_GT(signed_areas(plate.plate, plate.target.F).minCoeff(), 0);
  const EdgeTopology topology = edge_topology(plate.target.F);
  double worst = 0;
  for (int e = 0; e < topology.num_edges(); ++e) {
    const int a = topology.edges(e, 0), b = topology.edges(e, 1);
    const double flat = (plate.plate.row(a) - plate.plate.row(b)).norm();
    const double curved = (plate.target.V.row(a) - plate.target.V.row(b)).norm();
    worst = std::max(worst, std::abs(flat / curved - 1));
  }
  EXPECT_LT(worst, 1e-3);
  // The plate is the unrolled cylinder: 2 pi 40 / 3 = 83.8 mm by 60 mm, scaled to 100 mm.
  const Eigen::RowVector2d extent =
      plate.plate.colwise().maxCoeff() - plate.plate.colwise().minCoeff();
  EXPECT_NEAR(extent.maxCoeff(), 100, 1e-9);
}

TEST(Flatten, PlaneGetsExactSingularValuesAndConstantTheta1) {
  const Mesh target = plane_patch();
  FlattenOptions options;
  options.width_mm = 120;
  const FlatPlate plate = flatten(target, options);
  EXPECT_GT(signed_areas(plate.plate, plate.target.F).minCoeff(), 0);
  EXPECT_LT((plate.singular_values.col(0).array() - 1 / 0.58).abs().maxCoeff(), 1e-6);
  EXPECT_LT((plate.singular_values.col(1).array() - 1 / 1.08).abs().maxCoeff(), 1e-6);
  EXPECT_LT(line_field_difference(
                plate.theta1, Eigen::VectorXd::Constant(plate.theta1.size(), plate.theta1(0)), 0),
            1e-6);
  EXPECT_LT(plate.feasibility.max_deviation, 1e-6);
  EXPECT_EQ(plate.feasibility.infeasible_area_fraction, 0);
}

// Conventions and invariants.

TEST(Flatten, NormalSideIsTheTopAndFlipPrintsTheMirrorImage) {
  // The examples have their normals up (+z); the plate keeps the face order and is
  // counter-clockwise seen from +z.
  const Mesh target = make_example("paraboloid");
  FlattenOptions options;
  options.width_mm = 90;
  const FlatPlate top = flatten(target, options);
  EXPECT_EQ(top.target.F, target.F);
  EXPECT_GT(signed_areas(top.plate, top.target.F).minCoeff(), 0);

  options.flip = true;
  const FlatPlate bottom = flatten(target, options);
  Eigen::MatrixXi reversed = target.F;
  reversed.col(1).swap(reversed.col(2));
  EXPECT_EQ(bottom.target.F, reversed);
  EXPECT_GT(signed_areas(bottom.plate, bottom.target.F).minCoeff(), 0);
  // Printing the other side down is the mirror image of the plate (no mirrored target), and the
  // print directions mirror with it.
  Eigen::MatrixXd mirrored = bottom.plate;
  mirrored.col(1) *= -1;
  const RigidFit fit = rigid_fit(mirrored, top.plate);
  EXPECT_LT(fit.max_distance, 1e-3 * options.width_mm);
  EXPECT_LT(line_field_difference(-bottom.theta1, top.theta1, -fit.angle), 1e-3);
  EXPECT_NEAR(bottom.feasibility.mean_deviation, top.feasibility.mean_deviation, 1e-5);
}

// Candidate k of a flipped target is the mirror image of candidate k, so a design can choose the
// stretch on one side and flatten the other; and the candidates are different plates.
TEST(Flatten, EachStretchCandidateFlipsToItsMirrorImage) {
  const Mesh target = paper_mesh("beetle", 2000);
  FlattenOptions options;
  options.width_mm = 200;
  std::vector<double> deviations;
  for (int k = 0; k < kStretchCandidates; ++k) {
    options.stretch_candidate = k;
    options.flip = false;
    const FlatPlate top = flatten(target, options);
    options.flip = true;
    const FlatPlate bottom = flatten(target, options);
    EXPECT_EQ(top.stretch_candidate, k);
    EXPECT_EQ(bottom.stretch_candidate, k);
    Eigen::MatrixXd mirrored = bottom.plate;
    mirrored.col(1) *= -1;
    const RigidFit fit = rigid_fit(mirrored, top.plate);
    EXPECT_LT(fit.max_distance, 1e-3 * options.width_mm) << "candidate " << k;
    EXPECT_LT(line_field_difference(-bottom.theta1, top.theta1, -fit.angle), 1e-3);
    deviations.push_back(top.feasibility.mean_deviation);
  }
  // The beetle's candidates reach different local minima (docs/flatten.md: the direction decides
  // which), or the choice would not matter.
  const auto [low, high] = std::minmax_element(deviations.begin(), deviations.end());
  EXPECT_GT(*high - *low, 0.1 * *low);

  options.stretch_candidate = kStretchCandidates;
  EXPECT_THROW(flatten(target, options), UserError);
}

TEST(Flatten, RotatedTargetGivesTheSamePlateUpToARigidMotion) {
  const Mesh target = paper_mesh("beetle", 2000);
  FlattenOptions options;
  options.width_mm = 200;
  const FlatPlate plate = flatten(target, options);

  Mesh rotated = target;
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(2.0, Eigen::Vector3d(-1, 3, 2).normalized()).toRotationMatrix();
  rotated.V = (target.V * R.transpose()).rowwise() + Eigen::RowVector3d(30, -7, 12);
  const FlatPlate moved = flatten(rotated, options);

  const RigidFit fit = rigid_fit(moved.plate, plate.plate);
  EXPECT_LT(fit.max_distance, 1e-6 * options.width_mm);
  EXPECT_LT(line_field_difference(moved.theta1, plate.theta1, -fit.angle), 1e-6);
  // The design's target is the rotated one, scaled by the same factor.
  const double scale = (plate.target.V.row(1) - plate.target.V.row(0)).norm() /
                       (target.V.row(1) - target.V.row(0)).norm();
  EXPECT_NEAR((moved.target.V.row(1) - moved.target.V.row(0)).norm(),
              scale * (rotated.V.row(1) - rotated.V.row(0)).norm(), 1e-9 * options.width_mm);
}

TEST(Flatten, RejectsBadOptionsAndNonDisks) {
  const Mesh target = make_example("dome");
  FlattenOptions options;
  options.width_mm = -5;
  EXPECT_THROW(flatten(target, options), UserError);
  options.width_mm = 100;
  options.w_D = -1;
  EXPECT_THROW(flatten(target, options), UserError);
  options.w_D = 0.1;
  options.lambda1 = options.lambda2 = 1;  // no preferred direction to smooth
  EXPECT_THROW(flatten(target, options), UserError);

  Mesh two_holes = grid_mesh(6, 6, [](double u, double v) { return Eigen::Vector3d(u, v, 0); });
  Eigen::MatrixXi kept(two_holes.num_faces() - 2, 3);
  for (int f = 0, k = 0; f < two_holes.num_faces(); ++f) {
    if (f != 30 && f != 31) kept.row(k++) = two_holes.F.row(f);
  }
  two_holes.F = kept;
  try {
    flatten(two_holes, FlattenOptions{});
    ADD_FAILURE() << "a surface with a hole was flattened";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kTopology);
  }
}

// The paper's meshes and the built-in examples.

struct PaperCase {
  std::string name;
  int faces;  // paper Table 1
  double width_mm;
  double w_D;
};

// Test names and failure messages show the model, not the bytes of the struct.
void PrintTo(const PaperCase& c, std::ostream* os) { *os << c.name; }

class FlattenPaperMesh : public ::testing::TestWithParam<PaperCase> {};

void expect_printable(const FlatPlate& plate, const std::string& what) {
  EXPECT_GT(signed_areas(plate.plate, plate.target.F).minCoeff(), 0) << what;
  EXPECT_LT(plate.feasibility.mean_deviation, 0.02) << what;
  for (const std::string& warning : plate.warnings) ADD_FAILURE() << what << ": " << warning;
}

TEST_P(FlattenPaperMesh, GivesAFlipFreePlateWithinTwoPercent) {
  const PaperCase& c = GetParam();
  const Mesh target = paper_mesh(c.name, c.faces);
  ASSERT_EQ(target.num_faces(), c.faces);
  FlattenOptions options;
  options.width_mm = c.width_mm;
  options.w_D = c.w_D;
  const FlatPlate plate = flatten(target, options);
  expect_printable(plate, c.name);
  const Eigen::RowVector2d extent =
      plate.plate.colwise().maxCoeff() - plate.plate.colwise().minCoeff();
  EXPECT_NEAR(extent.maxCoeff(), c.width_mm, 1e-9);
  std::cout << c.name << ": mean deviation " << 100 * plate.feasibility.mean_deviation << " %, max "
            << 100 * plate.feasibility.max_deviation << " %, infeasible area "
            << 100 * plate.feasibility.infeasible_area_fraction << " %, Dirichlet "
            << plate.direction_dirichlet << "\n";

  // Where the paper smooths, smoothing must make the directions smoother without doubling the
  // deviation from the material's shrink.
  if (c.w_D > 0) {
    options.w_D = 0;
    const FlatPlate rough = flatten(target, options);
    expect_printable(rough, c.name + " without smoothing");
    EXPECT_LT(plate.direction_dirichlet, rough.direction_dirichlet) << c.name;
    EXPECT_LT(plate.feasibility.mean_deviation, 2 * rough.feasibility.mean_deviation) << c.name;
    std::cout << c.name << " without smoothing: mean deviation "
              << 100 * rough.feasibility.mean_deviation << " %, Dirichlet "
              << rough.direction_dirichlet << "\n";
  }
}

INSTANTIATE_TEST_SUITE_P(Paper, FlattenPaperMesh,
                         ::testing::Values(PaperCase{"hemisphere-big", 17152, 150, 0.1},
                                           PaperCase{"saddle", 2048, 100, 0},
                                           PaperCase{"beetle", 8448, 200, 0},
                                           PaperCase{"face", 3996, 200, 0.1},
                                           PaperCase{"top", 3584, 250, 0},
                                           PaperCase{"hat", 11008, 100, 0.1}),
                         [](const auto& info) {
                           std::string name = info.param.name;
                           for (char& ch : name) {
                             if (ch == '-') ch = '_';
                           }
                           return name;
                         });

TEST(FlattenExamples, EveryBuiltInExampleGivesAFlipFreePlateWithinTwoPercent) {
  for (const ExampleInfo& example : example_list()) {
    for (double w_D : {0.0, 0.1}) {
      FlattenOptions options;
      options.width_mm = 100;
      options.w_D = w_D;
      const FlatPlate plate = flatten(make_example(example.name), options);
      expect_printable(plate, example.name + " w_D " + std::to_string(w_D));
    }
  }
}

// The command line.

TEST(FlattenCli, SameInputGivesByteIdenticalFlatPly) {
  const fs::path dir = testing::scratch_dir();
  for (const char* run : {"a", "b"}) {
    const auto r = testing::run_cli({"flatten", "--example", "saddle", "--width", "120", "--wD",
                                     "0.1", "--faces", "3000", "-o", (dir / run).string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("singular-value deviation"), std::string::npos) << r.out;
  }
  const std::string flat = read_bytes(dir / "a" / "flat.ply");
  ASSERT_FALSE(flat.empty());
  EXPECT_EQ(flat, read_bytes(dir / "b" / "flat.ply"));
  EXPECT_EQ(read_bytes(dir / "a" / "target.ply"), read_bytes(dir / "b" / "target.ply"));

  // flat.ply pairs with target.ply: same faces, z = 0, theta1 per face in [-pi/2, pi/2).
  const MeshFile plate = read_mesh(dir / "a" / "flat.ply");
  const MeshFile target = read_mesh(dir / "a" / "target.ply");
  EXPECT_EQ(plate.mesh.F, target.mesh.F);
  EXPECT_GE(plate.mesh.num_faces(), 3000);
  EXPECT_EQ(plate.mesh.V.col(2).cwiseAbs().maxCoeff(), 0);
  const Eigen::VectorXd* theta1 = plate.properties.find_face("theta1");
  ASSERT_NE(theta1, nullptr);
  ASSERT_EQ(theta1->size(), plate.mesh.num_faces());
  EXPECT_GE(theta1->minCoeff(), -kPi / 2);
  EXPECT_LT(theta1->maxCoeff(), kPi / 2);
  const Eigen::RowVector3d extent =
      plate.mesh.V.colwise().maxCoeff() - plate.mesh.V.colwise().minCoeff();
  EXPECT_NEAR(extent.maxCoeff(), 120, 1e-9);
}

TEST(FlattenCli, NegativeWidthExitsWithStatus2AndWritesNothing) {
  const fs::path out = testing::scratch_dir() / "out";
  const auto r =
      testing::run_cli({"flatten", "--example", "dome", "--width", "-5", "-o", out.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("--width"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace flatmorph::flatten_test
