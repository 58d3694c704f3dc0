// flatmorph heightfield from the command line: a small hill with a checkerboard texture writes the
// whole run folder, its G-code passes `flatmorph check`, and bad requests are refused before any
// work with one line and exit status 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.h"

namespace flatmorph::cli_heightfield_test {
namespace {

using testing::run_cli;

TEST(CliHeightField, WritesTheRunFolderAndAGcodeThatPassesTheCheck) {
  const std::filesystem::path dir = testing::scratch_dir() / "hill";
  const auto r = run_cli({"heightfield", "--example", "hill", "--diameter", "80", "--height", "18",
                          "--checkerboard", "10", "--dpi", "100", "-o", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"flat.ply", "flat.stack.json", "target.ply", "simulated.ply",
                           "gcode_simulated.ply", "plate.gcode", "toolpath.json", "texture.png",
                           "design.json", "report.html", "plate_shrinkage.png"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  }
  std::ifstream in(dir / "design.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("method"), "heightfield");
  const nlohmann::json& m = j.at("metrics");
  EXPECT_LE(m.at("invalid_edges_pct").get<double>(), 5.0);
  EXPECT_LT(m.at("dist_avg_pct").get<double>(), 2.0);
  EXPECT_GT(m.at("print_time_s").get<double>(), 0.0);
  EXPECT_EQ(m.at("traces").get<int>(), 1);
  EXPECT_EQ(j.at("texture_marks_mm").size(), 3u);
  // The stack file names the per-face layer heights the paths print.
  EXPECT_NE(testing::read_file(dir / "flat.stack.json").find("layer_height"), std::string::npos);
  const auto check = run_cli({"check", (dir / "plate.gcode").string()});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_NE(r.out.find("risen shape"), std::string::npos) << r.out;
}

TEST(CliHeightField, RefusesBadRequestsBeforeAnyWork) {
  const std::filesystem::path dir = testing::scratch_dir() / "out";
  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  const std::filesystem::path png = testing::scratch_dir() / "bump.png";
  for (const Case& c : std::vector<Case>{
           {{"heightfield", "-o", dir.string()}, "needs a height field"},
           {{"heightfield", "--example", "volcano", "-o", dir.string()}, "hill, saddle, island"},
           {{"heightfield", png.string(), "-o", dir.string()}, "--size WxD"},
           {{"heightfield", png.string(), "--size", "100", "--height", "10", "-o", dir.string()},
            "--size 100"},
           {{"heightfield", "--example", "hill", "--material", "pla-paper", "-o", dir.string()},
            "thickness curve"},
           {{"heightfield", "--example", "hill", "--lu", "0", "-o", dir.string()}, "--lu 0"},
       }) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.says << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "design.json")) << c.says;
  }
}

}  // namespace
}  // namespace flatmorph::cli_heightfield_test
