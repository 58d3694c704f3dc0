// `flatmorph calibrate print` and `calibrate fit` as a user runs them: print, measure (here:
// synthetic measurements of known ratios), fit, and use the fitted material.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "test_support.h"

namespace flatmorph {
namespace {

namespace fs = std::filesystem;
using testing::run_cli;

// Fills the after-heating columns of the template: set s shrinks to lambda1 = 0.56 + 0.02 s,
// lambda2 1.07, lambda3 1.5, curvature 0.03 /mm, with a small per-sample wobble.
std::string fill(const std::string& sheet) {
  std::istringstream in(sheet);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line.rfind("sample,", 0) == 0) {
      out += line + "\n";
      continue;
    }
    std::vector<std::string> c;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) c.push_back(cell);
    const int sample = std::stoi(c[0]), set = std::stoi(c[1]);
    const double wobble = 1 + 0.002 * ((sample % 3) - 1);
    const double l0 = std::stod(c[6]), w0 = std::stod(c[7]), t0 = std::stod(c[8]);
    out += fmt::format("{},{},{},{},{},{},{},{},{},{:.4f},{:.4f},{:.4f},{:.5f},,\n", c[0], c[1],
                       c[2], c[3], c[4], c[5], c[6], c[7], c[8], l0 * (0.56 + 0.02 * set) * wobble,
                       w0 * 1.07 * wobble, t0 * 1.5 * wobble, 0.03 * wobble);
  }
  return out;
}

TEST(CliCalibrate, PrintMeasureFit) {
  const fs::path dir = testing::scratch_dir();
  const auto r = run_cli({"calibrate", "print", "--printer", "creality-cr10s-pro", "--material",
                          "pla-paper", "--nozzle-temps", "190,200", "--layer-heights", "0.08,0.12",
                          "--repeats", "3", "-o", (dir / "calib.gcode").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(dir / "calib.gcode")) << r.out;
  ASSERT_TRUE(fs::exists(dir / "calib.csv"));
  ASSERT_TRUE(fs::exists(dir / "calib.svg"));
  // The G-code passes `flatmorph check` and sets each temperature.
  const auto check = run_cli({"check", (dir / "calib.gcode").string(), "--printer",
                              "creality-cr10s-pro", "--material", "pla-paper"});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  const std::string gcode = testing::read_file(dir / "calib.gcode");
  EXPECT_NE(gcode.find("M109 S200"), std::string::npos);
  EXPECT_NE(testing::read_file(dir / "calib.svg").find("#12 (set 4)"), std::string::npos);

  std::ofstream(dir / "measured.csv") << fill(testing::read_file(dir / "calib.csv"));
  const auto fit = run_cli(
      {"calibrate", "fit", (dir / "measured.csv").string(), "-o", (dir / "my-pla.json").string()});
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  EXPECT_NE(fit.out.find("<- written"), std::string::npos) << fit.out;
  const nlohmann::json m = nlohmann::json::parse(testing::read_file(dir / "my-pla.json"));
  // Set 1 (190 C, 0.08 mm) contracts most: lambda1 0.58.
  EXPECT_EQ(m["name"], "my-pla");
  EXPECT_NEAR(m["lambda1"].get<double>(), 0.58, 1e-3);
  EXPECT_NEAR(m["lambda2"].get<double>(), 1.07, 1e-3);
  EXPECT_NEAR(m["lambda3"].get<double>(), 1.5, 1e-3);
  EXPECT_NEAR(m["delta_lambda1"].get<double>(), -0.8 * 1.5 * 0.58 * 0.03, 2e-4);
  EXPECT_EQ(m["nozzle_temperature"].get<double>(), 190);
  EXPECT_EQ(m["layer_height"].get<double>(), 0.08);
  EXPECT_EQ(m["bed_temperature"].get<double>(), 55);  // from pla-paper, as printed
  EXPECT_TRUE(fs::exists(dir / "my-pla.svg"));
  // The file is a material everywhere --material is accepted.
  const auto show = run_cli({"check", (dir / "calib.gcode").string(), "--printer",
                             "creality-cr10s-pro", "--material", (dir / "my-pla.json").string()});
  EXPECT_EQ(show.exit_code, 0) << show.out << show.err;

  // --set picks another one.
  const auto fit3 = run_cli({"calibrate", "fit", (dir / "measured.csv").string(), "--set", "3",
                             "-o", (dir / "set3.json").string()});
  ASSERT_EQ(fit3.exit_code, 0) << fit3.err;
  const nlohmann::json m3 = nlohmann::json::parse(testing::read_file(dir / "set3.json"));
  EXPECT_NEAR(m3["lambda1"].get<double>(), 0.62, 1e-3);
  EXPECT_EQ(m3["nozzle_temperature"].get<double>(), 200);

  // The fitted material drives a design when `design` exists.
  const auto help = run_cli({"design", "--help"});
  if (help.exit_code == 0) {
    const auto d =
        run_cli({"design", "--example", "saddle", "--faces", "300", "--width", "60", "--material",
                 (dir / "my-pla.json").string(), "-o", (dir / "design").string()});
    ASSERT_EQ(d.exit_code, 0) << d.err;
    const nlohmann::json j =
        nlohmann::json::parse(testing::read_file(dir / "design" / "design.json"));
    const std::string text = j.dump();
    // The material's values, in a "material" object or at the top level.
    const nlohmann::json& used = j["material"].is_object() ? j["material"] : j;
    EXPECT_EQ(j["material"].is_object() ? used["name"] : j["material"], "my-pla") << text;
    for (const char* key : {"lambda1", "lambda2", "lambda3", "delta_lambda1"}) {
      ASSERT_TRUE(used.contains(key)) << key << " " << text;
      EXPECT_EQ(used[key].get<double>(), m[key].get<double>()) << key << " " << text;
    }
  }
}

TEST(CliCalibrate, SeveralFilesWhenTheSetsDoNotFitTheBed) {
  const fs::path dir = testing::scratch_dir();
  const auto r = run_cli({"calibrate", "print", "--printer", "creality-ender3-v2", "--material",
                          "pla-paper", "-o", (dir / "calib.gcode").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "calib.gcode"));
  for (const char* f : {"calib-1.gcode", "calib-2.gcode", "calib.csv", "calib.svg"}) {
    EXPECT_TRUE(fs::exists(dir / f)) << f << "\n" << r.out;
  }
  for (int i = 1; fs::exists(dir / fmt::format("calib-{}.gcode", i)); ++i) {
    const auto check = run_cli({"check", (dir / fmt::format("calib-{}.gcode", i)).string(),
                                "--printer", "creality-ender3-v2", "--material", "pla-paper"});
    EXPECT_EQ(check.exit_code, 0) << check.out;
  }
}

TEST(CliCalibrate, ThicknessRampAddsTheCurve) {
  const fs::path dir = testing::scratch_dir();
  const auto r =
      run_cli({"calibrate", "print", "--thickness-ramp", "--printer", "prusa-mk4", "--material",
               "pla-paper", "--repeats", "2", "-o", (dir / "ramp.gcode").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // lambda1 = 0.45 + 1.2 h on 6-layer samples.
  std::istringstream in(testing::read_file(dir / "ramp.csv"));
  std::string filled;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line.rfind("sample,", 0) == 0) {
      filled += line + "\n";
      continue;
    }
    std::vector<std::string> c;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) c.push_back(cell);
    const double h = std::stod(c[4]);
    filled += fmt::format("{},{},{},{},{},{},{},{},{},{:.5f},{:.3f},{:.4f},,,\n", c[0], c[1], c[2],
                          c[3], c[4], c[5], c[6], c[7], c[8], 80 * (0.45 + 1.2 * h), 20 * 1.06,
                          std::stod(c[8]) * 1.4);
  }
  std::ofstream(dir / "ramp-measured.csv") << filled;
  const auto fit = run_cli({"calibrate", "fit", (dir / "ramp-measured.csv").string(), "-o",
                            (dir / "ramp-pla.json").string()});
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  const nlohmann::json m = nlohmann::json::parse(testing::read_file(dir / "ramp-pla.json"));
  ASSERT_TRUE(m.contains("thickness_curve")) << m.dump(2);
  EXPECT_EQ(m["thickness_curve"]["min_layer_height"].get<double>(), 0.08);
  EXPECT_EQ(m["thickness_curve"]["max_layer_height"].get<double>(), 0.28);
  EXPECT_EQ(m["thickness_curve"]["layers"].get<int>(), 6);
  EXPECT_NEAR(m["lambda1"].get<double>(), 0.45 + 1.2 * 0.08, 1e-4);  // the best: thinnest
}

TEST(CliCalibrate, BadMeasurementsGiveOneLineNamingLineAndColumn) {
  const fs::path dir = testing::scratch_dir();
  ASSERT_EQ(run_cli({"calibrate", "print", "--printer", "creality-cr10s-pro", "--material",
                     "pla-paper", "--nozzle-temps", "190", "--layer-heights", "0.08", "--repeats",
                     "2", "-o", (dir / "c.gcode").string()})
                .exit_code,
            0);
  std::string sheet = fill(testing::read_file(dir / "c.csv"));
  // Empty the width_after of the last row.
  const size_t last = sheet.rfind('\n', sheet.size() - 2) + 1;
  std::vector<std::string> c;
  std::stringstream ls(sheet.substr(last));
  for (std::string cell; std::getline(ls, cell, ',');) c.push_back(cell);
  c[10] = "";
  std::string row;
  for (size_t i = 0; i < c.size(); ++i) row += (i ? "," : "") + c[i];
  sheet = sheet.substr(0, last) + row;
  std::ofstream(dir / "bad.csv") << sheet;
  const int line = static_cast<int>(std::count(sheet.begin(), sheet.end(), '\n'));
  const auto fit =
      run_cli({"calibrate", "fit", (dir / "bad.csv").string(), "-o", (dir / "out.json").string()});
  EXPECT_EQ(fit.exit_code, 2);
  EXPECT_EQ(std::count(fit.err.begin(), fit.err.end(), '\n'), 1) << fit.err;
  EXPECT_NE(fit.err.find(fmt::format("bad.csv: line {}, column 11 (width_after)", line)),
            std::string::npos)
      << fit.err;
  EXPECT_FALSE(fs::exists(dir / "out.json"));

  // Options out of range: one line, nothing written.
  const auto hot =
      run_cli({"calibrate", "print", "--printer", "creality-cr10s-pro", "--material", "pla-paper",
               "--nozzle-temps", "260", "-o", (dir / "hot.gcode").string()});
  EXPECT_EQ(hot.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "hot.gcode"));
  EXPECT_FALSE(fs::exists(dir / "hot.csv"));
}

}  // namespace
}  // namespace flatmorph
