#include "calibration/hinge_sheet.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include "calibration/calibration_print.h"
#include "calibration/sheet_csv.h"
#include "common/angles.h"
#include "common/error.h"
#include "common/file_text.h"
#include "common/markup.h"

namespace flatmorph {
namespace {

constexpr const char* kColumns[] = {"strip", "case", "print_speed", "width", "fold_angle"};

void validate(const PrinterProfile& printer, const HingeSheetOptions& o) {
  if (o.speeds.empty() || o.widths.empty() || (!o.case_a && !o.case_b)) {
    throw UserError(
        ErrorCategory::kOption,
        "the hinge sheet needs at least one speed, one actuator width and one case (A or B)");
  }
  for (double v : o.speeds) {
    if (!(v >= 1)) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("hinge speed {:g} mm/s: give speeds of 1 mm/s or more (in mm/s: "
                                  "the paper's 3000-9000 "
                                  "mm/min are 50-150 mm/s)",
                                  v));
    }
    if (v > printer.travel_speed) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format(
              "hinge speed {:g} mm/s is above {:g} mm/s, the travel speed of printer {} and the "
              "fastest its profile moves the head: give --hinge-speeds up to {:g} mm/s (in mm/s, "
              "not "
              "mm/min), or a printer profile with a higher speeds.travel",
              v, printer.travel_speed, printer.name, printer.travel_speed));
    }
  }
  for (double w : o.widths) {
    if (!(w >= 1 && w <= 100)) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("actuator width {:g} mm: give widths of 1 to 100 mm", w));
    }
  }
  auto repeated = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return std::adjacent_find(v.begin(), v.end()) != v.end();
  };
  if (repeated(o.speeds) || repeated(o.widths)) {
    throw UserError(ErrorCategory::kOption,
                    "a hinge speed or width is listed twice: list each once");
  }
  if (std::string problem = hinge_stack_problem(o.stack); !problem.empty()) {
    throw UserError(ErrorCategory::kOption, "the actuator's layer stack is unusable: " + problem);
  }
  if (!(o.hinge_length >= 5 && o.hinge_length <= 100) ||
      !(o.face_length >= 2 * o.notch_depth + o.stack.overlap && o.face_length <= 200) ||
      !(o.notch_depth >= 1)) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format(
            "hinge strips of {:g} mm faces, {:g} mm hinges and {:g} mm notches: give hinges of 5 "
            "to "
            "100 mm, notches of 1 mm or more and faces at least twice the notch plus the {:g} mm "
            "overlap, up to 200 mm",
            o.face_length, o.hinge_length, o.notch_depth, o.stack.overlap));
  }
  if (!(o.spacing >= 0 && o.spacing <= 5) || !(o.gap >= 1) || !(o.margin >= 0)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("spacing {:g}, gap {:g}, margin {:g} mm: give a spacing of 0 (the "
                                "nozzle) to 5 mm, a gap "
                                "of 1 mm or more, a margin of 0 or more",
                                o.spacing, o.gap, o.margin));
  }
}

// Lines filling a box, `along_x` or along y, alternating in direction, `style.width` set to the
// spacing that fits a whole number of lines near `spacing`. For the notches: `end_cut(y)` shortens
// a line along x at its +x end (mm), and a line along y at x is printed on the intervals `runs(x)`
// returns, (y0, y1) pairs.
template <typename Cut, typename Runs>
void fill_box(const Eigen::AlignedBox2d& box, bool along_x, double spacing, double z,
              SegmentStyle style, Cut end_cut, Runs runs, std::vector<PathPolyline>& out) {
  const Eigen::Vector2d size = box.sizes();
  const double across = along_x ? size.y() : size.x();
  const int lines = std::max(1, static_cast<int>(std::lround(across / spacing)));
  style.width = across / lines;
  const double inset = style.width / 2;
  for (int i = 0; i < lines; ++i) {
    const double offset = (i + 0.5) * style.width;
    if (along_x) {
      const double y = box.min().y() + offset;
      const Eigen::Vector2d a(box.min().x() + inset, y);
      const Eigen::Vector2d b(box.max().x() - inset - end_cut(y), y);
      if (b.x() - a.x() <= 0) continue;
      out.push_back(i % 2 == 0 ? straight_path(a, b, z, style) : straight_path(b, a, z, style));
      continue;
    }
    const double x = box.min().x() + offset;
    for (const auto& [y0, y1] : runs(x)) {
      const Eigen::Vector2d a(x, y0 + inset), b(x, y1 - inset);
      if (b.y() - a.y() <= 0) continue;
      out.push_back(i % 2 == 0 ? straight_path(a, b, z, style) : straight_path(b, a, z, style));
    }
  }
}

// A (case, speed) group, as the legend names it: "case A, 75 mm/s (4500 mm/min)".
std::string group_label(bool pla_on_bed, double speed) {
  return fmt::format("case {}, {:g} mm/s ({:g} mm/min)", pla_on_bed ? "A" : "B", speed, 60 * speed);
}

}  // namespace

HingeSheetPlan plan_hinge_sheet(const PrinterProfile& printer, const HingeSheetOptions& o) {
  validate(printer, o);
  HingeSheetPlan plan;
  plan.options = o;
  plan.extrusion_width = o.spacing > 0 ? o.spacing : printer.nozzle_diameter;

  std::vector<bool> cases;
  if (o.case_a) cases.push_back(true);
  if (o.case_b) cases.push_back(false);
  const int groups = static_cast<int>(cases.size() * o.speeds.size());
  plan.code_bits = notch_code_bits(groups);
  const double slot = o.hinge_length / plan.code_bits;
  if (slot < kMinNotchSlotWidth || slot < 2 * plan.extrusion_width) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format(
            "{} groups of strips (cases x speeds) need a {}-notch code, whose notches would be "
            "{:.2f} "
            "mm wide on a {:g} mm hinge (at least {:g} mm and 2 lines are needed): print fewer "
            "speeds or one case at a time",
            groups, plan.code_bits, slot, o.hinge_length,
            std::max(kMinNotchSlotWidth, 2 * plan.extrusion_width)));
  }

  // Rows from the far side of the bed, strips left to right in the order case, speed, width.
  const Eigen::Vector2d usable = usable_bed_area(printer, o.margin);
  std::vector<Eigen::Vector2d> corners;  // top left of each strip, from the sheet's top left
  double x = 0, widest = 0;
  int rows = 1;
  int code = 0;
  for (bool pla_on_bed : cases) {
    for (double speed : o.speeds) {
      ++code;
      for (double width : o.widths) {
        const double length = width + 2 * o.face_length;
        if (length > usable.x() + 1e-9) {
          throw UserError(ErrorCategory::kInfeasible,
                          fmt::format("a hinge strip {:g} mm long does not fit the {:.0f} mm the "
                                      "bed of {} leaves ({:g} mm margin): give narrower widths",
                                      length, usable.x(), printer.name, o.margin));
        }
        if (x > 0 && x + length > usable.x() + 1e-9) {
          x = 0;
          ++rows;
        }
        corners.emplace_back(x, -(rows - 1) * (o.hinge_length + o.gap));
        x += length + o.gap;
        widest = std::max(widest, x - o.gap);
        HingeStrip s;
        s.id = static_cast<int>(plan.strips.size()) + 1;
        s.code = code;
        s.pla_on_bed = pla_on_bed;
        s.speed = speed;
        s.width = width;
        plan.strips.push_back(s);
      }
    }
  }
  const double height = rows * o.hinge_length + (rows - 1) * o.gap;
  if (height > usable.y() + 1e-9) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("the {} hinge strips need {:.0f} x {:.0f} mm but the bed of {} leaves {:.0f} "
                    "x {:.0f} mm ({:g} mm margin): print fewer speeds or widths, one case at a "
                    "time, or on a larger printer",
                    plan.strips.size(), widest, height, printer.name, usable.x(), usable.y(),
                    o.margin));
  }
  const Eigen::Vector2d top_left(-widest / 2, height / 2);
  for (size_t i = 0; i < plan.strips.size(); ++i) {
    HingeStrip& s = plan.strips[i];
    const Eigen::Vector2d lo = top_left + corners[i] - Eigen::Vector2d(0, o.hinge_length);
    const double length = s.width + 2 * o.face_length;
    s.outline = Eigen::AlignedBox2d(lo, lo + Eigen::Vector2d(length, o.hinge_length));
    const double mid = lo.x() + length / 2;
    s.actuator = Eigen::AlignedBox2d(Eigen::Vector2d(mid - s.width / 2, lo.y()),
                                     Eigen::Vector2d(mid + s.width / 2, lo.y() + o.hinge_length));
    s.bonded = Eigen::AlignedBox2d(
        Eigen::Vector2d(mid - s.width / 2 - o.stack.overlap, lo.y()),
        Eigen::Vector2d(mid + s.width / 2 + o.stack.overlap, lo.y() + o.hinge_length));
  }

  // Layers: faces in PLA, the bonded band in active PLA or TPU as the case says (notes §8).
  const int layers = o.stack.pla_layers + o.stack.tpu_layers;
  const double h = o.stack.layer_height;
  int tool = 0;  // the tool the layer below ended with
  for (int k = 0; k < layers; ++k) {
    ToolpathLayer layer;
    layer.z = (k + 1) * h;
    layer.height = h;
    std::vector<PathPolyline> by_tool[2];
    SegmentStyle style;
    style.layer_height = h;
    for (const HingeStrip& s : plan.strips) {
      const std::vector<bool> notches = notch_code(s.code, plan.code_bits);
      const double y0 = s.outline.min().y(), x1 = s.outline.max().x();
      auto notched = [&](double y) {
        const int j = std::clamp(static_cast<int>((y - y0) / slot), 0, plan.code_bits - 1);
        return notches[static_cast<size_t>(j)];
      };
      // Faces: lines along x on even layers, along y on odd ones, at the material's speed.
      style.tool = 0;
      style.feed_rate = 0;
      const Eigen::AlignedBox2d left(s.outline.min(),
                                     Eigen::Vector2d(s.bonded.min().x(), s.outline.max().y()));
      const Eigen::AlignedBox2d right(Eigen::Vector2d(s.bonded.max().x(), y0), s.outline.max());
      const bool along_x = k % 2 == 0;
      auto whole = [&](double) {
        return std::vector<std::pair<double, double>>{{y0, s.outline.max().y()}};
      };
      fill_box(
          left, along_x, plan.extrusion_width, layer.z, style, [](double) { return 0.0; }, whole,
          by_tool[0]);
      fill_box(
          right, along_x, plan.extrusion_width, layer.z, style,
          [&](double y) { return notched(y) ? o.notch_depth : 0.0; },
          [&](double line_x) {
            if (line_x < x1 - o.notch_depth) return whole(line_x);
            std::vector<std::pair<double, double>> runs;  // the unnotched slots, merged
            for (int j = 0; j < plan.code_bits; ++j) {
              if (notches[static_cast<size_t>(j)]) continue;
              const double a = y0 + j * slot, b = a + slot;
              if (!runs.empty() && std::abs(runs.back().second - a) < 1e-9) {
                runs.back().second = b;
              } else {
                runs.emplace_back(a, b);
              }
            }
            return runs;
          },
          by_tool[0]);
      // The bonded band: active PLA across the hinge at the strip's speed, or TPU along it.
      const bool active = s.pla_on_bed ? k < o.stack.pla_layers : k >= o.stack.tpu_layers;
      style.tool = active ? 0 : 1;
      style.feed_rate = active ? s.speed : o.stack.tpu_speed;
      fill_box(
          s.bonded, active, plan.extrusion_width, layer.z, style, [](double) { return 0.0; }, whole,
          by_tool[style.tool]);
    }
    // All of one tool, then the other, starting with the tool the layer below ended with.
    const int first = by_tool[tool].empty() ? 1 - tool : tool;
    for (int t : {first, 1 - first}) {
      for (PathPolyline& p : by_tool[t]) layer.paths.push_back(std::move(p));
      if (!by_tool[t].empty()) tool = t;
    }
    plan.toolpath.layers.push_back(std::move(layer));
  }
  return plan;
}

std::vector<std::string> hinge_sheet_legend(const HingeSheetPlan& plan) {
  const HingeSheetOptions& o = plan.options;
  std::vector<std::string> values;
  for (int j = 0; j < plan.code_bits; ++j) values.push_back(std::to_string(1 << j));
  std::vector<std::string> legend = {
      fmt::format("Each strip is a {:g} mm face, the actuator (its width W is the strip's width "
                  "column: 5, 10, ... mm; measure it to tell the strips of a code apart), and a "
                  "{:g} mm face whose far end carries the strip's code as notches, {} slots of "
                  "{:.1f} mm across the {:g} mm hinge.",
                  o.face_length, o.face_length, plan.code_bits, o.hinge_length / plan.code_bits,
                  o.hinge_length),
      "Lay the strip bed face down with the coded face to your right, as it lay on the printer "
      "seen from the front.",
      fmt::format("From the front edge (nearest you) to the back, the slots are worth {}; the "
                  "code is the sum of the notched slots' values.",
                  fmt::join(values, ", ")),
  };
  int code = 0;
  for (const HingeStrip& s : plan.strips) {
    if (s.code == code) continue;
    code = s.code;
    legend.push_back(fmt::format("code {}: {}", code, group_label(s.pla_on_bed, s.speed)));
  }
  return legend;
}

std::string hinge_sheet_csv_template(const HingeSheetPlan& plan, const Material& pla,
                                     const PrinterProfile& printer) {
  const HingeStack& stack = plan.options.stack;
  std::string out;
  auto comment = [&out](const std::string& s) { out += "# " + s + "\n"; };
  comment(
      "flatmorph hinge calibration (Thermorph, CHI 2018, Fig. 6-7). Heat the sheet in water at "
      "70 C for about 2 minutes, let the strips fold, take them out, measure each strip's fold "
      "angle, then run");
  comment("  flatmorph calibrate fit THIS_FILE.csv -o my-pla.json");
  comment(
      "fold_angle: degrees, 180 minus the included angle between the two faces (the paper's "
      "definition): 0 for a strip that stayed flat, 90 for a right angle; negative when it "
      "folded the other way (case A away from the bed face, case B toward it).");
  comment("Write skip in fold_angle for a strip that was lost or broke.");
  comment(
      "case A: PLA printed on the bed, TPU on top, folds toward the bed face; case B: TPU on the "
      "bed, PLA on top, folds away from it. print_speed: the active PLA's, mm/s (x 60 = mm/min); "
      "width: the actuator's, mm.");
  for (const std::string& s : hinge_sheet_legend(plan)) comment(s);
  comment("kind = hinge-sheet");
  comment(fmt::format("strips = {}", plan.strips.size()));
  comment(fmt::format("printer = {}", printer.name));
  comment(fmt::format("extrusion_width = {:g}", plan.extrusion_width));
  nlohmann::ordered_json j;
  j["layer_height"] = stack.layer_height;
  j["pla_layers"] = stack.pla_layers;
  j["tpu_layers"] = stack.tpu_layers;
  j["tpu_print_speed"] = stack.tpu_speed;
  j["overlap"] = stack.overlap;
  comment("hinge_stack = " + j.dump());
  comment("material = " + nlohmann::ordered_json::parse(material_json(pla)).dump());
  out += "strip,case,print_speed,width,code,fold_angle\n";
  for (const HingeStrip& s : plan.strips) {
    out += fmt::format("{},{},{:g},{:g},{},\n", s.id, s.pla_on_bed ? "A" : "B", s.speed, s.width,
                       s.code);
  }
  return out;
}

std::string hinge_sheet_layout_svg(const HingeSheetPlan& plan, const PrinterProfile& printer,
                                   const Eigen::Vector2d& plate_to_bed,
                                   const std::string& gcode_name) {
  const HingeSheetOptions& o = plan.options;
  const std::vector<std::string> legend = hinge_sheet_legend(plan);
  const double pad = 10;
  const Eigen::Vector2d bed = printer.bed_size;
  const double panel_h = bed.y() + 2 * pad + 8;
  const double total_w = std::max(bed.x() + 2 * pad, 200.0);
  const double total_h = panel_h + 8 + 5.5 * static_cast<double>(legend.size() + 1);
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.1f}mm\" height=\"{1:.1f}mm\" "
      "viewBox=\"0 0 {0:.3f} {1:.3f}\" font-family=\"sans-serif\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      total_w, total_h);
  const double ox = pad, oy = pad + 8;
  const Eigen::Vector2d bed_lo =
      printer.origin_at_center ? Eigen::Vector2d(-bed / 2) : Eigen::Vector2d::Zero();
  // Bed coordinates -> picture: x right, y up (the far side of the bed at the top).
  auto X = [&](double x) { return ox + (x + plate_to_bed.x() - bed_lo.x()); };
  auto Y = [&](double y) { return oy + bed.y() - (y + plate_to_bed.y() - bed_lo.y()); };
  svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"5\">hinge sheet: {}</text>\n", ox,
                     oy - 3, xml_escape(gcode_name));
  if (printer.bed_shape == BedShape::kCircular) {
    svg += fmt::format(
        "<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"{:.2f}\" fill=\"#f4f4f4\" stroke=\"#888\" "
        "stroke-width=\"0.5\"/>\n",
        ox + bed.x() / 2, oy + bed.y() / 2, bed.x() / 2);
  } else {
    svg += fmt::format(
        "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"#f4f4f4\" "
        "stroke=\"#888\" stroke-width=\"0.5\"/>\n",
        ox, oy, bed.x(), bed.y());
  }
  auto rect = [&](const Eigen::AlignedBox2d& b, const char* fill) {
    svg += fmt::format(
        "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"{}\" "
        "stroke=\"#333\" stroke-width=\"0.2\"/>\n",
        X(b.min().x()), Y(b.max().y()), b.sizes().x(), b.sizes().y(), fill);
  };
  const double slot = o.hinge_length / plan.code_bits;
  for (const HingeStrip& s : plan.strips) {
    rect(s.outline, "#9ecae1");
    rect(s.actuator, s.pla_on_bed ? "#fdae6b" : "#a1d99b");  // case A orange, case B green
    const std::vector<bool> notches = notch_code(s.code, plan.code_bits);
    for (int j = 0; j < plan.code_bits; ++j) {
      if (!notches[static_cast<size_t>(j)]) continue;
      const double y = s.outline.min().y() + j * slot;
      rect(Eigen::AlignedBox2d(Eigen::Vector2d(s.outline.max().x() - o.notch_depth, y),
                               Eigen::Vector2d(s.outline.max().x(), y + slot)),
           "#f4f4f4");
    }
    const Eigen::Vector2d c = s.actuator.center();
    svg += fmt::format(
        "<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"2.2\" text-anchor=\"middle\">#{} {} "
        "{:g}/s W{:g}</text>\n",
        X(c.x()), Y(c.y()) + 0.8, s.id, s.pla_on_bed ? "A" : "B", s.speed, s.width);
  }
  double y = panel_h + 6;
  for (const std::string& line :
       std::vector<std::string>{"orange: case A actuator (PLA on the bed); green: case B (TPU on "
                                "the bed); #strip case speed (mm/s) width (mm)"}) {
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"4\">{}</text>\n", pad, y,
                       xml_escape(line));
    y += 5.5;
  }
  for (const std::string& line : legend) {
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"4\">{}</text>\n", pad, y,
                       xml_escape(line));
    y += 5.5;
  }
  svg += "</svg>\n";
  return svg;
}

bool is_hinge_sheet(std::string_view text) {
  size_t pos = 0;
  while (pos < text.size()) {
    const size_t end = std::min(text.find('\n', pos), text.size());
    const std::string_view line = trim_cell(text.substr(pos, end - pos));
    pos = end + 1;
    if (line.empty()) continue;
    if (line.front() != '#') return false;  // the comments come first
    const std::string_view body = trim_cell(line.substr(1));
    if (body.starts_with("kind = ")) return trim_cell(body.substr(7)) == "hinge-sheet";
  }
  return false;
}

namespace {

HingeStack parse_stack(std::string_view value, const std::string& where) {
  auto fail = [&](const std::string& problem) -> UserError {
    return UserError(ErrorCategory::kFormat,
                     fmt::format("{} (hinge_stack): {}; keep the template's line", where, problem));
  };
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(value);
  } catch (const nlohmann::json::exception&) {
    throw fail("not a JSON object");
  }
  if (!j.is_object()) throw fail("not a JSON object");
  HingeStack s;
  auto number = [&](const char* key, double fallback) {
    if (!j.contains(key)) return fallback;
    if (!j[key].is_number()) throw fail(fmt::format("\"{}\" is not a number", key));
    return j[key].get<double>();
  };
  s.layer_height = number("layer_height", s.layer_height);
  const double pla = number("pla_layers", s.pla_layers), tpu = number("tpu_layers", s.tpu_layers);
  if (pla != std::floor(pla) || tpu != std::floor(tpu) || pla < 1 || tpu < 1 || pla > 20 ||
      tpu > 20) {
    throw fail("the layer counts are not whole numbers of 1 to 20");
  }
  s.pla_layers = static_cast<int>(pla);
  s.tpu_layers = static_cast<int>(tpu);
  s.tpu_speed = number("tpu_print_speed", s.tpu_speed);
  s.overlap = number("overlap", s.overlap);
  if (std::string problem = hinge_stack_problem(s); !problem.empty()) throw fail(problem);
  return s;
}

HingeStripMeasurement parse_strip(const SheetRow& r, int line) {
  HingeStripMeasurement m;
  m.line = line;
  m.strip = r.whole("strip");
  const std::string kind = lower_case(r.text("case"));
  if (kind != "a" && kind != "b") {
    r.fail("case", fmt::format("\"{}\" is no case: write A (PLA on the bed) or B (TPU on the bed)",
                               r.text("case")));
  }
  m.pla_on_bed = kind == "a";
  m.speed = r.positive("print_speed");
  if (m.speed > 1000) {
    r.fail("print_speed",
           fmt::format("{:g} mm/s is faster than any printer extrudes; give the speed in mm/s "
                       "(the G-code's mm/min divided by 60)",
                       m.speed));
  }
  m.width = r.positive("width");
  if (lower_case(r.text("fold_angle")) == "skip") {
    m.skipped = true;
    return m;
  }
  const double degrees = r.number("fold_angle");
  if (!(degrees >= -180 && degrees <= 180)) {
    r.fail("fold_angle",
           fmt::format("{:g} degrees is no fold angle: give 180 minus the included angle between "
                       "the faces, -180 to 180 degrees (0: flat)",
                       degrees));
  }
  m.fold_angle = degrees * kDegree;
  return m;
}

}  // namespace

bool is_hinge_sheet_file(const std::filesystem::path& path) {
  try {
    return is_hinge_sheet(read_file_text(path, "measurements"));
  } catch (const UserError&) {
    return false;  // the ordinary reader says why
  }
}

HingeSheet parse_hinge_measurements(std::string_view text, const std::string& source) {
  HingeSheet sheet;
  sheet.source = source;
  std::vector<std::string> names;
  int header_line = 0;
  bool kind = false;
  for (const SheetLine& l : sheet_lines(text)) {
    const int line = l.line;
    const std::string_view raw = l.text;
    if (l.comment) {
      const std::string& key = l.key;
      const std::string_view value = l.value;
      const std::string where = fmt::format("{}: line {}", source, line);
      if (key == "kind") {
        if (value != "hinge-sheet") {
          throw UserError(ErrorCategory::kFormat,
                          fmt::format("{}: kind \"{}\" is not hinge-sheet; keep the template's "
                                      "line",
                                      where, value));
        }
        kind = true;
      } else if (key == "strips") {
        int n = 0;
        const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
        if (ec != std::errc() || ptr != value.data() + value.size() || n < 1) {
          throw UserError(ErrorCategory::kFormat,
                          fmt::format("{}: \"strips = {}\" is not a count; keep the template's "
                                      "line",
                                      where, value));
        }
        sheet.expected_strips = n;
        sheet.expected_strips_line = line;
      } else if (key == "hinge_stack") {
        sheet.stack = parse_stack(value, where);
      } else if (key == "material") {
        sheet.material = parse_material_json(value, where + " (material)");
      }
      continue;
    }
    if (names.empty()) {
      if (!kind) {
        throw UserError(ErrorCategory::kFormat,
                        fmt::format("{}: no \"# kind = hinge-sheet\" line before the columns; "
                                    "start from the CSV that 'flatmorph calibrate print "
                                    "--hinge-sheet' wrote",
                                    source));
      }
      header_line = line;
      names = sheet_columns(raw, line, source, kColumns);
      continue;
    }
    std::vector<std::string_view> cells = split_cells(raw);
    if (cells.size() > names.size()) {
      throw UserError(
          ErrorCategory::kFormat,
          fmt::format("{}: line {}, column {}: the row has {} cells but line {} names {} "
                      "columns; remove the extra cells (a decimal comma? write 45.5, not 45,5)",
                      source, line, names.size() + 1, cells.size(), header_line, names.size()));
    }
    sheet.rows.push_back(
        parse_strip(SheetRow(source, line, names, std::move(cells), "strip", "fold_angle"), line));
  }
  if (names.empty() || sheet.rows.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: no measurements (a line naming the columns, then one row per "
                                "strip); start from the CSV that 'flatmorph calibrate print "
                                "--hinge-sheet' wrote",
                                source));
  }
  std::map<int, int> lines;  // strip -> line
  for (const HingeStripMeasurement& m : sheet.rows) {
    if (const auto [it, fresh] = lines.emplace(m.strip, m.line); !fresh) {
      SheetRow(source, m.line, names, {}, "strip", "fold_angle")
          .fail("strip", fmt::format("strip {} appears twice (also on line {}); one row per strip",
                                     m.strip, it->second));
    }
  }
  if (sheet.expected_strips >= 0 && static_cast<int>(sheet.rows.size()) != sheet.expected_strips) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: line {}: the template lists {} strips but the file has {} "
                                "rows (last on line {}); keep one row per printed strip and write "
                                "skip in fold_angle for a lost one",
                                source, sheet.expected_strips_line, sheet.expected_strips,
                                sheet.rows.size(), sheet.rows.back().line));
  }
  return sheet;
}

HingeSheet read_hinge_measurements(const std::filesystem::path& path) {
  return parse_hinge_measurements(read_file_text(path, "measurements"), path.string());
}

HingeCurveFit fit_hinge_curve(const HingeSheet& sheet, int max_degree) {
  HingeCurveFit fit;
  fit.curve.calibrated = true;
  fit.curve.stack = sheet.stack;
  if (sheet.material) fit.curve.nozzle_temperature = sheet.material->nozzle_temperature;
  double lo = 0, hi = std::numeric_limits<double>::infinity();
  for (bool pla_on_bed : {true, false}) {
    const std::string name = hinge_case_name(pla_on_bed);
    std::vector<double> speeds, curvatures;
    std::map<double, std::pair<double, int>> by_speed;  // speed -> (sum of κ, strips)
    for (const HingeStripMeasurement& m : sheet.rows) {
      if (m.skipped || m.pla_on_bed != pla_on_bed) continue;
      speeds.push_back(m.speed);
      curvatures.push_back(m.fold_angle / m.width);  // Step 3: θ = κ W
      by_speed[m.speed].first += curvatures.back();
      by_speed[m.speed].second += 1;
    }
    if (by_speed.size() < 2) {
      throw UserError(
          ErrorCategory::kFormat,
          fmt::format("{}: {} has measured strips at {} speed{}; the hinge curve needs "
                      "two or more: measure them, or print 'calibrate print "
                      "--hinge-sheet' with several --hinge-speeds",
                      sheet.source, name, by_speed.size(), by_speed.size() == 1 ? "" : "s"));
    }
    std::string means;
    for (const auto& [v, sum] : by_speed) {
      const double mean = sum.first / sum.second;
      means += fmt::format("{}{:g} mm/s: {:.4f} /mm", means.empty() ? "" : ", ", v, mean);
      if (!(mean > 0)) {
        throw UserError(ErrorCategory::kFormat,
                        fmt::format("{}: the {} strips printed at {:g} mm/s fold by {:.4f} rad per "
                                    "mm of width on average, not in their case's direction; "
                                    "check their angles' signs and the case column",
                                    sheet.source, name, v, mean));
      }
    }
    std::vector<double> coefficients;
    try {
      coefficients = fit_monotone_curve(speeds, curvatures, max_degree, kHingeCurveParameter);
    } catch (const UserError&) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: no fold per mm that changes steadily with the speed fits "
                                  "the {} strips (mean fold per mm of width at {}); check the "
                                  "angles, widths and cases",
                                  sheet.source, name, means));
    }
    (pla_on_bed ? fit.curve.case_a_coefficients : fit.curve.case_b_coefficients) = coefficients;
    lo = std::max(lo, by_speed.begin()->first);
    hi = std::min(hi, by_speed.rbegin()->first);
    double sum = 0, worst = 0;
    int count = 0;
    for (const HingeStripMeasurement& m : sheet.rows) {
      if (m.skipped || m.pla_on_bed != pla_on_bed) continue;
      HingeStripFit s{m.strip, m.pla_on_bed, m.speed,
                      m.width, m.fold_angle, polynomial_value(coefficients, m.speed) * m.width};
      const double r = s.fold_angle - s.predicted;
      sum += r * r;
      worst = std::max(worst, std::abs(r));
      ++count;
      fit.strips.push_back(s);
    }
    (pla_on_bed ? fit.rms_residual_a : fit.rms_residual_b) = std::sqrt(sum / count);
    (pla_on_bed ? fit.max_residual_a : fit.max_residual_b) = worst;
  }
  if (!(hi > lo)) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: the two cases were measured at speeds that share no range "
                                "(both need strips at two or more common speeds); measure both "
                                "cases at the same speeds",
                                sheet.source));
  }
  fit.curve.min_speed = lo;
  fit.curve.max_speed = hi;
  if (std::string problem = hinge_curve_problem(fit.curve); !problem.empty()) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: the fitted hinge curve is unusable ({}); check the angles",
                                sheet.source, problem));
  }
  std::sort(fit.strips.begin(), fit.strips.end(),
            [](const HingeStripFit& a, const HingeStripFit& b) { return a.strip < b.strip; });
  return fit;
}

}  // namespace flatmorph
