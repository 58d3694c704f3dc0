// Printer profiles: the shipped presets are complete and consistent; each kind of mistake in a
// user's profile gets its own message naming the file, the key and the fix.
#include "gcode/printer_profile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/embedded_profiles.h"
#include "common/error.h"
#include "test_support.h"

namespace flatmorph::printer_profile_test {
namespace {

using nlohmann::json;

json preset_json(const std::string& name) {
  for (const EmbeddedProfile& p : embedded_profiles()) {
    if (p.kind == "printers" && p.name == name) return json::parse(p.text);
  }
  throw std::runtime_error("no preset " + name);
}

// The message of the UserError(kProfile) that parsing `j` throws, or "" if it parses.
std::string profile_error(const json& j) {
  try {
    parse_printer(j.dump(), "my-printer.json");
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kProfile) << e.what();
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("my-printer.json: ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  return "";
}

TEST(PrinterProfile, EveryPresetLoadsAndIsConsistent) {
  const std::vector<std::string> names = printer_preset_names();
  ASSERT_GE(names.size(), 9u);
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const PrinterProfile p = load_printer(name);
    EXPECT_EQ(p.name, name);  // the file name and the "name" key agree
    EXPECT_FALSE(p.description.empty());
    EXPECT_GT(p.bed_size.minCoeff(), 100);
    EXPECT_GT(p.max_height, 100);
    EXPECT_EQ(p.nozzle_diameter, 0.4);
    EXPECT_EQ(p.filament_diameter, 1.75);
    EXPECT_TRUE(on_bed(p, bed_center(p), 0));
    EXPECT_NE(p.start_gcode.find("{nozzle_temperature}"), std::string::npos);
    // The firmware dialect and E mode fit together: Bambu printers want relative E.
    if (p.flavor == GcodeFlavor::kBambu) {
      EXPECT_TRUE(p.relative_e);
    }
  }
}

TEST(PrinterProfile, PresetsDescribeTheRealMachines) {
  const PrinterProfile cr10 = load_printer("creality-cr10s-pro");
  EXPECT_EQ(cr10.bed_size, Eigen::Vector2d(300, 300));
  EXPECT_EQ(cr10.max_height, 400);
  EXPECT_EQ(cr10.flavor, GcodeFlavor::kMarlin);
  const PrinterProfile x1c = load_printer("bambu-x1c");
  EXPECT_EQ(x1c.bed_size, Eigen::Vector2d(256, 256));
  EXPECT_EQ(x1c.flavor, GcodeFlavor::kBambu);
  EXPECT_EQ(load_printer("creality-k1-max").flavor, GcodeFlavor::kKlipper);
  EXPECT_EQ(load_printer("prusa-mk3s").axis_min.y(), -4);  // the purge line runs at y = -3
  const PrinterProfile delta = load_printer("generic-delta");
  EXPECT_EQ(delta.bed_shape, BedShape::kCircular);
  EXPECT_TRUE(delta.origin_at_center);
  EXPECT_TRUE(on_bed(delta, {70, 70}, 0));
  EXPECT_FALSE(on_bed(delta, {75, 75}, 0));  // inside the 200 mm square, outside the circle
  EXPECT_EQ(describe_bed(delta), "200 mm round x 300 mm high, centre origin");
  // Klipper's square_corner_velocity becomes a junction deviation: scv^2 (sqrt(2) - 1) / a.
  const PrinterProfile klipper = load_printer("generic-klipper");
  EXPECT_NEAR(klipper.junction_deviation, 25 * (std::sqrt(2.0) - 1) / 3000, 1e-15);
}

TEST(PrinterProfile, MissingKey) {
  json j = preset_json("generic-marlin");
  j.erase("nozzle_diameter");
  EXPECT_NE(profile_error(j).find("missing key \"nozzle_diameter\""), std::string::npos);
  j = preset_json("generic-marlin");
  j["retraction"].erase("speed");
  EXPECT_NE(profile_error(j).find("missing key \"retraction.speed\""), std::string::npos);
}

TEST(PrinterProfile, WrongType) {
  json j = preset_json("generic-marlin");
  j["bed"]["size"] = "220x220";
  EXPECT_NE(profile_error(j).find("\"bed.size\" must be two numbers"), std::string::npos);
  j = preset_json("generic-marlin");
  j["filament_diameter"] = "1.75";
  EXPECT_NE(profile_error(j).find("\"filament_diameter\" must be a number"), std::string::npos);
  j = preset_json("generic-marlin");
  j["relative_e"] = 1;
  EXPECT_NE(profile_error(j).find("\"relative_e\" must be true or false"), std::string::npos);
  j = preset_json("generic-marlin");
  j["start_gcode"] = 42;
  EXPECT_NE(profile_error(j).find("\"start_gcode\" must be an array of G-code lines"),
            std::string::npos);
}

TEST(PrinterProfile, NegativeOrZeroSize) {
  json j = preset_json("generic-marlin");
  j["bed"]["size"] = {-220, 220};
  EXPECT_NE(profile_error(j).find("\"bed.size\" is -220 (a negative value)"), std::string::npos);
  j = preset_json("generic-marlin");
  j["bed"]["size"] = {0, 220};
  EXPECT_NE(profile_error(j).find("the bed size must be positive"), std::string::npos);
  j = preset_json("generic-marlin");
  j["retraction"]["length"] = -1;
  EXPECT_NE(profile_error(j).find("\"retraction.length\" is -1 (a negative value)"),
            std::string::npos);
}

TEST(PrinterProfile, UnknownFlavorShapeOrigin) {
  json j = preset_json("generic-marlin");
  j["flavor"] = "marlinn";
  EXPECT_NE(profile_error(j).find("unknown G-code flavor \"marlinn\": expected marlin, klipper, "
                                  "reprapfirmware or bambu"),
            std::string::npos);
  j = preset_json("generic-marlin");
  j["bed"]["shape"] = "hexagonal";
  EXPECT_NE(profile_error(j).find("unknown bed.shape \"hexagonal\""), std::string::npos);
  j = preset_json("generic-marlin");
  j["bed"]["origin"] = "back";
  EXPECT_NE(profile_error(j).find("unknown bed.origin \"back\""), std::string::npos);
}

TEST(PrinterProfile, UnknownPlaceholder) {
  json j = preset_json("generic-marlin");
  j["start_gcode"].push_back("M104 S{nozle_temperature}");
  const std::string message = profile_error(j);
  EXPECT_NE(message.find("start_gcode: line 17: unknown placeholder {nozle_temperature}; known: "
                         "nozzle_temperature"),
            std::string::npos)
      << message;
  j = preset_json("generic-marlin");
  j["end_gcode"].push_back("M117 {max_z");
  EXPECT_NE(profile_error(j).find("end_gcode: line 7: unclosed '{'"), std::string::npos);
  // Literal braces are written doubled.
  j = preset_json("generic-marlin");
  j["end_gcode"].push_back("M118 {{done}}");
  EXPECT_EQ(profile_error(j), "");
}

TEST(PrinterProfile, UnknownKeyIsATypo) {
  json j = preset_json("generic-marlin");
  j["retraction"]["lenght"] = 2;
  EXPECT_NE(profile_error(j).find("unknown key \"retraction.lenght\""), std::string::npos);
  j = preset_json("generic-marlin");
  j["nozzle_diamter"] = 0.4;
  EXPECT_NE(profile_error(j).find("unknown key \"nozzle_diamter\""), std::string::npos);
}

TEST(PrinterProfile, UnsafeOrUselessTemplates) {
  json j = preset_json("generic-marlin");
  j["end_gcode"] = {"M104 S0", "M140 S0"};
  EXPECT_NE(profile_error(j).find("end_gcode must turn the motors off: add M84"),
            std::string::npos);
  j["end_gcode"] = {"M104 S0", "M84"};
  EXPECT_NE(profile_error(j).find("end_gcode must turn the heaters off"), std::string::npos);
  j["end_gcode"] = {"TURN_OFF_HEATERS", "M18"};
  EXPECT_EQ(profile_error(j), "");
  j = preset_json("generic-marlin");
  j["start_gcode"] = {"G28", "M109 S200"};
  EXPECT_NE(profile_error(j).find("start_gcode never uses {nozzle_temperature}"),
            std::string::npos);
}

TEST(PrinterProfile, CorneringAndLimits) {
  json j = preset_json("generic-marlin");
  j["cornering"]["jerk"] = 8;
  EXPECT_NE(profile_error(j).find("cornering must hold exactly one of"), std::string::npos);
  j = preset_json("generic-delta");
  j["bed"]["axis_limits"] = {{"x", {-100, 100}}, {"y", {-100, 100}}};
  EXPECT_NE(profile_error(j).find("axis_limits applies to rectangular beds only"),
            std::string::npos);
  j = preset_json("prusa-mk3s");
  j["bed"]["axis_limits"]["x"] = {0, 200};
  EXPECT_NE(profile_error(j).find("axis_limits must contain the whole bed"), std::string::npos);
}

TEST(PrinterProfile, NotJson) {
  try {
    parse_printer("{\"name\": ", "broken.json");
    FAIL();
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kProfile);
    EXPECT_NE(std::string(e.what()).find("broken.json: not valid JSON"), std::string::npos);
  }
  EXPECT_NE(profile_error(json::array()).find("must be an object"), std::string::npos);
}

TEST(PrinterProfile, UnknownNameListsThePresets) {
  try {
    load_printer("ender3");
    FAIL();
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
    EXPECT_NE(std::string(e.what()).find("creality-ender3-v2"), std::string::npos) << e.what();
  }
}

TEST(PrinterProfile, UserFile) {
  json j = preset_json("generic-marlin");
  j["name"] = "my-printer";
  j["bed"]["size"] = {180, 180};
  const std::filesystem::path path = testing::scratch_dir() / "my-printer.json";
  std::ofstream(path) << j.dump(2);
  const PrinterProfile p = load_printer(path.string());
  EXPECT_EQ(p.name, "my-printer");
  EXPECT_EQ(p.bed_size, Eigen::Vector2d(180, 180));
  EXPECT_EQ(p.axis_max, Eigen::Vector2d(180, 180));
}

TEST(PrinterProfile, ExpandsTemplates) {
  const std::string out = expand_gcode_template("M104 S{nozzle_temperature}\nM118 {{ok}}\n",
                                                {{"nozzle_temperature", "190"}}, "t");
  EXPECT_EQ(out, "M104 S190\nM118 {ok}\n");
}

}  // namespace
}  // namespace flatmorph::printer_profile_test
