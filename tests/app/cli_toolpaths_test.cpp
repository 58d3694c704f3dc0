// `flatmorph toolpaths` on a plate written by `flatmorph flatten`, as a user runs it.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "test_support.h"

namespace flatmorph::cli_toolpaths_test {
namespace {

namespace fs = std::filesystem;
using testing::run_cli;

fs::path flatten_dome(const fs::path& dir, const std::string& layers = "10") {
  const auto r = run_cli({"flatten", "--example", "dome", "--width", "40", "--faces", "1000",
                          "--layers", layers, "-o", (dir / "design").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return dir / "design";
}

TEST(CliToolpaths, WritesCheckedGcodeAndLayerPictures) {
  const fs::path dir = testing::scratch_dir();
  const fs::path design = flatten_dome(dir, "4");  // the stack file says 4 layers
  const auto r = run_cli({"toolpaths", (design / "flat.ply").string(), "--printer", "prusa-mk3s",
                          "-o", (dir / "print").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("shorter than greedy nearest neighbour"), std::string::npos) << r.out;
  for (const char* f :
       {"plate.gcode", "layers/layer_001.svg", "layers/layer_004.svg", "layers/overview.png"}) {
    EXPECT_TRUE(fs::exists(dir / "print" / f)) << f;
  }
  EXPECT_FALSE(fs::exists(dir / "print" / "layers" / "layer_005.svg"));
  // The G-code passes the independent safety check of `flatmorph check` and has 4 layers.
  const auto check = run_cli({"check", (dir / "print" / "plate.gcode").string(), "--printer",
                              "prusa-mk3s", "--material", "pla-paper"});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  std::ifstream in(dir / "print" / "plate.gcode");
  std::stringstream text;
  text << in.rdbuf();
  int layer_changes = 0;
  for (size_t at = 0; (at = text.str().find(";LAYER_CHANGE", at)) != std::string::npos; ++at) {
    ++layer_changes;
  }
  EXPECT_EQ(layer_changes, 4);
}

TEST(CliToolpaths, RefusesAPlateOffTheBedAndWritesNothing) {
  const fs::path dir = testing::scratch_dir();
  const fs::path design = flatten_dome(dir, "2");
  const auto r =
      run_cli({"toolpaths", (design / "flat.ply").string(), "--printer", "creality-ender3-v2",
               "--at", "1000,1000", "-o", (dir / "print").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "print"));
}

TEST(CliToolpaths, BadOptionsGiveOneLineErrors) {
  const fs::path dir = testing::scratch_dir();
  const fs::path design = flatten_dome(dir);
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--printer", "no-such-printer"},
        // The plate's stack file decides its layers.
        std::vector<std::string>{"--printer", "prusa-mk3s", "--layers", "4"},
        std::vector<std::string>{"--printer", "prusa-mk3s", "--spacing", "-1"}}) {
    std::vector<std::string> args = {"toolpaths", (design / "flat.ply").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    args.insert(args.end(), {"-o", (dir / "print").string()});
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_FALSE(fs::exists(dir / "print"));
  }
}

}  // namespace
}  // namespace flatmorph::cli_toolpaths_test
