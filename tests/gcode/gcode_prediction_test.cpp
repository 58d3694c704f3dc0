// The shape predicted from a G-code file (src/run/gcode_prediction.h), with files written here by
// the tests, not by the design pipeline: a strip printed along its length curls as the
// calibration strip does, the same file turned or moved on the bed curls the same way (on the
// turned plate, or on the footprint it meshes itself), rings make a dome,
// radial lines a saddle, PLA printed on TPU bends as Timoshenko's bilayer.
#include "run/gcode_prediction.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "common/angles.h"
#include "mesh/operators.h"
#include "mesh/topology.h"
#include "plate/plate_fixtures.h"
#include "simulate/distance.h"
#include "simulate/shape_fits.h"
#include "simulate/surface_fit.h"
#include "test_support.h"

namespace flatmorph::gcode_prediction_test {
namespace {

using Polyline = std::vector<Eigen::Vector2d>;

struct PrintedLayer {
  std::vector<Polyline> paths;
  double z = 0;       // nozzle height, mm
  double height = 0;  // bead height, mm
  int tool = 0;
};

constexpr double kWidth = 0.4;
constexpr double kFilamentArea = std::numbers::pi * 1.75 * 1.75 / 4;

// A plain G-code file: relative E (M83), travels with G0, beads with G1 whose E is length ×
// width × height / filament section; no annotation.
std::string write_gcode(const std::vector<PrintedLayer>& layers) {
  std::string g = "G21\nG90\nM83\nG28\n";
  int tool = 0;
  for (const PrintedLayer& layer : layers) {
    if (layer.tool != tool) {
      g += fmt::format("T{}\n", layer.tool);
      tool = layer.tool;
    }
    g += fmt::format("G0 Z{:.4f} F600\n", layer.z);
    for (const Polyline& path : layer.paths) {
      g += fmt::format("G0 X{:.5f} Y{:.5f} F6000\n", path[0].x(), path[0].y());
      for (size_t i = 1; i < path.size(); ++i) {
        const double e = (path[i] - path[i - 1]).norm() * kWidth * layer.height / kFilamentArea;
        g += fmt::format("G1 X{:.5f} Y{:.5f} E{:.6f} F1800\n", path[i].x(), path[i].y(), e);
      }
    }
  }
  g += "M84\n";
  return g;
}

Eigen::Vector2d turned(const Eigen::Vector2d& p, double angle) {
  return Eigen::Vector2d(std::cos(angle) * p.x() - std::sin(angle) * p.y(),
                         std::sin(angle) * p.x() + std::cos(angle) * p.y());
}

// Lines along x filling [−a, a] × [−b, b] at the bead width, each its own path, turned by `angle`
// and then moved by `shift` (mm).
std::vector<Polyline> strip_lines(double a, double b, double angle,
                                  const Eigen::Vector2d& shift = Eigen::Vector2d::Zero()) {
  std::vector<Polyline> lines;
  for (double y = -b + kWidth / 2; y < b; y += kWidth) {
    lines.push_back({turned({-a, y}, angle) + shift, turned({a, y}, angle) + shift});
  }
  return lines;
}

std::vector<PrintedLayer> stack_of(const std::vector<Polyline>& paths, int layers, double height) {
  std::vector<PrintedLayer> out;
  for (int k = 1; k <= layers; ++k) out.push_back({paths, k * height, height, 0});
  return out;
}

GcodePrediction predict(const std::string& gcode, const std::vector<Material>& materials) {
  return predict_from_gcode(gcode, "test.gcode", materials);
}

// The curvature of the circle through the predicted points whose plate position lies within
// 0.6 mm of the line through `centre` along `direction` and within `half` of the centre.
double curvature_along(const GcodePrediction& p, const Eigen::Vector2d& direction, double half,
                       const Eigen::Vector2d& centre = Eigen::Vector2d::Zero()) {
  std::vector<int> line;
  const Eigen::MatrixXd& plate = p.plate.design.plate;
  for (Eigen::Index v = 0; v < plate.rows(); ++v) {
    const Eigen::Vector2d q = plate.row(v).transpose() - centre;
    const double along = q.dot(direction);
    const double off = std::abs(q.x() * direction.y() - q.y() * direction.x());
    if (off < 0.6 && std::abs(along) < half) line.push_back(static_cast<int>(v));
  }
  EXPECT_GT(line.size(), 8u);
  Eigen::MatrixXd P(line.size(), 3);
  for (size_t i = 0; i < line.size(); ++i) P.row(i) = p.result.V.row(line[i]);
  Eigen::Vector3d axis_point;
  return testing::fitted_circle_curvature(P, axis_point);
}

// Integrated Gaussian curvature (sum of angle defects) of the vertices within `radius` of the
// plate's origin.
double gaussian_curvature_near_centre(const GcodePrediction& p, double radius) {
  const Eigen::VectorXd defects = angle_defects(p.result.V, p.plate.design.F);
  double sum = 0;
  for (Eigen::Index v = 0; v < defects.size(); ++v) {
    if (p.plate.design.plate.row(v).norm() < radius) sum += defects(v);
  }
  return sum;
}

// Shrink & Morph §4.2: 10 layers along the strip, the bilayer term only: κ = −Δλ1 / (h λ3 λ1).
TEST(GcodePrediction, AStripPrintedAlongItsLengthCurlsAsTheCalibrationStrip) {
  const Material pla = load_material("pla-paper");
  const int layers = 10;
  const std::string gcode = write_gcode(stack_of(strip_lines(40, 10, 0), layers, pla.layer_height));
  const GcodePrediction p = predict(gcode, {pla});
  ASSERT_TRUE(p.result.converged) << p.result.warning;
  EXPECT_EQ(p.plate.design.stack.num_layers(), layers);
  const double h = layers * pla.layer_height;
  const double expected = -pla.delta_lambda1 / (h * pla.lambda3 * pla.lambda1);
  const double kappa = curvature_along(p, {1, 0}, 30);
  EXPECT_NEAR(kappa, expected, 0.03 * expected);

  // The same file turned by 30°, on the same plate mesh turned: the same shape, turned.
  const double angle = std::numbers::pi / 6;
  GcodePredictionOptions options;
  options.plate_V = p.plate.design.plate * Eigen::Rotation2Dd(angle).toRotationMatrix().transpose();
  options.plate_F = p.plate.design.F;
  const GcodePrediction q = predict_from_gcode(
      write_gcode(stack_of(strip_lines(40, 10, angle), layers, pla.layer_height)), "turned.gcode",
      {pla}, options);
  ASSERT_TRUE(q.result.converged) << q.result.warning;
  ASSERT_EQ(q.result.V.rows(), p.result.V.rows()) << "every face of the turned plate is printed";
  const ShapeDistance d = shape_distance(rigidly_aligned(q.result.V, p.result.V), p.result.V);
  // The beads are sampled on a lattice fixed to the bed, not to the plate: a turned plate is
  // sampled at other points.
  EXPECT_LT(d.mean_percent, 0.02);
  EXPECT_LT(d.max_percent, 0.3);
}

// A slicer lays a part anywhere on the bed at any angle: the plate meshed from its footprint turns
// and moves with it, so the prediction does too. A 60 x 12 mm strip of 5 layers along its length
// turned by 0°, 7°, 30° and 45°: the same curvature, κ = −Δλ1 / (h λ3 λ1), and the same shape.
TEST(GcodePrediction, AStripTurnedOnTheBedCurlsTheSameWhateverTheAngle) {
  const Material pla = load_material("pla-paper");
  const int layers = 5;
  const double h = layers * pla.layer_height;
  const double expected = -pla.delta_lambda1 / (h * pla.lambda3 * pla.lambda1);
  GcodePrediction straight;
  for (const double degrees : {0.0, 7.0, 30.0, 45.0}) {
    const double angle = degrees * kDegree;
    const GcodePrediction p =
        predict(write_gcode(stack_of(strip_lines(30, 6, angle), layers, pla.layer_height)), {pla});
    ASSERT_TRUE(p.result.converged) << degrees << "°: " << p.result.warning;
    const double kappa = curvature_along(p, turned({1, 0}, angle), 25);
    // Across the strip it stays straight.
    const double across = curvature_along(p, turned({0, 1}, angle), 5);
    std::cout << degrees << "°: κ " << kappa << " /mm along (" << expected << " expected), "
              << across << " across; energy " << p.result.energy << " mJ (membrane "
              << p.result.membrane_energy << ")\n";
    EXPECT_NEAR(kappa, expected, 0.03 * expected) << degrees << "°";
    EXPECT_LT(std::abs(across), 0.02 * expected) << degrees << "°";
    if (degrees == 0) {
      straight = p;
      continue;
    }
    EXPECT_EQ(p.plate.design.F.rows(), straight.plate.design.F.rows()) << degrees << "°";
    const ShapeDistance d = closest_point_rigid_fit(p.result.V, p.plate.design.F, straight.result.V,
                                                    straight.plate.design.F)
                                .distance;
    std::cout << "  to the straight strip's shape: " << d.mean_percent << " / " << d.max_percent
              << " % of the diagonal\n";
    EXPECT_LT(d.max_percent, 0.5) << degrees << "°";
  }
}

// The same strip moved about the bed, and moved and turned: the same shape.
TEST(GcodePrediction, AStripMovedOnTheBedCurlsTheSame) {
  const Material pla = load_material("pla-paper");
  const int layers = 5;
  const auto strip = [&](double angle, const Eigen::Vector2d& shift) {
    return predict(
        write_gcode(stack_of(strip_lines(30, 6, angle, shift), layers, pla.layer_height)), {pla});
  };
  const GcodePrediction here = strip(0, {0, 0});
  for (const auto& [angle, shift] : {std::pair{0.0, Eigen::Vector2d(37.3, -12.9)},
                                     std::pair{0.52, Eigen::Vector2d(101.7, 55.2)}}) {
    const GcodePrediction there = strip(angle, shift);
    ASSERT_TRUE(there.result.converged) << there.result.warning;
    ASSERT_EQ(there.plate.design.F.rows(), here.plate.design.F.rows());
    // The lattice moved with the part, so the shape is the same to rounding. (A part symmetric
    // about its centre may be meshed from either end: the same mesh, its vertices in another
    // order, hence the comparison by closest points.)
    const ShapeDistance d = closest_point_rigid_fit(there.result.V, there.plate.design.F,
                                                    here.result.V, here.plate.design.F)
                                .distance;
    EXPECT_LT(d.max_percent, 1e-4) << "moved by " << shift.transpose() << ", turned by " << angle;
  }
}

// Rings shrink around and grow across: the disk's circumference gets short for its radius, a dome
// (K > 0). Radial lines do the opposite, a saddle (K < 0).
TEST(GcodePrediction, RingsMakeADomeAndRadialLinesASaddle) {
  const Material pla = load_material("pla-paper");
  const double radius = 20;
  std::vector<Polyline> rings, spokes;
  for (double r = kWidth / 2; r < radius; r += kWidth) {
    Polyline ring;
    const int n = std::max(8, static_cast<int>(2 * std::numbers::pi * r / 0.5));
    for (int i = 0; i <= n; ++i) {
      const double a = 2 * std::numbers::pi * i / n;
      ring.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    rings.push_back(ring);
  }
  // A smaller disk for the saddle: radial shrink by 0.58 wrinkles a wide thin disk into many
  // waves.
  const double spoke_length = radius / 2;
  const int n = static_cast<int>(2 * std::numbers::pi * spoke_length / kWidth);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    spokes.push_back({{0, 0}, {spoke_length * std::cos(a), spoke_length * std::sin(a)}});
  }
  const GcodePrediction dome = predict(write_gcode(stack_of(rings, 10, pla.layer_height)), {pla});
  GcodePredictionOptions coarse;
  coarse.deposit.resolution_mm = 2;
  const GcodePrediction saddle = predict_from_gcode(
      write_gcode(stack_of(spokes, 10, pla.layer_height)), "spokes.gcode", {pla}, coarse);
  EXPECT_TRUE(dome.result.converged) << dome.result.warning;
  EXPECT_TRUE(saddle.result.converged) << saddle.result.warning;
  std::cout << "K near the centre: dome " << gaussian_curvature_near_centre(dome, 10) << ", saddle "
            << gaussian_curvature_near_centre(saddle, 5) << "\n";
  EXPECT_EQ(boundary_loops(dome.plate.design.F).size(), 1u) << "the footprint of a disk is a disk";
  EXPECT_EQ(boundary_loops(saddle.plate.design.F).size(), 1u);
  EXPECT_GT(gaussian_curvature_near_centre(dome, 10), 0.05);
  EXPECT_LT(gaussian_curvature_near_centre(saddle, 5), -0.05);
}

// One PLA layer (shrinking 1 % every way, 14 times stiffer) printed on one TPU layer, 0.5 mm
// each: the strip bends as Timoshenko's bilayer, κ = 6 Δε (1 + m)² / (h (3 (1 + m)² + (1 + m n)
// (m² + 1/(m n)))) with m = 1, n = 14, h = 1 mm.
TEST(GcodePrediction, PlaPrintedOnTpuBendsAsTimoshenkosBilayer) {
  Material pla, tpu;
  pla.name = "pla";
  pla.lambda1 = pla.lambda2 = 0.99;
  pla.lambda3 = 1.0;
  pla.delta_lambda1 = 0;
  pla.young_modulus_along = pla.young_modulus_across = 14.0;
  pla.poisson_ratio = tpu.poisson_ratio = 0.4;
  tpu.name = "tpu";
  tpu.lambda1 = tpu.lambda2 = tpu.lambda3 = 1.0;
  tpu.delta_lambda1 = 0;
  tpu.young_modulus_along = tpu.young_modulus_across = 1.0;
  const std::vector<Polyline> lines = strip_lines(40, 5, 0);
  const std::string gcode = write_gcode({{lines, 0.5, 0.5, 1}, {lines, 1.0, 0.5, 0}});
  const GcodePrediction p = predict(gcode, {pla, tpu});
  ASSERT_TRUE(p.result.converged) << p.result.warning;
  const double m = 1, n = 14, h = 1, strain = 0.01;
  const double timoshenko = 6 * strain * (1 + m) * (1 + m) /
                            (h * (3 * (1 + m) * (1 + m) + (1 + m * n) * (m * m + 1 / (m * n))));
  EXPECT_NEAR(curvature_along(p, {1, 0}, 30), timoshenko, 0.05 * timoshenko);
}

// The same rings written two ways: relative E, each ring one G2 full circle, a retraction and a
// wipe between rings; and absolute E, each ring as 720 G1 chords. They deposit the same stack.
TEST(GcodePrediction, ArcsRelativeEAndRetractionsGiveTheStackOfTheirSegmentTwin) {
  std::string arcs = "G21\nG90\nM83\n", segments = "G21\nG90\nM82\nG92 E0\n";
  double e = 0;
  for (int k = 1; k <= 3; ++k) {
    const double z = 0.1 * k;
    arcs += fmt::format("G0 Z{:.3f}\n", z);
    segments += fmt::format("G0 Z{:.3f}\n", z);
    for (double r = kWidth / 2 + 1; r < 15; r += kWidth) {
      const double per_mm = kWidth * 0.1 / kFilamentArea;
      arcs += fmt::format("G0 X{:.5f} Y0\nG1 E0.81 F2400\n", r);  // what the last retracted
      arcs += fmt::format("G2 X{:.5f} Y0 I{:.5f} J0 E{:.6f} F1800\n", r, -r,
                          2 * std::numbers::pi * r * per_mm);
      arcs += "G1 E-0.8 F2400\nG1 X0.5 Y0.5 E-0.01\n";  // retract, then wipe inwards
      segments += fmt::format("G0 X{:.5f} Y0\n", r);
      const int n = 720;
      for (int i = 1; i <= n; ++i) {
        const double a = -2 * std::numbers::pi * i / n;  // clockwise, as G2
        e += 2 * r * std::sin(std::numbers::pi / n) * per_mm;
        segments +=
            fmt::format("G1 X{:.5f} Y{:.5f} E{:.6f} F1800\n", r * std::cos(a), r * std::sin(a), e);
      }
    }
  }
  arcs += "M84\n";
  segments += "M84\n";
  const testing::TestPlate disk = testing::disk_plate(14, 14);
  const Material pla = load_material("pla-paper");
  auto stack_of_file = [&](const std::string& text) {
    return deposited_plate(read_gcode_deposition(text, "rings.gcode"), disk.V, disk.F, {pla},
                           "rings.gcode");
  };
  const DepositedPlate a = stack_of_file(arcs), b = stack_of_file(segments);
  ASSERT_EQ(a.design.stack.num_layers(), 3);
  ASSERT_EQ(b.design.stack.num_layers(), 3);
  ASSERT_EQ(a.kept_faces, b.kept_faces);
  for (int k = 0; k < 3; ++k) {
    const Layer& la = a.design.stack.layers[k];
    const Layer& lb = b.design.stack.layers[k];
    for (Eigen::Index f = 0; f < la.theta.size(); ++f) {
      ASSERT_EQ(la.covers(f), lb.covers(f)) << k << " " << f;
      if (!la.covers(f)) continue;
      EXPECT_NEAR(la.printed_thickness(f), lb.printed_thickness(f), 0.02 * lb.printed_thickness(f));
      // The arcs' chords turn by up to 0.2 rad on the smallest ring.
      EXPECT_LT(std::abs(std::remainder(la.theta(f) - lb.theta(f), std::numbers::pi)), 0.03);
    }
  }
}

}  // namespace
}  // namespace flatmorph::gcode_prediction_test
