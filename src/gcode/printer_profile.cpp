#include "gcode/printer_profile.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/embedded_profiles.h"
#include "common/error.h"
#include "common/file_text.h"

namespace flatmorph {
namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& source, const std::string& message) {
  throw UserError(ErrorCategory::kProfile, fmt::format("{}: {}", source, message));
}

std::string type_name(const json& j) {
  switch (j.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array";
    case json::value_t::string:
      return "a string";
    case json::value_t::boolean:
      return "a boolean";
    default:
      return "a number";
  }
}

// Reads the keys of one JSON object, so that a missing key, a key of the wrong type and a key
// nobody reads (a typo) each get their own message naming the key's full path.
class ObjectReader {
 public:
  ObjectReader(const json& object, std::string path, const std::string& source)
      : object_(object), path_(std::move(path)), source_(source) {
    if (!object_.is_object()) {
      fail(source_, fmt::format("\"{}\" must be an object {{...}}, not {}", name_or_root(),
                                type_name(object_)));
    }
  }

  bool has(const char* key) const { return object_.contains(key); }

  const json& get(const char* key, const char* hint) {
    if (!object_.contains(key)) {
      fail(source_, fmt::format("missing key \"{}\" ({})", full(key), hint));
    }
    read_.insert(key);
    return object_.at(key);
  }

  double number(const char* key, const char* hint, double lo, double hi) {
    const json& v = get(key, hint);
    if (!v.is_number()) {
      fail(source_,
           fmt::format("\"{}\" must be a number ({}), not {}", full(key), hint, type_name(v)));
    }
    return check_range(key, v.get<double>(), lo, hi);
  }

  double optional_number(const char* key, const char* hint, double lo, double hi, double fallback) {
    return has(key) ? number(key, hint, lo, hi) : fallback;
  }

  bool boolean(const char* key, const char* hint) {
    const json& v = get(key, hint);
    if (!v.is_boolean()) {
      fail(source_,
           fmt::format("\"{}\" must be true or false ({}), not {}", full(key), hint, type_name(v)));
    }
    return v.get<bool>();
  }

  std::string string(const char* key, const char* hint) {
    const json& v = get(key, hint);
    if (!v.is_string()) {
      fail(source_,
           fmt::format("\"{}\" must be a string ({}), not {}", full(key), hint, type_name(v)));
    }
    return v.get<std::string>();
  }

  // A pair of numbers [a, b].
  Eigen::Vector2d pair(const char* key, const char* hint, double lo, double hi) {
    const json& v = get(key, hint);
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number()) {
      fail(source_, fmt::format("\"{}\" must be two numbers [a, b] ({}), not {}", full(key), hint,
                                v.dump()));
    }
    return {check_range(key, v[0].get<double>(), lo, hi),
            check_range(key, v[1].get<double>(), lo, hi)};
  }

  // G-code lines: an array of strings (one per line) or one string with newlines.
  std::string lines(const char* key, const char* hint) {
    const json& v = get(key, hint);
    if (v.is_string()) return v.get<std::string>();
    if (!v.is_array()) {
      fail(source_, fmt::format("\"{}\" must be an array of G-code lines ({}), not {}", full(key),
                                hint, type_name(v)));
    }
    std::string text;
    for (size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_string()) {
        fail(source_, fmt::format("\"{}\" line {} must be a string, not {}", full(key), i + 1,
                                  type_name(v[i])));
      }
      text += v[i].get<std::string>();
      text += '\n';
    }
    return text;
  }

  ObjectReader object(const char* key, const char* hint) {
    return ObjectReader(get(key, hint), full(key), source_);
  }

  // Call once every key was read: any other key is a typo or a setting flatmorph does not know.
  void reject_unknown() const {
    for (const auto& [key, value] : object_.items()) {
      if (!read_.count(key)) {
        std::vector<std::string> known(read_.begin(), read_.end());
        fail(source_, fmt::format("unknown key \"{}\" (keys read here: {}); see docs/gcode.md",
                                  full(key.c_str()), fmt::join(known, ", ")));
      }
    }
  }

  std::string full(const char* key) const { return path_.empty() ? key : path_ + "." + key; }

 private:
  std::string name_or_root() const { return path_.empty() ? "(the file)" : path_; }

  double check_range(const char* key, double x, double lo, double hi) const {
    if (!std::isfinite(x) || x < lo || x > hi) {
      const char* why = x < 0 && lo >= 0 ? "a negative value" : "out of range";
      fail(source_, fmt::format("\"{}\" is {} ({}); expected a number in [{}, {}]", full(key), x,
                                why, lo, hi));
    }
    return x;
  }

  const json& object_;
  std::string path_;
  const std::string& source_;
  std::set<std::string> read_;
};

GcodeFlavor parse_flavor(const std::string& s, const std::string& source) {
  if (s == "marlin") return GcodeFlavor::kMarlin;
  if (s == "klipper") return GcodeFlavor::kKlipper;
  if (s == "reprapfirmware") return GcodeFlavor::kRepRapFirmware;
  if (s == "bambu") return GcodeFlavor::kBambu;
  fail(source, fmt::format("unknown G-code flavor \"{}\": expected marlin, klipper, "
                           "reprapfirmware or bambu",
                           s));
}

// Whether one of `commands` (e.g. "M104") appears in the template with the parameter letter
// `zero_param` set to 0 (e.g. 'S' for "M104 S0"), or at all when `zero_param` is 0.
bool template_has(const std::string& text, const std::vector<std::string>& commands,
                  char zero_param) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find(';'));
    std::istringstream words(line);
    std::string first;
    if (!(words >> first)) continue;
    std::transform(first.begin(), first.end(), first.begin(), ::toupper);
    if (std::find(commands.begin(), commands.end(), first) == commands.end()) continue;
    if (zero_param == 0) return true;
    std::string word;
    while (words >> word) {
      std::transform(word.begin(), word.end(), word.begin(), ::toupper);
      if (word.empty() || word[0] != zero_param) continue;
      // "S0", "S0.0" and "S00" all mean zero.
      char* end = nullptr;
      const double value = std::strtod(word.c_str() + 1, &end);
      if (end != word.c_str() + 1 && *end == '\0' && value == 0) return true;
    }
  }
  return false;
}

// The "tool_change" object; `p` has its bed and extruders read.
ToolChange parse_tool_change(ObjectReader r, const PrinterProfile& p, const std::string& source) {
  ToolChange t;
  t.gcode = r.lines("gcode", "park, select with T{next_tool}, heat; an array of lines");
  t.shared_nozzle = r.has("shared_nozzle") && r.boolean("shared_nozzle",
                                                        "true when the tools are filament slots "
                                                        "feeding one nozzle (AMS, MMU)");
  if (t.shared_nozzle) {
    t.flush_volume = r.number("flush_volume",
                              "mm^3 of the next filament pushed through the shared nozzle to "
                              "clear the previous one, e.g. 140",
                              1, 5000);
  } else if (r.has("flush_volume")) {
    fail(source,
         "tool_change.flush_volume applies to a shared nozzle only (\"shared_nozzle\": "
         "true); each of these tools has its own nozzle: remove it");
  }
  if (r.has("prime")) {
    ObjectReader prime = r.object("prime", "volume, area, wipe");
    t.prime_volume = prime.number("volume", "mm^3 laid on the bed after each change", 0.1, 1000);
    ObjectReader area = prime.object("area", "{\"x\": [min, max], \"y\": [min, max]} in mm");
    const Eigen::Vector2d x = area.pair("x", "[min, max] in mm", -10000, 10000);
    const Eigen::Vector2d y = area.pair("y", "[min, max] in mm", -10000, 10000);
    area.reject_unknown();
    t.wipe_length = prime.number("wipe", "mm the nozzle moves back along the bead", 0, 100);
    prime.reject_unknown();
    t.prime_area_min = {x[0], y[0]};
    t.prime_area_max = {x[1], y[1]};
    const Eigen::Vector2d size = t.prime_area_max - t.prime_area_min;
    if (size.minCoeff() < 2 * p.nozzle_diameter) {
      fail(source, fmt::format("tool_change.prime.area is {:g} x {:g} mm; it needs at least two "
                               "nozzle widths each way: give [min, max] with min < max",
                               size.x(), size.y()));
    }
    if ((t.prime_area_min.array() < p.axis_min.array() - 1e-9).any() ||
        (t.prime_area_max.array() > p.axis_max.array() + 1e-9).any()) {
      fail(source, fmt::format("tool_change.prime.area x [{:g}, {:g}], y [{:g}, {:g}] leaves the "
                               "reachable area x [{:g}, {:g}], y [{:g}, {:g}]: move it onto the "
                               "bed",
                               t.prime_area_min.x(), t.prime_area_max.x(), t.prime_area_min.y(),
                               t.prime_area_max.y(), p.axis_min.x(), p.axis_max.x(), p.axis_min.y(),
                               p.axis_max.y()));
    }
  }
  r.reject_unknown();
  const std::string where = source + ": tool_change.gcode";
  expand_gcode_template(t.gcode, {}, where, tool_change_placeholders());
  // The writer and the check follow the active tool through T commands: the template must say
  // which tool comes next, and only that one.
  if (!template_has(t.gcode, {"T{NEXT_TOOL}"}, 0)) {
    fail(source,
         "tool_change.gcode never selects the next tool: add a line \"T{next_tool}\" (with the "
         "firmware's parameters, if any)");
  }
  if (t.shared_nozzle && t.gcode.find("{flush_length}") == std::string::npos) {
    fail(source,
         "tool_change.gcode of a shared nozzle never uses {flush_length}, so the previous "
         "filament would stay in the nozzle: flush with a line such as \"G1 E{flush_length} "
         "F300\" where the purge goes (a chute, a wiper)");
  }
  return t;
}

// The "filament_swap" object: the firmware's defaults for `flavor`, with the keys given.
FilamentSwap parse_filament_swap(ObjectReader r, GcodeFlavor flavor, const std::string& source) {
  FilamentSwap swap = default_filament_swap(flavor);
  if (r.has("message")) {
    swap.message =
        r.string("message", "one line that shows {message} on the screen, e.g. \"M117 {message}\"");
    if (swap.message.find('\n') != std::string::npos) {
      fail(source, "filament_swap.message must be one line, e.g. \"M117 {message}\"");
    }
  }
  if (r.has("gcode")) {
    swap.gcode = r.lines("gcode", "the firmware's pause for a manual swap, e.g. [\"M600\"]");
  }
  r.reject_unknown();
  if (swap.gcode.find_first_not_of(" \t\r\n") == std::string::npos) {
    fail(source,
         "filament_swap.gcode is empty, so the print would go on without a pause: give the "
         "firmware's pause, e.g. [\"M600\"] (docs/gcode.md)");
  }
  expand_gcode_template(swap.message, {}, source + ": filament_swap.message",
                        filament_swap_placeholders());
  expand_gcode_template(swap.gcode, {}, source + ": filament_swap.gcode",
                        filament_swap_placeholders());
  return swap;
}

PrinterProfile parse_printer_json(const json& root, const std::string& source) {
  PrinterProfile p;
  ObjectReader r(root, "", source);
  p.name = r.string("name", "the preset name, e.g. \"my-printer\"");
  p.description = r.has("description") ? r.string("description", "one line") : "";
  p.flavor = parse_flavor(
      r.string("flavor", "the firmware: marlin, klipper, reprapfirmware or bambu"), source);

  {
    ObjectReader bed = r.object("bed", "shape, size or diameter, origin, max_height");
    const std::string shape = bed.string("shape", "\"rectangular\" or \"circular\"");
    if (shape == "rectangular") {
      p.bed_shape = BedShape::kRectangular;
      p.bed_size = bed.pair("size", "width and depth in mm, e.g. [220, 220]", 0, 10000);
    } else if (shape == "circular") {
      p.bed_shape = BedShape::kCircular;
      const double d = bed.number("diameter", "mm", 0, 10000);
      p.bed_size = {d, d};
    } else {
      fail(source,
           fmt::format("unknown bed.shape \"{}\": expected rectangular or circular", shape));
    }
    if (p.bed_size.minCoeff() <= 0) {
      fail(source, "the bed size must be positive, e.g. [220, 220] mm");
    }
    const std::string origin = bed.string("origin", "\"corner\" or \"center\"");
    if (origin != "corner" && origin != "center") {
      fail(source, fmt::format("unknown bed.origin \"{}\": expected corner (the front-left corner "
                               "is x = y = 0) or center",
                               origin));
    }
    p.origin_at_center = origin == "center";
    p.max_height = bed.number("max_height", "mm", 0, 10000);
    if (p.max_height <= 0) fail(source, "bed.max_height must be positive (mm)");
    const Eigen::Vector2d lo =
        p.origin_at_center ? Eigen::Vector2d(-p.bed_size / 2) : Eigen::Vector2d::Zero();
    p.axis_min = lo;
    p.axis_max = lo + p.bed_size;
    if (bed.has("axis_limits")) {
      if (p.bed_shape != BedShape::kRectangular) {
        fail(source, "bed.axis_limits applies to rectangular beds only; remove it");
      }
      ObjectReader limits = bed.object("axis_limits", "{\"x\": [min, max], \"y\": [min, max]}");
      const Eigen::Vector2d x = limits.pair("x", "[min, max] in mm", -10000, 10000);
      const Eigen::Vector2d y = limits.pair("y", "[min, max] in mm", -10000, 10000);
      limits.reject_unknown();
      p.axis_min = {x[0], y[0]};
      p.axis_max = {x[1], y[1]};
      if ((p.axis_min.array() > lo.array() + 1e-9).any() ||
          (p.axis_max.array() < (lo + p.bed_size).array() - 1e-9).any()) {
        fail(source,
             "bed.axis_limits must contain the whole bed (they say where the head may go, "
             "which includes the printable bed)");
      }
    }
    bed.reject_unknown();
  }

  p.nozzle_diameter = r.number("nozzle_diameter", "mm, e.g. 0.4", 0.05, 5);
  p.filament_diameter = r.number("filament_diameter", "mm, 1.75 or 2.85", 0.5, 5);
  p.extruder_count =
      static_cast<int>(r.optional_number("extruders", "how many tools (T0, T1, ...)", 1, 16, 1));
  p.relative_e = r.boolean("relative_e", "true for M83, false for M82");

  {
    ObjectReader ret = r.object("retraction", "length, speed, z_hop, min_travel, firmware");
    p.retract_length = ret.number("length", "mm of filament", 0, 20);
    p.retract_speed = ret.number("speed", "mm/s", 1, 500);
    p.z_hop = ret.number("z_hop", "mm, 0 for none", 0, 10);
    p.retract_min_travel = ret.number("min_travel", "mm", 0, 1000);
    p.firmware_retraction = ret.boolean("firmware", "true for G10/G11");
    ret.reject_unknown();
  }
  {
    ObjectReader s = r.object("speeds", "print, first_layer, travel, z in mm/s");
    p.print_speed = s.number("print", "mm/s", 1, 2000);
    p.first_layer_speed = s.number("first_layer", "mm/s", 1, 2000);
    p.travel_speed = s.number("travel", "mm/s", 1, 2000);
    p.z_speed = s.number("z", "mm/s", 0.1, 500);
    s.reject_unknown();
  }
  {
    ObjectReader a = r.object("acceleration", "print and travel in mm/s^2");
    p.print_acceleration = a.number("print", "mm/s^2", 1, 1e6);
    p.travel_acceleration = a.number("travel", "mm/s^2", 1, 1e6);
    a.reject_unknown();
  }
  {
    ObjectReader c = r.object("cornering",
                              "one of junction_deviation (mm), jerk (mm/s), "
                              "square_corner_velocity (mm/s)");
    const int given = c.has("junction_deviation") + c.has("jerk") + c.has("square_corner_velocity");
    if (given != 1) {
      fail(source,
           "cornering must hold exactly one of junction_deviation (mm, Marlin 2), jerk "
           "(mm/s, classic jerk) or square_corner_velocity (mm/s, Klipper)");
    }
    if (c.has("junction_deviation")) {
      p.cornering = CorneringModel::kJunctionDeviation;
      p.junction_deviation = c.number("junction_deviation", "mm", 1e-4, 1);
    } else if (c.has("jerk")) {
      p.cornering = CorneringModel::kJerk;
      p.jerk = c.number("jerk", "mm/s", 0.01, 100);
    } else {
      // Klipper's own conversion (docs/Kinematics.md): a 90-degree corner taken at
      // square_corner_velocity under the print acceleration.
      const double scv = c.number("square_corner_velocity", "mm/s", 0.01, 100);
      p.cornering = CorneringModel::kJunctionDeviation;
      p.junction_deviation = scv * scv * (std::sqrt(2.0) - 1.0) / p.print_acceleration;
    }
    c.reject_unknown();
  }

  p.start_gcode = r.lines("start_gcode", "heat, home, level, purge; an array of lines");
  p.end_gcode = r.lines("end_gcode", "lift, park, heaters and motors off; an array of lines");
  if (r.has("tool_change")) {
    if (p.extruder_count < 2) {
      fail(source,
           "tool_change applies to printers with more than one tool; set \"extruders\" or "
           "remove it");
    }
    p.tool_change = parse_tool_change(
        r.object("tool_change", "gcode, shared_nozzle, flush_volume, prime"), p, source);
  } else if (p.extruder_count > 1) {
    fail(source, fmt::format("a printer with {} extruders needs \"tool_change\" (at least "
                             "{{\"gcode\": [\"T{{next_tool}}\"]}}); see docs/gcode.md",
                             p.extruder_count));
  }
  if (r.has("filament_swap")) {
    if (p.extruder_count > 1) {
      fail(source,
           "filament_swap applies to printers with one extruder (a manual swap at a pause); "
           "this one changes tools with tool_change: remove it");
    }
    p.filament_swap = parse_filament_swap(
        r.object("filament_swap", "message, gcode; {} for the firmware's defaults"), p.flavor,
        source);
  }
  r.reject_unknown();

  // Templates are checked now, not when a first print is written.
  expand_gcode_template(p.start_gcode, {}, source + ": start_gcode");
  expand_gcode_template(p.end_gcode, {}, source + ": end_gcode");
  for (const char* needed : {"{nozzle_temperature}", "{bed_temperature}"}) {
    if (p.start_gcode.find(needed) == std::string::npos) {
      fail(source, fmt::format("start_gcode never uses {}, so the material's temperature would be "
                               "ignored; heat with e.g. M109 S{}",
                               needed, needed));
    }
  }
  const bool all_off = template_has(p.end_gcode, {"TURN_OFF_HEATERS"}, 0);
  if (!all_off && (!template_has(p.end_gcode, {"M104", "M109"}, 'S') ||
                   !template_has(p.end_gcode, {"M140", "M190"}, 'S'))) {
    fail(source, "end_gcode must turn the heaters off: add M104 S0 and M140 S0");
  }
  if (!template_has(p.end_gcode, {"M84", "M18"}, 0)) {
    fail(source, "end_gcode must turn the motors off: add M84");
  }
  if (p.firmware_retraction && p.flavor == GcodeFlavor::kBambu) {
    fail(source,
         "Bambu firmware has no G10/G11 firmware retraction; set retraction.firmware to "
         "false");
  }
  return p;
}

json parse_json(std::string_view text, const std::string& source) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers like 1e400
    fail(source, fmt::format("not valid JSON ({})", e.what()));
  }
}

}  // namespace

FilamentSwap default_filament_swap(GcodeFlavor flavor) {
  switch (flavor) {
    case GcodeFlavor::kMarlin:
    case GcodeFlavor::kKlipper:
      return {"M117 {message}", "M600"};
    case GcodeFlavor::kRepRapFirmware:
      return {"M117 \"{message}\"", "M600"};
    case GcodeFlavor::kBambu:
      // Bambu firmware documents no message command: the screen says "paused".
      return {"; {message}", "M400 U1"};
  }
  return {"M117 {message}", "M600"};
}

std::vector<std::string> printer_preset_names() {
  std::vector<std::string> names;
  for (const EmbeddedProfile& p : embedded_profiles()) {
    if (p.kind == "printers") names.emplace_back(p.name);
  }
  return names;
}

PrinterProfile parse_printer(std::string_view json_text, const std::string& source) {
  return parse_printer_json(parse_json(json_text, source), source);
}

PrinterProfile load_printer(const std::string& name_or_path) {
  for (const EmbeddedProfile& p : embedded_profiles()) {
    if (p.kind == "printers" && p.name == name_or_path) {
      return parse_printer(p.text, fmt::format("built-in printer {}", p.name));
    }
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(name_or_path, ec)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("unknown printer \"{}\": not a preset ({}) and no such file; "
                                "'flatmorph printers' lists the presets",
                                name_or_path, fmt::join(printer_preset_names(), ", ")));
  }
  return parse_printer(read_file_text(name_or_path, "printer file"), name_or_path);
}

std::string_view to_string(GcodeFlavor flavor) {
  switch (flavor) {
    case GcodeFlavor::kMarlin:
      return "marlin";
    case GcodeFlavor::kKlipper:
      return "klipper";
    case GcodeFlavor::kRepRapFirmware:
      return "reprapfirmware";
    case GcodeFlavor::kBambu:
      return "bambu";
  }
  return "unknown";
}

std::string describe_bed(const PrinterProfile& printer) {
  const std::string origin = printer.origin_at_center ? ", centre origin" : "";
  if (printer.bed_shape == BedShape::kCircular) {
    return fmt::format("{:g} mm round x {:g} mm high{}", printer.bed_size.x(), printer.max_height,
                       origin);
  }
  return fmt::format("{:g} x {:g} x {:g} mm{}", printer.bed_size.x(), printer.bed_size.y(),
                     printer.max_height, origin);
}

Eigen::Vector2d bed_center(const PrinterProfile& printer) {
  return printer.origin_at_center ? Eigen::Vector2d::Zero() : Eigen::Vector2d(printer.bed_size / 2);
}

bool on_bed(const PrinterProfile& printer, const Eigen::Vector2d& p, double tolerance) {
  const Eigen::Vector2d c = bed_center(printer);
  if (printer.bed_shape == BedShape::kCircular) {
    return (p - c).norm() <= printer.bed_size.x() / 2 + tolerance;
  }
  const Eigen::Vector2d half = printer.bed_size / 2;
  return ((p - c).cwiseAbs().array() <= half.array() + tolerance).all();
}

Eigen::Vector2d usable_bed_area(const PrinterProfile& printer, double margin) {
  if (printer.bed_shape == BedShape::kCircular) {
    const double side = printer.bed_size.x() / std::numbers::sqrt2 - 2 * margin;
    return {side, side};
  }
  return printer.bed_size - Eigen::Vector2d::Constant(2 * margin);
}

const std::vector<GcodePlaceholder>& gcode_placeholders() {
  static const std::vector<GcodePlaceholder> kPlaceholders = {
      {"nozzle_temperature", "the material's nozzle temperature, degrees C"},
      {"bed_temperature", "the material's bed temperature, degrees C"},
      {"first_layer_height", "height of the first layer, mm"},
      {"nozzle_diameter", "mm"},
      {"filament_diameter", "mm"},
      {"bed_size_x", "bed width, mm"},
      {"bed_size_y", "bed depth, mm"},
      {"max_height", "highest nozzle position, mm"},
      {"min_x", "print bounding box on the bed (skirt included), mm; for adaptive levelling"},
      {"min_y", "print bounding box, mm"},
      {"max_x", "print bounding box, mm"},
      {"max_y", "print bounding box, mm"},
      {"size_x", "print bounding box width, mm"},
      {"size_y", "print bounding box depth, mm"},
      {"center_x", "centre of the print bounding box, mm"},
      {"center_y", "centre of the print bounding box, mm"},
      {"max_z", "top of the print, mm"},
      {"park_z", "max_z + 20 mm, at most max_height: where the end G-code lifts the nozzle"},
      {"layer_count", "number of layers"},
      {"travel_feed_rate", "travel speed, mm/min (for F)"},
      {"printer_name", "the printer profile's name"},
      {"material_name", "the material's name"},
  };
  return kPlaceholders;
}

const std::vector<GcodePlaceholder>& tool_change_placeholders() {
  static const std::vector<GcodePlaceholder> kPlaceholders = {
      {"previous_tool", "the tool in use until the change (0, 1, ...)"},
      {"next_tool", "the tool that prints next"},
      {"previous_temperature", "the previous tool's material nozzle temperature, degrees C"},
      {"next_temperature", "the next tool's material nozzle temperature, degrees C"},
      {"x", "where the next tool starts printing, bed coordinates, mm"},
      {"y", "where the next tool starts printing, bed coordinates, mm"},
      {"z", "height of the layer the next tool prints, mm"},
      {"travel_feed_rate", "travel speed, mm/min (for F)"},
      {"safe_z",
       "2 mm above everything printed so far, at most max_height: where to cross the "
       "print"},
      {"flush_temperature",
       "degrees C both materials take: the higher of the two, at most the lower maximum (the "
       "flush of a shared nozzle)"},
      {"flush_length",
       "mm of the next filament that flush_volume takes (0 with a nozzle per tool)"},
      {"retract_length",
       "the profile's retraction, mm: a shared nozzle's template ends its flush "
       "with this retraction"},
  };
  return kPlaceholders;
}

const std::vector<GcodePlaceholder>& filament_swap_placeholders() {
  static const std::vector<GcodePlaceholder> kPlaceholders = {
      {"message", "what to do, e.g. \"Load tpu-generic (T1)\""},
      {"previous_tool", "the tool whose material comes out (0, 1, ...)"},
      {"next_tool", "the tool whose material goes in"},
      {"previous_material", "the name of the material that comes out"},
      {"next_material", "the name of the material that goes in"},
      {"previous_temperature", "the previous material's nozzle temperature, degrees C"},
      {"next_temperature", "the next material's nozzle temperature, degrees C"},
      {"swap_temperature",
       "degrees C the nozzle waits at during the swap: the hotter of the two materials' "
       "temperatures, at most the lower maximum, so that the old one unloads and the new one "
       "purges (the next material's when no temperature suits both)"},
      {"safe_z", "2 mm above everything printed so far, at most max_height"},
  };
  return kPlaceholders;
}

std::string expand_gcode_template(std::string_view text,
                                  const std::vector<std::pair<std::string, std::string>>& values,
                                  const std::string& source,
                                  const std::vector<GcodePlaceholder>& known) {
  std::string out;
  out.reserve(text.size() + 64);
  int line = 1;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (c == '}' && i + 1 < text.size() && text[i + 1] == '}') {
      out += '}';
      ++i;
      continue;
    }
    if (c != '{') {
      out += c;
      continue;
    }
    if (i + 1 < text.size() && text[i + 1] == '{') {
      out += '{';
      ++i;
      continue;
    }
    const size_t close = text.find_first_of("}\n", i + 1);
    if (close == std::string_view::npos || text[close] != '}') {
      fail(source, fmt::format("line {}: unclosed '{{'; write {{{{ for a literal brace", line));
    }
    const std::string_view name = text.substr(i + 1, close - i - 1);
    if (std::none_of(known.begin(), known.end(),
                     [&](const GcodePlaceholder& p) { return p.name == name; })) {
      std::vector<std::string_view> names;
      for (const GcodePlaceholder& p : known) names.push_back(p.name);
      fail(source, fmt::format("line {}: unknown placeholder {{{}}}; known: {}", line, name,
                               fmt::join(names, ", ")));
    }
    if (!values.empty()) {
      const auto it = std::find_if(values.begin(), values.end(),
                                   [&](const auto& v) { return v.first == name; });
      if (it == values.end()) {
        throw std::logic_error(fmt::format("no value for the G-code placeholder {{{}}}", name));
      }
      out += it->second;
    }
    i = close;
  }
  return out;
}

}  // namespace flatmorph
