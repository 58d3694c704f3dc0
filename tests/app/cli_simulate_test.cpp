// `flatmorph simulate` on a plate written by `flatmorph flatten`, as a user runs it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "mesh/io.h"
#include "plate/plate_fixtures.h"
#include "simulate/distance.h"
#include "test_support.h"

namespace flatmorph::cli_simulate_test {
namespace {

namespace fs = std::filesystem;
using testing::run_cli;

// A small dome plate: 60 mm wide, the example's 2904 faces.
fs::path flatten_dome(const fs::path& dir) {
  const auto r = run_cli({"flatten", "--example", "dome", "--width", "60", "--faces", "1000", "-o",
                          (dir / "design").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return dir / "design";
}

TEST(CliSimulate, PredictsTheDomeFromFlatAndFromTheTarget) {
  const fs::path dir = testing::scratch_dir();
  const fs::path design = flatten_dome(dir);
  const auto r = run_cli({"simulate", (design / "flat.ply").string(), "--from",
                          (design / "target.ply").string(), "--target",
                          (design / "target.ply").string(), "-o", (dir / "sim.ply").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("from start:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("from flat :"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("distance to target: average"), std::string::npos) << r.out;
  const MeshFile sim = read_mesh(dir / "sim.ply");
  const MeshFile target = read_mesh(design / "target.ply");
  ASSERT_EQ(sim.mesh.num_vertices(), target.mesh.num_vertices());
  EXPECT_EQ(sim.mesh.F, target.mesh.F);
  const Eigen::VectorXd* deviation = sim.properties.find_vertex("deviation_mm");
  ASSERT_NE(deviation, nullptr);
  // A 60 mm dome flattened for the paper's PLA, theta2 = 0: the prediction is near the target
  // (a few % of its size), not far from it, and deviation_mm is the real per-vertex distance.
  const double diagonal =
      (target.mesh.V.colwise().maxCoeff() - target.mesh.V.colwise().minCoeff()).norm();
  EXPECT_LT(deviation->mean(), 0.05 * diagonal);
  EXPECT_NEAR((*deviation)(0), (sim.mesh.V.row(0) - target.mesh.V.row(0)).norm(), 1e-9);
}

TEST(CliSimulate, ForwardPredictionFromFlatRisesIntoADome) {
  const fs::path dir = testing::scratch_dir();
  const fs::path design = flatten_dome(dir);
  const auto r =
      run_cli({"simulate", (design / "flat.ply").string(), "-o", (dir / "sim.ply").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const MeshFile sim = read_mesh(dir / "sim.ply");
  // The flat plate must leave the plane: its height range is a sizeable part of its width.
  const Eigen::Vector3d extent = sim.mesh.V.colwise().maxCoeff() - sim.mesh.V.colwise().minCoeff();
  EXPECT_GT(extent.minCoeff(), 0.1 * extent.maxCoeff()) << extent.transpose();
}

// A 20 mm disk printed along its radii (theta1 per face, rings 1 mm apart; no stack file: 10
// layers of pla-paper): it buckles into a saddle, and --json says how the solve ended.
TEST(CliSimulate, TheJsonSaysWhyTheSimulationEnded) {
  const fs::path dir = testing::scratch_dir();
  const testing::TestPlate plate = testing::disk_plate(10, 10);
  Eigen::VectorXd theta1(plate.F.rows());
  for (Eigen::Index f = 0; f < plate.F.rows(); ++f) {
    const Eigen::RowVector2d c =
        (plate.V.row(plate.F(f, 0)) + plate.V.row(plate.F(f, 1)) + plate.V.row(plate.F(f, 2))) / 3;
    theta1(f) = std::atan2(c.y(), c.x());
  }
  MeshProperties properties;
  properties.set_face("theta1", theta1);
  write_ply(dir / "disk.ply", Mesh{testing::embed(plate.V), plate.F}, properties);
  auto r = run_cli(
      {"simulate", (dir / "disk.ply").string(), "--json", "-o", (dir / "disk_sim.ply").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);  // only the JSON on stdout
  EXPECT_EQ(j.at("metrics").at("sim_stop_reason"), "converged");
  EXPECT_TRUE(j.at("metrics").at("converged").get<bool>());
  EXPECT_GT(j.at("metrics").at("stimulus_steps").get<int>(), 1);
  EXPECT_EQ(r.err.find("warning: simulation"), std::string::npos) << r.err;
  // A time budget too small for one iteration: the start is written, and the reason says so on
  // stderr and in the JSON.
  r = run_cli({"simulate", (dir / "disk.ply").string(), "--json", "--max-seconds", "1e-9", "-o",
               (dir / "disk_budget.ply").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  const std::string reason = j.at("metrics").at("sim_stop_reason");
  EXPECT_NE(reason.find("time budget of 1e-09 s"), std::string::npos) << reason;
  EXPECT_NE(r.err.find("warning: simulation: " + reason), std::string::npos) << r.err;
  EXPECT_TRUE(read_mesh(dir / "disk_budget.ply").mesh.V.allFinite());
  r = run_cli({"simulate", (dir / "disk.ply").string(), "--max-seconds", "0", "-o",
               (dir / "zero.ply").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--max-seconds"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "zero.ply"));
}

TEST(CliSimulate, BadInputsGiveOneLineErrorsAndNoOutput) {
  const fs::path dir = testing::scratch_dir();
  const fs::path design = flatten_dome(dir);
  // target.ply is not flat and has no theta1.
  auto r = run_cli({"simulate", (design / "target.ply").string(), "-o", (dir / "a.ply").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not flat"), std::string::npos) << r.err;
  // The plate's stack file decides its layers and materials.
  r = run_cli({"simulate", (design / "flat.ply").string(), "--layers", "6", "-o",
               (dir / "b.ply").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("stack file"), std::string::npos) << r.err;
  r = run_cli({"simulate", (design / "flat.ply").string(), "-o", (dir / "c.obj").string()});
  EXPECT_EQ(r.exit_code, 2);
  // Without the stack file, the options apply (and are checked).
  fs::remove(design / "flat.stack.json");
  r = run_cli({"simulate", (design / "flat.ply").string(), "--material", "unobtainium", "-o",
               (dir / "d.ply").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unobtainium"), std::string::npos) << r.err;
  r = run_cli({"simulate", (design / "flat.ply").string(), "--layers", "0", "-o",
               (dir / "b.ply").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--layers"), std::string::npos) << r.err;
  for (const char* name : {"a.ply", "b.ply", "c.obj", "d.ply"}) {
    EXPECT_FALSE(fs::exists(dir / name)) << name;
  }
}

// A 30 x 10 mm strip of 6 layers along x, as a slicer without annotations would write it.
std::string strip_gcode(bool relative_e) {
  std::string g = relative_e ? "G21\nG90\nM83\n" : "G21\nG90\nM82\nG92 E0\n";
  const double area = 3.14159265358979 * 1.75 * 1.75 / 4;
  double e = 0;
  for (int k = 1; k <= 6; ++k) {
    g += "G0 Z" + std::to_string(0.1 * k) + "\n";
    for (int i = 0; i < 25; ++i) {
      const double y = -5 + 0.2 + 0.4 * i;
      const double x0 = i % 2 ? 15 : -15, x1 = -x0;
      const double de = 30 * 0.4 * 0.1 / area;
      e += de;
      g += "G0 X" + std::to_string(x0) + " Y" + std::to_string(y) + "\n";
      g += "G1 X" + std::to_string(x1) + " Y" + std::to_string(y) + " E" +
           std::to_string(relative_e ? de : e) + " F1800\n";
    }
  }
  return g + "M84\n";
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

TEST(CliSimulate, PredictsAGcodeFileOnItsFootprintAndWritesARunFolder) {
  const fs::path dir = testing::scratch_dir();
  write_text(dir / "strip.gcode", strip_gcode(true));
  const auto r = run_cli({"simulate", (dir / "strip.gcode").string(), "--material", "pla-paper",
                          "-o", (dir / "out" / "strip.ply").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("6 layers"), std::string::npos) << r.out;
  const Mesh shape = read_mesh(dir / "out" / "strip.ply").mesh;
  // Curled: it no longer lies in a plane.
  EXPECT_GT(shape.V.col(2).maxCoeff() - shape.V.col(2).minCoeff(), 1.0);
  for (const char* file : {"flat.ply", "flat.stack.json", "design.json", "report.html"}) {
    EXPECT_TRUE(fs::exists(dir / "out" / "strip" / file)) << file;
  }
  // The same strip with absolute E reads as the same plate, so curls the same. (Its beads' widths
  // differ in rounding, so its plate does by 1e-6 mm, enough to register the shape at another of
  // the central faces a symmetric plate has: the same shape, moved.)
  write_text(dir / "strip_abs.gcode", strip_gcode(false));
  const auto a = run_cli({"simulate", (dir / "strip_abs.gcode").string(), "-o",
                          (dir / "out" / "strip_abs.ply").string()});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const Mesh twin = read_mesh(dir / "out" / "strip_abs.ply").mesh;
  ASSERT_EQ(twin.V.rows(), shape.V.rows());
  EXPECT_LT((rigidly_aligned(twin.V, shape.V) - shape.V).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(CliSimulate, HostileGcodeGivesOneLineAndExit2) {
  const fs::path dir = testing::scratch_dir();
  const std::string good = strip_gcode(true);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"truncated.gcode", good.substr(0, good.size() / 2 - 7)},
      {"nothing.gcode", "G21\nG90\nM83\nG0 X10 Y10 Z0.2\nG0 X20\nM84\n"},
      {"nan.gcode", "G21\nM83\nG0 Z0.2\nG1 X10 Y10 E0.5\nG1 Xnan Y3 E0.5\nM84\n"},
      {"inches.gcode", "G20\nM83\nG0 Z0.01\nG1 X1 Y1 E0.1\nM84\n"},
      // Relative E declared, absolute values written: beads far too wide.
      {"mixed.gcode", "G21\nM83\nG0 Z0.2\nG1 X10 Y0 E5\nG1 X20 Y0 E10\nG1 X30 Y0 E15\nM84\n"},
  };
  for (const auto& [name, text] : cases) {
    write_text(dir / name, text);
    const auto r = run_cli({"simulate", (dir / name).string(), "-o", (dir / "x.ply").string()});
    EXPECT_EQ(r.exit_code, 2) << name << "\n" << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << name << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.ply")) << name;
    EXPECT_FALSE(fs::exists(dir / "x")) << name;
  }
  // --target is compared vertex by vertex, so it needs the plate it was designed on.
  write_text(dir / "strip.gcode", good);
  for (const char* cover : {"0", "1.5", "nan"}) {
    const auto bad = run_cli({"simulate", (dir / "strip.gcode").string(), "--min-cover", cover,
                              "-o", (dir / "x.ply").string()});
    EXPECT_EQ(bad.exit_code, 2) << cover;
    EXPECT_NE(bad.err.find("--min-cover"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "x.ply")) << cover;
  }
}

// A cylinder of `radius` mm about the y axis touching the xy plane along it: the arc of `length`
// mm across and `width` mm along y, n x m cells.
Mesh cylinder(double radius, double length, double width, int n, int m) {
  Mesh mesh;
  mesh.V.resize((n + 1) * (m + 1), 3);
  mesh.F.resize(2 * n * m, 3);
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double angle = (double(i) / n - 0.5) * length / radius;
      mesh.V.row(j * (n + 1) + i) << radius * std::sin(angle), width * (double(j) / m - 0.5),
          radius * (1 - std::cos(angle));
    }
  }
  for (int j = 0, f = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i, f += 2) {
      const int a = j * (n + 1) + i;
      mesh.F.row(f) << a, a + 1, a + n + 2;
      mesh.F.row(f + 1) << a, a + n + 2, a + n + 1;
    }
  }
  return mesh;
}

// Without the plate a G-code was designed on, a target is compared by shape: the strip's
// predicted shape against a cylinder of the curvature the calibration strip has, κ = −Δλ1 / (h λ3
// λ1), lies close; against one of twice that curvature, not; a target that is not a surface is
// refused before any work, naming the file.
TEST(CliSimulate, ComparesAGcodeFileWithAnyTargetMeshByShape) {
  const fs::path dir = testing::scratch_dir();
  write_text(dir / "strip.gcode", strip_gcode(true));
  const double kappa = 0.0226764665509417 / (0.6 * 1.52 * 0.58);  // pla-paper, 6 x 0.1 mm
  auto distance_to = [&](double curvature, const std::string& name) {
    write_obj(dir / (name + ".obj"), cylinder(1 / curvature, 24, 14, 48, 14));
    const auto r =
        run_cli({"simulate", (dir / "strip.gcode").string(), "--material", "pla-paper", "--target",
                 (dir / (name + ".obj")).string(), "-o", (dir / (name + ".ply")).string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("distance to target by shape (closest points"), std::string::npos)
        << r.out;
    const nlohmann::json design =
        nlohmann::json::parse(testing::read_file(dir / name / "design.json"));
    EXPECT_EQ(design["target_comparison"].get<std::string>().rfind("shape", 0), 0u) << design;
    const Mesh shown = read_mesh(dir / name / "target.ply").mesh;
    EXPECT_EQ(shown.F.rows(), 2 * 48 * 14) << "the target as given";
    return std::pair{design["metrics"]["gcode_dist_avg_pct"].get<double>(),
                     design["metrics"]["gcode_dist_max_pct"].get<double>()};
  };
  const auto [avg, max] = distance_to(kappa, "cylinder");
  EXPECT_LT(avg, 0.05);
  EXPECT_LT(max, 0.2);
  const auto [wrong_avg, wrong_max] = distance_to(2 * kappa, "tighter");
  EXPECT_GT(wrong_avg, 1.0);
  EXPECT_GT(wrong_max, 2.0);

  write_text(dir / "garbage.ply", "not a mesh\n");
  // Written by hand: the mesh writers refuse a shape with NaN coordinates.
  write_text(dir / "nan.obj", "v 0 0 0\nv 10 0 0\nv 0 10 nan\nv 10 10 0\nf 1 2 3\nf 2 4 3\n");
  for (const char* target : {"missing.ply", "garbage.ply", "nan.obj"}) {
    const auto r = run_cli({"simulate", (dir / "strip.gcode").string(), "--target",
                            (dir / target).string(), "-o", (dir / "x.ply").string()});
    EXPECT_EQ(r.exit_code, 2) << target;
    EXPECT_NE(r.err.find(target), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.ply")) << target;
  }
}

}  // namespace
}  // namespace flatmorph::cli_simulate_test
