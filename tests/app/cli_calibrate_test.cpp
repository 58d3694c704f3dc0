// `flatmorph calibrate print` and `calibrate fit` as a user runs them: print, measure (here:
// synthetic measurements of known ratios), fit, and use the fitted material.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "material/material.h"
#include "test_support.h"

namespace flatmorph::cli_calibrate_test {
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

// The rows of a sheet with the after-heating columns filled from the named columns of each row:
// `after(row)` gives length_after, width_after, thickness_after.
std::string fill_by_name(
    const std::string& sheet,
    const std::function<std::array<double, 3>(const std::map<std::string, double>&)>& after) {
  std::istringstream in(sheet);
  std::string out;
  std::vector<std::string> names;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> c;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) c.push_back(cell);
    if (line.empty() || line[0] == '#' || names.empty()) {
      if (!line.empty() && line[0] != '#') names = c;
      out += line + "\n";
      continue;
    }
    std::map<std::string, double> row;
    for (size_t i = 0; i < c.size(); ++i) {
      if (!c[i].empty()) row[names[i]] = std::stod(c[i]);
    }
    const std::array<double, 3> a = after(row);
    for (size_t i = 0; i < names.size(); ++i) {
      const std::string& name = names[i];
      out += i ? "," : "";
      if (name == "length_after" || name == "width_after" || name == "thickness_after") {
        out += fmt::format("{:.6f}", a[name == "length_after" ? 0 : name == "width_after" ? 1 : 2]);
      } else if (i < c.size()) {
        out += c[i];
      }
    }
    out += "\n";
  }
  return out;
}

// A speed ramp printed, measured (lambda1 = 0.8 - 0.0015 v: faster shrinks more) and fitted, alone
// and beside an ordinary sheet; the material file's speed curve is read back by load_material.
TEST(CliCalibrate, SpeedRampAddsTheSpeedCurve) {
  const fs::path dir = testing::scratch_dir();
  const auto r =
      run_cli({"calibrate", "print", "--speed-ramp", "--printer", "prusa-mk4", "--material",
               "pla-paper", "--repeats", "2", "-o", (dir / "speed.gcode").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("6 speed-ramp sets"), std::string::npos) << r.out;
  const std::string sheet = testing::read_file(dir / "speed.csv");
  EXPECT_NE(sheet.find("# kind = speed-ramp\n"), std::string::npos);
  EXPECT_NE(sheet.find("layers,print_speed,length_before"), std::string::npos) << sheet;
  const auto check = run_cli({"check", (dir / "speed.gcode").string(), "--printer", "prusa-mk4",
                              "--material", "pla-paper"});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  // 150 mm/s, the fastest default speed, is printed as F9000 (mm/min).
  EXPECT_NE(testing::read_file(dir / "speed.gcode").find(" F9000\n"), std::string::npos);

  auto lambda1 = [](double v) { return 0.8 - 0.0015 * v; };
  std::ofstream(dir / "speed-measured.csv") << fill_by_name(sheet, [&](const auto& row) {
    return std::array<double, 3>{row.at("length_before") * lambda1(row.at("print_speed")),
                                 row.at("width_before") * 1.06, row.at("thickness_before") * 1.4};
  });
  const auto fit = run_cli({"calibrate", "fit", (dir / "speed-measured.csv").string(), "-o",
                            (dir / "fast-pla.json").string()});
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  EXPECT_NE(fit.out.find("speed curve: lambda1(v)"), std::string::npos) << fit.out;
  const Material m = load_material((dir / "fast-pla.json").string());
  ASSERT_TRUE(m.speed_curve.has_value());
  EXPECT_EQ(m.speed_curve->min_print_speed, 20);
  EXPECT_EQ(m.speed_curve->max_print_speed, 150);
  EXPECT_EQ(m.speed_curve->layer_height, 0.08);
  EXPECT_EQ(m.speed_curve->nozzle_temperature, 190);
  for (double v : {20.0, 55.0, 150.0}) {
    EXPECT_NEAR(lambda1_at_print_speed(*m.speed_curve, v), lambda1(v), 1e-6) << v;
  }
  // The set that shrinks most (150 mm/s) is written, with the speed it was measured at.
  EXPECT_EQ(m.print_speed, 150);
  EXPECT_NEAR(m.lambda1, lambda1(150), 1e-6);
  EXPECT_NEAR(printed_lambda1(m, 0.08, 60), lambda1(60), 1e-6);
  EXPECT_NE(testing::read_file(dir / "fast-pla.svg").find("print speed (mm/s)"), std::string::npos);

  // Beside an ordinary sheet: that sheet's set is written (at pla-paper's 30 mm/s, inside the
  // ramp), with the speed curve, and each sheet gets its plot.
  ASSERT_EQ(run_cli({"calibrate", "print", "--printer", "prusa-mk4", "--material", "pla-paper",
                     "--nozzle-temps", "190", "--layer-heights", "0.08", "--repeats", "2", "-o",
                     (dir / "sets.gcode").string()})
                .exit_code,
            0);
  std::ofstream(dir / "sets-measured.csv") << fill(testing::read_file(dir / "sets.csv"));
  const auto both =
      run_cli({"calibrate", "fit", (dir / "sets-measured.csv").string(),
               (dir / "speed-measured.csv").string(), "-o", (dir / "both.json").string()});
  ASSERT_EQ(both.exit_code, 0) << both.err;
  const Material b = load_material((dir / "both.json").string());
  ASSERT_TRUE(b.speed_curve.has_value());
  EXPECT_EQ(b.print_speed, 30);
  EXPECT_NEAR(b.lambda1, 0.58, 1e-3);  // fill(): set 1 shrinks to 0.56 + 0.02
  EXPECT_NE(testing::read_file(dir / "both.svg").find("layer height (mm)"), std::string::npos);
  EXPECT_NE(testing::read_file(dir / "both-speed.svg").find("print speed (mm/s)"),
            std::string::npos);

  // A ramp that leaves out the sets' 30 mm/s cannot scale their lambda1: refused, nothing written.
  ASSERT_EQ(run_cli({"calibrate", "print", "--speed-ramp", "--print-speeds", "40,80,120",
                     "--printer", "prusa-mk4", "--material", "pla-paper", "--repeats", "2", "-o",
                     (dir / "narrow.gcode").string()})
                .exit_code,
            0);
  std::ofstream(dir / "narrow-measured.csv")
      << fill_by_name(testing::read_file(dir / "narrow.csv"), [&](const auto& row) {
           return std::array<double, 3>{row.at("length_before") * lambda1(row.at("print_speed")),
                                        row.at("width_before") * 1.06,
                                        row.at("thickness_before") * 1.4};
         });
  const auto narrow =
      run_cli({"calibrate", "fit", (dir / "sets-measured.csv").string(),
               (dir / "narrow-measured.csv").string(), "-o", (dir / "narrow.json").string()});
  EXPECT_EQ(narrow.exit_code, 2);
  EXPECT_NE(narrow.err.find("print_speed 30 mm/s lies outside the calibrated range [40, 120]"),
            std::string::npos)
      << narrow.err;
  EXPECT_FALSE(fs::exists(dir / "narrow.json"));
}

TEST(CliCalibrate, SpeedRampRefusals) {
  const fs::path dir = testing::scratch_dir();
  auto refused = [&](std::vector<std::string> args, const std::string& says) {
    args.insert(args.begin(), {"calibrate", "print", "--material", "pla-paper", "-o",
                               (dir / "x.gcode").string()});
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.gcode"));
    EXPECT_FALSE(fs::exists(dir / "x.csv"));
  };
  refused({"--printer", "prusa-mk4", "--speed-ramp", "--thickness-ramp"},
          "--thickness-ramp and --speed-ramp");
  refused({"--printer", "prusa-mk4", "--speed-ramp", "--print-speeds", "30,250"},
          "250 mm/s is above 200 mm/s, the travel speed of printer");
  refused({"--printer", "prusa-mk4", "--print-speeds", "30,60"}, "add --speed-ramp");
  // The default speeds stop at a slower printer's travel speed (120 mm/s) instead.
  const auto r =
      run_cli({"calibrate", "print", "--speed-ramp", "--printer", "generic-marlin", "--material",
               "pla-paper", "--repeats", "1", "-o", (dir / "slow.gcode").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("5 speed-ramp sets"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("150 mm/s"), std::string::npos) << r.out;
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
}  // namespace flatmorph::cli_calibrate_test
