// A run folder is written as one unit (src/run/run_folder.h): a rerun never leaves files of an
// earlier run (issue 20: a rerun with --no-gcode leaves no G-code), a failure leaves the folder as
// it was, a folder of other files is refused before any work, and the same run gives the same
// bytes.
#include "run/run_folder.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "common/error.h"
#include "mesh/io.h"
#include "mesh/mesh_fixtures.h"
#include "plate/plate_fixtures.h"
#include "test_support.h"

namespace flatmorph::run_folder_test {
namespace {

namespace fs = std::filesystem;

// A small plate printed along x in 4 layers, with a made-up predicted shape.
RunOutputs small_run() {
  const testing::TestPlate p = testing::rectangle_plate(20, 10, 6, 3);
  const int nf = static_cast<int>(p.F.rows());
  RunOutputs run;
  run.method = "test";
  run.plate.plate = p.V;
  run.plate.F = p.F;
  run.plate.method = "test";
  run.plate.stack = shrink_morph_layer_stack(Eigen::VectorXd::Zero(nf), Eigen::VectorXd::Zero(nf),
                                             Material{}, 4, 0.08);
  Mesh shape{testing::embed(p.V), p.F};
  shape.V.col(2) = 0.01 * shape.V.col(0).cwiseAbs2();
  run.target = Mesh{testing::embed(p.V), p.F};
  run.predicted = shape;
  run.predicted_deviation_mm = shape.V.col(2);
  run.parameters = {{"input", "a test"}, {"layers", 4}};
  run.metrics = {{"dist_to_optim_avg_pct", 0.5}};
  run.metric_list = {{"dist_to_optim_avg_pct", 0.5, "% of the target's bounding-box diagonal"}};
  return run;
}

TEST(RunFolder, TheSameRunGivesTheSameBytesAndAFailureLeavesTheFolderAsItWas) {
  const fs::path dir = testing::scratch_dir() / "run";
  const RunOutputs run = small_run();
  write_run_folder(dir, run, nullptr);
  const std::vector<std::string> names = {"flat.ply",      "flat.stack.json", "target.ply",
                                          "simulated.ply", "design.json",     "report.html"};
  std::vector<std::string> first;
  for (const std::string& name : names) {
    ASSERT_TRUE(fs::exists(dir / name)) << name;
    first.push_back(testing::read_file(dir / name));
  }
  EXPECT_NE(first[4].find("\"metrics_list\""), std::string::npos);
  EXPECT_NE(first[4].find("\"flatmorph_version\""), std::string::npos);
  // The report names the folder, not the temporary it was written in.
  EXPECT_EQ(first[5].find(".tmp"), std::string::npos);
  write_run_folder(dir, run, nullptr);
  for (size_t i = 0; i < names.size(); ++i)
    EXPECT_EQ(testing::read_file(dir / names[i]), first[i]) << names[i];
  // A run that fails while writing (a stack of another plate) leaves the earlier run whole.
  RunOutputs broken = run;
  broken.plate.stack.layers[2].theta.resize(3);
  EXPECT_THROW(write_run_folder(dir, broken, nullptr), UserError);
  for (size_t i = 0; i < names.size(); ++i)
    EXPECT_EQ(testing::read_file(dir / names[i]), first[i]) << names[i];
  for (const auto& entry : fs::directory_iterator(dir.parent_path())) {
    EXPECT_EQ(entry.path().filename(), "run") << "left behind: " << entry.path();
  }
}

TEST(RunFolder, AFolderOfOtherFilesIsRefusedBeforeAnyWork) {
  const fs::path dir = testing::scratch_dir() / "mine";
  fs::create_directories(dir);
  std::ofstream(dir / "notes.txt") << "my notes\n";
  EXPECT_THROW(write_run_folder(dir, small_run(), nullptr), UserError);
  const auto r = testing::run_cli({"design", "--example", "dome", "-o", dir.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("new or empty folder"), std::string::npos) << r.err;
  EXPECT_EQ(testing::read_file(dir / "notes.txt"), "my notes\n");
  EXPECT_FALSE(fs::exists(dir / "design.json"));
}

// Issue 20's acceptance: a rerun into the same folder with --no-gcode leaves no G-code from the
// earlier run (nor its toolpath or layer pictures), and design.json is the new run's.
TEST(RunFolder, ARerunWithoutGcodeLeavesNoGcodeOfTheEarlierRun) {
  const fs::path dir = testing::scratch_dir() / "cap";
  // What is written is checked, not the design: a coarse cap (288 faces) designs in a second.
  const fs::path cap = dir.parent_path() / "cap.obj";
  write_obj(cap, testing::grid_mesh(12, 12, [](double u, double v) {
              const double x = 40 * u - 20, y = 40 * v - 20;
              return Eigen::Vector3d(x, y, -(x * x + y * y) / 100);
            }));
  const std::vector<std::string> design = {"design",  cap.string(), "--faces", "1",
                                           "--width", "40",         "-o",      dir.string()};
  auto r = testing::run_cli(design);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"plate.gcode", "toolpath.json", "layers/layer_001.svg", "layers.png"}) {
    EXPECT_TRUE(fs::exists(dir / name)) << name;
  }
  std::vector<std::string> again = design;
  again.insert(again.end() - 2, {"--no-gcode", "--layers", "6"});
  r = testing::run_cli(again);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"plate.gcode", "toolpath.json", "layers", "layers.png"}) {
    EXPECT_FALSE(fs::exists(dir / name)) << name;
  }
  EXPECT_NE(testing::read_file(dir / "design.json").find("\"layers\": 6"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "report.html"));
}

}  // namespace
}  // namespace flatmorph::run_folder_test
