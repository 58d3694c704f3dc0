#include "material/material.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/atomic_file.h"
#include "common/embedded_profiles.h"
#include "common/error.h"

namespace flatmorph {
namespace {

// One number a material file may hold, with the range that makes physical sense.
struct NumberKey {
  const char* key;
  double Material::*field;
  double lo;
  double hi;
};

// The ranges are wide on purpose (other filaments, other printers); they only catch typos and
// units mistakes (0.58 written as 58, Kelvin for Celsius).
constexpr NumberKey kNumberKeys[] = {
    {"lambda1", &Material::lambda1, 0.2, 1.5},
    {"lambda2", &Material::lambda2, 0.2, 2.0},
    {"lambda3", &Material::lambda3, 0.2, 3.0},
    {"delta_lambda1", &Material::delta_lambda1, -0.5, 0.5},
    {"young_modulus_along", &Material::young_modulus_along, 1e-9, 1e12},
    {"young_modulus_across", &Material::young_modulus_across, 1e-9, 1e12},
    {"poisson_ratio", &Material::poisson_ratio, 0.0, 0.49},
    {"layer_height", &Material::layer_height, 0.01, 1.0},
    {"nozzle_temperature", &Material::nozzle_temperature, 100, 350},
    {"bed_temperature", &Material::bed_temperature, 0, 130},
    {"min_nozzle_temperature", &Material::min_nozzle_temperature, 100, 350},
    {"max_nozzle_temperature", &Material::max_nozzle_temperature, 100, 350},
    {"max_bed_temperature", &Material::max_bed_temperature, 0, 130},
    {"density", &Material::density, 0.5, 3.0},
    {"print_speed", &Material::print_speed, 0, 500},
    {"first_layer_speed", &Material::first_layer_speed, 0, 500},
    {"fan_speed", &Material::fan_speed, 0, 100},
    {"first_layer_fan_speed", &Material::first_layer_fan_speed, 0, 100},
};

std::vector<std::string> known_keys() {
  std::vector<std::string> keys = {"name", "description"};
  for (const NumberKey& k : kNumberKeys) keys.emplace_back(k.key);
  keys.emplace_back("thickness_curve");
  return keys;
}

// The optional "thickness_curve" object (thickness_curve.h).
ThicknessCurve parse_thickness_curve(const nlohmann::json& j, const std::string& source) {
  const std::string where = fmt::format("{}: \"thickness_curve\"", source);
  if (!j.is_object()) {
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{} must be an object {{\"lambda1_coefficients\": [...], "
                                "\"min_layer_height\": ..., \"max_layer_height\": ...}}",
                                where));
  }
  const std::vector<std::string> keys = {"description",      "lambda1_coefficients",
                                         "min_layer_height", "max_layer_height",
                                         "layers",           "nozzle_temperature"};
  for (const auto& [key, value] : j.items()) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      throw UserError(ErrorCategory::kProfile, fmt::format("{}: unknown key \"{}\"; it may hold {}",
                                                           where, key, fmt::join(keys, ", ")));
    }
  }
  auto number = [&](const char* key, bool required, double fallback) {
    if (!j.contains(key)) {
      if (required) {
        throw UserError(ErrorCategory::kProfile, fmt::format("{} lacks \"{}\"", where, key));
      }
      return fallback;
    }
    if (!j[key].is_number()) {
      throw UserError(ErrorCategory::kProfile, fmt::format("{}: \"{}\" must be a number, not {}",
                                                           where, key, j[key].dump()));
    }
    return j[key].get<double>();
  };
  ThicknessCurve curve;
  if (!j.contains("lambda1_coefficients") || !j["lambda1_coefficients"].is_array()) {
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{} needs \"lambda1_coefficients\": an array of 1 to 5 numbers "
                                "c0, c1, ... with lambda1(h) = c0 + c1 h + ... (h in mm)",
                                where));
  }
  for (const nlohmann::json& c : j["lambda1_coefficients"]) {
    if (!c.is_number()) {
      throw UserError(
          ErrorCategory::kProfile,
          fmt::format("{}: \"lambda1_coefficients\" holds {}, not a number", where, c.dump()));
    }
    curve.lambda1_coefficients.push_back(c.get<double>());
  }
  curve.min_layer_height = number("min_layer_height", true, 0);
  curve.max_layer_height = number("max_layer_height", true, 0);
  const double layers = number("layers", false, curve.layers);
  if (layers != std::floor(layers) || layers < 1 || layers > 1000) {
    throw UserError(
        ErrorCategory::kProfile,
        fmt::format("{}: \"layers\" is {}, expected a whole number of layers", where, layers));
  }
  curve.layers = static_cast<int>(layers);
  curve.nozzle_temperature = number("nozzle_temperature", false, 0);
  if (const std::string problem = thickness_curve_problem(curve); !problem.empty()) {
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{} is unusable: {}; calibrate again", where, problem));
  }
  return curve;
}

Material parse_material(const nlohmann::json& j, const std::string& source, std::string name) {
  if (!j.is_object()) {
    throw UserError(
        ErrorCategory::kProfile,
        fmt::format("{}: a material file must hold a JSON object {{\"lambda1\": ...}}", source));
  }
  const std::vector<std::string> keys = known_keys();
  for (const auto& [key, value] : j.items()) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      throw UserError(ErrorCategory::kProfile,
                      fmt::format("{}: unknown key \"{}\"; a material file may hold {}", source,
                                  key, fmt::join(keys, ", ")));
    }
  }
  Material m;
  m.name = std::move(name);
  for (const char* key : {"name", "description"}) {
    if (!j.contains(key)) continue;
    if (!j[key].is_string()) {
      throw UserError(ErrorCategory::kProfile,
                      fmt::format("{}: \"{}\" must be a string", source, key));
    }
    (std::string_view(key) == "name" ? m.name : m.description) = j[key].get<std::string>();
  }
  for (const NumberKey& k : kNumberKeys) {
    if (!j.contains(k.key)) continue;
    const nlohmann::json& value = j[k.key];
    if (!value.is_number()) {
      throw UserError(ErrorCategory::kProfile, fmt::format("{}: \"{}\" must be a number, not {}",
                                                           source, k.key, value.dump()));
    }
    const double x = value.get<double>();
    if (!std::isfinite(x) || x < k.lo || x > k.hi) {
      throw UserError(ErrorCategory::kProfile,
                      fmt::format("{}: \"{}\" is {}, expected a number in [{}, {}]", source, k.key,
                                  x, k.lo, k.hi));
    }
    m.*k.field = x;
  }
  if (j.contains("thickness_curve")) {
    m.thickness_curve = parse_thickness_curve(j["thickness_curve"], source);
  }
  if (m.nozzle_temperature < m.min_nozzle_temperature ||
      m.nozzle_temperature > m.max_nozzle_temperature) {
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{}: nozzle_temperature {} C lies outside the material's safe "
                                "range [min_nozzle_temperature {}, max_nozzle_temperature {}]; fix "
                                "one of the three",
                                source, m.nozzle_temperature, m.min_nozzle_temperature,
                                m.max_nozzle_temperature));
  }
  if (m.bed_temperature > m.max_bed_temperature) {
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{}: bed_temperature {} C is above max_bed_temperature {} C; fix "
                                "one of the two",
                                source, m.bed_temperature, m.max_bed_temperature));
  }
  return m;
}

nlohmann::json parse_json(std::string_view text, const std::string& source) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e400
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{}: not valid JSON ({})", source, e.what()));
  }
}

}  // namespace

Material parse_material_json(std::string_view text, const std::string& source) {
  const nlohmann::json j = parse_json(text, source);
  std::string name = j.is_object() && j.contains("name") && j["name"].is_string()
                         ? j["name"].get<std::string>()
                         : std::string();
  return parse_material(j, source, std::move(name));
}

std::string material_json(const Material& m) {
  nlohmann::ordered_json j;
  j["name"] = m.name;
  j["description"] = m.description;
  for (const NumberKey& k : kNumberKeys) j[k.key] = m.*k.field;
  if (m.thickness_curve) {
    const ThicknessCurve& c = *m.thickness_curve;
    nlohmann::ordered_json t;
    t["description"] =
        "lambda1(h) = sum of lambda1_coefficients[i] * h^i, h the layer height in mm, valid for "
        "min_layer_height <= h <= max_layer_height; measured on samples of `layers` layers";
    t["lambda1_coefficients"] = c.lambda1_coefficients;
    t["min_layer_height"] = c.min_layer_height;
    t["max_layer_height"] = c.max_layer_height;
    t["layers"] = c.layers;
    t["nozzle_temperature"] = c.nozzle_temperature;
    j["thickness_curve"] = std::move(t);
  }
  return j.dump(2) + "\n";
}

void write_material(const std::filesystem::path& path, const Material& material) {
  const std::string text = material_json(material);
  write_file_atomically(path, false, [&](std::ostream& out) { out << text; });
}

std::vector<std::string> material_preset_names() {
  std::vector<std::string> names;
  for (const EmbeddedProfile& p : embedded_profiles()) {
    if (p.kind == "materials") names.emplace_back(p.name);
  }
  return names;
}

Material load_material(const std::string& name_or_path) {
  for (const EmbeddedProfile& p : embedded_profiles()) {
    if (p.kind == "materials" && p.name == name_or_path) {
      const std::string source = fmt::format("built-in material {}", p.name);
      return parse_material(parse_json(p.text, source), source, std::string(p.name));
    }
  }
  const std::filesystem::path path(name_or_path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("unknown material \"{}\": not a preset ({}) and no such file",
                                name_or_path, fmt::join(material_preset_names(), ", ")));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw UserError(
        ErrorCategory::kFile,
        fmt::format("{}: cannot open the material file; check its permissions", name_or_path));
  }
  std::stringstream text;
  text << in.rdbuf();
  return parse_material(parse_json(text.str(), name_or_path), name_or_path, path.stem().string());
}

}  // namespace flatmorph
