// Materials: the shipped presets (profiles/materials/*.json) and user files in the same format.
#include "material/material.h"

#include <gtest/gtest.h>

#include <fstream>

#include "common/error.h"
#include "test_support.h"

namespace flatmorph {
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
}  // namespace flatmorph
