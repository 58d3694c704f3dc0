#include "gcode/gcode_writer.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/error.h"
#include "gcode/estimate.h"
#include "gcode/gcode_check.h"
#include "gcode/tool_change.h"
#include "mesh/convex_hull.h"

namespace flatmorph {
namespace {

// Fixed-point units of the numbers written: X/Y/Z with 3 decimals, E with 5. Positions and E are
// tracked in these integer units, so that what the writer believes is exactly what the printer
// reads, and rounding never accumulates.
constexpr double kXyzUnits = 1e3;
constexpr double kEUnits = 1e5;
// The start G-code leaves the nozzle near the bed at an unknown place (after a purge line): the
// first travel lifts at least this much (mm) so it does not drag through the purge blob.
constexpr double kFirstTravelLift = 1.0;
// How far the end G-code's park position is above the print (mm): room to grab the plate.
constexpr double kParkClearance = 20.0;
// How far above everything printed the head crosses the print during a tool change (mm).
constexpr double kToolChangeClearance = 2.0;

// Appends `units` / 10^decimals in fixed notation ("-12.500"), without going through printf: the
// writer prints millions of numbers and the output must not depend on the locale.
void append_fixed(std::string& out, long long units, int decimals) {
  if (units < 0) {
    out += '-';
    units = -units;
  }
  long long scale = 1;
  for (int i = 0; i < decimals; ++i) scale *= 10;
  out += std::to_string(units / scale);
  if (decimals == 0) return;
  out += '.';
  std::string frac = std::to_string(units % scale);
  out.append(static_cast<size_t>(decimals) - frac.size(), '0');
  out += frac;
}

std::string fixed(double value, int decimals) {
  std::string s;
  append_fixed(s, std::llround(value * std::pow(10.0, decimals)), decimals);
  return s;
}

double filament_area(const PrinterProfile& printer) {
  return std::numbers::pi * printer.filament_diameter * printer.filament_diameter / 4;
}

// Checks what the writer relies on; a toolpath violating it is a bug of the code that made it,
// except for tools: a tool the printer lacks or without a material is the user's choice.
void validate_toolpath(const Toolpath& toolpath, const PrinterProfile& printer,
                       const std::vector<Material>& tool_materials) {
  if (toolpath.layers.empty()) throw std::invalid_argument("make_gcode: the toolpath has no layer");
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    const ToolpathLayer& layer = toolpath.layers[k];
    if (!(layer.z > 0) || !(layer.height > 0) || !std::isfinite(layer.z)) {
      throw std::invalid_argument(
          fmt::format("make_gcode: layer {} has z {} and height {}", k + 1, layer.z, layer.height));
    }
    for (const PathPolyline& path : layer.paths) {
      if (path.points.rows() < 2 || path.segments.size() + 1 != size_t(path.points.rows())) {
        throw std::invalid_argument(
            fmt::format("make_gcode: a path of layer {} has {} points and {} segments", k + 1,
                        path.points.rows(), path.segments.size()));
      }
      if (!path.points.allFinite() || (path.points.col(2).array() <= 0).any()) {
        throw std::invalid_argument(
            fmt::format("make_gcode: a path of layer {} has a point that is not finite or not "
                        "above the bed",
                        k + 1));
      }
      for (const SegmentStyle& s : path.segments) {
        if (s.travel) continue;
        if (!(s.width > 0) || !(s.layer_height > 0) || !(s.feed_rate >= 0) ||
            !std::isfinite(s.width + s.layer_height + s.feed_rate)) {
          throw std::invalid_argument(
              fmt::format("make_gcode: a segment of layer {} has width {}, height {}, feed rate {}",
                          k + 1, s.width, s.layer_height, s.feed_rate));
        }
        // A filament swap prints every tool's material through the one nozzle.
        if (s.tool < 0 || (s.tool >= printer.extruder_count && !printer.filament_swap)) {
          throw UserError(ErrorCategory::kInfeasible,
                          fmt::format("the toolpath uses tool T{} but the printer {} has {} "
                                      "extruder(s): choose a printer with more tools, or one "
                                      "whose profile has a filament_swap (docs/gcode.md)",
                                      s.tool, printer.name, printer.extruder_count));
        }
        if (static_cast<size_t>(s.tool) >= tool_materials.size()) {
          throw UserError(ErrorCategory::kOption,
                          fmt::format("the toolpath prints with tool T{} but only {} material(s) "
                                      "were given ({} for T0): give one material per tool, "
                                      "comma-separated in the order T0,T1,...",
                                      s.tool, tool_materials.size(), tool_materials[0].name));
        }
      }
    }
  }
}

// The boundary of the hull grown by `r`: straight edges moved out by r joined by arcs of radius r
// around the hull's corners (steps of at most 10 degrees).
std::vector<Eigen::Vector2d> offset_hull(const std::vector<Eigen::Vector2d>& hull, double r) {
  std::vector<Eigen::Vector2d> out;
  const size_t n = hull.size();
  auto arc = [&](const Eigen::Vector2d& c, double from, double sweep) {
    const int steps = std::max(1, static_cast<int>(std::ceil(sweep / (std::numbers::pi / 18))));
    for (int s = 0; s <= steps; ++s) {
      const double a = from + sweep * s / steps;
      out.push_back(c + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
  };
  if (n == 1) {
    arc(hull[0], 0, 2 * std::numbers::pi);
    out.pop_back();
    return out;
  }
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& prev = hull[(i + n - 1) % n];
    const Eigen::Vector2d& here = hull[i];
    const Eigen::Vector2d& next = hull[(i + 1) % n];
    // Outward normals of a counter-clockwise polygon are its edge directions turned clockwise.
    const Eigen::Vector2d d_in = (here - prev).normalized();
    const Eigen::Vector2d d_out = (next - here).normalized();
    const double a_in = std::atan2(-d_in.x(), d_in.y());
    const double a_out = std::atan2(-d_out.x(), d_out.y());
    double sweep = a_out - a_in;
    while (sweep < 0) sweep += 2 * std::numbers::pi;
    while (sweep >= 2 * std::numbers::pi) sweep -= 2 * std::numbers::pi;
    arc(here, a_in, sweep);
  }
  return out;
}

std::string fan_command(GcodeFlavor flavor, double percent) {
  if (percent <= 0) return "M107";
  if (flavor == GcodeFlavor::kRepRapFirmware) {
    return "M106 S" + fixed(percent / 100, 2);  // RepRapFirmware reads 0..1
  }
  return fmt::format("M106 S{}", std::lround(std::min(percent, 100.0) / 100 * 255));
}

// Emits the moves of the print and keeps the machine state: where the head is, what the E register
// holds, the feed rate, the active tool, whether each tool's filament is retracted, and the
// annotations in effect.
// A material's own speeds (mm/s) where it sets them, the printer's otherwise.
double print_speed(const PrinterProfile& printer, const Material& material) {
  return material.print_speed > 0 ? material.print_speed : printer.print_speed;
}
double first_layer_speed(const PrinterProfile& printer, const Material& material) {
  return material.first_layer_speed > 0 ? material.first_layer_speed : printer.first_layer_speed;
}

class Emitter {
 public:
  Emitter(const PrinterProfile& printer, const std::vector<Material>& tool_materials,
          const Eigen::Vector2d& offset, std::optional<PrimePad> pad)
      : printer_(printer),
        materials_(tool_materials),
        offset_(offset),
        pad_(std::move(pad)),
        extruded_(tool_materials.size(), 0.0),
        retracted_(static_cast<size_t>(printer.extruder_count), false) {}

  // The filament a tool prints with, as the firmware sees it: its own, or on a printer that swaps
  // by hand, the one in the nozzle (the pause leaves E as it was).
  size_t filament(int tool) const { return printer_.filament_swap ? 0 : static_cast<size_t>(tool); }

  std::string& out() { return out_; }
  std::vector<Motion>& motions() { return motions_; }
  // mm of filament per tool.
  const std::vector<double>& extruded() const { return extruded_; }
  int tool() const { return tool_; }
  int tool_changes() const { return tool_changes_; }

  void line(std::string_view text) {
    out_ += text;
    out_ += '\n';
  }

  // `first_of_section`: the layer lies on the bed (the first layer of the print or of a section).
  void begin_layer(const ToolpathLayer& layer, bool first_of_section) {
    out_ += ";LAYER_CHANGE\n;Z:";
    out_ += fixed(layer.z, 3);
    out_ += "\n;HEIGHT:";
    height_ = std::llround(layer.height * kXyzUnits);
    append_fixed(out_, height_, 3);
    out_ += '\n';
    type_.reset();  // say the type again in every layer, as PrusaSlicer does
    if (!printer_.relative_e || printer_.flavor == GcodeFlavor::kBambu) {
      // Absolute E restarts at each layer so its numbers stay small; Bambu printers expect it
      // with relative E too.
      e_exact_ -= static_cast<double>(e_units_) / kEUnits;
      e_units_ = 0;
      line("G92 E0");
    }
    first_of_section_ = first_of_section;
    first_travel_of_layer_ = true;
  }

  void path(const PathPolyline& path) {
    // Change tools before travelling, so the new tool is the one that arrives.
    for (size_t i = 0; i < path.segments.size(); ++i) {
      if (!path.segments[i].travel) {
        change_tool(path.segments[i].tool, point(path, i));
        break;
      }
    }
    travel_to(point(path, 0));
    for (size_t i = 0; i < path.segments.size(); ++i) {
      const SegmentStyle& s = path.segments[i];
      const Eigen::Vector3d to = point(path, i + 1);
      if (s.travel) {
        travel_to(to);
        continue;
      }
      if (s.tool != tool_) {
        change_tool(s.tool, point(path, i));
        travel_to(point(path, i));
      }
      annotate(path.type, s);
      extrude_to(to,
                 (path.points.row(i + 1) - path.points.row(i)).norm() * s.width * s.layer_height /
                     filament_area(printer_),
                 s.tool, extrusion_speed(s));
    }
  }

  // Goes on with `tool`, which starts printing at `start` (bed coordinates): the previous tool
  // retracts where it stands, then the profile's tool-change template parks it and brings the next
  // one (or, on a shared nozzle, has the firmware swap the filament and flushes the old one out),
  // whose fan setting then applies, and the next tool primes on the pad if the profile says so.
  // The template may move the head anywhere, so its position counts as unknown until the next
  // travel sets it (lifting first, as after the start G-code).
  void change_tool(int tool, const Eigen::Vector3d& start) {
    if (tool == tool_) return;
    retract();
    if (printer_.filament_swap) {
      swap_filament(tool);
      return;
    }
    const ToolChange& change = printer_.tool_change;
    const Material& from = materials_[static_cast<size_t>(tool_)];
    const Material& to = materials_[static_cast<size_t>(tool)];
    // The length as written, so that the filament count is what the printer pushes.
    const double flush_length =
        change.shared_nozzle ? std::round(change.flush_volume / filament_area(printer_) * 100) / 100
                             : 0.0;
    const std::vector<std::pair<std::string, std::string>> values = {
        {"previous_tool", std::to_string(tool_)},
        {"next_tool", std::to_string(tool)},
        {"previous_temperature", fmt::format("{:.0f}", from.nozzle_temperature)},
        {"next_temperature", fmt::format("{:.0f}", to.nozzle_temperature)},
        {"x", fixed(start.x(), 3)},
        {"y", fixed(start.y(), 3)},
        {"z", fixed(start.z(), 3)},
        {"travel_feed_rate", std::to_string(std::lround(printer_.travel_speed * 60))},
        {"safe_z", fixed(safe_z() / kXyzUnits, 3)},
        {"flush_temperature", fmt::format("{:.0f}", flush_temperature(from, to))},
        {"flush_length", fmt::format("{:.2f}", flush_length)},
        {"retract_length", fmt::format("{:g}", printer_.retract_length)},
    };
    out_ += fmt::format(
        "; ---- tool change T{} -> T{} (tool_change.gcode of the printer profile)\n", tool_, tool);
    out_ += expand_gcode_template(change.gcode, values,
                                  fmt::format("printer {}: tool_change.gcode", printer_.name),
                                  tool_change_placeholders());
    if (!out_.empty() && out_.back() != '\n') out_ += '\n';
    tool_ = tool;
    if (change.shared_nozzle) {
      // The firmware loaded the next filament, the template flushed it and ended with a
      // retraction (docs/gcode.md).
      extruded_[static_cast<size_t>(tool)] += flush_length;
      retracted_[static_cast<size_t>(tool)] =
          printer_.firmware_retraction || printer_.retract_length > 0;
    }
    after_change(to);
    if (pad_) prime(to);
  }

  // One nozzle: the print pauses and the user swaps the filament by hand (FilamentSwap). Above the
  // print, with the message on the screen, the nozzle waits at a temperature both filaments take
  // (the old one unloads, the new one purges), the firmware pauses, then the nozzle takes the next
  // material's own temperature. The annotation ;FILAMENT_SWAP:T<n> tells the check and the
  // readers whose material prints from there on.
  void swap_filament(int tool) {
    const FilamentSwap& swap = *printer_.filament_swap;
    const Material& from = materials_[static_cast<size_t>(tool_)];
    const Material& to = materials_[static_cast<size_t>(tool)];
    const double hot = swap_temperature(from, to);
    const std::vector<std::pair<std::string, std::string>> values = {
        {"message", fmt::format("Load {} (T{})", to.name, tool)},
        {"previous_tool", std::to_string(tool_)},
        {"next_tool", std::to_string(tool)},
        {"previous_material", from.name},
        {"next_material", to.name},
        {"previous_temperature", fmt::format("{:.0f}", from.nozzle_temperature)},
        {"next_temperature", fmt::format("{:.0f}", to.nozzle_temperature)},
        {"swap_temperature", fmt::format("{:.0f}", hot)},
        {"safe_z", fixed(safe_z() / kXyzUnits, 3)},
    };
    const std::string source = fmt::format("printer {}: filament_swap", printer_.name);
    out_ += fmt::format(
        "; ---- filament swap T{} -> T{}: {} out, {} in (filament_swap of the printer profile)\n",
        tool_, tool, from.name, to.name);
    out_ += fmt::format(";FILAMENT_SWAP:T{}\n", tool);
    move_z(known_ ? std::max(pos_.z(), safe_z()) : safe_z());
    line(expand_gcode_template(swap.message, values, source + ".message",
                               filament_swap_placeholders()));
    line(fmt::format("M109 S{:.0f} ; wait: {} unloads and {} purges at this", hot, from.name,
                     to.name));
    out_ +=
        expand_gcode_template(swap.gcode, values, source + ".gcode", filament_swap_placeholders());
    if (!out_.empty() && out_.back() != '\n') out_ += '\n';
    if (to.nozzle_temperature != hot) {
      // Marlin's M109 S waits only for heating; R waits for cooling too (Klipper's S does both).
      const bool cooling = to.nozzle_temperature < hot;
      const char* wait = cooling && printer_.flavor == GcodeFlavor::kMarlin ? "R" : "S";
      line(fmt::format("M109 {}{:.0f} ; {}'s own temperature, wait", wait, to.nozzle_temperature,
                       to.name));
    }
    tool_ = tool;
    after_change(to);
  }

  // After a tool change or a swap, with `to` the next tool's material. The template's own E moves
  // (a prime) say nothing about the print's E register. It restarts at 0 with the filament of the
  // next tool where that tool left it: E moves retract, so a tool parked retracted stands one
  // retraction below its unretracted register. The head's position counts as unknown.
  void after_change(const Material& to) {
    line("G92 E0");
    e_units_ = 0;
    e_exact_ = retracted_[filament(tool_)] && !printer_.firmware_retraction
                   ? static_cast<double>(std::llround(printer_.retract_length * kEUnits)) / kEUnits
                   : 0.0;
    ++tool_changes_;
    known_ = false;
    feed_ = -1;  // the template may have set its own F
    // Said at every change: on tool changers each tool may have its own part-cooling fan.
    line(fan_command(printer_.flavor, first_of_section_ ? to.first_layer_fan_speed : to.fan_speed));
  }

  void retract() {
    if (retracted_[filament(tool_)] ||
        (printer_.retract_length <= 0 && !printer_.firmware_retraction)) {
      return;
    }
    if (printer_.firmware_retraction) {
      line("G10 ; retract (firmware)");
    } else {
      e_move(-std::llround(printer_.retract_length * kEUnits), printer_.retract_speed,
             " ; retract");
    }
    motions_.push_back({Eigen::Vector3d::Zero(), -printer_.retract_length, printer_.retract_speed});
    retracted_[filament(tool_)] = true;
  }

  // Retracts and lifts the nozzle to `z` (mm) where it stands, if it is lower: before heating for
  // a new section, above everything printed so far.
  void lift_to(double z) {
    retract();
    if (!known_) return;
    const int target = lift_units(z);
    if (target > pos_.z()) move_z(target);
  }

  void unretract() {
    if (!retracted_[filament(tool_)]) return;
    if (printer_.firmware_retraction) {
      line("G11 ; unretract (firmware)");
    } else {
      e_move(std::llround(printer_.retract_length * kEUnits), printer_.retract_speed,
             " ; unretract");
    }
    motions_.push_back({Eigen::Vector3d::Zero(), printer_.retract_length, printer_.retract_speed});
    retracted_[filament(tool_)] = false;
  }

 private:
  // Above everything printed so far, where the head may cross the print (mm / 1000).
  int safe_z() const {
    return std::min(printed_top_ + lift_units(kToolChangeClearance),
                    lift_units(printer_.max_height));
  }

  // Lays the next tool's prime (`material` is its) on the pad where the last prime stopped, then
  // wipes the nozzle back along the bead and retracts: reached and left above the print.
  void prime(const Material& material) {
    const PrimePad& pad = *pad_;
    const ToolChange& change = printer_.tool_change;
    const double begin = prime_used_;
    const double end = begin + change.prime_volume / (pad.bead_width * pad.bead_height);
    if (end > pad.capacity() + 1e-9) {
      throw std::logic_error("make_gcode: the prime pad is full although its capacity was checked");
    }
    const int lift = safe_z();
    if (!known_ || pos_.z() < lift) move_z(lift);
    const Eigen::Vector2d first = pad.point(begin);
    move_xy(to_units(Eigen::Vector3d(first.x(), first.y(), 0)).head<2>(), printer_.travel_speed);
    move_z(lift_units(pad.bead_height));
    unretract();
    out_ += ";TYPE:Wipe tower\n;WIDTH:";
    width_ = std::llround(pad.bead_width * kXyzUnits);
    append_fixed(out_, width_, 3);
    out_ += "\n;HEIGHT:";
    height_ = std::llround(pad.bead_height * kXyzUnits);
    append_fixed(out_, height_, 3);
    out_ += '\n';
    type_.reset();  // the print's next path says its type again
    const double speed = first_layer_speed(printer_, material);
    const double per_mm = pad.bead_width * pad.bead_height / filament_area(printer_);
    Eigen::Vector2d at = first;
    std::vector<Eigen::Vector2d> points = pad.corners_between(begin, end);
    points.push_back(pad.point(end));
    for (const Eigen::Vector2d& p : points) {
      extrude_to(Eigen::Vector3d(p.x(), p.y(), pad.bead_height), (p - at).norm() * per_mm, tool_,
                 speed);
      at = p;
    }
    prime_used_ = end;
    const double wiped = std::max(begin, end - change.wipe_length);
    if (wiped < end) {
      std::vector<Eigen::Vector2d> wipe = pad.corners_between(end, wiped);
      wipe.push_back(pad.point(wiped));
      for (const Eigen::Vector2d& p : wipe) {
        move_xy(to_units(Eigen::Vector3d(p.x(), p.y(), 0)).head<2>(), printer_.travel_speed);
      }
    }
    retract();
    // Off the pad above everything printed: the next travel may cross a finished section.
    move_z(safe_z());
  }

  Eigen::Vector3d point(const PathPolyline& path, size_t i) const {
    return {path.points(i, 0) + offset_.x(), path.points(i, 1) + offset_.y(), path.points(i, 2)};
  }

  double extrusion_speed(const SegmentStyle& s) const {
    if (s.feed_rate > 0) return s.feed_rate;
    const Material& m = materials_[static_cast<size_t>(s.tool)];
    return first_of_section_ ? first_layer_speed(printer_, m) : print_speed(printer_, m);
  }

  void annotate(PathType type, const SegmentStyle& s) {
    if (type_ != type) {
      out_ += ";TYPE:";
      out_ += prusaslicer_type_name(type);
      out_ += '\n';
      type_ = type;
    }
    const long long width = std::llround(s.width * kXyzUnits);
    if (width != width_) {
      out_ += ";WIDTH:";
      append_fixed(out_, width, 3);
      out_ += '\n';
      width_ = width;
    }
    const long long height = std::llround(s.layer_height * kXyzUnits);
    if (height != height_) {
      out_ += ";HEIGHT:";
      append_fixed(out_, height, 3);
      out_ += '\n';
      height_ = height;
    }
  }

  // Travel to `p`: retract and lift for long travels and at the start of a layer, never extrude.
  void travel_to(const Eigen::Vector3d& p) {
    const Eigen::Vector3i target = to_units(p);
    if (known_ && target == pos_) return;
    const bool first = !known_;
    const double xy = first ? 0 : (p.head<2>() - position().head<2>()).norm();
    const bool long_travel = first || first_travel_of_layer_ || xy >= printer_.retract_min_travel;
    first_travel_of_layer_ = false;
    if (long_travel) retract();
    int cruise_z = std::max(pos_.z(), target.z());
    if (first) {
      cruise_z = target.z() + lift_units(std::max(printer_.z_hop, kFirstTravelLift));
    } else if (long_travel && printer_.z_hop > 0) {
      cruise_z += lift_units(printer_.z_hop);
    }
    if (first || cruise_z != pos_.z()) move_z(cruise_z);
    if (first || target.head<2>() != pos_.head<2>())
      move_xy(target.head<2>(), printer_.travel_speed);
    if (target.z() != pos_.z()) move_z(target.z());
    unretract();
  }

  static int lift_units(double mm) { return static_cast<int>(std::lround(mm * kXyzUnits)); }

  Eigen::Vector3d position() const { return pos_.cast<double>() / kXyzUnits; }

  static Eigen::Vector3i to_units(const Eigen::Vector3d& p) {
    return {static_cast<int>(std::lround(p.x() * kXyzUnits)),
            static_cast<int>(std::lround(p.y() * kXyzUnits)),
            static_cast<int>(std::lround(p.z() * kXyzUnits))};
  }

  void move_z(int z) {
    const double speed = printer_.z_speed;
    out_ += "G0 Z";
    append_fixed(out_, z, 3);
    feed(speed);
    out_ += '\n';
    if (known_) {
      motions_.push_back({Eigen::Vector3d(0, 0, (z - pos_.z()) / kXyzUnits), 0, feed_speed()});
    }
    pos_.z() = z;
  }

  void move_xy(const Eigen::Vector2i& xy, double speed) {
    out_ += "G0 X";
    append_fixed(out_, xy.x(), 3);
    out_ += " Y";
    append_fixed(out_, xy.y(), 3);
    feed(speed);
    out_ += '\n';
    if (known_) {
      motions_.push_back(
          {Eigen::Vector3d((xy.x() - pos_.x()) / kXyzUnits, (xy.y() - pos_.y()) / kXyzUnits, 0), 0,
           feed_speed()});
    }
    pos_.head<2>() = xy;
    known_ = true;
  }

  void extrude_to(const Eigen::Vector3d& p, double filament, int tool, double speed) {
    const Eigen::Vector3i target = to_units(p);
    e_exact_ += filament;
    extruded_[static_cast<size_t>(tool)] += filament;
    const long long e_target = std::llround(e_exact_ * kEUnits);
    const long long delta = e_target - e_units_;
    out_ += "G1 X";
    append_fixed(out_, target.x(), 3);
    out_ += " Y";
    append_fixed(out_, target.y(), 3);
    if (target.z() != pos_.z()) {
      out_ += " Z";
      append_fixed(out_, target.z(), 3);
    }
    out_ += " E";
    append_fixed(out_, printer_.relative_e ? delta : e_target, 5);
    feed(speed);
    out_ += '\n';
    motions_.push_back({(target - pos_).cast<double>() / kXyzUnits, delta / kEUnits, feed_speed()});
    e_units_ = e_target;
    pos_ = target;
    printed_top_ = std::max(printed_top_, target.z());
  }

  void e_move(long long delta, double speed, std::string_view comment) {
    e_units_ += delta;
    out_ += "G1 E";
    append_fixed(out_, printer_.relative_e ? delta : e_units_, 5);
    feed(speed);
    out_ += comment;
    out_ += '\n';
  }

  // Appends " F<mm/min>" when the feed rate changes (F is modal, shared by G0 and G1).
  void feed(double speed) {
    const long f = std::lround(speed * 60);
    if (f == feed_) return;
    feed_ = f;
    out_ += " F";
    out_ += std::to_string(f);
  }
  double feed_speed() const { return feed_ / 60.0; }

  const PrinterProfile& printer_;
  const std::vector<Material>& materials_;  // per tool
  Eigen::Vector2d offset_;
  std::optional<PrimePad> pad_;  // where tool changes prime, if the profile says
  double prime_used_ = 0;        // mm of the pad's serpentine laid so far
  int printed_top_ = 0;          // highest extrusion so far, mm / 1000
  std::string out_;
  std::vector<Motion> motions_;
  Eigen::Vector3i pos_ = Eigen::Vector3i::Zero();  // mm / 1000
  bool known_ = false;
  long long e_units_ = 0;         // the E register since the last G92, mm / 1e5
  double e_exact_ = 0;            // filament since the last G92 without rounding, mm
  std::vector<double> extruded_;  // all filament extruded per tool, mm
  long feed_ = -1;                // mm/min
  // Per tool: each has its own filament, which stays retracted while the tool is parked.
  std::vector<bool> retracted_;
  int tool_ = 0;  // the start G-code leaves the firmware on T0
  int tool_changes_ = 0;
  bool first_of_section_ = true;
  bool first_travel_of_layer_ = true;
  std::optional<PathType> type_;
  long long width_ = -1;  // the ;WIDTH: and ;HEIGHT: in effect, mm / 1000
  long long height_ = -1;
};

struct Placement {
  Eigen::Vector2d offset;
  Eigen::Vector2d min;  // bed coordinates, skirt included
  Eigen::Vector2d max;
};

// Places the plate's bounding-box centre at `options.at` or the bed centre and checks that every
// point of the print (skirt included) lies on the bed.
Placement place(const Toolpath& toolpath, const std::vector<PathPolyline>& skirt,
                const PrinterProfile& printer, const GcodeOptions& options) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      lo = lo.cwiseMin(path.points.leftCols<2>().colwise().minCoeff().transpose());
      hi = hi.cwiseMax(path.points.leftCols<2>().colwise().maxCoeff().transpose());
    }
  }
  if (!lo.allFinite()) throw std::invalid_argument("make_gcode: the toolpath has no path");
  const Eigen::Vector2d plate_size = hi - lo;
  Eigen::Vector2d all_lo = lo, all_hi = hi;
  for (const PathPolyline& loop : skirt) {
    all_lo = all_lo.cwiseMin(loop.points.leftCols<2>().colwise().minCoeff().transpose());
    all_hi = all_hi.cwiseMax(loop.points.leftCols<2>().colwise().maxCoeff().transpose());
  }
  const Eigen::Vector2d center = options.at ? *options.at : bed_center(printer);
  Placement placement;
  placement.offset = center - (lo + hi) / 2;
  placement.min = all_lo + placement.offset;
  placement.max = all_hi + placement.offset;

  bool fits = true;
  auto check = [&](const Eigen::Matrix<double, Eigen::Dynamic, 3>& points) {
    for (Eigen::Index i = 0; i < points.rows() && fits; ++i) {
      fits = on_bed(printer, points.row(i).head<2>().transpose() + placement.offset, 1e-6);
    }
  };
  if (printer.bed_shape == BedShape::kRectangular) {
    fits = on_bed(printer, placement.min, 1e-6) && on_bed(printer, placement.max, 1e-6);
  } else {
    for (const ToolpathLayer& layer : toolpath.layers) {
      for (const PathPolyline& path : layer.paths) check(path.points);
    }
    for (const PathPolyline& loop : skirt) check(loop.points);
  }
  if (fits) return placement;

  const std::string with_skirt = skirt.empty()
                                     ? ""
                                     : fmt::format(" ({:.1f} x {:.1f} mm with the skirt)",
                                                   (all_hi - all_lo).x(), (all_hi - all_lo).y());
  const std::string bed = fmt::format("the {} bed of {}", describe_bed(printer), printer.name);
  if (options.at) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("the plate ({:.1f} x {:.1f} mm{}) placed at --at {:g},{:g} spans x [{:.1f}, "
                    "{:.1f}], y [{:.1f}, {:.1f}] and leaves {}: move it or drop --at to centre it",
                    plate_size.x(), plate_size.y(), with_skirt, options.at->x(), options.at->y(),
                    placement.min.x(), placement.max.x(), placement.min.y(), placement.max.y(),
                    bed));
  }
  throw UserError(ErrorCategory::kInfeasible,
                  fmt::format("the plate is {:.1f} x {:.1f} mm{} and does not fit {}: scale the "
                              "design down or choose a larger printer ('flatmorph printers')",
                              plate_size.x(), plate_size.y(), with_skirt, bed));
}

// Sections must start at layer 0, in increasing order, within the toolpath, at temperatures the
// material allows. A section's own temperature is set with M109 on the active tool, so it needs a
// print with one tool (`material` is that tool's).
void validate_sections(const std::vector<PrintSection>& sections, const Toolpath& toolpath,
                       const Material& material, size_t tools_used) {
  for (size_t s = 0; s < sections.size(); ++s) {
    if (sections[s].nozzle_temperature != 0 && tools_used > 1) {
      throw UserError(ErrorCategory::kOption,
                      "sections with their own nozzle temperature need a print with one tool; "
                      "this one uses several: print the sections with one tool");
    }
    const size_t first = sections[s].first_layer;
    if ((s == 0 && first != 0) || (s > 0 && first <= sections[s - 1].first_layer) ||
        first >= toolpath.layers.size()) {
      throw std::invalid_argument(fmt::format(
          "make_gcode: section {} starts at layer index {} (previous {}, {} layers)", s + 1, first,
          s > 0 ? static_cast<long>(sections[s - 1].first_layer) : -1L, toolpath.layers.size()));
    }
    const double t = sections[s].nozzle_temperature;
    if (t != 0 && (t < material.min_nozzle_temperature || t > material.max_nozzle_temperature)) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format("nozzle temperature {:g} C{} lies outside the safe range [{:g}, "
                      "{:g}] C of material {}: choose temperatures inside it",
                      t, sections[s].label.empty() ? "" : " (" + sections[s].label + ")",
                      material.min_nozzle_temperature, material.max_nozzle_temperature,
                      material.name));
    }
  }
}

// "1.00, 2.00": one value per tool, as the slicers list them per extruder.
std::string per_tool(const std::vector<double>& values, double scale) {
  std::string s;
  for (double v : values) s += (s.empty() ? "" : ", ") + fmt::format("{:.2f}", v * scale);
  return s;
}

// `unit`: said before the source ("first layer 15 mm/s (from the material)"), or left out.
std::string speeds_of(const PrinterProfile& printer, const Material& material,
                      std::string_view unit) {
  return fmt::format("print {:g}, first layer {:g}{} (from the {})", print_speed(printer, material),
                     first_layer_speed(printer, material), unit,
                     material.print_speed > 0 ? "material" : "printer");
}

std::string header(const PrinterProfile& printer, const std::vector<Material>& tool_materials,
                   const Toolpath& toolpath, const GcodeOptions& options, GcodeResult& result,
                   int section_tool) {
  std::string h;
  auto add = [&h, &result](const std::string& s) {
    h += "; ";
    h += s;
    h += '\n';
    if (const size_t at = s.find(" = "); at != std::string::npos) {
      result.summary.emplace_back(s.substr(0, at), s.substr(at + 3));
    }
  };
  const bool one = tool_materials.size() == 1;
  const Material& material = tool_materials.front();
  add(fmt::format("generated by flatmorph {}", FLATMORPH_VERSION));
  add("the plate self-shapes in hot water: print it on a clean bed, then immerse it");
  h += ";\n";
  add(fmt::format("estimated printing time (normal mode) = {}",
                  format_duration(result.print_time)));
  std::vector<double> volumes;
  for (double length : result.tool_filament_length) {
    volumes.push_back(length * filament_area(printer));
  }
  add(fmt::format("filament used [mm] = {}", per_tool(result.tool_filament_length, 1)));
  add(fmt::format("filament used [cm3] = {}", per_tool(volumes, 1e-3)));
  add(fmt::format("filament used [g] = {}", per_tool(result.tool_filament_mass, 1)));
  add(fmt::format("total filament used [g] = {:.2f}", result.filament_mass));
  add("(time: moves with acceleration and cornering limits; heating, homing, levelling and the "
      "start G-code not included)");
  h += ";\n";
  add(fmt::format("printer = {}", printer.name));
  if (!printer.description.empty())
    add(fmt::format("printer_description = {}", printer.description));
  add(fmt::format("gcode_flavor = {}", to_string(printer.flavor)));
  add(fmt::format("bed = {} {}, origin at the {}", describe_bed(printer),
                  printer.bed_shape == BedShape::kCircular ? "circular" : "rectangular",
                  printer.origin_at_center ? "centre" : "front-left corner"));
  add(fmt::format("nozzle_diameter = {:g} mm", printer.nozzle_diameter));
  add(fmt::format("filament_diameter = {:g} mm", printer.filament_diameter));
  add(printer.relative_e ? "extrusion = relative E (M83)"
                         : "extrusion = absolute E (M82), G92 E0 at each layer");
  add(fmt::format(
      "extrusion_formula = E = segment length x width x layer height / (pi x {:g}^2 / 4)",
      printer.filament_diameter));
  add(
      fmt::format("retraction = {:g} mm at {:g} mm/s{}, z-hop {:g} mm, for travels of {:g} mm and "
                  "more and at layer changes",
                  printer.retract_length, printer.retract_speed,
                  printer.firmware_retraction ? " (firmware G10/G11)" : "", printer.z_hop,
                  printer.retract_min_travel));
  if (one) {
    add(fmt::format("speeds = {}, travel {:g}, z {:g} mm/s", speeds_of(printer, material, ""),
                    printer.travel_speed, printer.z_speed));
  } else {
    add(fmt::format("speeds = travel {:g}, z {:g} mm/s; print speeds per tool below",
                    printer.travel_speed, printer.z_speed));
  }
  add(fmt::format("acceleration = print {:g}, travel {:g} mm/s^2; cornering {}",
                  printer.print_acceleration, printer.travel_acceleration,
                  printer.cornering == CorneringModel::kJerk
                      ? fmt::format("jerk {:g} mm/s", printer.jerk)
                      : fmt::format("junction deviation {:g} mm", printer.junction_deviation)));
  if (!one && printer.filament_swap) {
    // The materials in the order the pauses ask for them, as the writer changes tools.
    std::string order;
    int tool = 0;
    for (const ToolpathLayer& layer : toolpath.layers) {
      for (const PathPolyline& path : layer.paths) {
        for (const SegmentStyle& s : path.segments) {
          if (s.travel || s.tool == tool) continue;
          tool = s.tool;
          order += fmt::format(", T{} {}", tool, tool_materials[static_cast<size_t>(tool)].name);
        }
      }
    }
    add(
        fmt::format("filament_swaps = {} (the printer pauses for each: filament_swap of the "
                    "printer profile; load T0's material {} before starting, then{}; their time "
                    "is not in the estimate)",
                    result.tool_changes, tool_materials.front().name,
                    order.empty() ? " nothing else" : order.substr(1)));
  } else if (!one) {
    const ToolChange& change = printer.tool_change;
    std::string how =
        change.shared_nozzle
            ? fmt::format("one shared nozzle, {:g} mm^3 flushed at each", change.flush_volume)
            : "a nozzle per tool, all used stay at their temperature until the end";
    if (change.prime_volume > 0) {
      how += fmt::format("; {:g} mm^3 primed on the bed at each, wiped {:g} mm",
                         change.prime_volume, change.wipe_length);
    }
    add(
        fmt::format("tool_changes = {} (tool_change.gcode of the printer profile; {}; their time "
                    "is not in the estimate)",
                    result.tool_changes, how));
  }
  for (size_t t = 0; t < tool_materials.size(); ++t) {
    // One material: the keys as they always were; several: each key says its tool ("T1 material").
    const std::string tool = one ? "" : fmt::format("T{} ", t);
    const Material& m = tool_materials[t];
    h += ";\n";
    add(fmt::format("{}material = {}", tool, m.name));
    if (!m.description.empty())
      add(fmt::format("{}material_description = {}", tool, m.description));
    add(fmt::format("{}nozzle_temperature = {:g} C (safe range {:g}..{:g})", tool,
                    m.nozzle_temperature, m.min_nozzle_temperature, m.max_nozzle_temperature));
    add(fmt::format("{}bed_temperature = {:g} C (at most {:g})", tool, m.bed_temperature,
                    m.max_bed_temperature));
    if (!one) add(fmt::format("{}speeds = {}", tool, speeds_of(printer, m, " mm/s")));
    add(fmt::format("{}fan = {:g} % from the second layer, {:g} % on the first", tool, m.fan_speed,
                    m.first_layer_fan_speed));
    add(
        fmt::format("{}shrink = lambda1 {:.12g}, lambda2 {:.12g}, lambda3 {:.12g}, delta_lambda1 "
                    "{:.12g}",
                    tool, m.lambda1, m.lambda2, m.lambda3, m.delta_lambda1));
    // The curves too, to full precision: with the line above they are the whole shrink model the
    // design was made with, which a reader of the file (flatmorph simulate) takes over the
    // preset's.
    add(m.speed_curve
            ? fmt::format("{}speed_curve = lambda1 coefficients {:.12g}, speeds {:.12g}..{:.12g} "
                          "mm/s, layer height {:.12g} mm",
                          tool, fmt::join(m.speed_curve->lambda1_coefficients, " "),
                          m.speed_curve->min_print_speed, m.speed_curve->max_print_speed,
                          m.speed_curve->layer_height)
            : fmt::format("{}speed_curve = none", tool));
    add(m.thickness_curve
            ? fmt::format("{}thickness_curve = lambda1 coefficients {:.12g}, layer heights "
                          "{:.12g}..{:.12g} mm",
                          tool, fmt::join(m.thickness_curve->lambda1_coefficients, " "),
                          m.thickness_curve->min_layer_height, m.thickness_curve->max_layer_height)
            : fmt::format("{}thickness_curve = none", tool));
    add(fmt::format("{}density = {:g} g/cm3", tool, m.density));
  }
  h += ";\n";
  const Eigen::Vector2d& t = result.plate_to_bed;
  add(
      fmt::format("plate_to_bed = x_bed = x_plate {} {:.3f}, y_bed = y_plate {} {:.3f}, z_bed = "
                  "z_plate (mm; plate coordinates as in flat.ply)",
                  t.x() < 0 ? '-' : '+', std::abs(t.x()), t.y() < 0 ? '-' : '+', std::abs(t.y())));
  add(options.at ? fmt::format("placement = plate centre at ({:g}, {:g}) (--at)", options.at->x(),
                               options.at->y())
                 : std::string("placement = centred on the bed"));
  add(fmt::format("print_area = x [{:.3f}, {:.3f}], y [{:.3f}, {:.3f}] mm on the bed",
                  result.print_min.x(), result.print_max.x(), result.print_min.y(),
                  result.print_max.y()));
  add(fmt::format("skirt = {} loop(s), {:g} mm from the plate", options.skirt_loops,
                  options.skirt_distance));
  std::string heights;
  for (const ToolpathLayer& layer : toolpath.layers) {
    heights += (heights.empty() ? "" : ", ") + fmt::format("{:g}", layer.height);
  }
  add(fmt::format("layers = {}, top at z = {:.3f} mm; heights {}", toolpath.layers.size(),
                  toolpath.layers.back().z, heights));
  for (size_t s = 0; s < options.sections.size(); ++s) {
    const PrintSection& section = options.sections[s];
    const size_t last = s + 1 < options.sections.size() ? options.sections[s + 1].first_layer
                                                        : toolpath.layers.size();
    const double t = section.nozzle_temperature > 0
                         ? section.nozzle_temperature
                         : tool_materials[static_cast<size_t>(section_tool)].nozzle_temperature;
    add(fmt::format("section {} = layers {}-{} printed from the bed up at {:g} C{}{}", s + 1,
                    section.first_layer + 1, last, t, section.label.empty() ? "" : ": ",
                    section.label));
  }
  h += ";\n";
  return h;
}

// Counts the lines of `text` before offset `end`.
int lines_before(const std::string& text, size_t end) {
  return static_cast<int>(std::count(text.begin(), text.begin() + end, '\n'));
}

}  // namespace

std::string_view prusaslicer_type_name(PathType type) {
  switch (type) {
    case PathType::kPerimeter:
      return "Perimeter";
    case PathType::kExternalPerimeter:
      return "External perimeter";
    case PathType::kSolidInfill:
      return "Solid infill";
    case PathType::kSkirt:
      return "Skirt/Brim";
    case PathType::kCustom:
      return "Custom";
  }
  return "Custom";
}

std::vector<PathPolyline> skirt_loops(const Toolpath& toolpath, int loops, double distance,
                                      double width, double layer_height) {
  std::vector<PathPolyline> result;
  if (loops <= 0 || toolpath.layers.empty()) return result;
  const ToolpathLayer& first = toolpath.layers.front();
  Eigen::MatrixX2d points(0, 2);
  for (const PathPolyline& path : first.paths) {
    points.conservativeResize(points.rows() + path.points.rows(), 2);
    points.bottomRows(path.points.rows()) = path.points.leftCols(2);
  }
  if (points.rows() == 0) return result;
  const Eigen::MatrixX2d corners = convex_hull(points);
  std::vector<Eigen::Vector2d> hull(corners.rows());
  for (Eigen::Index i = 0; i < corners.rows(); ++i) hull[i] = corners.row(i).transpose();
  for (int k = loops - 1; k >= 0; --k) {
    // The bead's centre line lies half a width outside the gap.
    const std::vector<Eigen::Vector2d> ring = offset_hull(hull, distance + (k + 0.5) * width);
    PathPolyline loop;
    loop.type = PathType::kSkirt;
    loop.closed = true;
    loop.points.resize(static_cast<Eigen::Index>(ring.size()) + 1, 3);
    for (size_t i = 0; i <= ring.size(); ++i) {
      const Eigen::Vector2d& q = ring[i % ring.size()];
      loop.points.row(static_cast<Eigen::Index>(i)) << q.x(), q.y(), first.z;
    }
    SegmentStyle style;
    style.width = width;
    style.layer_height = layer_height;
    style.feed_rate = 0;
    loop.segments.assign(ring.size(), style);
    result.push_back(std::move(loop));
  }
  return result;
}

namespace {

// What the print asks of the printer before anything is written: one material per tool (or a
// printer that swaps filament), a toolpath the printer can follow, a bed every material bears and
// a skirt that makes sense.
void validate_print(const Toolpath& toolpath, const PrinterProfile& printer,
                    const std::vector<Material>& tool_materials, const GcodeOptions& options) {
  if (tool_materials.empty()) {
    throw UserError(ErrorCategory::kOption, "no material given: give one material per tool");
  }
  if (tool_materials.size() > static_cast<size_t>(printer.extruder_count) &&
      !printer.filament_swap) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{} materials given but the printer {} has {} tool(s): give one "
                                "material per tool, or choose a printer with more tools or a "
                                "filament_swap",
                                tool_materials.size(), printer.name, printer.extruder_count));
  }
  validate_toolpath(toolpath, printer, tool_materials);
  // The bed is shared: the start G-code heats it for T0's material, which every other must bear.
  const Material& bed_material = tool_materials.front();
  for (const Material& m : tool_materials) {
    if (bed_material.bed_temperature > m.max_bed_temperature) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("the bed temperature {:g} C of {} (T0) is above {:g} C, the most "
                                  "{} allows: put the material with the cooler bed on T0",
                                  bed_material.bed_temperature, bed_material.name,
                                  m.max_bed_temperature, m.name));
    }
  }
  if (options.skirt_loops < 0 || !(options.skirt_distance >= 0)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("skirt: {} loops at {} mm; expected 0 or more loops at a distance "
                                ">= 0",
                                options.skirt_loops, options.skirt_distance));
  }
}

// Which tools the print uses, and the one that prints first (0 when nothing is extruded).
struct PrintTools {
  std::set<int> used;
  int first = -1;
};

PrintTools print_tools(const Toolpath& toolpath) {
  PrintTools tools;
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      for (const SegmentStyle& s : path.segments) {
        if (s.travel) continue;
        tools.used.insert(s.tool);
        if (tools.first < 0) tools.first = s.tool;
      }
    }
  }
  if (tools.first < 0) tools.first = 0;
  return tools;
}

// The skirt primes the tool that prints first, as wide and as high as the first extruded segment
// of the first layer.
std::vector<PathPolyline> priming_skirt(const Toolpath& toolpath, const PrinterProfile& printer,
                                        const GcodeOptions& options, int first_tool) {
  double skirt_width = printer.nozzle_diameter;
  double skirt_height = toolpath.layers.front().height;
  for (const PathPolyline& path : toolpath.layers.front().paths) {
    const auto it = std::find_if(path.segments.begin(), path.segments.end(),
                                 [](const SegmentStyle& s) { return !s.travel; });
    if (it != path.segments.end()) {
      skirt_width = it->width;
      skirt_height = it->layer_height;
      break;
    }
  }
  std::vector<PathPolyline> skirt =
      skirt_loops(toolpath, options.skirt_loops, options.skirt_distance, skirt_width, skirt_height);
  for (PathPolyline& loop : skirt) {
    for (SegmentStyle& s : loop.segments) s.tool = first_tool;
  }
  return skirt;
}

// Refuses a print whose head, lifted for travels and section changes, would pass the printer's
// height.
void check_print_height(const Toolpath& toolpath, const PrinterProfile& printer,
                        const GcodeOptions& options) {
  double top = 0;
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) top = std::max(top, path.points.col(2).maxCoeff());
  }
  // A section change lifts above the print, and the travel that follows lifts by z_hop again.
  const double highest = top + std::max(printer.z_hop, kFirstTravelLift) +
                         (options.sections.size() > 1 ? printer.z_hop : 0.0);
  if (highest > printer.max_height) {
    throw UserError(ErrorCategory::kInfeasible,
                    fmt::format("the print reaches z = {:.2f} mm (with travel lifts) but {} "
                                "reaches only {:g} mm: use fewer or thinner layers",
                                highest, printer.name, printer.max_height));
  }
}

const Material& tool_material(const std::vector<Material>& tool_materials, int tool) {
  return tool_materials[static_cast<size_t>(tool)];
}

// Every tool has a heater of its own (a shared nozzle has one, which each tool change sets).
bool tools_heat_apart(const PrinterProfile& printer) {
  return printer.extruder_count > 1 && !printer.tool_change.shared_nozzle;
}

// What follows the start G-code: the E mode, said explicitly whatever the start G-code did, and
// the tools heated. The start G-code heated T0 (the firmware's tool after it) to T0's material.
// Every other tool the print uses is heated now, all at once, and stays at its temperature until
// the end: tools alternate often in a plate, and cooling each between its turns would cost a
// reheat every time.
std::string print_prologue(Emitter& emit, const PrinterProfile& printer,
                           const std::vector<Material>& tool_materials, const PrintTools& tools) {
  emit.line("; ---- flatmorph: print begins");
  emit.line("G90 ; absolute X, Y, Z");
  emit.line(printer.relative_e ? "M83 ; relative E" : "M82 ; absolute E");
  emit.line("G92 E0");
  const bool own_heaters = tools_heat_apart(printer);
  for (int tool : tools.used) {
    if (tool > 0 && own_heaters) {
      const Material& m = tool_material(tool_materials, tool);
      emit.line(fmt::format("M104 T{} S{:.0f} ; heat tool {} ({})", tool, m.nozzle_temperature,
                            tool, m.name));
    }
  }
  for (int tool : tools.used) {
    if (tool > 0 && own_heaters) {
      emit.line(fmt::format("M109 T{} S{:.0f} ; wait for tool {}", tool,
                            tool_material(tool_materials, tool).nozzle_temperature, tool));
    }
  }
  if (own_heaters && !tools.used.count(0)) {
    emit.line("M104 T0 S0 ; the print does not use tool 0");
  }
  emit.line(fan_command(printer.flavor,
                        tool_material(tool_materials, emit.tool()).first_layer_fan_speed));
  std::string prologue = std::move(emit.out());
  emit.out().clear();
  return prologue;
}

// The layers' text, one string per layer, each timed on its own into result.layer_times: the
// sections' starts (their own nozzle temperature, a lift above the print), the fans, the skirt
// under the first layer, the retraction and the heaters off after the last.
std::vector<std::string> print_layers(Emitter& emit, const Toolpath& toolpath,
                                      const PrinterProfile& printer,
                                      const std::vector<Material>& tool_materials,
                                      const GcodeOptions& options,
                                      const std::vector<PathPolyline>& skirt,
                                      const PrintTools& tools, GcodeResult& result) {
  const auto material_of = [&](int tool) -> const Material& {
    return tool_material(tool_materials, tool);
  };
  const bool own_heaters = tools_heat_apart(printer);
  std::vector<std::string> layer_texts;
  size_t section = 0;              // index into options.sections (when there are any)
  size_t section_first_layer = 0;  // index of the current section's first layer
  double nozzle_target = material_of(tools.first).nozzle_temperature;
  double printed_top = 0;  // highest z printed so far (mm)
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    const ToolpathLayer& layer = toolpath.layers[k];
    const PrintSection* starts = nullptr;
    for (size_t s = section; s < options.sections.size(); ++s) {
      if (options.sections[s].first_layer == k) {
        starts = &options.sections[s];
        section = s;
        section_first_layer = k;
      }
    }
    emit.begin_layer(layer, k == section_first_layer);
    if (starts != nullptr) {
      emit.line(fmt::format("; ---- section {} of {}{}{}", section + 1, options.sections.size(),
                            starts->label.empty() ? "" : ": ", starts->label));
      if (k > 0) emit.lift_to(printed_top + std::max(printer.z_hop, kFirstTravelLift));
      const double target = starts->nozzle_temperature > 0
                                ? starts->nozzle_temperature
                                : material_of(tools.first).nozzle_temperature;
      if (target != nozzle_target) {
        emit.line(fmt::format("M109 S{:.0f} ; nozzle temperature of this section, wait", target));
        nozzle_target = target;
      }
      const Material& m = material_of(emit.tool());
      if (k > 0 && m.fan_speed != m.first_layer_fan_speed) {
        emit.line(fan_command(printer.flavor, m.first_layer_fan_speed));
      }
    }
    // The fan of the tool in use; a tool change within the layer sets the next tool's.
    const Material& m = material_of(emit.tool());
    if (k == section_first_layer + 1 && m.fan_speed != m.first_layer_fan_speed) {
      emit.line(fan_command(printer.flavor, m.fan_speed));
    }
    if (k == 0) {
      for (const PathPolyline& loop : skirt) emit.path(loop);
    }
    for (const PathPolyline& path : layer.paths) {
      emit.path(path);
      printed_top = std::max(printed_top, path.points.col(2).maxCoeff());
    }
    if (k + 1 == toolpath.layers.size()) {
      emit.retract();
      emit.line("M107 ; fan off");
      // The end G-code's M104 S0 reaches the active tool only.
      if (own_heaters) {
        for (int tool : tools.used)
          emit.line(fmt::format("M104 T{} S0 ; tool {} heater off", tool, tool));
      }
    }
    // Layers are estimated one by one, each from rest to rest: they are joined by a retraction or
    // a z move, where the head stops anyway.
    result.layer_times.push_back(estimate_time(emit.motions(), motion_limits(printer)));
    emit.motions().clear();
    layer_texts.push_back(std::move(emit.out()));
    emit.out().clear();
  }
  return layer_texts;
}

// The print's time and filament, in all and per tool.
void tally_print(GcodeResult& result, const Emitter& emit, const PrinterProfile& printer,
                 const std::vector<Material>& tool_materials) {
  for (double t : result.layer_times) result.print_time += t;
  result.tool_filament_length = emit.extruded();
  for (size_t t = 0; t < tool_materials.size(); ++t) {
    const double length = result.tool_filament_length[t];
    result.tool_filament_mass.push_back(length * filament_area(printer) / 1000 *
                                        tool_materials[t].density);
    result.filament_length += length;
    result.filament_mass += result.tool_filament_mass.back();
  }
  result.filament_volume = result.filament_length * filament_area(printer);
  result.tool_changes = emit.tool_changes();
}

// The values the printer profile's start and end G-code may name ({bed_temperature}, ...).
std::vector<std::pair<std::string, std::string>> profile_template_values(
    const Toolpath& toolpath, const PrinterProfile& printer,
    const std::vector<Material>& tool_materials, const Placement& placement) {
  const double max_z = toolpath.layers.back().z;
  std::string material_names;
  for (const Material& m : tool_materials) {
    material_names += (material_names.empty() ? "" : ",") + m.name;
  }
  return {
      {"nozzle_temperature", fmt::format("{:.0f}", tool_materials.front().nozzle_temperature)},
      {"bed_temperature", fmt::format("{:.0f}", tool_materials.front().bed_temperature)},
      {"first_layer_height", fixed(toolpath.layers.front().height, 3)},
      {"nozzle_diameter", fmt::format("{:g}", printer.nozzle_diameter)},
      {"filament_diameter", fmt::format("{:g}", printer.filament_diameter)},
      {"bed_size_x", fmt::format("{:g}", printer.bed_size.x())},
      {"bed_size_y", fmt::format("{:g}", printer.bed_size.y())},
      {"max_height", fmt::format("{:g}", printer.max_height)},
      {"min_x", fixed(placement.min.x(), 3)},
      {"min_y", fixed(placement.min.y(), 3)},
      {"max_x", fixed(placement.max.x(), 3)},
      {"max_y", fixed(placement.max.y(), 3)},
      {"size_x", fixed(placement.max.x() - placement.min.x(), 3)},
      {"size_y", fixed(placement.max.y() - placement.min.y(), 3)},
      {"center_x", fixed((placement.min.x() + placement.max.x()) / 2, 3)},
      {"center_y", fixed((placement.min.y() + placement.max.y()) / 2, 3)},
      {"max_z", fixed(max_z, 3)},
      {"park_z", fixed(std::min(max_z + kParkClearance, printer.max_height), 3)},
      {"layer_count", std::to_string(toolpath.layers.size())},
      {"travel_feed_rate", std::to_string(std::lround(printer.travel_speed * 60))},
      {"printer_name", printer.name},
      {"material_name", material_names},
  };
}

// Where the profile's start and end G-code lie in the file (byte offsets, [begin, end)): a
// violation there is the profile's to fix.
struct ProfileSpans {
  size_t start_begin = 0, start_end = 0;
  size_t end_begin = 0, end_end = 0;
};

// The file: the header, the profile's start G-code, the prologue, the layers (with M73 progress
// on the flavors that show it) and the profile's end G-code.
ProfileSpans assemble_gcode(std::string& text, const std::string& header, const std::string& start,
                            const std::string& prologue,
                            const std::vector<std::string>& layer_texts, const std::string& end,
                            const PrinterProfile& printer, const GcodeResult& result) {
  ProfileSpans spans;
  text = header;
  text += "; ---- start G-code of the printer profile\n";
  spans.start_begin = text.size();
  text += start;
  if (!start.empty() && start.back() != '\n') text += '\n';
  spans.start_end = text.size();
  text += prologue;
  const bool progress =
      printer.flavor == GcodeFlavor::kMarlin || printer.flavor == GcodeFlavor::kBambu;
  double elapsed = 0;
  for (size_t k = 0; k < layer_texts.size(); ++k) {
    if (progress) {
      // M73: percentage done and minutes left, shown on the printer's display.
      const double percent = result.print_time > 0 ? 100 * elapsed / result.print_time : 0;
      text += fmt::format("M73 P{} R{}\n", static_cast<int>(percent),
                          static_cast<long>(std::ceil((result.print_time - elapsed) / 60)));
    }
    text += layer_texts[k];
    elapsed += result.layer_times[k];
  }
  if (progress) text += "M73 P100 R0\n";
  text += "; ---- end G-code of the printer profile\n";
  spans.end_begin = text.size();
  text += end;
  if (!end.empty() && end.back() != '\n') text += '\n';
  spans.end_end = text.size();
  text += "; ---- end of file\n";
  return spans;
}

// The whole file through the safety check: a violation in the profile's start or end G-code is
// the profile's (its line named there), anywhere else a bug of the writer.
void check_written_gcode(const std::string& text, const ProfileSpans& spans,
                         const PrinterProfile& printer,
                         const std::vector<Material>& tool_materials) {
  const std::vector<GcodeViolation> violations = check_gcode(text, printer, tool_materials, 1);
  if (violations.empty()) return;
  const GcodeViolation& v = violations.front();
  const int start_first = lines_before(text, spans.start_begin) + 1;
  const int start_last = lines_before(text, spans.start_end);
  const int end_first = lines_before(text, spans.end_begin) + 1;
  const int end_last = lines_before(text, spans.end_end);
  if (v.line >= start_first && v.line <= start_last) {
    throw UserError(
        ErrorCategory::kProfile,
        fmt::format("printer {}: start_gcode line {} is unsafe ({}: {}); fix the "
                    "profile",
                    printer.name, v.line - start_first + 1, to_string(v.kind), v.reason));
  }
  if (v.line >= end_first && v.line <= end_last) {
    throw UserError(ErrorCategory::kProfile,
                    fmt::format("printer {}: end_gcode line {} is unsafe ({}: {}); fix the "
                                "profile",
                                printer.name, v.line - end_first + 1, to_string(v.kind), v.reason));
  }
  throw std::logic_error(
      fmt::format("the G-code written for {} fails its safety check at line "
                  "{} ({}: {}); this is a bug of flatmorph, please report it",
                  printer.name, v.line, to_string(v.kind), v.reason));
}

}  // namespace

GcodeResult make_gcode(const Toolpath& toolpath, const PrinterProfile& printer,
                       const std::vector<Material>& tool_materials, const GcodeOptions& options) {
  validate_print(toolpath, printer, tool_materials, options);
  const PrintTools tools = print_tools(toolpath);
  validate_sections(options.sections, toolpath, tool_material(tool_materials, tools.first),
                    tools.used.size());
  const std::vector<PathPolyline> skirt = priming_skirt(toolpath, printer, options, tools.first);
  const Placement placement = place(toolpath, skirt, printer, options);
  check_print_height(toolpath, printer, options);
  const std::optional<PrimePad> pad = validate_tool_changes(
      toolpath, printer, tool_materials, tools.used, tools.first, placement.min, placement.max);

  GcodeResult result;
  result.plate_to_bed = placement.offset;
  result.print_min = placement.min;
  result.print_max = placement.max;
  Emitter emit(printer, tool_materials, placement.offset, pad);
  const std::string prologue = print_prologue(emit, printer, tool_materials, tools);
  const std::vector<std::string> layer_texts =
      print_layers(emit, toolpath, printer, tool_materials, options, skirt, tools, result);
  tally_print(result, emit, printer, tool_materials);

  const std::vector<std::pair<std::string, std::string>> values =
      profile_template_values(toolpath, printer, tool_materials, placement);
  const std::string source = fmt::format("printer {}", printer.name);
  const std::string start = expand_gcode_template(printer.start_gcode, values, source);
  const std::string end = expand_gcode_template(printer.end_gcode, values, source);
  // The header lists the print's figures (and adds them to result.summary).
  const std::string head = header(printer, tool_materials, toolpath, options, result, tools.first);
  const ProfileSpans spans =
      assemble_gcode(result.text, head, start, prologue, layer_texts, end, printer, result);
  check_written_gcode(result.text, spans, printer, tool_materials);
  return result;
}

GcodeResult write_gcode(const std::filesystem::path& path, const Toolpath& toolpath,
                        const PrinterProfile& printer, const std::vector<Material>& tool_materials,
                        const GcodeOptions& options) {
  GcodeResult result = make_gcode(toolpath, printer, tool_materials, options);
  write_file_atomically(path, true, [&](std::ostream& out) { out << result.text; });
  return result;
}

namespace {

// The plate's bounding box over all layers (plate coordinates, mm).
std::pair<Eigen::Vector2d, Eigen::Vector2d> plate_bounds(const Toolpath& toolpath) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const ToolpathLayer& layer : toolpath.layers) {
    for (const PathPolyline& path : layer.paths) {
      lo = lo.cwiseMin(path.points.leftCols<2>().colwise().minCoeff().transpose());
      hi = hi.cwiseMax(path.points.leftCols<2>().colwise().maxCoeff().transpose());
    }
  }
  return {lo, hi};
}

// Consecutive pieces of the toolpath printed by one tool, in print order: a path whose extruding
// segments change tool is cut there (a travel before the cut stays with the earlier piece).
struct MaterialRun {
  int tool = 0;
  Toolpath toolpath;  // its layers, with the toolpath's z and height, tools set to 0
  size_t first_layer = 0, last_layer = 0;
};

std::vector<MaterialRun> material_runs(const Toolpath& toolpath) {
  std::vector<MaterialRun> runs;
  auto add = [&](size_t k, const PathPolyline& path, size_t from, size_t to, int tool) {
    if (runs.empty() || runs.back().tool != tool) {
      runs.push_back({tool, {}, k, k});
    }
    MaterialRun& run = runs.back();
    const ToolpathLayer& layer = toolpath.layers[k];
    if (run.toolpath.layers.empty() || run.last_layer != k) {
      run.toolpath.layers.push_back({layer.z, layer.height, {}});
      run.last_layer = k;
    }
    PathPolyline piece;
    piece.type = path.type;
    piece.closed = path.closed && from == 0 && to == path.segments.size();
    piece.points = path.points.middleRows(static_cast<Eigen::Index>(from),
                                          static_cast<Eigen::Index>(to - from + 1));
    piece.segments.assign(path.segments.begin() + static_cast<std::ptrdiff_t>(from),
                          path.segments.begin() + static_cast<std::ptrdiff_t>(to));
    for (SegmentStyle& s : piece.segments) s.tool = 0;
    run.toolpath.layers.back().paths.push_back(std::move(piece));
  };
  for (size_t k = 0; k < toolpath.layers.size(); ++k) {
    for (const PathPolyline& path : toolpath.layers[k].paths) {
      size_t from = 0;
      int tool = -1;  // of the extruding segments in [from, i)
      for (size_t i = 0; i < path.segments.size(); ++i) {
        const SegmentStyle& s = path.segments[i];
        if (s.travel) continue;
        if (tool >= 0 && s.tool != tool) {
          add(k, path, from, i, tool);
          from = i;
        }
        tool = s.tool;
      }
      if (tool >= 0) add(k, path, from, path.segments.size(), tool);
    }
  }
  return runs;
}

}  // namespace

std::vector<MaterialFile> make_material_files(const Toolpath& toolpath,
                                              const PrinterProfile& printer,
                                              const std::vector<Material>& tool_materials,
                                              const GcodeOptions& options) {
  if (!options.sections.empty()) {
    throw std::invalid_argument(
        "make_material_files: a print in sections cannot be cut by material");
  }
  if (toolpath.layers.empty()) {
    throw std::invalid_argument("make_material_files: the toolpath has no layer");
  }
  const std::vector<MaterialRun> runs = material_runs(toolpath);
  for (const MaterialRun& run : runs) {
    if (run.tool < 0 || static_cast<size_t>(run.tool) >= tool_materials.size()) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("the toolpath prints with tool T{} but {} material(s) were "
                                  "given: give one material per tool, comma-separated in the "
                                  "order T0,T1,...",
                                  run.tool, tool_materials.size()));
    }
  }
  // Each file places its own bounding box where that part lies in the whole print.
  const auto [lo, hi] = plate_bounds(toolpath);
  const Eigen::Vector2d at = options.at ? *options.at : bed_center(printer);
  const Eigen::Vector2d plate_to_bed = at - (lo + hi) / 2;
  std::vector<MaterialFile> files;
  for (const MaterialRun& run : runs) {
    GcodeOptions own = options;
    const auto [run_lo, run_hi] = plate_bounds(run.toolpath);
    own.at = (run_lo + run_hi) / 2 + plate_to_bed;
    if (!files.empty()) own.skirt_loops = 0;  // the first file's skirt is on the bed already
    MaterialFile file;
    file.label = fmt::format("F{}", files.size() + 1);
    file.tool = run.tool;
    file.first_layer = run.first_layer;
    file.last_layer = run.last_layer;
    file.gcode =
        make_gcode(run.toolpath, printer, {tool_materials[static_cast<size_t>(run.tool)]}, own);
    files.push_back(std::move(file));
  }
  return files;
}

std::vector<MaterialFile> write_material_files(const std::filesystem::path& path,
                                               const Toolpath& toolpath,
                                               const PrinterProfile& printer,
                                               const std::vector<Material>& tool_materials,
                                               const GcodeOptions& options) {
  std::vector<MaterialFile> files = make_material_files(toolpath, printer, tool_materials, options);
  for (const MaterialFile& file : files) {
    const std::filesystem::path named =
        path.parent_path() / (path.stem().string() + "-" + file.label + path.extension().string());
    write_file_atomically(named, true, [&](std::ostream& out) { out << file.gcode.text; });
  }
  return files;
}

}  // namespace flatmorph
