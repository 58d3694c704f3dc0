// `flatmorph simulate` on a plate written by `flatmorph flatten`, as a user runs it.
#include <gtest/gtest.h>

#include "mesh/io.h"
#include "test_support.h"

namespace flatmorph {
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

}  // namespace
}  // namespace flatmorph
