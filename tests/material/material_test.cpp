// Materials: the shipped presets (profiles/materials/*.json) and user files in the same format.
#include "material/material.h"

#include <gtest/gtest.h>

#include <fstream>

#include "common/error.h"
#include "test_support.h"

namespace flatmorph::material_test {
namespace {

namespace fs = std::filesystem;

fs::path write_material(const std::string& name, const std::string& json) {
  const fs::path path = testing::scratch_dir() / name;
  std::ofstream(path) << json;
  return path;
}

// The message of the UserError that loading `json` as a file throws, checking its category.
std::string material_error(const std::string& json, ErrorCategory category) {
  const fs::path path = write_material("bad.json", json);
  try {
    load_material(path.string());
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), category) << e.what();
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << json << " was accepted";
  return "";
}

TEST(Material, PresetsAreShipped) {
  const std::vector<std::string> names = material_preset_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "pla-paper"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "pla-generic"), names.end());
  for (const std::string& name : names) {
    const Material m = load_material(name);
    EXPECT_EQ(m.name, name);
    EXPECT_FALSE(m.description.empty());
    EXPECT_GE(m.nozzle_temperature, m.min_nozzle_temperature);
    EXPECT_LE(m.nozzle_temperature, m.max_nozzle_temperature);
  }
}

// The paper's PLA (Shrink & Morph §4) is both the JSON preset and the defaults of Material, which
// other stages use directly: the two must not drift apart.
TEST(Material, PaperPlaPresetEqualsTheDefaults) {
  const Material preset = load_material("pla-paper");
  const Material defaults;
  EXPECT_EQ(preset.lambda1, 0.58);
  EXPECT_EQ(preset.lambda2, 1.08);
  EXPECT_EQ(preset.lambda3, 1.52);
  EXPECT_EQ(preset.delta_lambda1, -0.0226764665509417);
  EXPECT_EQ(preset.nozzle_temperature, 190);
  EXPECT_EQ(preset.bed_temperature, 55);
  EXPECT_EQ(preset.layer_height, 0.08);
  EXPECT_EQ(preset.print_speed, 30);
  EXPECT_EQ(preset.first_layer_speed, 15);
  EXPECT_EQ(preset.young_modulus_along / preset.young_modulus_across, 10);
  for (auto field :
       {&Material::lambda1, &Material::lambda2, &Material::lambda3, &Material::delta_lambda1,
        &Material::young_modulus_along, &Material::young_modulus_across, &Material::poisson_ratio,
        &Material::layer_height, &Material::nozzle_temperature, &Material::bed_temperature,
        &Material::max_nozzle_temperature, &Material::max_bed_temperature, &Material::density,
        &Material::min_nozzle_temperature, &Material::print_speed, &Material::first_layer_speed,
        &Material::fan_speed, &Material::first_layer_fan_speed}) {
    EXPECT_EQ(preset.*field, defaults.*field);
  }
}

TEST(Material, GenericPlaSaysItIsUncalibrated) {
  const Material m = load_material("pla-generic");
  EXPECT_NE(m.description.find("UNCALIBRATED"), std::string::npos) << m.description;
}

TEST(Material, UserFileKeepsThePaperValuesItDoesNotSet) {
  const fs::path path =
      write_material("my-pla.json", R"({"lambda1": 0.62, "nozzle_temperature": 200})");
  const Material m = load_material(path.string());
  EXPECT_EQ(m.name, "my-pla");
  EXPECT_EQ(m.lambda1, 0.62);
  EXPECT_EQ(m.nozzle_temperature, 200);
  EXPECT_EQ(m.lambda2, 1.08);
  EXPECT_EQ(m.first_layer_speed, 15);
}

TEST(Material, FileErrorsNameTheProblem) {
  EXPECT_NE(material_error("{\"lambda1\": ", ErrorCategory::kProfile).find("not valid JSON"),
            std::string::npos);
  EXPECT_NE(material_error("[1, 2]", ErrorCategory::kProfile).find("must hold a JSON object"),
            std::string::npos);
  EXPECT_NE(material_error(R"({"lambda1": "0.58"})", ErrorCategory::kProfile)
                .find("\"lambda1\" must be a number"),
            std::string::npos);
  EXPECT_NE(material_error(R"({"lambda1": 58})", ErrorCategory::kProfile)
                .find("\"lambda1\" is 58, expected a number in [0.2, 1.5]"),
            std::string::npos);
  EXPECT_NE(
      material_error(R"({"lamda1": 0.58})", ErrorCategory::kProfile).find("unknown key \"lamda1\""),
      std::string::npos);
  EXPECT_NE(
      material_error(R"({"name": 3})", ErrorCategory::kProfile).find("\"name\" must be a string"),
      std::string::npos);
  EXPECT_NE(material_error(R"({"nozzle_temperature": 240})", ErrorCategory::kProfile)
                .find("nozzle_temperature 240 C lies outside the material's safe range"),
            std::string::npos);
  EXPECT_NE(material_error(R"({"bed_temperature": 80})", ErrorCategory::kProfile)
                .find("bed_temperature 80 C is above max_bed_temperature 70 C"),
            std::string::npos);
}

// lambda1(v) = 0.7 - 0.002 v on [20, 100] mm/s: 0.66 at 20, 0.64 at pla-paper's 30, 0.5 at 100.
SpeedCurve linear_speed_curve() {
  SpeedCurve c;
  c.lambda1_coefficients = {0.7, -0.002};
  c.min_print_speed = 20;
  c.max_print_speed = 100;
  c.layer_height = 0.08;
  c.nozzle_temperature = 200;
  return c;
}

TEST(Material, SpeedCurveRoundTripsThroughTheFile) {
  Material m = load_material("pla-paper");
  m.name = "fast-pla";
  m.speed_curve = linear_speed_curve();
  m.speed_curve->lambda1_coefficients = {0.71, -2.1e-3, 1.0 / 3 * 1e-6};  // not short decimals
  const fs::path path = testing::scratch_dir() / "fast-pla.json";
  flatmorph::write_material(path, m);
  const Material back = load_material(path.string());
  ASSERT_TRUE(back.speed_curve.has_value());
  EXPECT_EQ(back.speed_curve->lambda1_coefficients, m.speed_curve->lambda1_coefficients);
  EXPECT_EQ(back.speed_curve->min_print_speed, 20);
  EXPECT_EQ(back.speed_curve->max_print_speed, 100);
  EXPECT_EQ(back.speed_curve->layer_height, 0.08);
  EXPECT_EQ(back.speed_curve->nozzle_temperature, 200);
  EXPECT_FALSE(back.thickness_curve.has_value());
  EXPECT_EQ(material_json(back), material_json(m));
  // The documented key order: the curves last, the speed curve after the thickness curve.
  const std::string text = material_json(m);
  EXPECT_LT(text.find("\"first_layer_fan_speed\""), text.find("\"speed_curve\""));
  m.thickness_curve = ThicknessCurve{{0.5, 1.0}, 0.08, 0.28, 6, 200};
  const std::string both = material_json(m);
  EXPECT_LT(both.find("\"thickness_curve\""), both.find("\"speed_curve\""));
  // Without one the file has no such key, and the presets have none.
  EXPECT_EQ(material_json(load_material("pla-paper")).find("speed_curve"), std::string::npos);
}

TEST(Material, SpeedCurveErrorsNameTheKeyAndTheFile) {
  const std::string good = R"("lambda1_coefficients": [0.7, -0.002], "min_print_speed": 20)";
  for (const auto& [curve, says] : std::vector<std::pair<std::string, std::string>>{
           {R"({"lambda1_coefficients": [0.5, 0.004, -0.00004], "min_print_speed": 20, )"
            R"("max_print_speed": 100})",
            "not strictly monotone"},  // turns at 50 mm/s
           {R"({"lambda1_coefficients": [0.7, -0.002], "min_print_speed": 100, )"
            R"("max_print_speed": 20})",
            "not an interval of positive print speeds"},
           {R"({"lambda1_coefficients": [0.7, -0.00003], "min_print_speed": 1500, )"
            R"("max_print_speed": 9000})",
            "mm/min"},
           {"{" + good + R"(, "max_print_speed": "100"})", "\"max_print_speed\" must be a number"},
           {"{" + good + "}", "lacks \"max_print_speed\""},
           {R"({"lambda1_coefficients": 0.7, "min_print_speed": 20, "max_print_speed": 100})",
            "needs \"lambda1_coefficients\""},
           {R"({"lambda1_coefficients": [0.7, "a"], "min_print_speed": 20, )"
            R"("max_print_speed": 100})",
            "holds \"a\", not a number"},
           {"{" + good + R"(, "max_print_speed": 100, "speed": 3})", "unknown key \"speed\""},
           {"[0.7, -0.002]", "must be an object"},
       }) {
    const std::string message = material_error(R"({"lambda1": 0.6, "speed_curve": )" + curve + "}",
                                               ErrorCategory::kProfile);
    EXPECT_NE(message.find("\"speed_curve\""), std::string::npos) << message;
    EXPECT_NE(message.find(says), std::string::npos) << message;
  }
  // The ratios are scaled from print_speed, which must lie in the calibrated range.
  const std::string message = material_error(
      "{\"print_speed\": 120, \"speed_curve\": {" + good + ", \"max_print_speed\": 100}}",
      ErrorCategory::kProfile);
  EXPECT_NE(message.find("print_speed 120 mm/s lies outside the calibrated range [20, 100] mm/s"),
            std::string::npos)
      << message;
}

TEST(Material, PrintedLambda1FollowsTheCurvesAndClampsToTheirRanges) {
  Material m = load_material("pla-paper");  // lambda1 0.58 measured at 30 mm/s
  // No curve: the speed and the height change nothing.
  for (double h : {0.05, 0.08, 0.3}) {
    for (double v : {10.0, 30.0, 200.0}) EXPECT_EQ(printed_lambda1(m, h, v), 0.58);
  }
  m.speed_curve = linear_speed_curve();
  EXPECT_NEAR(printed_lambda1(m, 0.08, 30), 0.58, 1e-15);
  EXPECT_NEAR(printed_lambda1(m, 0.08, 60), 0.58 * 0.58 / 0.64, 1e-15);
  EXPECT_NEAR(printed_lambda1(m, 0.08, 100), 0.58 * 0.5 / 0.64, 1e-15);
  // A first layer at 15 mm/s reads as 20, the slowest calibrated; 300 mm/s as 100.
  EXPECT_EQ(printed_lambda1(m, 0.08, 15), printed_lambda1(m, 0.08, 20));
  EXPECT_NEAR(printed_lambda1(m, 0.08, 15), 0.58 * 0.66 / 0.64, 1e-15);
  EXPECT_EQ(printed_lambda1(m, 0.08, 300), printed_lambda1(m, 0.08, 100));
  // No known speed (a G-code without F): the speed the ratios were measured at.
  EXPECT_NEAR(printed_lambda1(m, 0.08, 0), 0.58, 1e-15);
  // With a thickness curve (lambda1(h) = 0.5 + h on [0.08, 0.28]) the speed factor multiplies it.
  m.thickness_curve = ThicknessCurve{{0.5, 1.0}, 0.08, 0.28, 6, 200};
  EXPECT_NEAR(printed_lambda1(m, 0.2, 30), 0.7, 1e-15);
  EXPECT_NEAR(printed_lambda1(m, 0.2, 60), 0.7 * 0.58 / 0.64, 1e-15);
  EXPECT_NEAR(printed_lambda1(m, 0.04, 60), 0.58 * 0.58 / 0.64, 1e-15);  // h clamped to 0.08
}

TEST(Material, UnknownNameListsThePresets) {
  try {
    load_material("petg");
    FAIL();
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
    EXPECT_NE(std::string(e.what()).find("pla-paper"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace flatmorph::material_test
