#include "calibration/calibration_print.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/markup.h"

namespace flatmorph {
namespace {

bool has_duplicates(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return std::adjacent_find(v.begin(), v.end()) != v.end();
}

void validate_speed_ramp(const PrinterProfile& printer, const CalibrationPrintOptions& o) {
  if (o.nozzle_temperatures.size() != 1 || o.layer_heights.size() != 1) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format(
            "--speed-ramp prints one nozzle temperature and one layer height, {} and {} were given "
            "({} C; {} mm): give one of each with --nozzle-temps and --layer-heights (default: the "
            "material's)",
            o.nozzle_temperatures.size(), o.layer_heights.size(),
            fmt::join(o.nozzle_temperatures, ","), fmt::join(o.layer_heights, ",")));
  }
  if (o.print_speeds.empty())
    throw UserError(ErrorCategory::kOption, "--speed-ramp needs at least one print speed");
  // The profile has no extrusion speed limit of its own: its travel speed is the fastest it
  // lets the head move.
  for (double v : o.print_speeds) {
    if (!(v >= 1)) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format("print speed {:g} mm/s: give speeds of 1 mm/s or more (in mm/s, not the "
                      "mm/min of a G-code feed rate)",
                      v));
    }
    if (v > printer.travel_speed) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format(
              "print speed {:g} mm/s is above {:g} mm/s, the travel speed of printer {} and the "
              "fastest its profile moves the head: give --print-speeds up to {:g} mm/s, or a "
              "printer "
              "profile with a higher speeds.travel",
              v, printer.travel_speed, printer.name, printer.travel_speed));
    }
  }
  if (has_duplicates(o.print_speeds)) {
    throw UserError(ErrorCategory::kOption, "a print speed is listed twice: list each once");
  }
  if (std::lround(o.thickness / o.layer_heights.front()) < 2) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("a speed-ramp sample of {:g} mm at {:g} mm layers has one layer, printed at "
                    "the first-layer speed whatever the set's speed: give a --thickness of two "
                    "layers or more",
                    o.thickness, o.layer_heights.front()));
  }
}

void validate(const PrinterProfile& printer, const Material& material,
              const CalibrationPrintOptions& o) {
  if (o.nozzle_temperatures.empty() || o.layer_heights.empty()) {
    throw UserError(ErrorCategory::kOption,
                    "give at least one nozzle temperature and one layer height");
  }
  if (o.thickness_ramp && o.speed_ramp) {
    throw UserError(
        ErrorCategory::kOption,
        "--thickness-ramp and --speed-ramp are two calibrations, each with its own measurement "
        "sheet: print them one at a time");
  }
  if (o.thickness_ramp && o.nozzle_temperatures.size() != 1) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("--thickness-ramp prints one temperature, {} were given ({}): give one with "
                    "--nozzle-temps",
                    o.nozzle_temperatures.size(), fmt::join(o.nozzle_temperatures, ",")));
  }
  for (double t : o.nozzle_temperatures) {
    if (!(t >= material.min_nozzle_temperature && t <= material.max_nozzle_temperature)) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format("nozzle temperature {:g} C lies outside the safe range [{:g}, {:g}] C of "
                      "material {}: "
                      "choose temperatures inside it, or a material file with a wider range",
                      t, material.min_nozzle_temperature, material.max_nozzle_temperature,
                      material.name));
    }
  }
  const double max_height = 0.8 * printer.nozzle_diameter;
  for (double h : o.layer_heights) {
    if (!(h >= 0.02 && h <= max_height)) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format(
              "layer height {:g} mm is out of range: give 0.02 to {:g} mm (80 % of the {:g} mm "
              "nozzle)",
              h, max_height, printer.nozzle_diameter));
    }
  }
  if (has_duplicates(o.nozzle_temperatures) || has_duplicates(o.layer_heights)) {
    throw UserError(ErrorCategory::kOption,
                    "a nozzle temperature or layer height is listed twice: list each once");
  }
  if (o.repeats < 1 || o.repeats > 50) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--repeats {} is out of range: give 1 to 50", o.repeats));
  }
  if (!(o.length >= 10 && o.length <= 1000 && o.width >= 3 && o.width <= o.length)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("sample size {:g} x {:g} mm: give a length of 10 to 1000 mm "
                                "and a width of 3 mm up to the length",
                                o.length, o.width));
  }
  if (!o.thickness_ramp && !(o.thickness > 0 && o.thickness <= 10)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("--thickness {:g} mm: give 0 to 10 mm", o.thickness));
  }
  if (o.thickness_ramp && (o.ramp_layers < 1 || o.ramp_layers > 100)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{} ramp layers: give 1 to 100", o.ramp_layers));
  }
  if (!(o.spacing >= 0 && o.spacing <= 5) || !(o.gap >= 1) || !(o.set_gap >= o.gap) ||
      !(o.margin >= 0)) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format(
            "spacing {:g}, gap {:g}, set gap {:g}, margin {:g} mm: give a spacing of 0 (the "
            "nozzle) to "
            "5 mm, a gap of 1 mm or more, a set gap at least the gap, a margin of 0 or more",
            o.spacing, o.gap, o.set_gap, o.margin));
  }
  if (!(o.notch_depth >= 1 && o.notch_depth <= o.length / 4)) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("notch depth {:g} mm: give 1 mm to a quarter of the length", o.notch_depth));
  }
  if (o.speed_ramp) validate_speed_ramp(printer, o);
}

}  // namespace

PathPolyline straight_path(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double z,
                           const SegmentStyle& style) {
  PathPolyline p;
  p.points.resize(2, 3);
  p.points.row(0) << a.x(), a.y(), z;
  p.points.row(1) << b.x(), b.y(), z;
  p.segments = {style};
  p.type = PathType::kSolidInfill;
  return p;
}

int notch_code_bits(int count) {
  int bits = 1;
  while ((1 << bits) - 2 < count) ++bits;
  return bits;
}

std::string CalibrationSet::label() const {
  std::string label = fmt::format("set {}: {:g} C, {:g} mm x {} layers", id, nozzle_temperature,
                                  layer_height, layers);
  if (print_speed > 0) label += fmt::format(", {:g} mm/s", print_speed);
  return label;
}

std::vector<bool> notch_code(int id, int bits) {
  std::vector<bool> code(static_cast<size_t>(bits));
  for (int j = 0; j < bits; ++j) code[static_cast<size_t>(j)] = ((id >> j) & 1) != 0;
  return code;
}

CalibrationPlan plan_calibration(const PrinterProfile& printer, const Material& material,
                                 const CalibrationPrintOptions& o) {
  validate(printer, material, o);
  CalibrationPlan plan;
  plan.options = o;
  const double spacing = o.spacing > 0 ? o.spacing : printer.nozzle_diameter;
  plan.paths_per_layer = std::max(1, static_cast<int>(std::lround(o.width / spacing)));
  plan.extrusion_width = o.width / plan.paths_per_layer;

  // A speed ramp has one temperature and one height (validate): its sets differ by speed alone.
  const std::vector<double> speeds = o.speed_ramp ? o.print_speeds : std::vector<double>{0.0};
  for (double t : o.nozzle_temperatures) {
    for (double h : o.layer_heights) {
      for (double v : speeds) {
        CalibrationSet set;
        set.id = static_cast<int>(plan.sets.size()) + 1;
        set.nozzle_temperature = t;
        set.layer_height = h;
        set.layers = o.thickness_ramp ? o.ramp_layers
                                      : std::max(1, static_cast<int>(std::lround(o.thickness / h)));
        set.print_speed = v;
        plan.sets.push_back(set);
      }
    }
  }
  const int count = static_cast<int>(plan.sets.size()) * o.repeats;
  plan.code_bits = notch_code_bits(count);
  const double slot = o.width / plan.code_bits;
  if (slot < kMinNotchSlotWidth || slot < 2 * plan.extrusion_width) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format(
            "{} samples need a {}-notch code, whose notches would be {:.2f} mm wide on a {:g} mm "
            "wide sample (at least {:g} mm and 2 paths are needed): print fewer sets or repeats, "
            "or "
            "wider samples",
            count, plan.code_bits, slot, o.width,
            std::max(kMinNotchSlotWidth, 2 * plan.extrusion_width)));
  }

  // A set is a block of samples stacked along y (several columns if the bed is too shallow).
  const Eigen::Vector2d usable = usable_bed_area(printer, o.margin);
  const int rows = std::min(
      o.repeats, static_cast<int>(std::floor((usable.y() + o.gap) / (o.width + o.gap) + 1e-9)));
  const int columns = rows > 0 ? (o.repeats + rows - 1) / rows : 0;
  const Eigen::Vector2d block(columns * o.length + (columns - 1) * o.gap,
                              rows * o.width + (rows - 1) * o.gap);
  if (rows < 1 || block.x() > usable.x() + 1e-9) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("a set of {} samples of {:g} x {:g} mm needs {:.0f} x {:.0f} mm but the bed of "
                    "{} leaves {:.0f} x {:.0f} mm ({:g} mm margin): use fewer repeats, smaller "
                    "samples or a larger printer",
                    o.repeats, o.length, o.width, block.x(), std::max(0.0, block.y()), printer.name,
                    usable.x(), usable.y(), o.margin));
  }
  const int across =
      static_cast<int>(std::floor((usable.x() + o.set_gap) / (block.x() + o.set_gap) + 1e-9));
  const int down =
      static_cast<int>(std::floor((usable.y() + o.set_gap) / (block.y() + o.set_gap) + 1e-9));
  const int per_plate = std::max(1, across * down);

  // Ids and places, plate by plate.
  const size_t plates = (plan.sets.size() + per_plate - 1) / per_plate;
  for (size_t p = 0; p < plates; ++p) {
    const size_t first = p * per_plate;
    const size_t n = std::min(plan.sets.size() - first, static_cast<size_t>(per_plate));
    const int cols = std::min(across, static_cast<int>(n));
    const int lines = static_cast<int>((n + cols - 1) / cols);
    const Eigen::Vector2d extent(cols * block.x() + (cols - 1) * o.set_gap,
                                 lines * block.y() + (lines - 1) * o.set_gap);
    CalibrationPlate plate;
    for (size_t b = 0; b < n; ++b) {
      const CalibrationSet& set = plan.sets[first + b];
      plate.sets.push_back(set.id);
      // Blocks left to right, then front to back from the far side (top of the layout picture).
      const int bx = static_cast<int>(b) % cols, by = static_cast<int>(b) / cols;
      const Eigen::Vector2d corner(-extent.x() / 2 + bx * (block.x() + o.set_gap),
                                   extent.y() / 2 - by * (block.y() + o.set_gap));  // top left
      for (int r = 0; r < o.repeats; ++r) {
        CalibrationSample s;
        s.id = static_cast<int>(plan.samples.size()) + 1;
        s.set = set.id;
        s.repeat = r + 1;
        s.plate = static_cast<int>(p) + 1;
        const int c = r / rows, row = r % rows;
        s.center = corner + Eigen::Vector2d(c * (o.length + o.gap) + o.length / 2,
                                            -(row * (o.width + o.gap) + o.width / 2));
        plan.samples.push_back(s);
      }
    }
    plan.plates.push_back(std::move(plate));
  }

  // Toolpaths: per set, its layers from the bed up; per layer, every sample of the set, paths
  // along x alternating in direction; odd layers run the same paths backwards, so each layer
  // starts where the previous one ended.
  for (CalibrationPlate& plate : plan.plates) {
    for (int set_id : plate.sets) {
      const CalibrationSet& set = plan.sets[static_cast<size_t>(set_id - 1)];
      PrintSection section;
      section.first_layer = plate.toolpath.layers.size();
      section.nozzle_temperature = set.nozzle_temperature;
      section.label = set.label();
      plate.sections.push_back(section);
      SegmentStyle style;
      style.width = plan.extrusion_width;
      style.layer_height = set.layer_height;
      for (int k = 1; k <= set.layers; ++k) {
        // The set's speed from the second layer on; 0 leaves the first to the writer's first-layer
        // speed (and the ordinary sets to the material's speeds).
        style.feed_rate = k > 1 ? set.print_speed : 0.0;
        ToolpathLayer layer;
        layer.z = k * set.layer_height;
        layer.height = set.layer_height;
        for (const CalibrationSample& s : plan.samples) {
          if (s.set != set.id) continue;
          const std::vector<bool> code = notch_code(s.id, plan.code_bits);
          for (int i = 0; i < plan.paths_per_layer; ++i) {
            const double v = (i + 0.5) * plan.extrusion_width;  // from the sample's -y edge
            const int slot_index = std::min(plan.code_bits - 1, static_cast<int>(v / slot));
            const double cut = code[static_cast<size_t>(slot_index)] ? o.notch_depth : 0.0;
            const double y = s.center.y() - o.width / 2 + v;
            const Eigen::Vector2d a(s.center.x() - o.length / 2 + plan.extrusion_width / 2, y);
            const Eigen::Vector2d b(s.center.x() + o.length / 2 - plan.extrusion_width / 2 - cut,
                                    y);
            layer.paths.push_back(i % 2 == 0 ? straight_path(a, b, layer.z, style)
                                             : straight_path(b, a, layer.z, style));
          }
        }
        if (k % 2 == 0) {
          std::reverse(layer.paths.begin(), layer.paths.end());
          for (PathPolyline& p : layer.paths) p.points = p.points.colwise().reverse().eval();
        }
        plate.toolpath.layers.push_back(std::move(layer));
      }
    }
  }
  return plan;
}

std::vector<std::string> calibration_notch_legend(const CalibrationPlan& plan) {
  std::vector<std::string> values;
  for (int j = 0; j < plan.code_bits; ++j) values.push_back(std::to_string(1 << j));
  return {
      fmt::format("Each sample carries its id as notches in its coded end, {} slots of {:.1f} mm "
                  "across the width.",
                  plan.code_bits, plan.options.width / plan.code_bits),
      "Lay the sample top face up (the face that was not on the bed) with the notched end to "
      "your right, as it lay on the printer seen from the front.",
      fmt::format("From the front edge (nearest you) to the back, the slots are worth {}; the id "
                  "is the sum of the notched slots' values.",
                  fmt::join(values, ", ")),
      "Measure lengths along an edge without a notch (the full length).",
  };
}

Material plate_material(const CalibrationPlan& plan, size_t plate, const Material& material) {
  Material m = material;
  m.nozzle_temperature =
      plan.sets[static_cast<size_t>(plan.plates[plate].sets.front() - 1)].nozzle_temperature;
  return m;
}

std::string calibration_csv_template(const CalibrationPlan& plan, const Material& material,
                                     const PrinterProfile& printer) {
  const CalibrationPrintOptions& o = plan.options;
  std::string out;
  auto comment = [&out](const std::string& s) { out += "# " + s + "\n"; };
  comment(
      "flatmorph calibration measurements (Shrink & Morph §4.1). Heat the samples in a 90 C "
      "water bath, measure them, fill in one row per sample, then run");
  comment("  flatmorph calibrate fit THIS_FILE.csv -o my-material.json");
  comment(
      "Lengths in mm. *_before: as printed (pre-filled with the nominal size; measure them if "
      "you can). *_after: after heating.");
  comment(
      "length_after: along the curled sample (its arc length); or leave it empty and give "
      "rise and chord: the arc length is computed.");
  comment(
      "curvature (1/mm) of the curled sample, > 0 when its top face (not the bed face) is on "
      "the inside of the curl; or leave it empty and give rise and chord:");
  comment(
      "  chord = straight distance between the two ends, rise = height of the middle above "
      "that chord, > 0 under the same rule (curvature = 2 rise / (rise^2 + chord^2 / 4)).");
  comment("Write skip in length_after for a sample that was lost or broke.");
  for (const std::string& s : calibration_notch_legend(plan)) comment(s);
  comment(fmt::format("kind = {}", o.thickness_ramp ? "thickness-ramp"
                                   : o.speed_ramp   ? "speed-ramp"
                                                    : "sets"));
  if (o.speed_ramp) {
    comment(fmt::format(
        "print_speed (mm/s): every layer of the set but the first, which is printed at the "
        "material's first-layer speed ({:g} mm/s) so that it sticks",
        material.first_layer_speed));
  }
  comment(fmt::format("samples = {}", plan.samples.size()));
  comment(fmt::format("printer = {}", printer.name));
  comment(fmt::format("extrusion_width = {:g}", plan.extrusion_width));
  // One line: the material the samples were printed with (speeds, bed, fan ...), read back by
  // `calibrate fit` to write the fitted material with the same printing parameters.
  comment("material = " + nlohmann::ordered_json::parse(material_json(material)).dump());
  // The speed column only on a speed ramp, where it is what the sets differ by.
  out += fmt::format(
      "sample,set,plate,nozzle_temperature,layer_height,layers,{}length_before,width_before,"
      "thickness_before,length_after,width_after,thickness_after,curvature,rise,chord\n",
      o.speed_ramp ? "print_speed," : "");
  for (const CalibrationSample& s : plan.samples) {
    const CalibrationSet& set = plan.sets[static_cast<size_t>(s.set - 1)];
    out += fmt::format("{},{},{},{:g},{:g},{},{}{:g},{:g},{:g},,,,,,\n", s.id, s.set, s.plate,
                       set.nozzle_temperature, set.layer_height, set.layers,
                       o.speed_ramp ? fmt::format("{:g},", set.print_speed) : "", o.length, o.width,
                       set.thickness());
  }
  return out;
}

std::string calibration_layout_svg(const CalibrationPlan& plan, const PrinterProfile& printer,
                                   const std::vector<Eigen::Vector2d>& plate_to_bed,
                                   const std::vector<std::string>& gcode_names) {
  const CalibrationPrintOptions& o = plan.options;
  const double pad = 10;
  const double legend_h = 14 + 5.5 * (4 + static_cast<double>(plan.sets.size()));
  const Eigen::Vector2d bed = printer.bed_size;
  const double panel_w = bed.x() + 2 * pad;
  const double panel_h = bed.y() + 2 * pad + 8;
  const double total_w = panel_w * static_cast<double>(plan.plates.size());
  const double total_h = panel_h + legend_h;
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.1f}mm\" height=\"{1:.1f}mm\" "
      "viewBox=\"0 0 {0:.3f} {1:.3f}\" font-family=\"sans-serif\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      total_w, total_h);
  const Eigen::Vector2d bed_lo =
      printer.origin_at_center ? Eigen::Vector2d(-bed / 2) : Eigen::Vector2d::Zero();
  for (size_t p = 0; p < plan.plates.size(); ++p) {
    const double ox = p * panel_w + pad;
    const double oy = pad + 8;
    // Bed coordinates -> picture: x right, y up (the far side of the bed at the top).
    auto X = [&](double x) { return ox + (x - bed_lo.x()); };
    auto Y = [&](double y) { return oy + bed.y() - (y - bed_lo.y()); };
    svg += fmt::format(
        "<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"5\">plate {} of {}: {}</text>\n", ox, oy - 3,
        p + 1, plan.plates.size(), xml_escape(p < gcode_names.size() ? gcode_names[p] : ""));
    if (printer.bed_shape == BedShape::kCircular) {
      svg += fmt::format(
          "<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"{:.2f}\" fill=\"#f4f4f4\" "
          "stroke=\"#888\" stroke-width=\"0.5\"/>\n",
          ox + bed.x() / 2, oy + bed.y() / 2, bed.x() / 2);
    } else {
      svg += fmt::format(
          "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" "
          "fill=\"#f4f4f4\" stroke=\"#888\" stroke-width=\"0.5\"/>\n",
          ox, oy, bed.x(), bed.y());
    }
    const Eigen::Vector2d offset =
        p < plate_to_bed.size() ? plate_to_bed[p] : Eigen::Vector2d::Zero();
    for (const CalibrationSample& s : plan.samples) {
      if (s.plate != static_cast<int>(p) + 1) continue;
      const Eigen::Vector2d c = s.center + offset;
      const double x0 = c.x() - o.length / 2, y0 = c.y() - o.width / 2;
      // The outline with its notches, counter-clockwise from the front-left corner.
      const std::vector<bool> code = notch_code(s.id, plan.code_bits);
      const double slot = o.width / plan.code_bits;
      std::string points = fmt::format("{:.2f},{:.2f} ", X(x0), Y(y0));
      for (int j = 0; j < plan.code_bits; ++j) {
        const double x = x0 + o.length - (code[static_cast<size_t>(j)] ? o.notch_depth : 0);
        points += fmt::format("{:.2f},{:.2f} {:.2f},{:.2f} ", X(x), Y(y0 + j * slot), X(x),
                              Y(y0 + (j + 1) * slot));
      }
      points += fmt::format("{:.2f},{:.2f}", X(x0), Y(y0 + o.width));
      svg += fmt::format(
          "<polygon points=\"{}\" fill=\"#9ecae1\" stroke=\"#08519c\" "
          "stroke-width=\"0.3\"/>\n",
          points);
      svg += fmt::format(
          "<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"{:.1f}\" "
          "text-anchor=\"middle\">#{} (set {})</text>\n",
          X(c.x()), Y(c.y()) + std::min(5.0, o.width / 3) / 3, std::min(5.0, o.width / 3), s.id,
          s.set);
    }
  }
  double y = panel_h + 6;
  auto text = [&](const std::string& s) {
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"4\">{}</text>\n", pad, y,
                       xml_escape(s));
    y += 5.5;
  };
  for (const std::string& s : calibration_notch_legend(plan)) text(s);
  for (const CalibrationSet& set : plan.sets) {
    int first = 0, last = 0;
    for (const CalibrationSample& s : plan.samples) {
      if (s.set != set.id) continue;
      if (first == 0) first = s.id;
      last = s.id;
    }
    text(fmt::format("{} ({:g} mm thick): samples #{} to #{}", set.label(), set.thickness(), first,
                     last));
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace flatmorph
