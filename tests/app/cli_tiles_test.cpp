// flatmorph tiles from the command line: the dome example writes the whole run folder with its
// profile plot, its G-code passes `flatmorph check`, a drawing and a layout are read, and bad
// requests are refused before any work with one line and exit status 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.h"

namespace flatmorph::cli_tiles_test {
namespace {

using testing::run_cli;

TEST(CliTiles, TheDomeWritesTheRunFolderAndAGcodeThatPassesTheCheck) {
  const std::filesystem::path dir = testing::scratch_dir() / "dome";
  const auto r = run_cli({"tiles", "--example", "dome", "-o", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"flat.ply", "flat.stack.json", "simulated.ply", "plate.gcode",
                           "toolpath.json", "design.json", "report.html", "profile_0.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  }
  std::ifstream in(dir / "design.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("method"), "tiles");
  const nlohmann::json& m = j.at("metrics");
  EXPECT_TRUE(m.at("sides_as_designed").get<bool>());
  EXPECT_EQ(m.at("max_paths_per_tile_pass").get<int>(), 1);
  EXPECT_LT(m.at("depth_error_max_pct").get<double>(), 3.0);
  EXPECT_GT(m.at("print_time_s").get<double>(), 0.0);
  // The cap's top needs less shrink than the material gives: clamped, and said once.
  EXPECT_TRUE(j.at("tiles").at(0).at("clamped").get<bool>());
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(testing::read_file(dir / "profile_0.svg").find("<svg"), std::string::npos);
  const auto check = run_cli({"check", (dir / "plate.gcode").string()});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

// A lattice's lines cover a sixth of a face in each layer (0.4 mm lines 2.5 mm apart): read back
// from plate.gcode they are still printed, so the G-code's prediction holds the whole network and
// not only its largest piece (it kept a third of the faces when a layer had to cover a quarter of
// a face); what is left out are the lattice's cells no line crosses. Both models see lines at
// their height covering their share (Layer::cover), and agree (they differed by 10-20 % of the
// diagonal when the stack thinned the lattice's layers instead).
TEST(CliTiles, TheBraceletsGcodePredictionHoldsItsLatticeAndAgreesWithTheStack) {
  const std::filesystem::path dir = testing::scratch_dir() / "bracelet";
  const auto r =
      run_cli({"tiles", "--example", "bracelet", "--mesh-edge", "2", "-o", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(dir / "design.json");
  const nlohmann::json m = nlohmann::json::parse(in).at("metrics");
  const int faces = m.at("faces").get<int>();
  EXPECT_GT(faces, 1000);
  EXPECT_LT(m.at("gcode_unprinted_faces").get<int>(), faces / 5);
  EXPECT_TRUE(m.at("gcode_converged").get<bool>());
  EXPECT_LT(m.at("gcode_vs_fields_avg_pct").get<double>(), 2.0);
}

TEST(CliTiles, ReadsALayoutWithADrawingAndPerTileSettings) {
  const std::filesystem::path scratch = testing::scratch_dir();  // emptied on every call
  const std::filesystem::path folder = scratch / "layout";
  std::filesystem::create_directories(folder);
  {
    std::ofstream dxf(folder / "two.dxf");
    dxf << "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n4\n0\nENDSEC\n"
           "0\nSECTION\n2\nENTITIES\n"
           "0\nCIRCLE\n8\n0\n10\n0\n20\n0\n30\n0\n40\n12\n"
           "0\nCIRCLE\n8\n0\n10\n40\n20\n0\n30\n0\n40\n12\n"
           "0\nENDSEC\n0\nEOF\n";
    std::ofstream json(folder / "layout.json");
    json << R"({"outlines": "two.dxf", "defaults": {"profile": "cone", "height": 6},
                "tiles": [{"index": 1, "side": "down"}]})";
  }
  const std::filesystem::path dir = scratch / "layout-out";
  const auto r =
      run_cli({"tiles", (folder / "layout.json").string(), "--no-gcode", "-o", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(dir / "design.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j.at("tiles").size(), 2u);
  EXPECT_EQ(j.at("tiles").at(0).at("risen_side"), "up");
  EXPECT_EQ(j.at("tiles").at(1).at("risen_side"), "down");
  EXPECT_FALSE(std::filesystem::exists(dir / "plate.gcode"));
}

TEST(CliTiles, RefusesBadRequestsBeforeAnyWork) {
  const std::filesystem::path scratch = testing::scratch_dir();
  const std::filesystem::path dir = scratch / "tiles-out";
  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  const std::filesystem::path missing = scratch / "missing.dxf";
  for (const Case& c : std::vector<Case>{
           {{"tiles", "-o", dir.string()}, "needs tiles"},
           {{"tiles", "--example", "teapot", "-o", dir.string()}, "dome, spin-top"},
           {{"tiles", "--example", "dome", "--side", "left", "-o", dir.string()}, "--side left"},
           {{"tiles", "--example", "dome", "--profile", "blob", "-o", dir.string()}, "blob"},
           {{"tiles", "--example", "dome", "--material", "pla-paper", "-o", dir.string()},
            "thickness curve"},
           {{"tiles", "--example", "dome", "--height", "50", "-o", dir.string()}, "height"},
           {{"tiles", "--example", "dome", "--strict", "-o", dir.string()}, "strict"},
           {{"tiles", missing.string(), "-o", dir.string()}, "missing.dxf"},
       }) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.says << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "design.json")) << c.says;
  }
}

}  // namespace
}  // namespace flatmorph::cli_tiles_test
