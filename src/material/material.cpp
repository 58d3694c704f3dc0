#include "material/material.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/error.h"

namespace flatmorph {
namespace {

Material paper_pla() {
  Material m;
  m.name = "pla-paper";
  m.description =
      "Polymaker PolyMax PLA (grey), 190 C, 0.08 mm layers, 0.4 mm nozzle: the material of "
      "Shrink & Morph §4 (lambda 0.58 / 1.08 / 1.52)";
  return m;  // the defaults of Material are this material
}

void check_range(const std::string& source, const char* key, double value, double lo, double hi) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{}: \"{}\" is {}, expected a number in [{}, {}]", source, key,
                                value, lo, hi));
  }
}

Material parse_material(const nlohmann::json& j, const std::string& source) {
  Material m;
  m.name = std::filesystem::path(source).stem().string();
  auto read = [&](const char* key, double& field, double lo, double hi) {
    if (!j.contains(key)) return;
    if (!j[key].is_number()) {
      throw UserError(ErrorCategory::kProfile,
                      fmt::format("{}: \"{}\" must be a number", source, key));
    }
    field = j[key].get<double>();
    check_range(source, key, field, lo, hi);
  };
  if (j.contains("name") && j["name"].is_string()) m.name = j["name"].get<std::string>();
  if (j.contains("description") && j["description"].is_string()) {
    m.description = j["description"].get<std::string>();
  }
  read("lambda1", m.lambda1, 0.2, 1.5);
  read("lambda2", m.lambda2, 0.2, 2.0);
  read("lambda3", m.lambda3, 0.2, 3.0);
  read("delta_lambda1", m.delta_lambda1, -0.5, 0.5);
  read("young_modulus_along", m.young_modulus_along, 1e-9, 1e12);
  read("young_modulus_across", m.young_modulus_across, 1e-9, 1e12);
  read("poisson_ratio", m.poisson_ratio, 0.0, 0.49);
  read("layer_height", m.layer_height, 0.01, 1.0);
  read("nozzle_temperature", m.nozzle_temperature, 100, 350);
  read("bed_temperature", m.bed_temperature, 0, 130);
  read("max_nozzle_temperature", m.max_nozzle_temperature, 100, 350);
  read("max_bed_temperature", m.max_bed_temperature, 0, 130);
  read("density", m.density, 0.5, 3.0);
  return m;
}

}  // namespace

std::vector<std::string> material_preset_names() { return {"pla-paper"}; }

Material load_material(const std::string& name_or_path) {
  if (name_or_path == "pla-paper") return paper_pla();
  const std::filesystem::path path(name_or_path);
  if (!std::filesystem::exists(path)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("unknown material \"{}\": not a preset ({}) and no such file",
                                name_or_path, fmt::join(material_preset_names(), ", ")));
  }
  std::ifstream in(path);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{}: not valid JSON ({})", name_or_path, e.what()));
  }
  if (!j.is_object()) {
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{}: a material file must hold a JSON object", name_or_path));
  }
  return parse_material(j, name_or_path);
}

}  // namespace flatmorph
