#include "material/material.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/embedded_profiles.h"
#include "common/error.h"
#include "common/file_text.h"

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
  keys.emplace_back("speed_curve");
  keys.emplace_back("hinge_curve");
  return keys;
}

// One of the optional curve objects ("thickness_curve", "speed_curve", "hinge_curve"), read with
// errors that name the file and the key.
class CurveReader {
 public:
  // `keys`: those the object may hold; `shape`: the object as a user writes it, for the error when
  // it is no object.
  CurveReader(const nlohmann::json& j, const std::string& source, const char* key,
              const std::vector<std::string>& keys, const std::string& shape)
      : j_(j), where_(fmt::format("{}: \"{}\"", source, key)) {
    if (!j.is_object()) fail(fmt::format("must be an object {}", shape));
    for (const auto& [name, value] : j.items()) {
      if (std::find(keys.begin(), keys.end(), name) == keys.end()) {
        throw UserError(ErrorCategory::kProfile,
                        fmt::format("{}: unknown key \"{}\"; it may hold {}", where_, name,
                                    fmt::join(keys, ", ")));
      }
    }
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw UserError(ErrorCategory::kProfile, fmt::format("{} {}", where_, problem));
  }

  double number(const char* key, bool required, double fallback) const {
    if (!j_.contains(key)) {
      if (required) fail(fmt::format("lacks \"{}\"", key));
      return fallback;
    }
    if (!j_[key].is_number()) {
      throw UserError(ErrorCategory::kProfile, fmt::format("{}: \"{}\" must be a number, not {}",
                                                           where_, key, j_[key].dump()));
    }
    return j_[key].get<double>();
  }

  // A whole number in [lo, hi], or `fallback` when the key is absent.
  int whole(const char* key, int fallback, int lo, int hi) const {
    const double x = number(key, false, fallback);
    if (x != std::floor(x) || x < lo || x > hi) {
      fail(fmt::format("has \"{}\": {}, expected a whole number from {} to {}", key, x, lo, hi));
    }
    return static_cast<int>(x);
  }

  bool boolean(const char* key) const {
    if (!j_.contains(key) || !j_[key].is_boolean()) {
      fail(fmt::format("needs \"{}\": true or false", key));
    }
    return j_[key].get<bool>();
  }

  // The polynomial's coefficients under `key` (e.g. "lambda1_coefficients"); `formula` says what
  // they give, e.g. "lambda1 = c0 + c1 x + c2 x^2 + ... (x = h in mm)".
  std::vector<double> coefficients(const char* key, const std::string& formula) const {
    if (!j_.contains(key) || !j_[key].is_array()) {
      fail(fmt::format("needs \"{}\": an array of 1 to 5 numbers c0, c1, ... with {}", key,
                       formula));
    }
    std::vector<double> c;
    for (const nlohmann::json& x : j_[key]) {
      if (!x.is_number()) {
        throw UserError(ErrorCategory::kProfile,
                        fmt::format("{}: \"{}\" holds {}, not a number", where_, key, x.dump()));
      }
      c.push_back(x.get<double>());
    }
    return c;
  }

  // Refuses a curve its own check finds unusable.
  void require_usable(const std::string& problem) const {
    if (!problem.empty()) fail(fmt::format("is unusable: {}; calibrate again", problem));
  }

 private:
  const nlohmann::json& j_;
  std::string where_;
};

// The optional "thickness_curve" object (thickness_curve.h).
ThicknessCurve parse_thickness_curve(const nlohmann::json& j, const std::string& source) {
  const CurveReader r(j, source, "thickness_curve",
                      {"description", "lambda1_coefficients", "min_layer_height",
                       "max_layer_height", "layers", "nozzle_temperature"},
                      "{\"lambda1_coefficients\": [...], \"min_layer_height\": ..., "
                      "\"max_layer_height\": ...}");
  ThicknessCurve curve;
  curve.lambda1_coefficients = r.coefficients(
      "lambda1_coefficients", "lambda1 = c0 + c1 x + c2 x^2 + ... (x = h, the layer height in mm)");
  curve.min_layer_height = r.number("min_layer_height", true, 0);
  curve.max_layer_height = r.number("max_layer_height", true, 0);
  curve.layers = r.whole("layers", curve.layers, 1, 1000);
  curve.nozzle_temperature = r.number("nozzle_temperature", false, 0);
  r.require_usable(thickness_curve_problem(curve));
  return curve;
}

// The optional "speed_curve" object (speed_curve.h).
SpeedCurve parse_speed_curve(const nlohmann::json& j, const std::string& source) {
  const CurveReader r(j, source, "speed_curve",
                      {"description", "lambda1_coefficients", "min_print_speed", "max_print_speed",
                       "layer_height", "nozzle_temperature"},
                      "{\"lambda1_coefficients\": [...], \"min_print_speed\": ..., "
                      "\"max_print_speed\": ...} (mm/s)");
  SpeedCurve curve;
  curve.lambda1_coefficients =
      r.coefficients("lambda1_coefficients",
                     "lambda1 = c0 + c1 x + c2 x^2 + ... (x = v, the print speed in mm/s)");
  curve.min_print_speed = r.number("min_print_speed", true, 0);
  curve.max_print_speed = r.number("max_print_speed", true, 0);
  curve.layer_height = r.number("layer_height", false, 0);
  curve.nozzle_temperature = r.number("nozzle_temperature", false, 0);
  r.require_usable(speed_curve_problem(curve));
  return curve;
}

// The optional "hinge_curve" object (hinge_curve.h).
HingeCurve parse_hinge_curve(const nlohmann::json& j, const std::string& source) {
  const CurveReader r(
      j, source, "hinge_curve",
      {"description", "calibrated", "case_a_curvature_coefficients",
       "case_b_curvature_coefficients", "min_print_speed", "max_print_speed", "layer_height",
       "pla_layers", "tpu_layers", "tpu_print_speed", "overlap", "nozzle_temperature"},
      "{\"calibrated\": true, \"case_a_curvature_coefficients\": [...], "
      "\"case_b_curvature_coefficients\": [...], \"min_print_speed\": ..., "
      "\"max_print_speed\": ...} (1/mm, mm/s)");
  HingeCurve curve;
  curve.calibrated = r.boolean("calibrated");
  const std::string formula =
      "curvature = c0 + c1 v + c2 v^2 + ... in 1/mm (v = the active PLA's print speed in mm/s)";
  curve.case_a_coefficients = r.coefficients("case_a_curvature_coefficients", formula);
  curve.case_b_coefficients = r.coefficients("case_b_curvature_coefficients", formula);
  curve.min_speed = r.number("min_print_speed", true, 0);
  curve.max_speed = r.number("max_print_speed", true, 0);
  curve.stack.layer_height = r.number("layer_height", false, curve.stack.layer_height);
  curve.stack.pla_layers = r.whole("pla_layers", curve.stack.pla_layers, 1, 20);
  curve.stack.tpu_layers = r.whole("tpu_layers", curve.stack.tpu_layers, 1, 20);
  curve.stack.tpu_speed = r.number("tpu_print_speed", false, curve.stack.tpu_speed);
  curve.stack.overlap = r.number("overlap", false, curve.stack.overlap);
  curve.nozzle_temperature = r.number("nozzle_temperature", false, 0);
  r.require_usable(hinge_curve_problem(curve));
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
  if (j.contains("speed_curve")) {
    m.speed_curve = parse_speed_curve(j["speed_curve"], source);
    const SpeedCurve& c = *m.speed_curve;
    // A relative slack: the speeds come back from text.
    const double slack = 1e-9 * c.max_print_speed;
    if (!(m.print_speed >= c.min_print_speed - slack &&
          m.print_speed <= c.max_print_speed + slack)) {
      throw UserError(
          ErrorCategory::kProfile,
          fmt::format("{}: print_speed {:g} mm/s lies outside the calibrated range [{:g}, {:g}] "
                      "mm/s of \"speed_curve\", which scales lambda1 from the speed it was "
                      "measured at: set print_speed inside the range, or calibrate a range that "
                      "holds it ('flatmorph calibrate print --speed-ramp --print-speeds ...')",
                      source, m.print_speed, c.min_print_speed, c.max_print_speed));
    }
  }
  if (j.contains("hinge_curve")) m.hinge_curve = parse_hinge_curve(j["hinge_curve"], source);
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

nlohmann::json json_document(std::string_view text, const std::string& source) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e400
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("{}: not valid JSON ({})", source, e.what()));
  }
}

}  // namespace

Material parse_material_json(std::string_view text, const std::string& source) {
  const nlohmann::json j = json_document(text, source);
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
  if (m.speed_curve) {
    const SpeedCurve& c = *m.speed_curve;
    nlohmann::ordered_json t;
    t["description"] =
        "lambda1(v) = sum of lambda1_coefficients[i] * v^i, v the print speed in mm/s, valid for "
        "min_print_speed <= v <= max_print_speed; measured on samples of layer_height mm; a bead "
        "printed at v shrinks to lambda1(v) / lambda1(print_speed) times the material's lambda1";
    t["lambda1_coefficients"] = c.lambda1_coefficients;
    t["min_print_speed"] = c.min_print_speed;
    t["max_print_speed"] = c.max_print_speed;
    t["layer_height"] = c.layer_height;
    t["nozzle_temperature"] = c.nozzle_temperature;
    j["speed_curve"] = std::move(t);
  }
  if (m.hinge_curve) {
    const HingeCurve& c = *m.hinge_curve;
    nlohmann::ordered_json t;
    t["description"] =
        "Thermorph actuators: the fold angle per mm of printed actuator width, curvature(v) = sum "
        "of case_*_curvature_coefficients[i] * v^i in 1/mm (radius = 1 / curvature), v the "
        "active PLA's print speed in mm/s, valid for min_print_speed <= v <= max_print_speed; "
        "case A: PLA on the bed, folds toward the bed; case B: TPU on the bed, folds away from "
        "it; for actuators of pla_layers PLA and tpu_layers TPU layers of layer_height mm";
    t["calibrated"] = c.calibrated;
    t["case_a_curvature_coefficients"] = c.case_a_coefficients;
    t["case_b_curvature_coefficients"] = c.case_b_coefficients;
    t["min_print_speed"] = c.min_speed;
    t["max_print_speed"] = c.max_speed;
    t["layer_height"] = c.stack.layer_height;
    t["pla_layers"] = c.stack.pla_layers;
    t["tpu_layers"] = c.stack.tpu_layers;
    t["tpu_print_speed"] = c.stack.tpu_speed;
    t["overlap"] = c.stack.overlap;
    t["nozzle_temperature"] = c.nozzle_temperature;
    j["hinge_curve"] = std::move(t);
  }
  return j.dump(2) + "\n";
}

const ThicknessCurve& require_thickness_curve(const Material& material) {
  if (!material.thickness_curve) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("material \"{}\" has no thickness curve, which turns each path's "
                                "shrinkage into a layer height: give a material with a thickness "
                                "curve, e.g. pla-geodesy, or calibrate one ('flatmorph calibrate "
                                "print --thickness-ramp', then 'flatmorph calibrate fit')",
                                material.name));
  }
  return *material.thickness_curve;
}

double printed_lambda1(const Material& m, double layer_height_mm, double print_speed_mm_s) {
  double lambda1 = m.lambda1;
  if (m.thickness_curve) {
    const ThicknessCurve& c = *m.thickness_curve;
    lambda1 = lambda1_at_layer_height(
        c, std::clamp(layer_height_mm, c.min_layer_height, c.max_layer_height));
  }
  // A speed of 0 is one nobody gave (a G-code without F): the speed the ratios were measured at.
  if (m.speed_curve && print_speed_mm_s > 0) {
    const SpeedCurve& c = *m.speed_curve;
    auto at = [&c](double v) {
      return lambda1_at_print_speed(c, std::clamp(v, c.min_print_speed, c.max_print_speed));
    };
    lambda1 *= at(print_speed_mm_s) / at(m.print_speed);
  }
  return lambda1;
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
      return parse_material(json_document(p.text, source), source, std::string(p.name));
    }
  }
  const std::filesystem::path path(name_or_path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("unknown material \"{}\": not a preset ({}) and no such file",
                                name_or_path, fmt::join(material_preset_names(), ", ")));
  }
  return parse_material(json_document(read_file_text(path, "material file"), name_or_path),
                        name_or_path, path.stem().string());
}

}  // namespace flatmorph
