#include "gcode/gcode_check.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <stdexcept>

#include "gcode/gcode_parse.h"

namespace flatmorph {
namespace {

constexpr double kNoMotion = 1e-6;  // mm of filament or head motion treated as none
// Written by the G-code writer where a one-nozzle printer pauses for a manual filament swap.
constexpr std::string_view kSwapAnnotation = ";FILAMENT_SWAP:T";

class Checker {
 public:
  Checker(const PrinterProfile& printer, const std::vector<Material>& tool_materials,
          size_t max_violations)
      : printer_(printer), materials_(tool_materials), max_(max_violations) {
    // The bed carries every material: the most it may reach is the least of their maxima.
    for (const Material& m : materials_) {
      if (!bed_limit_ || m.max_bed_temperature < bed_limit_->max_bed_temperature) bed_limit_ = &m;
    }
  }

  std::vector<GcodeViolation> run(std::string_view text) {
    int number = 0;
    size_t begin = 0;
    std::string buffer;
    while (begin < text.size() && violations_.size() < max_) {
      size_t end = text.find('\n', begin);
      if (end == std::string_view::npos) end = text.size();
      line_ = ++number;
      const std::string_view raw = text.substr(begin, end - begin);
      if (trim(raw).starts_with(kSwapAnnotation)) swap_filament(trim(raw));
      process(strip(raw, buffer));
      begin = end + 1;
    }
    line_ = std::max(number, 1);
    finish();
    if (violations_.size() > max_) violations_.resize(max_);
    return std::move(violations_);
  }

 private:
  void flag(ViolationKind kind, std::string reason) {
    if (violations_.size() < max_) violations_.push_back({line_, kind, std::move(reason)});
  }

  bool relative_e() const { return relative_e_; }

  // ";FILAMENT_SWAP:T<n>": from here on tool n's material is in the one nozzle, and the nozzle
  // must wait (M109) before it extrudes. Tool changers say T<n> instead.
  void swap_filament(std::string_view annotation) {
    if (printer_.extruder_count > 1) return;
    const std::string_view digits = annotation.substr(kSwapAnnotation.size());
    int tool = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), tool);
    if (ec != std::errc() || end != digits.data() + digits.size() || tool < 0) {
      flag(ViolationKind::kMalformed,
           fmt::format("\"{}\": expected {}<tool number>", annotation, kSwapAnnotation));
      return;
    }
    if (static_cast<size_t>(tool) >= materials_.size()) {
      if (reported_tools_.insert(tool).second) {
        flag(ViolationKind::kToolWithoutMaterial,
             fmt::format("a filament swap loads T{}'s material but no material was given for it "
                         "({} material(s), for T0 to T{}): give one material per tool",
                         tool, materials_.size(), materials_.size() - 1));
      }
      return;
    }
    loaded_ = tool;
    swapped_ = true;
    swap_line_ = line_;
  }

  // The material whose filament `tool` prints: its own, or on a printer with one extruder, the
  // one the last filament swap loaded.
  const Material& material_of(int tool) const {
    return material(printer_.extruder_count == 1 ? loaded_ : tool);
  }

  void process(std::string_view line) {
    if (line.empty()) return;
    Command cmd;
    if (const auto bad = parse_command(line, cmd)) {
      if (is_classic(cmd.name) && known_command(cmd.name)) {
        flag(ViolationKind::kMalformed,
             fmt::format("\"{}\": the parameter {} is not a number", line, *bad));
      }
      return;
    }
    const std::string& n = cmd.name;
    if (n == "G0" || n == "G1") {
      if (!check_numbers(cmd, line, "XYZEF")) return;
      move(cmd, n == "G0", false, false);
    } else if (n == "G2" || n == "G3") {
      if (!check_numbers(cmd, line, "XYZEFIJR")) return;
      move(cmd, false, true, n == "G2");
    } else if (n == "G90" || n == "G91") {
      // Marlin 2, as the reader (gcode_reader.cpp): G90/G91 set every axis, E included, until
      // the next M82/M83.
      g91_ = relative_e_ = n == "G91";
      e_max_ = e_;
    } else if (n == "M82" || n == "M83") {
      relative_e_ = n == "M83";
      declared_ = true;
      e_max_ = e_;
    } else if (n == "G92") {
      if (!check_numbers(cmd, line, "XYZE")) return;
      const bool none = !cmd.has('X') && !cmd.has('Y') && !cmd.has('Z') && !cmd.has('E');
      for (int axis = 0; axis < 3; ++axis) {
        const char letter = "XYZ"[axis];
        if (none || cmd.has(letter)) {
          pos_[axis] = none ? 0 : *cmd.get(letter);
          known_[axis] = true;
        }
      }
      if (none || cmd.has('E')) e_ = e_max_ = none ? 0 : *cmd.get('E');
    } else if (n == "G28") {
      const bool all = !cmd.has('X') && !cmd.has('Y') && !cmd.has('Z');
      for (int axis = 0; axis < 3; ++axis) {
        if (all || cmd.has("XYZ"[axis])) known_[axis] = false;
      }
      moved_ = true;
      motors_off_ = false;
    } else if (n == "M104" || n == "M109") {
      if (!check_numbers(cmd, line, "STR")) return;
      const int tool = cmd.has('T') ? tool_number(*cmd.get('T')) : tool_;
      if (const auto t = cmd.has('S') ? cmd.get('S') : cmd.get('R')) {
        set_nozzle(tool, *t);
        if (n == "M109") swap_line_.reset();
      }
    } else if (n == "G10" && cmd.has('P')) {
      // RepRapFirmware: G10 P<tool> S<active> R<standby> sets a tool's temperatures.
      if (!check_numbers(cmd, line, "PSR")) return;
      const int tool = tool_number(*cmd.get('P'));
      if (cmd.has('S')) set_nozzle(tool, *cmd.get('S'));
      if (cmd.has('R')) set_nozzle(tool, *cmd.get('R'));
    } else if (n == "M140" || n == "M190") {
      if (!check_numbers(cmd, line, "SR")) return;
      if (const auto t = cmd.has('S') ? cmd.get('S') : cmd.get('R')) {
        bed_ = *t;
        if (bed_limit_ && *t > bed_limit_->max_bed_temperature) {
          flag(ViolationKind::kBedTemperature,
               fmt::format("bed set to {:g} C, above {:g} C, the most the material {} allows", *t,
                           bed_limit_->max_bed_temperature, bed_limit_->name));
        }
      }
    } else if (n == "TURN_OFF_HEATERS") {
      for (auto& [tool, target] : nozzle_) target = 0;
      bed_ = 0;
    } else if (n == "M84" || n == "M18") {
      // "M84 S<seconds>" sets the idle timeout; "M84 E" releases the extruder alone.
      const bool timeout = cmd.has('S') && !std::isnan(*cmd.get('S'));
      const bool some_axes = cmd.has('X') || cmd.has('Y') || cmd.has('Z') || cmd.has('E');
      const bool all_axes = cmd.has('X') && cmd.has('Y');
      if (!timeout && (!some_axes || all_axes)) motors_off_ = true;
    } else if (n == "M17") {
      motors_off_ = false;
    } else if (n[0] == 'T' && is_classic(n)) {
      const int next = tool_number(std::strtod(n.c_str() + 1, nullptr));
      // A filament changer loads the next filament into the nozzle: none of it is retracted.
      if (printer_.tool_change.shared_nozzle && next != tool_) retracted_[next] = 0;
      tool_ = next;
      known_tool(tool_, "selects");
    }
  }

  // Whether `tool` exists on the printer and has a material to judge it by; flags it (once per
  // tool) when not. `what` is the verb of the command ("selects", "heats", "extrudes with").
  bool known_tool(int tool, std::string_view what) {
    if (tool >= printer_.extruder_count) {
      if (reported_tools_.insert(tool).second) {
        flag(ViolationKind::kUnknownTool,
             fmt::format("{} T{} but {} has {} tool(s), T0 to T{}", what, tool, printer_.name,
                         printer_.extruder_count, printer_.extruder_count - 1));
      }
      return false;
    }
    if (static_cast<size_t>(tool) >= materials_.size()) {
      if (what != "selects" && reported_tools_.insert(tool).second) {
        flag(ViolationKind::kToolWithoutMaterial,
             fmt::format("{} T{} but no material was given for it ({} material(s), for T0 to "
                         "T{}): give one material per tool",
                         what, tool, materials_.size(), materials_.size() - 1));
      }
      return false;
    }
    return true;
  }

  const Material& material(int tool) const { return materials_[static_cast<size_t>(tool)]; }

  // The heater that warms `tool`'s filament: its own, or the one of a shared nozzle.
  int heater(int tool) const { return printer_.tool_change.shared_nozzle ? 0 : tool; }

  // Tool numbers as the firmware would take them; absurd ones are clamped rather than trusted.
  static int tool_number(double value) {
    return static_cast<int>(std::clamp(std::floor(value), 0.0, 255.0));
  }

  static bool known_command(const std::string& n) {
    static const char* kKnown[] = {"G0",  "G1",   "G2",   "G3",   "G10",  "G28",
                                   "G90", "G91",  "G92",  "M82",  "M83",  "M84",
                                   "M18", "M104", "M109", "M140", "M190", "M17"};
    return std::any_of(std::begin(kKnown), std::end(kKnown), [&](const char* k) { return n == k; });
  }

  // The parameters the rules read must be numbers ("G1 X" or "M104 S" are malformed).
  bool check_numbers(const Command& cmd, std::string_view line, std::string_view letters) {
    for (char letter : letters) {
      if (cmd.has(letter) && std::isnan(*cmd.get(letter))) {
        flag(ViolationKind::kMalformed,
             fmt::format("\"{}\": the parameter {} has no value", line, letter));
        return false;
      }
    }
    return true;
  }

  void set_nozzle(int tool, double target) {
    if (tool >= printer_.extruder_count) {
      known_tool(tool, "heats");
      return;
    }
    nozzle_[heater(tool)] = target;
    // Turning a heater off needs no material.
    if (target <= 0 || !known_tool(tool, "heats")) return;
    const Material& m = material_of(tool);
    if (target > m.max_nozzle_temperature) {
      flag(ViolationKind::kNozzleTemperature,
           fmt::format("nozzle (T{}) set to {:g} C, above {:g} C, the most the material {} allows",
                       tool, target, m.max_nozzle_temperature, m.name));
    }
  }

  void move(const Command& cmd, bool rapid, bool arc, bool clockwise) {
    const std::array<double, 3> from = pos_;
    const std::array<bool, 3> known_before = known_;
    for (int axis = 0; axis < 3; ++axis) {
      const char letter = "XYZ"[axis];
      if (!cmd.has(letter)) continue;
      const double v = *cmd.get(letter);
      if (g91_) {
        pos_[axis] += v;  // stays unknown if it was
      } else {
        pos_[axis] = v;
        known_[axis] = true;
      }
    }
    moved_ = true;
    motors_off_ = false;

    // Head path length (mm), when both ends are known.
    std::optional<double> xy_length, length;
    const bool xy_known = known_before[0] && known_before[1] && known_[0] && known_[1];
    std::vector<std::array<double, 2>> arc_points;
    if (xy_known) {
      const double dx = pos_[0] - from[0], dy = pos_[1] - from[1];
      xy_length = std::hypot(dx, dy);
      if (arc && (cmd.has('I') || cmd.has('J'))) {
        xy_length = arc_path(from, cmd, clockwise, arc_points);
      }
      const double dz = known_before[2] && known_[2] ? pos_[2] - from[2] : 0;
      length = std::hypot(*xy_length, dz);
    }
    // Only the axes this command moves: a head already off the bed was flagged when it left.
    const std::array<bool, 3> moved_axes = {known_[0] && (cmd.has('X') || cmd.has('Y')),
                                            known_[1] && (cmd.has('X') || cmd.has('Y')),
                                            known_[2] && cmd.has('Z')};
    check_position(pos_, moved_axes);
    for (const auto& p : arc_points) {
      if (violations_.empty() || violations_.back().line != line_) {
        check_position({p[0], p[1], pos_[2]}, {true, true, false});
      }
    }
    if (!cmd.has('E')) return;

    const double e = *cmd.get('E');
    const double de = relative_e() ? e : e - e_;
    e_ = relative_e() ? e_ + e : e;
    if (de > kNoMotion) {
      if (rapid) {
        flag(ViolationKind::kExtrusionOnTravel,
             fmt::format("G0 is a travel move but pushes {:.5f} mm of filament; extrude with G1",
                         de));
      }
      if (!declared_ && !reported_no_mode_) {
        reported_no_mode_ = true;
        flag(ViolationKind::kNoExtrusionMode,
             "extrusion before any M82 (absolute E) or M83 (relative E): the firmware's default "
             "mode may not be the one this file assumes");
      }
      double& retracted = retracted_[tool_];
      const double prime = std::min(de, retracted);
      retracted -= prime;
      const double extruded = de - prime;
      if (prime > kNoMotion && xy_length && *xy_length > kRetractMoveTolerance) {
        flag(ViolationKind::kUnretractWhileMoving,
             fmt::format("pushes back {:.3f} mm of retracted filament while travelling {:.3f} mm: "
                         "unretract in place (G1 E only), then move",
                         prime, *xy_length));
      }
      if (extruded > kNoMotion) check_extrusion(extruded, length);
    } else if (de < -kNoMotion) {
      retracted_[tool_] += -de;
      if (xy_length && *xy_length > kRetractMoveTolerance) {
        flag(ViolationKind::kRetractWhileMoving,
             fmt::format("pulls back {:.3f} mm of filament while travelling {:.3f} mm (more than "
                         "{:g} mm): retract in place, then travel",
                         -de, *xy_length, kRetractMoveTolerance));
      }
      const double allowed = printer_.retract_length + kEBackwardsSlack;
      if (!relative_e() && e_ < e_max_ - allowed) {
        flag(ViolationKind::kEBackwards,
             fmt::format("absolute E goes back to {:.5f}, {:.3f} mm below its maximum {:.5f} "
                         "without G92; a retraction is at most {:g} mm",
                         e_, e_max_ - e_, e_max_, allowed));
      }
    }
    if (!relative_e()) e_max_ = std::max(e_max_, e_);
  }

  void check_extrusion(double extruded, const std::optional<double>& length) {
    const auto target = nozzle_.find(heater(tool_));
    if (known_tool(tool_, "extrudes with")) {
      const Material& m = material_of(tool_);
      if (swap_line_) {
        flag(ViolationKind::kSwapTemperature,
             fmt::format("extrudes {} after the filament swap of line {} without waiting for the "
                         "nozzle since: wait for its temperature with M109 S{:g} after the swap",
                         m.name, *swap_line_, m.nozzle_temperature));
        swap_line_.reset();
      }
      if (target != nozzle_.end() && target->second < m.min_nozzle_temperature) {
        flag(ViolationKind::kColdExtrusion,
             fmt::format("extrudes while the nozzle (T{}) is set to {:g} C, below {:g} C, the "
                         "least the material {} needs",
                         tool_, target->second, m.min_nozzle_temperature, m.name));
      }
      // A shared nozzle keeps the temperature the previous filament was set to; said once per
      // filament and temperature.
      const int filament = printer_.extruder_count == 1 ? loaded_ : tool_;
      if (target != nozzle_.end() && (printer_.tool_change.shared_nozzle || swapped_) &&
          target->second > m.max_nozzle_temperature &&
          reported_hot_.insert({filament, target->second}).second) {
        flag(ViolationKind::kNozzleTemperature,
             fmt::format("extrudes T{} through the shared nozzle set to {:g} C, above {:g} C, the "
                         "most the material {} allows: set the nozzle to its temperature after "
                         "the change",
                         filament, target->second, m.max_nozzle_temperature, m.name));
      }
    }
    if (length && *length > kNoMotion) {
      const double area = extruded * std::numbers::pi * printer_.filament_diameter *
                          printer_.filament_diameter / 4 / *length;
      const double most =
          kMaxBeadAreaInNozzleSquares * printer_.nozzle_diameter * printer_.nozzle_diameter;
      if (area > most) {
        flag(ViolationKind::kOverExtrusion,
             fmt::format("{:.5f} mm of filament over {:.3f} mm of path is a bead of {:.2f} mm^2, "
                         "more than {:.2f} mm^2 a {:g} mm nozzle can lay: are E values in the "
                         "declared mode ({})?",
                         extruded, *length, area, most, printer_.nozzle_diameter,
                         relative_e() ? "relative, M83" : "absolute, M82"));
      }
    }
  }

  // Points along a G2/G3 arc given by its centre offset I, J from the start (every degree), and
  // the arc's length in xy.
  double arc_path(const std::array<double, 3>& from, const Command& cmd, bool clockwise,
                  std::vector<std::array<double, 2>>& points) const {
    const double cx = from[0] + cmd.get('I').value_or(0);
    const double cy = from[1] + cmd.get('J').value_or(0);
    const double r = std::hypot(from[0] - cx, from[1] - cy);
    const double a0 = std::atan2(from[1] - cy, from[0] - cx);
    const double a1 = std::atan2(pos_[1] - cy, pos_[0] - cx);
    double sweep = clockwise ? a0 - a1 : a1 - a0;
    while (sweep <= 1e-12) sweep += 2 * std::numbers::pi;
    const int steps = std::max(8, static_cast<int>(std::ceil(sweep * 180 / std::numbers::pi)));
    for (int s = 1; s < steps; ++s) {
      const double a = a0 + (clockwise ? -1 : 1) * sweep * s / steps;
      points.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
    }
    return r * sweep;
  }

  void check_position(const std::array<double, 3>& p, const std::array<bool, 3>& known) {
    const double tol = kBedTolerance;
    if (printer_.bed_shape == BedShape::kCircular) {
      const Eigen::Vector2d c = bed_center(printer_);
      const double r = printer_.bed_size.x() / 2;
      if (known[0] && known[1]) {
        const double d = std::hypot(p[0] - c.x(), p[1] - c.y());
        if (d > r + tol) {
          flag(ViolationKind::kOutsideBed,
               fmt::format("X {:.3f} Y {:.3f} lies {:.3f} mm from the bed centre, beyond its "
                           "{:g} mm radius ({})",
                           p[0], p[1], d, r, printer_.name));
        }
      } else {
        for (int axis = 0; axis < 2; ++axis) {
          if (known[axis] && std::abs(p[axis] - c[axis]) > r + tol) {
            flag(ViolationKind::kOutsideBed,
                 fmt::format("{} {:.3f} lies beyond the {:g} mm radius of the bed ({})", "XY"[axis],
                             p[axis], r, printer_.name));
          }
        }
      }
    } else {
      for (int axis = 0; axis < 2; ++axis) {
        if (known[axis] &&
            (p[axis] < printer_.axis_min[axis] - tol || p[axis] > printer_.axis_max[axis] + tol)) {
          flag(ViolationKind::kOutsideBed,
               fmt::format("{} {:.3f} is outside the {} range [{:g}, {:g}] of {}", "XY"[axis],
                           p[axis], "xy"[axis], printer_.axis_min[axis], printer_.axis_max[axis],
                           printer_.name));
        }
      }
    }
    if (known[2] && p[2] > printer_.max_height + tol) {
      flag(ViolationKind::kAboveMaxHeight,
           fmt::format("Z {:.3f} is above {:g} mm, the maximum height of {}", p[2],
                       printer_.max_height, printer_.name));
    }
    if (known[2] && p[2] < -tol) {
      flag(ViolationKind::kBelowBed,
           fmt::format("Z {:.3f} is below the bed surface (z = 0)", p[2]));
    }
  }

  void finish() {
    for (const auto& [tool, target] : nozzle_) {
      if (target > 0) {
        flag(ViolationKind::kHeatersOnAtEnd,
             fmt::format("the nozzle (T{}) is still set to {:g} C at the end of the file; end "
                         "with M104 S0",
                         tool, target));
      }
    }
    if (bed_ && *bed_ > 0) {
      flag(ViolationKind::kHeatersOnAtEnd,
           fmt::format("the bed is still set to {:g} C at the end of the file; end with M140 S0",
                       *bed_));
    }
    if (moved_ && !motors_off_) {
      flag(ViolationKind::kMotorsOnAtEnd, "the motors stay on after the last move; end with M84");
    }
  }

  const PrinterProfile& printer_;
  const std::vector<Material>& materials_;  // per tool
  const Material* bed_limit_ = nullptr;     // the material with the lowest max_bed_temperature
  const size_t max_;
  std::vector<GcodeViolation> violations_;
  int line_ = 0;

  std::array<double, 3> pos_{0, 0, 0};  // logical position (mm), valid where known_
  std::array<bool, 3> known_{false, false, false};
  bool g91_ = false;
  bool relative_e_ = false;  // M83, or G91 after the last M82/M83
  bool declared_ = false;
  bool reported_no_mode_ = false;
  double e_ = 0;      // the E register
  double e_max_ = 0;  // its largest value since the last G92 or mode change (absolute mode)
  // Filament pulled back and not yet pushed again (mm), per tool: each has its own filament.
  std::map<int, double> retracted_;
  int tool_ = 0;
  // One extruder: the tool whose material the last filament swap loaded (T0's at the start), and
  // the line of that swap while no M109 has followed it.
  int loaded_ = 0;
  bool swapped_ = false;
  std::optional<int> swap_line_;
  std::set<int> reported_tools_;                   // tools flagged as unknown or without a material
  std::map<int, double> nozzle_;                   // targets set so far, per heater (heater())
  std::set<std::pair<int, double>> reported_hot_;  // tools and temperatures flagged as too hot
  std::optional<double> bed_;
  bool moved_ = false;
  bool motors_off_ = false;
};

}  // namespace

std::string_view to_string(ViolationKind kind) {
  switch (kind) {
    case ViolationKind::kMalformed:
      return "malformed";
    case ViolationKind::kOutsideBed:
      return "outside-bed";
    case ViolationKind::kBelowBed:
      return "below-bed";
    case ViolationKind::kAboveMaxHeight:
      return "above-max-height";
    case ViolationKind::kNozzleTemperature:
      return "nozzle-temperature";
    case ViolationKind::kBedTemperature:
      return "bed-temperature";
    case ViolationKind::kColdExtrusion:
      return "cold-extrusion";
    case ViolationKind::kExtrusionOnTravel:
      return "extrusion-on-travel";
    case ViolationKind::kUnretractWhileMoving:
      return "unretract-while-moving";
    case ViolationKind::kRetractWhileMoving:
      return "retract-while-moving";
    case ViolationKind::kEBackwards:
      return "e-backwards";
    case ViolationKind::kOverExtrusion:
      return "over-extrusion";
    case ViolationKind::kNoExtrusionMode:
      return "no-e-mode";
    case ViolationKind::kHeatersOnAtEnd:
      return "heaters-on-at-end";
    case ViolationKind::kMotorsOnAtEnd:
      return "motors-on-at-end";
    case ViolationKind::kUnknownTool:
      return "unknown-tool";
    case ViolationKind::kToolWithoutMaterial:
      return "tool-without-material";
    case ViolationKind::kSwapTemperature:
      return "swap-temperature";
  }
  return "unknown";
}

std::vector<GcodeViolation> check_gcode(std::string_view text, const PrinterProfile& printer,
                                        const std::vector<Material>& tool_materials,
                                        size_t max_violations) {
  if (tool_materials.empty()) {
    throw std::invalid_argument("check_gcode: no material (one per tool, T0 first)");
  }
  return Checker(printer, tool_materials, max_violations).run(text);
}

}  // namespace flatmorph
