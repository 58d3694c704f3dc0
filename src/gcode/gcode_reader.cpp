#include "gcode/gcode_reader.h"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <numbers>

#include "common/error.h"
#include "gcode/gcode_parse.h"

namespace flatmorph {
namespace {

constexpr double kEpsilon = 1e-6;      // mm of filament or head motion treated as none
constexpr double kMaxSagitta = 0.005;  // mm between an arc and its chords
// Every chord of an arc turns by at most this (rad), so that even a tiny circle keeps its shape.
constexpr double kMaxChordAngle = std::numbers::pi / 2;
// The layer rule (gcode_reader.h): a rise from the previous extruding move, in mm, and from the
// current layer's lowest extruding z, as a fraction of the layer's nominal height.
constexpr double kLayerRise = 0.02;
constexpr double kLayerRiseFraction = 0.4;
// A bead wider than this many times its height, or than this many mm, cannot come out of a
// nozzle: the E values are not what the file's mode says.
constexpr double kMaxWidthOverHeight = 20;
constexpr double kMaxWidth = 5;
// Beads shorter than this (mm) are not judged by their width: positions rounded to 0.001 mm and
// E to 0.00001 mm make a tiny move's width meaningless.
constexpr double kMinJudgedLength = 0.05;
// Coordinates and E values beyond these (mm) are no print; refusing them keeps every computation
// finite.
constexpr double kMaxCoordinate = 1e6;
constexpr double kMaxE = 1e9;
// T numbers from here on are firmware specials (Bambu: T255 unloads the filament, T1000 appears
// in its start G-code), not tools.
constexpr int kFirstSpecialTool = 255;

// The commands the reader follows; everything else (temperatures, fans, macros) is ignored.
enum class Op {
  kOther,
  kMove,     // G0, G1
  kArcCw,    // G2
  kArcCcw,   // G3
  kRetract,  // G10 without P or L (firmware retraction)
  kUnretract,
  kPlaneXy,  // G17
  kPlaneXz,  // G18
  kPlaneYz,  // G19
  kInches,   // G20
  kHome,     // G28
  kAbsolute,
  kRelative,
  kSetPosition,  // G92
  kAbsoluteE,    // M82
  kRelativeE,    // M83
  kTool,
};

// The command of a classic name ("G1", "G01", "M83", "T1"); `number` gets a tool's number.
Op classify(std::string_view name, int& number) {
  int code = 0;
  const auto [end, ec] = std::from_chars(name.data() + 1, name.data() + name.size(), code);
  if (ec != std::errc() || end != name.data() + name.size()) return Op::kOther;  // "M620.1"
  if (name[0] == 'T') {
    number = code;
    return Op::kTool;
  }
  if (name[0] == 'M') {
    if (code == 82) return Op::kAbsoluteE;
    if (code == 83) return Op::kRelativeE;
    return Op::kOther;
  }
  switch (code) {
    case 0:
    case 1:
      return Op::kMove;
    case 2:
      return Op::kArcCw;
    case 3:
      return Op::kArcCcw;
    case 10:
      return Op::kRetract;
    case 11:
      return Op::kUnretract;
    case 17:
      return Op::kPlaneXy;
    case 18:
      return Op::kPlaneXz;
    case 19:
      return Op::kPlaneYz;
    case 20:
      return Op::kInches;
    case 28:
      return Op::kHome;
    case 90:
      return Op::kAbsolute;
    case 91:
      return Op::kRelative;
    case 92:
      return Op::kSetPosition;
    default:
      return Op::kOther;
  }
}

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

std::optional<double> parse_number(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

// "1.75 mm" or "1.75,2.85": every diameter, or nothing when one is not a positive number.
std::optional<std::vector<double>> parse_diameters(std::string_view value) {
  value = trim(value);
  if (value.size() > 2 && value.substr(value.size() - 2) == "mm") {
    value.remove_suffix(2);
  }
  std::vector<double> out;
  while (true) {
    const size_t comma = value.find(',');
    const std::optional<double> d = parse_number(value.substr(0, comma));
    if (!d || !(*d > 0) || *d > 100) return std::nullopt;
    out.push_back(*d);
    if (comma == std::string_view::npos) return out;
    value.remove_prefix(comma + 1);
  }
}

// The numbers of "0.9 -0.002" (space-separated), or nothing when one is not a number.
std::optional<std::vector<double>> parse_numbers(std::string_view s) {
  std::vector<double> out;
  s = trim(s);
  while (!s.empty()) {
    const size_t space = s.find(' ');
    const std::optional<double> v = parse_number(s.substr(0, space));
    if (!v) return std::nullopt;
    out.push_back(*v);
    if (space == std::string_view::npos) break;
    s = trim(s.substr(space + 1));
  }
  if (out.empty()) return std::nullopt;
  return out;
}

// "A..B UNIT" (the unit optional): (A, B).
std::optional<std::pair<double, double>> parse_range(std::string_view s, std::string_view unit) {
  s = trim(s);
  if (!unit.empty() && s.size() > unit.size() && s.substr(s.size() - unit.size()) == unit) {
    s.remove_suffix(unit.size());
  }
  const size_t dots = s.find("..");
  if (dots == std::string_view::npos) return std::nullopt;
  const std::optional<double> a = parse_number(s.substr(0, dots)),
                              b = parse_number(s.substr(dots + 2));
  if (!a || !b) return std::nullopt;
  return std::make_pair(*a, *b);
}

// The parts of "name1 value1, name2 value2, ..." after each expected name, in order; nothing
// when the names differ.
std::optional<std::vector<std::string_view>> named_parts(
    std::string_view s, const std::vector<std::string_view>& names) {
  std::vector<std::string_view> out;
  for (size_t i = 0; i < names.size(); ++i) {
    const size_t comma = i + 1 < names.size() ? s.find(", ") : std::string_view::npos;
    if (i + 1 < names.size() && comma == std::string_view::npos) return std::nullopt;
    const std::string_view part = trim(s.substr(0, comma));
    if (part.substr(0, names[i].size()) != names[i] || part.size() <= names[i].size() ||
        part[names[i].size()] != ' ') {
      return std::nullopt;
    }
    out.push_back(trim(part.substr(names[i].size())));
    if (comma != std::string_view::npos) s = s.substr(comma + 2);
  }
  return out;
}

std::optional<HeaderShrinkModel> parse_shrink_line(std::string_view value) {
  const auto parts = named_parts(value, {"lambda1", "lambda2", "lambda3", "delta_lambda1"});
  if (!parts) return std::nullopt;
  HeaderShrinkModel m;
  double* fields[] = {&m.lambda1, &m.lambda2, &m.lambda3, &m.delta_lambda1};
  for (size_t i = 0; i < 4; ++i) {
    const std::optional<double> v = parse_number((*parts)[i]);
    if (!v) return std::nullopt;
    *fields[i] = *v;
  }
  if (!(m.lambda1 > 0 && m.lambda2 > 0 && m.lambda3 > 0)) return std::nullopt;
  return m;
}

// "none": a model without the curve (an empty optional inside); else the curve, or nothing when
// the line does not read.
std::optional<std::optional<SpeedCurve>> parse_speed_curve_line(std::string_view value) {
  if (value == "none") return std::optional<SpeedCurve>();
  const auto parts = named_parts(value, {"lambda1 coefficients", "speeds", "layer height"});
  if (!parts) return std::nullopt;
  const auto coefficients = parse_numbers((*parts)[0]);
  const auto speeds = parse_range((*parts)[1], " mm/s");
  std::string_view height = (*parts)[2];
  if (height.size() > 3 && height.substr(height.size() - 3) == " mm") height.remove_suffix(3);
  const std::optional<double> h = parse_number(height);
  if (!coefficients || !speeds || !h) return std::nullopt;
  SpeedCurve curve{*coefficients, speeds->first, speeds->second, *h, 0};
  if (!speed_curve_problem(curve).empty()) return std::nullopt;
  return std::optional<SpeedCurve>(curve);
}

std::optional<std::optional<ThicknessCurve>> parse_thickness_curve_line(std::string_view value) {
  if (value == "none") return std::optional<ThicknessCurve>();
  const auto parts = named_parts(value, {"lambda1 coefficients", "layer heights"});
  if (!parts) return std::nullopt;
  const auto coefficients = parse_numbers((*parts)[0]);
  const auto heights = parse_range((*parts)[1], " mm");
  if (!coefficients || !heights) return std::nullopt;
  ThicknessCurve curve;
  curve.lambda1_coefficients = *coefficients;
  curve.min_layer_height = heights->first;
  curve.max_layer_height = heights->second;
  if (!thickness_curve_problem(curve).empty()) return std::nullopt;
  return std::optional<ThicknessCurve>(curve);
}

// The offset in "x_bed = x_plate - 12.000, ..." after `name` ("x_plate"): -12.
std::optional<double> plate_offset(std::string_view value, std::string_view name) {
  const size_t at = value.find(name);
  if (at == std::string_view::npos) return std::nullopt;
  std::string_view rest = trim(value.substr(at + name.size()));
  if (rest.empty() || (rest[0] != '+' && rest[0] != '-')) return std::nullopt;
  const double sign = rest[0] == '-' ? -1 : 1;
  rest = trim(rest.substr(1));
  double number = 0;
  const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), number);
  if (ec != std::errc() || end == rest.data() || !std::isfinite(number)) return std::nullopt;
  return sign * number;
}

// "\"A\";\"B\"" -> A, B.
std::vector<std::string> split_quoted_list(std::string_view value) {
  std::vector<std::string> out;
  while (true) {
    const size_t semicolon = value.find(';');
    std::string_view item = trim(value.substr(0, semicolon));
    if (item.size() >= 2 && item.front() == '"' && item.back() == '"') {
      item = item.substr(1, item.size() - 2);
    }
    out.emplace_back(item);
    if (semicolon == std::string_view::npos) return out;
    value.remove_prefix(semicolon + 1);
  }
}

// Per tool: each has its own filament.
struct ToolState {
  double retracted = 0;     // mm of filament pulled back and not pushed again yet
  bool retracting = false;  // E moved back last: a retraction going on (over a wipe's moves)
  bool firmware_retracted = false;
};

// What a bead needs once the whole file is read (layers, the header's filament diameter).
struct PendingBead {
  double filament = 0;  // mm of filament deposited
  bool width_given = false;
  bool height_given = false;
  bool before_layers = false;  // before the file's first layer annotation
};

class Reader {
 public:
  Reader(std::string_view text, const std::string& source, const GcodeReadOptions& options)
      : text_(text), source_(source), options_(options) {}

  GcodeDeposition run() {
    if (!(options_.filament_diameter > 0) || !std::isfinite(options_.filament_diameter)) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("{}: the filament diameter {} mm is not a positive number: give "
                                  "the diameter of the filament in mm (1.75 or 2.85)",
                                  source_, options_.filament_diameter));
    }
    const size_t max_lines = std::min<size_t>(options_.max_lines, INT_MAX - 1);
    size_t begin = 0;
    while (begin < text_.size()) {
      size_t end = text_.find('\n', begin);
      last_partial_ = end == std::string_view::npos;
      if (last_partial_) end = text_.size();
      ++line_;
      if (static_cast<size_t>(line_) > max_lines) {
        fail(ErrorCategory::kResource,
             fmt::format("more than {} lines (GcodeReadOptions::max_lines): not read; split the "
                         "print or raise the limit",
                         max_lines));
      }
      process(text_.substr(begin, end - begin));
      begin = end + 1;
    }
    return finish();
  }

  // Only the header's comment lines: nothing is judged, so any file gives what it says.
  GcodeHeaderInfo header_only() {
    size_t begin = 0;
    while (begin < text_.size()) {
      size_t end = text_.find('\n', begin);
      if (end == std::string_view::npos) end = text_.size();
      ++line_;
      const std::string_view line = trim(text_.substr(begin, end - begin));
      begin = end + 1;
      if (line.empty() || line.front() != ';') continue;
      const std::string_view c = trim(line.substr(1));
      if (starts_with(c, "TARGET_MACHINE.NAME:") || starts_with(c, "MACHINE_NAME:")) {
        set_printer(3, trim(c.substr(c.find(':') + 1)));
      } else if (const size_t eq = c.find(" = "); eq != std::string_view::npos) {
        header_line(c.substr(0, eq), trim(c.substr(eq + 3)));
      }
    }
    if (diameter_line_ > 0) {
      if (const auto diameters = parse_diameters(diameter_text_)) {
        header_.tool_filament_diameters = *diameters;
        header_.filament_diameter = diameters->front();
      }
    }
    header_.tool_materials = own_materials_.empty() ? slicer_materials_ : own_materials_;
    header_.tool_shrink = tool_shrink();
    return std::move(header_);
  }

 private:
  [[noreturn]] void fail(ErrorCategory category, const std::string& what) const {
    fail_at(category, std::max(line_, 1), what);
  }
  [[noreturn]] void fail_at(ErrorCategory category, int line, const std::string& what) const {
    throw UserError(category, fmt::format("{}:{}: {}", source_, line, what));
  }

  void process(std::string_view raw) {
    const std::string_view line = trim(raw);
    if (line.empty()) return;
    if (line.front() == ';') {
      comment(trim(line.substr(1)));
      return;
    }
    const std::string_view code = strip(line, buffer_);
    if (code.empty()) return;
    Command cmd;
    const std::optional<std::string> bad = parse_command(code, cmd);
    if (!is_classic(cmd.name)) return;  // a macro
    int number = 0;
    const Op op = classify(cmd.name, number);
    const bool reads_parameters = op == Op::kMove || op == Op::kArcCw || op == Op::kArcCcw ||
                                  op == Op::kRetract || op == Op::kHome || op == Op::kSetPosition;
    const bool moves =
        op == Op::kMove || op == Op::kArcCw || op == Op::kArcCcw || op == Op::kSetPosition;
    if (reads_parameters && last_partial_ && (bad || (moves && cut_short(cmd)))) {
      return;  // the file was cut in the middle of this line
    }
    if (bad && reads_parameters) {
      fail(ErrorCategory::kFormat,
           fmt::format("\"{}\": {} is not a parameter letter with a finite number: fix or remove "
                       "the line",
                       code, *bad));
    }
    switch (op) {
      case Op::kMove:
      case Op::kArcCw:
      case Op::kArcCcw:
        move(cmd, code, op);
        break;
      case Op::kRetract:
        // RepRapFirmware's G10 P<tool> sets temperatures, G10 L<n> work offsets.
        if (!cmd.has('P') && !cmd.has('L')) {
          ToolState& state = tool_state();
          if (!state.firmware_retracted) ++retractions_;
          state.firmware_retracted = true;
        }
        break;
      case Op::kUnretract:
        tool_state().firmware_retracted = false;
        break;
      case Op::kPlaneXy:
        plane_line_ = 0;
        break;
      case Op::kPlaneXz:
      case Op::kPlaneYz:
        plane_line_ = line_;
        plane_xz_ = op == Op::kPlaneXz;
        break;
      case Op::kInches:
        fail(ErrorCategory::kFormat,
             "the file uses inches (G20): re-export it in millimetres (G21)");
      case Op::kHome: {
        // Most printers home to 0; where exactly does not change what is deposited afterwards.
        const bool all = !cmd.has('X') && !cmd.has('Y') && !cmd.has('Z');
        for (int axis = 0; axis < 3; ++axis) {
          if (all || cmd.has("XYZ"[axis])) pos_[axis] = 0;
        }
        break;
      }
      case Op::kAbsolute:
      case Op::kRelative:
        // Marlin 2: G90/G91 set every axis, E included, until the next M82/M83.
        relative_xyz_ = relative_e_ = op == Op::kRelative;
        break;
      case Op::kSetPosition:
        set_position(cmd, code);
        break;
      case Op::kAbsoluteE:
      case Op::kRelativeE:
        relative_e_ = op == Op::kRelativeE;
        break;
      case Op::kTool:
        if (number < kFirstSpecialTool) {
          if (number != tool_) ++tool_changes_;
          tool_ = number;
        }
        break;
      case Op::kOther:
        break;
    }
  }

  // Whether a parameter of a move or of G92 lacks its value ("G1 X10 E").
  static bool cut_short(const Command& cmd) {
    for (const char letter : std::string_view("XYZEFIJR")) {
      if (cmd.has(letter) && std::isnan(*cmd.get(letter))) return true;
    }
    return false;
  }

  ToolState& tool_state() {
    if (static_cast<size_t>(tool_) >= tools_.size()) tools_.resize(static_cast<size_t>(tool_) + 1);
    return tools_[static_cast<size_t>(tool_)];
  }

  // The number of a parameter the command reads ("G1 X" has none).
  double value(const Command& cmd, char letter, std::string_view code, double limit) const {
    const double v = *cmd.get(letter);
    if (std::isnan(v)) {
      fail(ErrorCategory::kFormat,
           fmt::format("\"{}\": the parameter {} has no value: fix or remove the line", code,
                       letter));
    }
    if (std::abs(v) > limit) {
      fail(ErrorCategory::kFormat,
           fmt::format("\"{}\": {} {:g} is beyond {:g} mm, not a print: fix the line", code, letter,
                       v, limit));
    }
    return v;
  }

  void check_position(std::string_view code) const {
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(pos_[axis]) > kMaxCoordinate) {
        fail(ErrorCategory::kFormat,
             fmt::format("\"{}\" moves {} to {:g}, beyond {:g} mm, not a print: fix the line "
                         "(or the relative moves before it)",
                         code, "XYZ"[axis], pos_[axis], kMaxCoordinate));
      }
    }
  }

  void set_position(const Command& cmd, std::string_view code) {
    const bool none = !cmd.has('X') && !cmd.has('Y') && !cmd.has('Z') && !cmd.has('E');
    for (int axis = 0; axis < 3; ++axis) {
      const char letter = "XYZ"[axis];
      if (none) pos_[axis] = 0;
      if (cmd.has(letter)) pos_[axis] = value(cmd, letter, code, kMaxCoordinate);
    }
    if (none) e_ = 0;
    if (cmd.has('E')) e_ = value(cmd, 'E', code, kMaxE);
  }

  void move(const Command& cmd, std::string_view code, Op op) {
    const Eigen::Vector3d from = pos_;
    for (int axis = 0; axis < 3; ++axis) {
      const char letter = "XYZ"[axis];
      if (!cmd.has(letter)) continue;
      const double v = value(cmd, letter, code, kMaxCoordinate);
      pos_[axis] = relative_xyz_ ? pos_[axis] + v : v;
    }
    check_position(code);
    if (cmd.has('F')) {
      // Marlin ignores a feed rate that is not positive.
      if (const double f = value(cmd, 'F', code, HUGE_VAL); f > 0) feed_ = f;
    }
    double de = 0;
    if (cmd.has('E')) {
      const double e = value(cmd, 'E', code, kMaxE);
      de = relative_e_ ? e : e - e_;
      e_ = relative_e_ ? e_ + e : e;
    }
    std::optional<Arc> arc;
    if (op != Op::kMove) arc = arc_of(cmd, code, from, op == Op::kArcCw);
    const double xy = arc ? arc->length() : (pos_ - from).head<2>().norm();

    ToolState& state = tool_state();
    if (de < -kEpsilon) {
      state.retracted -= de;
      if (!state.retracting) ++retractions_;
      state.retracting = true;
      return;
    }
    if (de <= kEpsilon) return;
    state.retracting = false;
    const double refill = std::min(de, state.retracted);
    state.retracted -= refill;
    const double extruded = de - refill;
    if (extruded <= kEpsilon || xy <= kEpsilon) return;  // an unretraction, a prime, a blob
    if (!(from.z() > 0) || !(pos_.z() > 0)) {
      fail(ErrorCategory::kFormat,
           fmt::format("\"{}\" extrudes at z = {:.3f} mm, on or below the bed: the z of the file "
                       "is wrong (a G92 Z offset?)",
                       code, std::min(from.z(), pos_.z())));
    }
    if (!arc) {
      add_bead(from, pos_, extruded);
      return;
    }
    if (arc->chords() > static_cast<double>(options_.max_beads - beads_.size())) {
      too_many_beads();
    }
    // Within the coordinate limits an arc has at most some 10^5 chords.
    const int chords = static_cast<int>(arc->chords());
    Eigen::Vector3d a = from;
    for (int i = 1; i <= chords; ++i) {
      const Eigen::Vector3d b = i == chords ? pos_ : arc->at(static_cast<double>(i) / chords);
      add_bead(a, b, extruded / chords);
      a = b;
    }
  }

  // A G2/G3 arc in the XY plane: centre, start angle and radius, signed sweep (rad), and the end
  // radius, between which the radius goes linearly when the file's two radii differ a little.
  struct Arc {
    Eigen::Vector2d centre;
    double angle = 0, sweep = 0, radius = 0, end_radius = 0;
    Eigen::Vector3d from, to;

    double length() const { return std::abs(sweep) * (radius + end_radius) / 2; }

    Eigen::Vector3d at(double t) const {
      const double a = angle + sweep * t, r = radius + (end_radius - radius) * t;
      return {centre.x() + r * std::cos(a), centre.y() + r * std::sin(a),
              from.z() + (to.z() - from.z()) * t};
    }

    // How many chords keep the sagitta within kMaxSagitta, as a double to be compared with the
    // beads left before it is trusted.
    double chords() const {
      const double r = std::max(radius, end_radius);
      const double step = r <= kMaxSagitta / 2
                              ? kMaxChordAngle
                              : std::min(kMaxChordAngle, 2 * std::acos(1 - kMaxSagitta / r));
      return std::max(1.0, std::ceil(std::abs(sweep) / step));
    }
  };

  Arc arc_of(const Command& cmd, std::string_view code, const Eigen::Vector3d& from,
             bool clockwise) const {
    if (plane_line_ > 0) {
      fail(ErrorCategory::kFormat,
           fmt::format("\"{}\" is an arc in the {} plane ({} on line {}): only arcs in the XY "
                       "plane (G17) are read; re-export without arcs or with arcs in XY",
                       code, plane_xz_ ? "XZ" : "YZ", plane_xz_ ? "G18" : "G19", plane_line_));
    }
    Arc arc;
    arc.from = from;
    arc.to = pos_;
    const Eigen::Vector2d p0 = from.head<2>(), p1 = pos_.head<2>();
    if (cmd.has('R')) {
      // Marlin: R > 0 the arc of at most half a turn, R < 0 the other; a radius too small for
      // the chord gives the half circle.
      const double r = value(cmd, 'R', code, kMaxCoordinate);
      const Eigen::Vector2d d = p1 - p0;
      const double distance = d.norm();
      if (distance <= kEpsilon) {
        fail(ErrorCategory::kFormat,
             fmt::format("\"{}\": an arc given by its radius R cannot end where it starts; give "
                         "its centre with I and J",
                         code));
      }
      const double h = std::sqrt(std::max(0.0, r * r - distance * distance / 4));
      const Eigen::Vector2d left(-d.y() / distance, d.x() / distance);
      arc.centre = (p0 + p1) / 2 + ((clockwise != (r < 0)) ? -h : h) * left;
    } else if (cmd.has('I') || cmd.has('J')) {
      const double i = cmd.has('I') ? value(cmd, 'I', code, kMaxCoordinate) : 0;
      const double j = cmd.has('J') ? value(cmd, 'J', code, kMaxCoordinate) : 0;
      arc.centre = p0 + Eigen::Vector2d(i, j);
    } else {
      fail(ErrorCategory::kFormat,
           fmt::format("\"{}\": an arc needs its centre (I, J) or its radius (R)", code));
    }
    arc.radius = (p0 - arc.centre).norm();
    arc.end_radius = (p1 - arc.centre).norm();
    if (arc.radius <= kEpsilon) {
      fail(
          ErrorCategory::kFormat,
          fmt::format("\"{}\": the arc's centre is its start point (radius 0): fix I and J", code));
    }
    arc.angle = std::atan2(p0.y() - arc.centre.y(), p0.x() - arc.centre.x());
    const double end_angle = std::atan2(p1.y() - arc.centre.y(), p1.x() - arc.centre.x());
    double sweep = clockwise ? arc.angle - end_angle : end_angle - arc.angle;
    if (sweep < 0) sweep += 2 * std::numbers::pi;
    if (p0 == p1) sweep = 2 * std::numbers::pi;  // I/J with the same start and end: a full circle
    arc.sweep = clockwise ? -sweep : sweep;
    return arc;
  }

  [[noreturn]] void too_many_beads() const {
    fail(ErrorCategory::kResource,
         fmt::format("more than {} beads (GcodeReadOptions::max_beads): not read; split the print "
                     "or raise the limit",
                     options_.max_beads));
  }

  void add_bead(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double filament) {
    if (beads_.size() >= options_.max_beads) too_many_beads();
    DepositedBead& bead = beads_.emplace_back();
    bead.start = a;
    bead.end = b;
    bead.width = width_.value_or(0);
    bead.height = height_.value_or(0);
    bead.feed_rate = feed_;
    bead.tool = tool_;
    bead.layer = std::max(0, layers_ - 1);
    bead.line = line_;
    bead.type = type_;
    pending_.push_back({filament, width_.has_value(), height_.has_value(), layers_ == 0});
  }

  // Annotations and header lines; `c` is the comment without its ";" and blanks.
  void comment(std::string_view c) {
    if (c == "LAYER_CHANGE" || c == "CHANGE_LAYER" ||
        (starts_with(c, "LAYER:") && is_integer(c.substr(6)))) {
      ++layers_;
      layer_tag_z_.emplace_back();
    } else if (starts_with(c, "TYPE:") || starts_with(c, "FEATURE:")) {
      type_ = trim(c.substr(c.find(':') + 1));
    } else if (starts_with(c, "WIDTH:") || starts_with(c, "LINE_WIDTH:")) {
      width_ = annotation(c, "bead width");
    } else if (starts_with(c, "HEIGHT:") || starts_with(c, "LAYER_HEIGHT:")) {
      height_ = annotation(c, "bead height");
    } else if (starts_with(c, "Z:") || starts_with(c, "Z_HEIGHT:")) {
      const double z = annotation(c, "layer z");
      if (layers_ > 0) layer_tag_z_.back() = z;
    } else if (starts_with(c, "FILAMENT_SWAP:T")) {
      // flatmorph's manual swap on one nozzle: tool n's material prints from here, through the
      // nozzle as the pause left it (the firmware restores E after a pause).
      const std::string_view digits = c.substr(15);
      int next = -1;
      const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), next);
      if (ec == std::errc() && end == digits.data() + digits.size() && next >= 0 &&
          next < kFirstSpecialTool && next != tool_) {
        const ToolState state = tool_state();
        tool_ = next;
        tool_state() = state;
      }
    } else if (starts_with(c, "TARGET_MACHINE.NAME:") || starts_with(c, "MACHINE_NAME:")) {
      set_printer(3, trim(c.substr(c.find(':') + 1)));
    } else if (const size_t eq = c.find(" = "); eq != std::string_view::npos) {
      header_line(c.substr(0, eq), trim(c.substr(eq + 3)));
    }
  }

  static bool is_integer(std::string_view s) {
    s = trim(s);
    if (!s.empty() && s.front() == '-') s.remove_prefix(1);
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
  }

  double annotation(std::string_view c, std::string_view what) const {
    const std::optional<double> v = parse_number(c.substr(c.find(':') + 1));
    if (!v || !(*v > 0) || *v > kMaxCoordinate) {
      fail(ErrorCategory::kFormat,
           fmt::format("\";{}\": the {} is not a positive number of mm: fix or remove the line", c,
                       what));
    }
    return *v;
  }

  // The tool `key` names for `base`: 0 for "base" itself, n for "Tn base"; nothing for another
  // key or a tool number out of range.
  static std::optional<int> tool_key(std::string_view key, std::string_view base) {
    if (key == base) return 0;
    if (key.size() < base.size() + 3 || key[0] != 'T' ||
        key.substr(key.size() - base.size() - 1) != fmt::format(" {}", base)) {
      return std::nullopt;
    }
    const std::string_view digits = key.substr(1, key.size() - base.size() - 2);
    int tool = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), tool);
    if (ec != std::errc() || end != digits.data() + digits.size() || tool < 0 ||
        tool >= kFirstSpecialTool) {
      return std::nullopt;
    }
    return tool;
  }

  // What a tool's shrink lines said (each unset until read; an inner unset optional is "none").
  struct ShrinkLines {
    std::optional<HeaderShrinkModel> shrink;
    std::optional<std::optional<SpeedCurve>> speed_curve;
    std::optional<std::optional<ThicknessCurve>> thickness_curve;
  };

  ShrinkLines& shrink_lines(int tool) {
    if (static_cast<size_t>(tool) >= shrink_lines_.size()) shrink_lines_.resize(tool + 1);
    return shrink_lines_[tool];
  }

  // The tools whose three lines were all read.
  std::vector<std::optional<HeaderShrinkModel>> tool_shrink() const {
    std::vector<std::optional<HeaderShrinkModel>> out(shrink_lines_.size());
    for (size_t t = 0; t < shrink_lines_.size(); ++t) {
      const ShrinkLines& l = shrink_lines_[t];
      if (!l.shrink || !l.speed_curve || !l.thickness_curve) continue;
      out[t] = *l.shrink;
      out[t]->speed_curve = *l.speed_curve;
      out[t]->thickness_curve = *l.thickness_curve;
    }
    return out;
  }

  // `rank`: 0 flatmorph's own key, then the slicers' in order of preference; the first line of
  // the best rank wins.
  void set_printer(int rank, std::string_view name) {
    if (rank < printer_rank_ && !name.empty()) {
      header_.printer = name;
      printer_rank_ = rank;
    }
  }

  void header_line(std::string_view key, std::string_view value) {
    if (key == "printer") {
      set_printer(0, value);
    } else if (key == "printer_settings_id") {
      set_printer(1, value);
    } else if (key == "printer_model") {
      set_printer(2, value);
    } else if (const std::optional<int> tool = tool_key(key, "material")) {
      if (static_cast<size_t>(*tool) >= own_materials_.size()) own_materials_.resize(*tool + 1);
      if (own_materials_[*tool].empty()) own_materials_[*tool] = value;
    } else if (const std::optional<int> tool = tool_key(key, "shrink")) {
      shrink_lines(*tool).shrink = parse_shrink_line(value);
    } else if (const std::optional<int> tool = tool_key(key, "speed_curve")) {
      shrink_lines(*tool).speed_curve = parse_speed_curve_line(value);
    } else if (const std::optional<int> tool = tool_key(key, "thickness_curve")) {
      shrink_lines(*tool).thickness_curve = parse_thickness_curve_line(value);
    } else if (key == "filament_settings_id") {
      if (slicer_materials_.empty()) slicer_materials_ = split_quoted_list(value);
    } else if (key == "filament_diameter") {
      if (diameter_line_ == 0) {
        diameter_line_ = line_;
        diameter_text_ = value;
      }
    } else if (key == "plate_to_bed") {
      const std::optional<double> x = plate_offset(value, "x_plate");
      const std::optional<double> y = plate_offset(value, "y_plate");
      if (x && y && !header_.plate_to_bed) header_.plate_to_bed = Eigen::Vector2d(*x, *y);
    }
  }

  // The header's filament diameters, and the section (mm²) of each tool's filament.
  std::vector<double> filament_sections() {
    if (diameter_line_ > 0) {
      if (const auto diameters = parse_diameters(diameter_text_)) {
        header_.tool_filament_diameters = *diameters;
        header_.filament_diameter = diameters->front();
      } else if (!options_.filament_diameter_given) {
        fail_at(ErrorCategory::kFormat, diameter_line_,
                fmt::format("filament_diameter = {}: not a diameter in mm; fix the line or give "
                            "the diameter",
                            diameter_text_));
      }
    }
    std::vector<double> sections;
    for (size_t tool = 0; tool < std::max<size_t>(tools_.size(), 1); ++tool) {
      const std::vector<double>& listed = header_.tool_filament_diameters;
      double d = options_.filament_diameter;
      if (!options_.filament_diameter_given && !listed.empty()) {
        d = tool < listed.size() ? listed[tool] : listed.front();
      }
      sections.push_back(std::numbers::pi * d * d / 4);
    }
    return sections;
  }

  GcodeDeposition finish() {
    GcodeDeposition out;
    if (beads_.empty()) {
      fail(ErrorCategory::kFormat,
           "the file deposits nothing: no G1 (nor G0, G2, G3) move extrudes while moving in x and "
           "y; give the G-code of a print");
    }
    const std::vector<double> sections = filament_sections();
    header_.tool_materials = own_materials_.empty() ? slicer_materials_ : own_materials_;
    header_.tool_shrink = tool_shrink();
    out.header = std::move(header_);
    out.tool_changes = tool_changes_;
    out.retractions = retractions_;
    out.layer_z = layers_ > 0 ? annotated_layers() : layers_by_z();
    out.num_layers = static_cast<int>(out.layer_z.size());

    for (size_t i = 0; i < beads_.size(); ++i) {
      DepositedBead& bead = beads_[i];
      const PendingBead& pending = pending_[i];
      bead.filament_mm3 = pending.filament * sections[static_cast<size_t>(bead.tool)];
      const double z = (bead.start.z() + bead.end.z()) / 2;
      // Beads before the first layer annotation, the start G-code's purge lines, lie on the bed
      // and are thick on purpose (Prusa's): their width is not judged.
      const bool purge = layers_ > 0 && pending.before_layers;
      const double below = purge || bead.layer == 0 ? 0 : out.layer_z[bead.layer - 1];
      const double height = pending.height_given   ? bead.height
                            : z - below > kEpsilon ? z - below
                                                   : z;
      const double length = (bead.end - bead.start).norm();
      // Every bead moves in x and y and lies above the bed: length and height are positive.
      const double width = bead.filament_mm3 / (length * height);
      if (!purge && length >= kMinJudgedLength &&
          (width > kMaxWidthOverHeight * height || width > kMaxWidth)) {
        fail_at(
            ErrorCategory::kFormat, bead.line,
            fmt::format("implausible extrusion: {:.4f} mm^3 of filament over {:.3f} mm make a "
                        "bead {:.2f} mm wide and {:.3f} mm high (more than {:g} times its "
                        "height or {:g} mm): the E mode (M82 absolute, M83 relative) may be "
                        "wrong, or E is not in mm of filament; fix the file's E mode",
                        bead.filament_mm3, length, width, height, kMaxWidthOverHeight, kMaxWidth));
      }
      bead.height = height;
      if (!pending.width_given) bead.width = width;
    }
    out.beads = std::move(beads_);
    return out;
  }

  // Layers by annotation: the ";Z:" of each, else the lowest nozzle z of its own beads.
  std::vector<double> annotated_layers() {
    std::vector<double> lowest(static_cast<size_t>(layers_), HUGE_VAL);
    for (size_t i = 0; i < beads_.size(); ++i) {
      if (pending_[i].before_layers) continue;
      const DepositedBead& b = beads_[i];
      double& z = lowest[static_cast<size_t>(b.layer)];
      z = std::min({z, b.start.z(), b.end.z()});
    }
    std::vector<double> layer_z(static_cast<size_t>(layers_));
    for (size_t k = 0; k < layer_z.size(); ++k) {
      if (layer_tag_z_[k]) {
        layer_z[k] = *layer_tag_z_[k];
      } else if (std::isfinite(lowest[k])) {
        layer_z[k] = lowest[k];
      } else {
        layer_z[k] = k > 0 ? layer_z[k - 1] : 0;
      }
    }
    return layer_z;
  }

  // Layers by z alone (the rule in gcode_reader.h); sets each bead's layer.
  std::vector<double> layers_by_z() {
    std::vector<double> layer_z;
    double previous_end = 0;
    for (DepositedBead& bead : beads_) {
      const double z = bead.start.z();
      bool next = layer_z.empty();
      if (!next) {
        const double lowest = layer_z.back();
        const double below = layer_z.size() > 1 ? layer_z[layer_z.size() - 2] : 0;
        const double nominal = lowest - below > kEpsilon ? lowest - below : lowest;
        next = z > previous_end + kLayerRise && z > lowest + kLayerRiseFraction * nominal;
      }
      if (next) layer_z.push_back(z);
      layer_z.back() = std::min({layer_z.back(), bead.start.z(), bead.end.z()});
      bead.layer = static_cast<int>(layer_z.size()) - 1;
      previous_end = bead.end.z();
    }
    return layer_z;
  }

  const std::string_view text_;
  const std::string& source_;
  const GcodeReadOptions& options_;
  int line_ = 0;
  bool last_partial_ = false;  // the line read is the last and has no end of line
  std::string buffer_;

  // Machine state.
  Eigen::Vector3d pos_ = Eigen::Vector3d::Zero();  // mm; printers start at (and home to) 0
  double e_ = 0;                                   // the E register, mm of filament
  bool relative_xyz_ = false;
  bool relative_e_ = false;  // Marlin's default: absolute
  double feed_ = 0;          // mm/min
  int tool_ = 0;
  std::vector<ToolState> tools_;
  int plane_line_ = 0;  // line of the G18/G19 in effect, 0 in the XY plane
  bool plane_xz_ = false;
  int tool_changes_ = 0;
  int retractions_ = 0;

  // Annotations in effect.
  std::string type_;
  std::optional<double> width_, height_;
  int layers_ = 0;  // layer annotations so far
  std::vector<std::optional<double>> layer_tag_z_;

  // Header lines.
  GcodeHeaderInfo header_;
  int printer_rank_ = INT_MAX;
  std::vector<std::string> own_materials_, slicer_materials_;
  std::vector<ShrinkLines> shrink_lines_;
  int diameter_line_ = 0;
  std::string diameter_text_;

  std::vector<DepositedBead> beads_;
  std::vector<PendingBead> pending_;
};

}  // namespace

GcodeDeposition read_gcode_deposition(std::string_view text, const std::string& source,
                                      const GcodeReadOptions& options) {
  return Reader(text, source, options).run();
}

GcodeHeaderInfo read_gcode_header(std::string_view text) {
  return Reader(text, "", GcodeReadOptions{}).header_only();
}

}  // namespace flatmorph
