#include "methods/tiles/dxf_outlines.h"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>

#include "common/angles.h"
#include "common/error.h"

namespace flatmorph {
namespace {

using outline_loops::DrawnLoop;
using outline_loops::OpenPiece;
using outline_loops::Origin;
using outline_loops::Point;
using outline_loops::printable;

// One group: a code line and its value line (the line number is the value's).
struct Pair {
  int code;
  std::string_view value;
  long long line;
};

std::string_view trim(std::string_view s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

std::string quoted(std::string_view s) { return fmt::format("\"{}\"", printable(s)); }

bool parse_integer(std::string_view s, long long& value) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), value);
  return !s.empty() && error == std::errc() && end == s.data() + s.size();
}

// The entity types read, for messages.
constexpr const char* kReadTypes = "LWPOLYLINE, POLYLINE, LINE, ARC and CIRCLE";

// What to do about an entity type that is not read.
std::string advice_for(std::string_view type) {
  if (type == "SPLINE" || type == "ELLIPSE" || type == "HELIX") {
    return "convert the outline to a polyline (explode / 'convert to polyline' in most CAD tools) "
           "and save again";
  }
  if (type == "INSERT") {
    return "explode the block (EXPLODE in most CAD tools) so that its outlines are drawn "
           "directly, and save again";
  }
  static constexpr std::string_view kAnnotations[] = {
      "TEXT",        "MTEXT",     "DIMENSION", "ARC_DIMENSION", "LEADER", "MLEADER",
      "MULTILEADER", "HATCH",     "SOLID",     "TRACE",         "POINT",  "ATTRIB",
      "ATTDEF",      "TOLERANCE", "IMAGE",     "WIPEOUT"};
  if (std::find(std::begin(kAnnotations), std::end(kAnnotations), type) != std::end(kAnnotations)) {
    return "the drawing must hold only the tile outlines; delete texts, dimensions, hatches and "
           "points (or leave their layers out of the export) and save again";
  }
  return std::string("only ") + kReadTypes +
         " entities are; convert it to a polyline or delete it, and save again";
}

// mm per drawing unit for the $INSUNITS codes read; the others are named in the refusal.
std::optional<double> millimetres_per_unit(long long code) {
  switch (code) {
    case 1:
      return 25.4;  // inch
    case 2:
      return 304.8;  // foot
    case 4:
      return 1.0;
    case 5:
      return 10.0;
    case 6:
      return 1000.0;
    default:
      return std::nullopt;
  }
}

std::string unit_name(long long code) {
  static constexpr const char* kNames[] = {"unitless",
                                           "inches",
                                           "feet",
                                           "miles",
                                           "millimetres",
                                           "centimetres",
                                           "metres",
                                           "kilometres",
                                           "microinches",
                                           "mils",
                                           "yards",
                                           "angstroms",
                                           "nanometres",
                                           "microns",
                                           "decimetres",
                                           "decametres",
                                           "hectometres",
                                           "gigametres",
                                           "astronomical units",
                                           "light years",
                                           "parsecs",
                                           "US survey feet",
                                           "US survey inches",
                                           "US survey yards",
                                           "US survey miles"};
  if (code >= 0 && code < static_cast<long long>(std::size(kNames))) return kNames[code];
  return "";
}

struct Vertex {
  double x = 0, y = 0, bulge = 0;
  bool has_y = false;
};

class Reader {
 public:
  Reader(const std::string& file, const OutlineReadOptions& options,
         std::vector<std::string>& warnings)
      : file_(file), options_(options), warnings_(warnings) {
    budget_.max = options.max_points;
  }

  std::vector<TileOutline> read(std::string_view text) {
    read_pairs(text);
    // Sections by name first: the units (HEADER) must be known before the entities.
    std::vector<std::pair<size_t, size_t>> entities;
    std::optional<std::pair<size_t, size_t>> header;
    size_t i = 0;
    while (i < pairs_.size()) {
      const Pair& p = pairs_[i];
      if (p.code == 0 && trim(p.value) == "EOF") break;
      if (p.code != 0 || trim(p.value) != "SECTION") {
        fail(p.line, fmt::format("expected a SECTION (group 0) or EOF, found group {} {}: the "
                                 "file is damaged; save the drawing again as ASCII DXF",
                                 p.code, quoted(p.value)));
      }
      if (i + 1 >= pairs_.size() || pairs_[i + 1].code != 2) {
        fail(p.line,
             "a SECTION without its name (group 2): the file is damaged; save the drawing "
             "again as ASCII DXF");
      }
      const std::string_view name = trim(pairs_[i + 1].value);
      size_t end = i + 2;
      while (end < pairs_.size() &&
             !(pairs_[end].code == 0 &&
               (trim(pairs_[end].value) == "ENDSEC" || trim(pairs_[end].value) == "EOF"))) {
        ++end;
      }
      if (end == pairs_.size() || trim(pairs_[end].value) != "ENDSEC") {
        fail(p.line, fmt::format("the {} section has no ENDSEC: the file is truncated or "
                                 "damaged; save the drawing again as ASCII DXF",
                                 quoted(name)));
      }
      if (name == "HEADER") header = {i + 2, end};
      if (name == "ENTITIES") entities.emplace_back(i + 2, end);
      i = end + 1;
    }
    read_units(header);
    if (entities.empty()) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: the DXF has no ENTITIES section, so no outline: draw "
                                  "the tiles and save the drawing again as ASCII DXF",
                                  file_));
    }
    for (const auto& [begin, end] : entities) read_entities(begin, end);
    if (paper_space_ > 0) {
      warnings_.push_back(
          fmt::format("{}: {} entities in paper space (a layout sheet, not the "
                      "model) are not read",
                      file_, paper_space_));
    }
    std::vector<DrawnLoop> chained =
        outline_loops::chain_pieces(pieces_, file_, options_, warnings_);
    for (DrawnLoop& loop : chained) loops_.push_back(std::move(loop));
    std::stable_sort(loops_.begin(), loops_.end(), [](const DrawnLoop& a, const DrawnLoop& b) {
      return a.origin.line < b.origin.line;
    });
    return outline_loops::nest_loops(std::move(loops_), file_, options_, warnings_,
                                     "draw each tile as a closed polyline, a circle, or a closed "
                                     "chain of lines and arcs, and save as ASCII DXF");
  }

 private:
  [[noreturn]] void fail(long long line, const std::string& message,
                         ErrorCategory category = ErrorCategory::kFormat) const {
    throw UserError(category, fmt::format("{}: {}", outline_loops::where(file_, line), message));
  }

  void read_pairs(std::string_view text) {
    size_t position = 0;
    long long line = 0;
    const auto next_line = [&](std::string_view& out) {
      if (position >= text.size()) return false;
      size_t end = text.find('\n', position);
      if (end == std::string_view::npos) end = text.size();
      out = text.substr(position, end - position);
      if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
      position = end + 1;
      ++line;
      return true;
    };
    std::string_view code_text, value;
    while (next_line(code_text)) {
      const std::string_view code = trim(code_text);
      if (code.empty() && position >= text.size()) break;  // a last empty line
      long long number = -1;
      if (!parse_integer(code, number) || number < 0 || number > 1071) {
        if (line == 1) {
          fail(line, fmt::format("not an ASCII DXF file (the first line should be a group code "
                                 "such as 0, it is {}): save the drawing as ASCII DXF",
                                 quoted(code_text)));
        }
        fail(line, fmt::format("expected a group code (a whole number from 0 to 1071), found "
                               "{}: the file is damaged; save the drawing again as ASCII DXF",
                               quoted(code_text)));
      }
      if (!next_line(value)) {
        fail(line, fmt::format("the file ends after group code {} without its value: it is "
                               "truncated; save the drawing again as ASCII DXF",
                               number));
      }
      pairs_.push_back({static_cast<int>(number), value, line});
      if (number == 0 && trim(value) == "EOF") return;
    }
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: the file ends without the EOF that closes a DXF (after line "
                                "{}): it is truncated; save the drawing again as ASCII DXF",
                                file_, line));
  }

  double number(const Pair& p) const {
    std::string_view s = trim(p.value);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    double value = 0;
    const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || end != s.data() + s.size() || error == std::errc::invalid_argument) {
      fail(p.line, fmt::format("{} is not a number (group code {}): the file is damaged; save "
                               "the drawing again as ASCII DXF",
                               quoted(p.value), p.code));
    }
    if (error == std::errc::result_out_of_range || !std::isfinite(value)) {
      fail(p.line,
           fmt::format("{} (group code {}) is not a finite number a drawing can hold: fix the "
                       "coordinates in the drawing",
                       quoted(p.value), p.code),
           ErrorCategory::kGeometry);
    }
    return value;
  }

  long long integer(const Pair& p) const {
    long long value = 0;
    if (!parse_integer(p.value, value)) {
      fail(p.line, fmt::format("{} is not a whole number (group code {}): the file is damaged; "
                               "save the drawing again as ASCII DXF",
                               quoted(p.value), p.code));
    }
    return value;
  }

  void read_units(const std::optional<std::pair<size_t, size_t>>& header) {
    std::optional<Pair> units;
    if (header) {
      for (size_t i = header->first; i < header->second; ++i) {
        if (pairs_[i].code != 9 || trim(pairs_[i].value) != "$INSUNITS") continue;
        for (size_t j = i + 1; j < header->second && pairs_[j].code != 9; ++j) {
          if (pairs_[j].code == 70) units = pairs_[j];
        }
      }
    }
    const long long code = units ? integer(*units) : 0;
    if (code == 0) {
      warnings_.push_back(fmt::format("{}: the drawing has no units ({}): read as millimetres",
                                      file_, units ? "$INSUNITS 0" : "no $INSUNITS"));
      return;
    }
    if (const std::optional<double> mm = millimetres_per_unit(code)) {
      unit_ = *mm;
      return;
    }
    const std::string name = unit_name(code);
    if (name.empty()) {
      fail(units->line, fmt::format("$INSUNITS {} is not a DXF unit code: set the drawing units "
                                    "to millimetres and save again",
                                    code));
    }
    fail(units->line,
         fmt::format("the drawing's units are {} ($INSUNITS {}), which flatmorph does not read: "
                     "set the drawing units to millimetres (or centimetres, metres, inches or "
                     "feet) and save again",
                     name, code));
  }

  // Whether the object coordinate system of an entity with this extrusion direction is the
  // world's mirrored in x (direction (0, 0, -1)); refuses a tilted one.
  bool mirrored(const Point& xy, double z, const Pair& entity) const {
    const double norm = std::hypot(xy.x(), xy.y(), z);
    if (norm > 0 && std::abs(xy.x()) <= 1e-6 * norm && std::abs(xy.y()) <= 1e-6 * norm) {
      return z < 0;
    }
    fail(entity.line,
         fmt::format("the {} is drawn in a tilted plane (extrusion direction ({:g}, {:g}, {:g})): "
                     "only outlines in the XY plane are read; draw it in the top view and save "
                     "again",
                     trim(entity.value), xy.x(), xy.y(), z));
  }

  // Reads the extrusion direction (210, 220, 230) if `p` is one of its groups.
  bool extrusion_group(const Pair& p, Point& xy, double& z) const {
    if (p.code == 210)
      xy.x() = number(p);
    else if (p.code == 220)
      xy.y() = number(p);
    else if (p.code == 230)
      z = number(p);
    else
      return false;
    return true;
  }

  Point to_mm(double x, double y, const Pair& entity, const std::string& what) {
    const Point p(x * unit_, y * unit_);
    outline_loops::check_point(p, outline_loops::where(file_, entity.line), what);
    return p;
  }

  void mirror(std::vector<Point>& points) const {
    for (Point& p : points) p.x() = -p.x();
  }

  void read_entities(size_t begin, size_t end) {
    if (begin < end && pairs_[begin].code != 0) {
      fail(pairs_[begin].line,
           "the ENTITIES section does not start with an entity (group 0): "
           "the file is damaged; save the drawing again as ASCII DXF");
    }
    size_t i = begin;
    while (i < end) {
      const Pair& entity = pairs_[i];
      size_t next = i + 1;
      while (next < end && pairs_[next].code != 0) ++next;
      const std::string_view type = trim(entity.value);
      bool paper = false;
      for (size_t k = i + 1; k < next; ++k) {
        if (pairs_[k].code == 67) paper = integer(pairs_[k]) != 0;
      }
      if (type == "POLYLINE") {
        // Its VERTEX entities follow, up to a SEQEND.
        size_t seqend = next;
        while (seqend < end && trim(pairs_[seqend].value) == "VERTEX") {
          do ++seqend;
          while (seqend < end && pairs_[seqend].code != 0);
        }
        if (seqend == end || trim(pairs_[seqend].value) != "SEQEND") {
          fail(entity.line,
               "the POLYLINE has no SEQEND after its vertices: the file is damaged "
               "or truncated; save the drawing again as ASCII DXF");
        }
        if (paper) {
          ++paper_space_;
        } else {
          read_polyline(i, seqend);
        }
        next = seqend + 1;
        while (next < end && pairs_[next].code != 0) ++next;
      } else if (paper || type == "VIEWPORT") {
        // Paper space is a layout sheet; a viewport is a window onto the model, not a shape.
        if (paper && type != "VIEWPORT") ++paper_space_;
      } else if (type == "LWPOLYLINE") {
        read_lwpolyline(i, next);
      } else if (type == "CIRCLE" || type == "ARC") {
        read_circle_or_arc(i, next);
      } else if (type == "LINE") {
        read_line(i, next);
      } else if (type == "VERTEX" || type == "SEQEND") {
        fail(entity.line, fmt::format("a {} without a POLYLINE before it: the file is damaged; "
                                      "save the drawing again as ASCII DXF",
                                      type));
      } else {
        fail(entity.line,
             fmt::format("{} entities are not read: {}", printable(type), advice_for(type)));
      }
      i = next;
    }
  }

  // Closed polylines become loops; open ones pieces of a chain, unless their ends meet.
  void add_polyline(std::vector<Point> points, bool closed, const Origin& origin) {
    if (!closed && points.size() > 2 &&
        (points.back() - points.front()).norm() <= options_.join_tolerance) {
      points.pop_back();
      closed = true;
    }
    if (closed || points.empty()) {
      loops_.push_back({std::move(points), origin});
      return;
    }
    if (points.size() == 1) points.push_back(points.front());
    pieces_.push_back({std::move(points), origin});
  }

  // The points (mm, object coordinates) of a polyline through `vertices` whose bulges are arcs:
  // bulge = tan(sweep / 4), positive counter-clockwise, from each vertex to the next.
  std::vector<Point> polyline_points(const std::vector<Vertex>& vertices, bool closed,
                                     const Pair& entity) {
    const std::string at = outline_loops::where(file_, entity.line);
    const std::string type(trim(entity.value));
    outline_loops::take_points(budget_, static_cast<double>(vertices.size()), at);
    std::vector<Point> mm;
    for (size_t k = 0; k < vertices.size(); ++k) {
      mm.emplace_back(vertices[k].x * unit_, vertices[k].y * unit_);
      if (!outline_loops::acceptable(mm.back())) {
        outline_loops::check_point(mm.back(), at, fmt::format("vertex {} of the {}", k + 1, type));
      }
    }
    std::vector<Point> points;
    for (size_t k = 0; k < mm.size(); ++k) {
      points.push_back(mm[k]);
      if (k + 1 == mm.size() && !closed) break;
      const double bulge = vertices[k].bulge;
      const Point& p = mm[k];
      const Point& q = mm[(k + 1) % mm.size()];
      const double chord = (q - p).norm();
      // Height of the arc over its chord: bulge x chord / 2. A flatter arc is its chord.
      if (bulge == 0 || chord == 0 || std::abs(bulge) * chord / 2 <= options_.chord_tolerance) {
        continue;
      }
      const Point u = (q - p) / chord;
      const Point left(-u.y(), u.x());
      // Centre and radius from the chord and the bulge, written so that no term overflows for a
      // huge bulge: r = c (b + 1/b) / 4, the centre c (1/b - b) / 4 left of the chord's middle.
      const double radius = chord / 4 * (std::abs(bulge) + 1 / std::abs(bulge));
      const Point centre = (p + q) / 2 + left * (chord / 4 * (1 / bulge - bulge));
      outline_loops::EllipseArc arc;
      arc.centre = centre;
      arc.axes = radius * Eigen::Matrix2d::Identity();
      arc.start = std::atan2(p.y() - centre.y(), p.x() - centre.x());
      arc.sweep = 4 * std::atan(bulge);
      outline_loops::append_arc_interior(
          arc, options_, budget_, at,
          fmt::format("the arc of bulge {:g} after vertex {} of the {}", bulge, k + 1, type),
          points);
    }
    return points;
  }

  void read_lwpolyline(size_t begin, size_t end) {
    const Pair& entity = pairs_[begin];
    std::vector<Vertex> vertices;
    long long flags = 0;
    Point extrusion_xy(0, 0);
    double extrusion_z = 1;
    for (size_t k = begin + 1; k < end; ++k) {
      const Pair& p = pairs_[k];
      if (extrusion_group(p, extrusion_xy, extrusion_z)) continue;
      if (p.code == 70) flags = integer(p);
      if (p.code == 10) vertices.push_back({number(p), 0, 0, false});
      if (p.code == 20 || p.code == 42) {
        if (vertices.empty() || (p.code == 20 && vertices.back().has_y)) {
          fail(p.line, fmt::format("group {} of the LWPOLYLINE comes without a vertex x (group "
                                   "10) before it: the file is damaged; save the drawing again "
                                   "as ASCII DXF",
                                   p.code));
        }
        if (p.code == 20) {
          vertices.back().y = number(p);
          vertices.back().has_y = true;
        } else {
          vertices.back().bulge = number(p);
        }
      }
    }
    for (size_t k = 0; k < vertices.size(); ++k) {
      if (!vertices[k].has_y) {
        fail(entity.line, fmt::format("vertex {} of the LWPOLYLINE has no y (group 20): the file "
                                      "is damaged; save the drawing again as ASCII DXF",
                                      k + 1));
      }
    }
    const bool flip = mirrored(extrusion_xy, extrusion_z, entity);
    const bool closed = (flags & 1) != 0;
    std::vector<Point> points = polyline_points(vertices, closed, entity);
    if (flip) mirror(points);
    add_polyline(std::move(points), closed, {"LWPOLYLINE", entity.line});
  }

  // A POLYLINE entity at `begin`, its VERTEX entities up to the SEQEND at `seqend`.
  void read_polyline(size_t begin, size_t seqend) {
    const Pair& entity = pairs_[begin];
    long long flags = 0;
    Point extrusion_xy(0, 0);
    double extrusion_z = 1;
    size_t k = begin + 1;
    for (; k < seqend && pairs_[k].code != 0; ++k) {
      if (extrusion_group(pairs_[k], extrusion_xy, extrusion_z)) continue;
      if (pairs_[k].code == 70) flags = integer(pairs_[k]);
    }
    if ((flags & (16 | 64)) != 0) {
      fail(entity.line,
           fmt::format("the POLYLINE is a {} (flag {}), not an outline: draw the outline as a 2D "
                       "polyline and save again",
                       (flags & 16) != 0 ? "3D polygon mesh" : "polyface mesh", flags));
    }
    // A 3D polyline (flag 8) has world coordinates; a 2D one those of its extrusion direction.
    const bool flip = (flags & 8) == 0 && mirrored(extrusion_xy, extrusion_z, entity);
    std::vector<Vertex> vertices;
    while (k < seqend) {
      const long long line = pairs_[k].line;
      Vertex v;
      bool has_x = false;
      long long vertex_flags = 0;
      for (++k; k < seqend && pairs_[k].code != 0; ++k) {
        const Pair& p = pairs_[k];
        if (p.code == 10) {
          v.x = number(p);
          has_x = true;
        }
        if (p.code == 20) {
          v.y = number(p);
          v.has_y = true;
        }
        if (p.code == 42 && (flags & 8) == 0) v.bulge = number(p);
        if (p.code == 70) vertex_flags = integer(p);
      }
      if (!has_x || !v.has_y) {
        fail(line,
             "a VERTEX without its x and y (groups 10 and 20): the file is damaged; save "
             "the drawing again as ASCII DXF");
      }
      // The control points of a spline-fit polyline frame the curve; its fitted vertices are it.
      if ((vertex_flags & 16) == 0) vertices.push_back(v);
    }
    const bool closed = (flags & 1) != 0;
    std::vector<Point> points = polyline_points(vertices, closed, entity);
    if (flip) mirror(points);
    add_polyline(std::move(points), closed, {"POLYLINE", entity.line});
  }

  void read_circle_or_arc(size_t begin, size_t end) {
    const Pair& entity = pairs_[begin];
    const bool is_arc = trim(entity.value) == "ARC";
    const std::string type = is_arc ? "ARC" : "CIRCLE";
    double x = 0, y = 0, radius = 0, start = 0, stop = 0;
    bool has_radius = false;
    Point extrusion_xy(0, 0);
    double extrusion_z = 1;
    for (size_t k = begin + 1; k < end; ++k) {
      const Pair& p = pairs_[k];
      if (extrusion_group(p, extrusion_xy, extrusion_z)) continue;
      if (p.code == 10) x = number(p);
      if (p.code == 20) y = number(p);
      if (p.code == 40) {
        radius = number(p);
        has_radius = true;
      }
      if (p.code == 50) start = number(p);
      if (p.code == 51) stop = number(p);
    }
    const bool flip = mirrored(extrusion_xy, extrusion_z, entity);
    const std::string at = outline_loops::where(file_, entity.line);
    const Point centre = to_mm(x, y, entity, fmt::format("the centre of the {}", type));
    if (!has_radius || !(radius > 0)) {
      fail(entity.line,
           fmt::format("the {} at ({:g}, {:g}) has {} radius {:g}: give it a positive radius or "
                       "delete it, and save again",
                       type, x, y, has_radius ? "the" : "no", radius),
           ErrorCategory::kGeometry);
    }
    outline_loops::EllipseArc arc;
    arc.centre = centre;
    arc.axes = radius * unit_ * Eigen::Matrix2d::Identity();
    arc.start = is_arc ? start * kPi / 180 : 0;
    // DXF arcs run counter-clockwise from the start angle to the end angle (degrees).
    double sweep = is_arc ? std::fmod(stop - start, 360.0) : 360;
    if (sweep < 0) sweep += 360;
    if (sweep == 0) {
      fail(entity.line,
           fmt::format("the ARC at ({:g}, {:g}) has zero sweep (it starts and ends at {:g} "
                       "degrees): draw a CIRCLE for a full circle, or delete it, and save again",
                       x, y, start),
           ErrorCategory::kGeometry);
    }
    arc.sweep = sweep * kPi / 180;
    const auto on_circle = [&](double t) {
      return Point(arc.centre + arc.axes * Point(std::cos(t), std::sin(t)));
    };
    std::vector<Point> points{on_circle(arc.start)};
    outline_loops::check_point(points.front(), at, fmt::format("the start of the {}", type));
    outline_loops::take_points(budget_, 1, at);
    outline_loops::append_arc_interior(arc, options_, budget_, at, fmt::format("the {}", type),
                                       points);
    if (is_arc) {
      outline_loops::take_points(budget_, 1, at);
      points.push_back(on_circle(stop * kPi / 180));
      outline_loops::check_point(points.back(), at, "the end of the ARC");
    }
    if (flip) mirror(points);
    if (is_arc) {
      pieces_.push_back({std::move(points), {type, entity.line}});
    } else {
      loops_.push_back({std::move(points), {type, entity.line}});
    }
  }

  // LINE endpoints are world coordinates whatever the extrusion (it only sets the thickness).
  void read_line(size_t begin, size_t end) {
    const Pair& entity = pairs_[begin];
    double v[4] = {0, 0, 0, 0};
    for (size_t k = begin + 1; k < end; ++k) {
      const Pair& p = pairs_[k];
      if (p.code == 10) v[0] = number(p);
      if (p.code == 20) v[1] = number(p);
      if (p.code == 11) v[2] = number(p);
      if (p.code == 21) v[3] = number(p);
    }
    outline_loops::take_points(budget_, 2, outline_loops::where(file_, entity.line));
    pieces_.push_back({{to_mm(v[0], v[1], entity, "the start of the LINE"),
                        to_mm(v[2], v[3], entity, "the end of the LINE")},
                       {"LINE", entity.line}});
  }

  const std::string& file_;
  const OutlineReadOptions& options_;
  std::vector<std::string>& warnings_;
  outline_loops::PointBudget budget_;
  double unit_ = 1;  // mm per drawing unit
  std::vector<Pair> pairs_;
  std::vector<DrawnLoop> loops_;
  std::vector<OpenPiece> pieces_;
  long long paper_space_ = 0;
};

}  // namespace

std::vector<TileOutline> read_dxf_outlines(std::string_view text, const std::string& source,
                                           const OutlineReadOptions& options,
                                           std::vector<std::string>* warnings) {
  outline_loops::check_options(options);
  outline_loops::check_size(text.size(), options, source);
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: empty file: export the outlines as ASCII DXF", source));
  }
  if (text.substr(0, 18) == "AutoCAD Binary DXF") {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: a binary DXF, which flatmorph does not read: save the drawing "
                                "as ASCII DXF (the DXF format choice in the save dialog)",
                                source));
  }
  std::vector<std::string> found;
  Reader reader(source, options, found);
  std::vector<TileOutline> tiles = reader.read(text);
  if (warnings != nullptr) warnings->insert(warnings->end(), found.begin(), found.end());
  return tiles;
}

}  // namespace flatmorph
