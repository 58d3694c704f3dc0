// flatmorph origami from the command line (issue 27): a built-in solid writes the whole run folder
// whose G-code passes `flatmorph check` on a two-tool printer and, with pauses, on a one-tool one;
// the crease pattern it writes reads back as a drawn pattern; a mesh that cannot fold is refused
// with one line naming its triangles, and nothing is written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "test_support.h"

namespace flatmorph::cli_origami_test {
namespace {

using testing::run_cli;

TEST(CliOrigami, TheCubeWritesTheRunFolderAndAGcodeThatPassesTheCheck) {
  const std::filesystem::path scratch = testing::scratch_dir();
  const std::filesystem::path dir = scratch / "cube";
  const auto r = run_cli({"origami", "--example", "cube", "--no-slicer", "-o", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"net.svg", "crease_pattern.svg", "pattern.fold", "simulated.ply",
                           "flat.ply", "flat.stack.json", "solid.obj", "plate.gcode",
                           "toolpath.json", "design.json", "report.html"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  }
  std::ifstream in(dir / "design.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("method"), "origami");
  EXPECT_EQ(j.at("hinge_curve"), "uncalibrated default");
  EXPECT_EQ(j.at("drawings"), nlohmann::json::array({"net.svg"}));  // shown in the report
  EXPECT_NE(testing::read_file(dir / "report.html").find("net.svg"), std::string::npos);
  const nlohmann::json& m = j.at("metrics");
  EXPECT_EQ(m.at("hinges").get<int>(), 5);
  EXPECT_LT(m.at("sharp_fold_error_pct").get<double>(), 0.1);
  EXPECT_LT(m.at("curved_plane_error_pct").get<double>(), 1e-4);
  EXPECT_FALSE(m.at("collision").get<bool>());
  EXPECT_EQ(m.at("tool_changes").get<int>(), 1);  // case A: TPU only in the last layer
  // The paper saves 60-87 % of the time against printing the solid.
  EXPECT_GT(m.at("time_saving_pct").get<double>(), 30);
  const nlohmann::json& hinge = j.at("sheets").at(0).at("hinges").at(0);
  EXPECT_NEAR(hinge.at("fold_angle_deg").get<double>(), -90, 1e-9);
  EXPECT_EQ(hinge.at("case"), "A");
  EXPECT_NEAR(hinge.at("width_mm").get<double>(),
              hinge.at("radius_mm").get<double>() * 3.14159265358979 / 2, 1e-9);
  const auto check = run_cli({"check", (dir / "plate.gcode").string(), "--printer", "prusa-xl-2t"});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;

  // The G-code on its own predicts with the PLA the design modelled (its header's shrink model:
  // the actuators' λ1 from their speed, no growth across), not pla-generic's Shrink & Morph
  // ratios (λ2 1.08, which curled the sheet and never settled).
  const auto simulated = run_cli({"simulate", (dir / "plate.gcode").string(), "--resolution", "4",
                                  "-o", (scratch / "from-gcode" / "cube.ply").string()});
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  EXPECT_NE(simulated.out.find("with the shrink ratios and curves it was designed with"),
            std::string::npos)
      << simulated.out;
  std::ifstream stack_in(scratch / "from-gcode" / "cube" / "flat.stack.json");
  const nlohmann::json stack = nlohmann::json::parse(stack_in);
  const nlohmann::json& pla = stack.at("materials").at(0);
  EXPECT_EQ(pla.at("name"), "pla-generic");
  EXPECT_EQ(pla.at("lambda2").get<double>(), 1.0);
  EXPECT_TRUE(pla.contains("speed_curve"));

  // The drawn pattern it wrote folds the same way: the forward flow.
  const std::filesystem::path drawn = scratch / "cube-drawn";
  const auto again = run_cli(
      {"origami", (dir / "crease_pattern.svg").string(), "--no-slicer", "-o", drawn.string()});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  std::ifstream in2(drawn / "design.json");
  const nlohmann::json k = nlohmann::json::parse(in2);
  EXPECT_EQ(k.at("metrics").at("hinges").get<int>(), 5);
  EXPECT_EQ(k.at("sheets").at(0).at("faces").get<int>(), 6);
}

// --simulate judges the sheet with the shared simulator, from its layers and from its G-code:
// each hinge's angles in design.json, the worst in the summary (two 30 mm faces and a 90°
// mountain: 1.3° off from the layers, 4.4° from the G-code, whose bonding margins bend too).
TEST(CliOrigami, SimulateJudgesEachHingeFromTheLayersAndFromTheGcode) {
  const std::filesystem::path scratch = testing::scratch_dir();
  std::ofstream(scratch / "two.svg")
      << ("<svg xmlns='http://www.w3.org/2000/svg' width='60mm' height='30mm' viewBox='0 0 60 30'>"
          "<polygon points='0,0 60,0 60,30 0,30' stroke='#000000' fill='none'/>"
          "<line x1='30' y1='0' x2='30' y2='30' stroke='#ff0000' data-fold-angle='-90'/></svg>");
  const auto r = run_cli({"origami", (scratch / "two.svg").string(), "--simulate", "--mesh-edge",
                          "2", "--no-slicer", "-o", (scratch / "two").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("simulated (the shared simulator, from the design's layers and from the "
                       "G-code): the worst hinge "),
            std::string::npos)
      << r.out;
  std::ifstream in(scratch / "two" / "design.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  const nlohmann::json& hinge = j.at("sheets").at(0).at("hinges").at(0);
  EXPECT_NEAR(hinge.at("simulated_angle_deg").get<double>(), -90, 5);
  EXPECT_NEAR(hinge.at("gcode_simulated_angle_deg").get<double>(), -90, 5);
  EXPECT_NEAR(j.at("metrics").at("sim_hinge_error_max_rad").get<double>(),
              std::abs(hinge.at("simulated_angle_deg").get<double>() + 90) * 3.14159265358979 / 180,
              1e-9);
}

TEST(CliOrigami, AOneToolPrinterPausesForTheTpuAndThePrintPassesTheCheck) {
  const std::filesystem::path dir = testing::scratch_dir() / "octahedron-mk4";
  const auto r = run_cli({"origami", "--example", "octahedron", "--printer", "prusa-mk4",
                          "--no-slicer", "-o", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string gcode = testing::read_file(dir / "plate.gcode");
  EXPECT_NE(gcode.find("M600"), std::string::npos);
  const auto check = run_cli({"check", (dir / "plate.gcode").string(), "--printer", "prusa-mk4",
                              "--material", "pla-generic,tpu-generic"});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  // And one file per material for printers that cannot pause: PLA, then TPU in the last layer.
  for (const char* part : {"plate-F1.gcode", "plate-F2.gcode"}) {
    const auto each = run_cli({"check", (dir / part).string(), "--printer", "prusa-mk4"});
    EXPECT_EQ(each.exit_code, 0) << part << ": " << each.out << each.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "plate-F3.gcode"));
}

// A solid whose net is larger than the bed is cut into nets that fit, and nets that do not fit one
// bed together are printed as several jobs: plate.gcode, plate_2.gcode, ..., each safe to print.
TEST(CliOrigami, SheetsThatDoNotFitOneBedPrintAsSeveralJobs) {
  const std::filesystem::path dir = testing::scratch_dir() / "icosahedron";
  const auto r = run_cli({"origami", "--example", "icosahedron", "--size", "130", "--printer",
                          "prusa-mk4", "--no-slicer", "-o", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(dir / "design.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  const int beds = j.at("metrics").at("beds").get<int>();
  EXPECT_GE(beds, 2);
  std::set<int> used;
  for (const nlohmann::json& sheet : j.at("sheets")) {
    const int bed = sheet.at("bed").get<int>();
    used.insert(bed);
    EXPECT_EQ(sheet.at("gcode"),
              bed == 1 ? "plate.gcode" : "plate_" + std::to_string(bed) + ".gcode");
  }
  EXPECT_EQ(static_cast<int>(used.size()), beds);
  for (int bed = 1; bed <= beds; ++bed) {
    const std::string name = bed == 1 ? "plate.gcode" : "plate_" + std::to_string(bed) + ".gcode";
    ASSERT_TRUE(std::filesystem::exists(dir / name)) << name;
    const auto check = run_cli({"check", (dir / name).string(), "--printer", "prusa-mk4"});
    EXPECT_EQ(check.exit_code, 0) << name << check.out << check.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / ("plate_" + std::to_string(beds + 1) + ".gcode")));
}

TEST(CliOrigami, RefusesMeshesThatCannotFoldAndBadRequestsBeforeAnyWork) {
  const std::filesystem::path scratch = testing::scratch_dir();
  const std::filesystem::path dir = scratch / "origami-out";
  // Three triangles on one edge: no sheet folds into that.
  const std::filesystem::path fin = scratch / "fin.obj";
  {
    std::ofstream out(fin);
    out << "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 -10 0\nv 0 0 10\n"
           "f 1 2 3\nf 2 1 4\nf 1 2 5\n";
  }
  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  for (const Case& c : std::vector<Case>{
           {{"origami", "-o", dir.string()}, "needs a solid"},
           {{"origami", "--example", "teapot", "-o", dir.string()}, "tetrahedron"},
           {{"origami", "--example", "cube", "--faces", "2", "-o", dir.string()}, "--faces 2"},
           {{"origami", "--example", "cube", "--actuator-speed", "0", "-o", dir.string()},
            "--actuator-speed"},
           {{"origami", "--example", "cube", "--simulate", "--mesh-edge", "0.1", "-o",
             dir.string()},
            "--mesh-edge 0.1"},
           {{"origami", "--example", "cube", "--fit-hinges", "99", "-o", dir.string()},
            "--fit-hinges 99"},
           {{"origami", fin.string(), "-o", dir.string()}, "triangles 0, 1 and 2"},
           {{"origami", "--example", "cube", "--size", "10", "-o", dir.string()},
            "scale the pattern"},
       }) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.says << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "design.json")) << c.says;
  }
}

}  // namespace
}  // namespace flatmorph::cli_origami_test
