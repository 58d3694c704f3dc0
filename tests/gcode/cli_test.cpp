// flatmorph printers, materials and check, run as a user would.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "gcode/gcode_writer.h"
#include "gcode_fixtures.h"
#include "test_support.h"

namespace flatmorph::cli_test {
namespace {

using testing::run_cli;

TEST(CliPrinters, ListsEveryPreset) {
  const testing::CliResult r = run_cli({"printers"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string& name : printer_preset_names()) {
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
  }
  EXPECT_NE(r.out.find("300 x 300 x 400 mm"), std::string::npos);  // the CR-10S Pro
}

TEST(CliPrinters, Json) {
  const testing::CliResult r = run_cli({"printers", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.size(), printer_preset_names().size());
  for (const auto& p : j) {
    EXPECT_TRUE(p.contains("name") && p.contains("bed") && p.contains("nozzle_diameter"));
    EXPECT_GT(p["bed"]["size"][0].get<double>(), 0);
  }
}

TEST(CliPrinters, PrintsOnePresetToStartFrom) {
  const testing::CliResult r = run_cli({"printers", "prusa-mk4"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // What it prints is a valid profile once saved to a file.
  const std::filesystem::path path = testing::scratch_dir() / "mine.json";
  std::ofstream(path) << r.out;
  EXPECT_EQ(load_printer(path.string()).bed_size, Eigen::Vector2d(250, 210));
  const testing::CliResult bad = run_cli({"printers", "prusa-mk5"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("unknown printer \"prusa-mk5\""), std::string::npos) << bad.err;
}

TEST(CliMaterials, ListsAndJson) {
  const testing::CliResult r = run_cli({"materials"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("pla-paper"), std::string::npos);
  EXPECT_NE(r.out.find("0.58 / 1.08 / 1.52"), std::string::npos);
  const testing::CliResult j = run_cli({"materials", "--json"});
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const nlohmann::json list = nlohmann::json::parse(j.out);
  EXPECT_EQ(list.size(), material_preset_names().size());
  EXPECT_EQ(list[0]["name"], material_preset_names()[0]);
  const testing::CliResult one = run_cli({"materials", "pla-paper"});
  EXPECT_EQ(nlohmann::json::parse(one.out)["lambda1"], 0.58);
}

TEST(CliCheck, FlagsAnUnsafeFile) {
  const std::string file =
      (testing::test_data_dir() / "gcode" / "unsafe" / "nozzle_too_hot.gcode").string();
  const testing::CliResult r = run_cli({"check", file, "--printer", "generic-marlin"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find(file + ":14: nozzle-temperature: nozzle (T0) set to 260 C"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("unsafe"), std::string::npos);
}

TEST(CliCheck, PassesWhatFlatmorphWrites) {
  const std::filesystem::path path = testing::scratch_dir() / "plate.gcode";
  write_gcode(path, testing::disk_toolpath(30, 3), load_printer("bambu-p1s"),
              {load_material("pla-generic")});
  const testing::CliResult r =
      run_cli({"check", path.string(), "--printer", "bambu-p1s", "--material", "pla-generic"});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("safe for bambu-p1s with pla-generic"), std::string::npos);
  // Its header names the printer and the material: nothing more is needed.
  const testing::CliResult own = run_cli({"check", path.string()});
  EXPECT_EQ(own.exit_code, 0) << own.out << own.err;
  EXPECT_NE(own.out.find("safe for bambu-p1s with pla-generic (materials from the file's header)"),
            std::string::npos)
      << own.out;
}

TEST(CliCheck, BadArguments) {
  const testing::CliResult missing = run_cli({"check", "nowhere.gcode", "--printer", "bambu-p1s"});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("nowhere.gcode: cannot open"), std::string::npos) << missing.err;
  const testing::CliResult no_printer = run_cli({"check", "nowhere.gcode"});
  EXPECT_EQ(no_printer.exit_code, 2);
  // A file that does not name its printer needs --printer.
  const std::filesystem::path bare = testing::scratch_dir() / "bare.gcode";
  std::ofstream(bare) << "M83\nG1 X1 Y1 F600\nM84\n";
  const testing::CliResult unnamed = run_cli({"check", bare.string()});
  EXPECT_EQ(unnamed.exit_code, 2);
  EXPECT_NE(unnamed.err.find("does not name its printer: give --printer"), std::string::npos)
      << unnamed.err;
  const testing::CliResult bad_material =
      run_cli({"check", "nowhere.gcode", "--printer", "bambu-p1s", "--material", "abs"});
  EXPECT_EQ(bad_material.exit_code, 2);
  EXPECT_NE(bad_material.err.find("unknown material \"abs\""), std::string::npos);
}

}  // namespace
}  // namespace flatmorph::cli_test
