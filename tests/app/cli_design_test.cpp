// `flatmorph design` end to end, as a user runs it: the files, design.json's metrics, bad options.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "mesh/io.h"
#include "mesh/mesh_fixtures.h"
#include "test_support.h"

namespace flatmorph::cli_design_test {
namespace {

namespace fs = std::filesystem;
using testing::run_cli;

TEST(CliDesign, WritesThePlateTheShapesAndTheMetrics) {
  const fs::path dir = testing::scratch_dir() / "out";
  const auto r =
      run_cli({"design", "--example", "dome", "--width", "60", "--faces", "1", "-o", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Progress: one plain line per report when stdout is not a terminal.
  EXPECT_NE(r.out.find("optimize theta2: 1, objective"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("trajectories: 1/10"), std::string::npos) << r.out;
  const MeshFile flat = read_mesh(dir / "flat.ply");
  const MeshFile target = read_mesh(dir / "target.ply");
  const MeshFile simulated = read_mesh(dir / "simulated.ply");
  ASSERT_NE(flat.properties.find_face("theta1"), nullptr);
  const Eigen::VectorXd* theta2 = flat.properties.find_vertex("theta2");
  ASSERT_NE(theta2, nullptr);
  EXPECT_GT(theta2->cwiseAbs().maxCoeff(), 0);
  const Eigen::VectorXd* deviation = simulated.properties.find_vertex("deviation_mm");
  ASSERT_NE(deviation, nullptr);
  EXPECT_NEAR((*deviation)(0), (simulated.mesh.V.row(0) - target.mesh.V.row(0)).norm(), 1e-9);
  EXPECT_EQ(simulated.mesh.F, target.mesh.F);

  std::ifstream in(dir / "design.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  const nlohmann::json& m = j.at("metrics");
  for (const char* key : {"faces", "vertices", "t_prepare_s", "t_param_s", "t_optim_s", "t_traj_s",
                          "dist_to_sim_avg_pct", "dist_to_sim_max_pct", "dist_to_optim_avg_pct",
                          "dist_to_optim_max_pct", "theta2_max_abs_rad", "optim_iterations"}) {
    EXPECT_TRUE(m.contains(key)) << key;
  }
  EXPECT_EQ(m.at("faces").get<int>(), target.mesh.num_faces());
  EXPECT_LT(m.at("dist_to_optim_avg_pct").get<double>(), m.at("dist_to_sim_avg_pct").get<double>());
  EXPECT_NEAR(m.at("theta2_max_abs_rad").get<double>(), theta2->cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(j.at("width_mm").get<double>(), 60);
  EXPECT_TRUE(j.at("normal_side_down").get<bool>());  // a dome prints concave side up
  EXPECT_GT(m.at("print_time_s").get<double>(), 0);
  // The loop closed (issue 22): plate.gcode read back and simulated lands near the fields' shape.
  EXPECT_EQ(m.at("gcode_unprinted_faces").get<int>(), 0);
  EXPECT_TRUE(m.at("gcode_converged").get<bool>());
  EXPECT_EQ(m.at("sim_stop_reason"), "converged");
  EXPECT_EQ(m.at("gcode_sim_stop_reason"), "converged");
  EXPECT_LT(m.at("gcode_vs_fields_avg_pct").get<double>(), 1.0);
  EXPECT_LT(m.at("gcode_dist_avg_pct").get<double>(), m.at("dist_to_sim_avg_pct").get<double>());

  // The print files of issue 6: G-code and the layer previews.
  EXPECT_TRUE(fs::exists(dir / "plate.gcode"));
  EXPECT_TRUE(fs::exists(dir / "layers" / "layer_001.svg"));
  EXPECT_TRUE(fs::exists(dir / "layers" / "overview.png"));
  EXPECT_TRUE(fs::exists(dir / "report.html"));  // issue 8
  // Both predicted shapes, and the report shows the one plate.gcode prints next to the other.
  EXPECT_TRUE(fs::exists(dir / "gcode_simulated.ply"));
  EXPECT_NE(testing::read_file(dir / "report.html").find("\"gcode_predicted\""), std::string::npos);

  // --json: design.json on stdout, no progress. --stretch: the flattening starts where it is told.
  const int chosen_stretch = j.at("stretch_candidate").get<int>();
  const int other_stretch = (chosen_stretch + 1) % 4;
  // These options' wiring is what is checked: a coarse cap (512 faces) designs in a second.
  const fs::path cap = dir.parent_path() / "cap.obj";
  write_obj(cap, testing::grid_mesh(16, 16, [](double u, double v) {
              const double x = 60 * u - 30, y = 60 * v - 30;
              return Eigen::Vector3d(x, y, -(x * x + y * y) / 120);
            }));
  const fs::path dir2 = dir.parent_path() / "out2";
  const auto json_run =
      run_cli({"design", cap.string(), "--width", "60", "--faces", "1", "--no-gcode", "--json",
               "--stretch", std::to_string(other_stretch), "-o", dir2.string()});
  ASSERT_EQ(json_run.exit_code, 0) << json_run.err;
  const nlohmann::json summary = nlohmann::json::parse(json_run.out);
  EXPECT_EQ(summary.at("metrics").at("faces").get<int>(), 512);
  EXPECT_EQ(json_run.out.find("optimize theta2"), std::string::npos) << json_run.out;
  EXPECT_EQ(summary.at("stretch_candidate").get<int>(), other_stretch);
  EXPECT_EQ(summary.at("stretch").get<std::string>(), std::to_string(other_stretch));

  // --stretch all: every stretch's result in design.json, the lowest objective's plate kept.
  const fs::path dir3 = dir.parent_path() / "out3";
  const auto all_run = run_cli({"design", cap.string(), "--width", "60", "--faces", "1",
                                "--no-gcode", "--json", "--stretch", "all", "-o", dir3.string()});
  ASSERT_EQ(all_run.exit_code, 0) << all_run.err;
  const nlohmann::json all = nlohmann::json::parse(all_run.out);
  const nlohmann::json& explored = all.at("explored_stretches");
  ASSERT_EQ(explored.size(), 4u);
  int lowest = 0;
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(explored[k].at("stretch_candidate").get<int>(), k);
    if (explored[k].at("optim_objective").get<double>() <
        explored[lowest].at("optim_objective").get<double>()) {
      lowest = k;
    }
  }
  EXPECT_EQ(all.at("stretch_candidate").get<int>(), lowest);
  EXPECT_EQ(all.at("metrics").at("optim_objective").get<double>(),
            explored[lowest].at("optim_objective").get<double>());
}

TEST(CliDesign, BadOptionsExit2AndWriteNothing) {
  const fs::path dir = testing::scratch_dir() / "out";
  const std::vector<std::vector<std::string>> bad = {
      {"design", "--example", "dome", "--width", "-5", "-o", dir.string()},
      {"design", "--example", "dome", "--wD", "-1", "-o", dir.string()},
      {"design", "--example", "dome", "--faces", "0", "-o", dir.string()},
      {"design", "--example", "nosuch", "-o", dir.string()},
      {"design", "--example", "dome", "--material", "nosuch", "-o", dir.string()},
      {"design", (testing::scratch_dir() / "missing.obj").string(), "-o", dir.string()},
      {"design", "--example", "dome", "--side", "left", "-o", dir.string()},
      {"design", "--example", "dome", "--stretch", "4", "-o", dir.string()},
      {"design", "--example", "dome", "--printer", "nosuch", "-o", dir.string()},
      // 600 mm does not fit the default printer's 220 mm bed: refused before anything is written.
      {"design", "--example", "dome", "--width", "600", "--faces", "1", "-o", dir.string()},
  };
  for (const auto& args : bad) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args[2] << " " << args[3] << "\n" << r.err;
    EXPECT_FALSE(r.err.empty());
    EXPECT_FALSE(fs::exists(dir)) << args[2] << " " << args[3];
  }
}

}  // namespace
}  // namespace flatmorph::cli_design_test
