#include "methods/origami/crease_pattern_svg.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <queue>
#include <tuple>

#include "common/angles.h"
#include "common/error.h"
#include "common/svg_drawing.h"
#include "mesh/plane_geometry.h"
#include "mesh/polygon.h"

namespace flatmorph {
namespace {

using svg::Element;
using svg::Point;

constexpr double kMaxCoordinate = 1e6;  // mm, as the tile outlines

std::string format_point(const Point& p) {
  return fmt::format("({:.4f}, {:.4f}) mm", p.x(), p.y());
}

int component_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// --- The drawing: lines with their kinds ---------------------------------------------------------

// One drawn element and what its stroke says.
struct DrawnLine {
  std::string what;  // "<line id=\"m1\">"
  long long line = 0;
  CreaseKind kind = CreaseKind::kBorder;  // kBorder: the outline
  double fold_angle = 0;                  // rad, FOLD's sign
  std::string colour;                     // "red (mountain)", for messages
};

struct Segment {
  Point a, b;  // mm, plate coordinates
  int line = 0;
};

std::optional<std::array<int, 3>> parse_colour(std::string_view text) {
  std::string s;
  for (char c : text) {
    if (c != ' ') s += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  // Origami Simulator's own names; its "green" is the cut colour #00ff00, not CSS green.
  static const std::pair<std::string_view, std::array<int, 3>> kNames[] = {
      {"black", {0, 0, 0}},       {"red", {255, 0, 0}},      {"blue", {0, 0, 255}},
      {"lime", {0, 255, 0}},      {"green", {0, 255, 0}},    {"yellow", {255, 255, 0}},
      {"magenta", {255, 0, 255}}, {"fuchsia", {255, 0, 255}}};
  for (const auto& [name, rgb] : kNames) {
    if (s == name) return rgb;
  }
  const auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
  };
  if (!s.empty() && s[0] == '#' && (s.size() == 4 || s.size() == 7)) {
    const bool short_form = s.size() == 4;
    std::array<int, 3> rgb{};
    for (int k = 0; k < 3; ++k) {
      const int hi = hex(s[short_form ? 1 + k : 1 + 2 * k]);
      const int lo = hex(s[short_form ? 1 + k : 2 + 2 * k]);
      if (hi < 0 || lo < 0) return std::nullopt;
      rgb[k] = hi * 16 + lo;
    }
    return rgb;
  }
  if (s.substr(0, 4) == "rgb(" && s.back() == ')') {
    std::array<int, 3> rgb{};
    std::string_view rest = std::string_view(s).substr(4, s.size() - 5);
    for (int k = 0; k < 3; ++k) {
      const size_t comma = std::min(rest.find(','), rest.size());
      std::string_view item = rest.substr(0, comma);
      rest.remove_prefix(std::min(comma + 1, rest.size()));
      const bool percent = !item.empty() && item.back() == '%';
      if (percent) item.remove_suffix(1);
      const std::optional<double> v = svg::number(item);
      if (!v) return std::nullopt;
      rgb[k] = static_cast<int>(std::lround(std::clamp(percent ? *v * 2.55 : *v, 0.0, 255.0)));
    }
    if (!rest.empty()) return std::nullopt;
    return rgb;
  }
  return std::nullopt;
}

// Reads each drawing element into lines and straight segments.
class PatternDrawing {
 public:
  PatternDrawing(const std::string& file, const CreasePatternReadOptions& options)
      : file_(file), options_(options) {}

  std::vector<DrawnLine> lines;
  std::vector<Segment> segments;
  long long unstroked = 0;

  void read(const svg::Shape& shape) {
    const Element& element = shape.element;
    const std::string_view name = shape.name;
    if (name == "use") {
      fail(element,
           "<use> elements (clones) are not read: unlink the clone (Inkscape: Edit > Clone > "
           "Unlink Clone) or draw the line itself, and save again");
    }
    const std::optional<std::string> stroke = svg::property(shape, "stroke", true);
    if (!stroke || *stroke == "none") {
      ++unstroked;
      return;
    }
    const bool straight = name == "line" || name == "polyline" || name == "polygon" ||
                          name == "rect" || name == "path";
    if (!straight) {
      fail(element, fmt::format("<{}> elements are not read: a crease pattern is straight lines "
                                "(line, polyline, polygon, rect, path); draw it as straight "
                                "segments or delete it, and save again",
                                printable(element.name)));
    }
    lines.push_back(style(shape, *stroke));
    const int index = static_cast<int>(lines.size()) - 1;
    const svg::Affine& map = shape.map;
    if (name == "line") {
      const auto at = [&](const char* x, const char* y) {
        return map(Point(length(element, x).value_or(0), length(element, y).value_or(0)));
      };
      add(at("x1", "y1"), at("x2", "y2"), index, element);
    } else if (name == "polyline" || name == "polygon") {
      std::optional<Point> first, last;
      int count = 0;
      svg::read_points(element, file_, [&](const Point& p) {
        const Point at = map(p);
        if (last) add(*last, at, index, element);
        if (!first) first = at;
        last = at;
        ++count;
      });
      if (name == "polygon" && count > 2) add(*last, *first, index, element);
    } else if (name == "rect") {
      read_rect(element, map, index);
    } else {
      Point start, current;
      svg::PathCallbacks callbacks;
      callbacks.begin = [&](const Point& p, int) { start = current = p; };
      callbacks.line_to = [&](const Point& to) {
        add(map(current), map(to), index, element);
        current = to;
      };
      callbacks.arc_to = [&](const Point&, const Point&, const svg::ArcCommand&) {
        fail(element, fmt::format("the {} has an arc (A command): a crease pattern is straight "
                                  "lines; draw it as straight segments, and save again",
                                  describe(element)));
      };
      callbacks.end = [&](bool closed) {
        if (closed) add(map(current), map(start), index, element);
      };
      svg::read_path(element, file_, callbacks);
    }
  }

 private:
  [[noreturn]] void fail(const Element& element, const std::string& message,
                         ErrorCategory category = ErrorCategory::kFormat) const {
    svg::fail(file_, element, message, category);
  }

  std::string describe(const Element& element) const { return svg::describe(element); }

  std::optional<double> length(const Element& element, std::string_view key) const {
    return svg::length(element, key, file_);
  }

  // The line's kind and angle from its stroke colour, opacity and data-fold-angle.
  DrawnLine style(const svg::Shape& shape, const std::string& stroke) const {
    const Element& element = shape.element;
    DrawnLine line;
    line.what = describe(element);
    line.line = element.line;
    const std::optional<std::array<int, 3>> rgb = parse_colour(stroke);
    const auto is = [&](int r, int g, int b) { return rgb && *rgb == std::array<int, 3>{r, g, b}; };
    double sign = 0;
    if (is(0, 0, 0) || is(0, 255, 0)) {
      line.colour = is(0, 0, 0) ? "black (outline)" : "green (cut)";
    } else if (is(255, 0, 0)) {
      line.colour = "red (mountain)";
      line.kind = CreaseKind::kMountain;
      sign = -1;
    } else if (is(0, 0, 255)) {
      line.colour = "blue (valley)";
      line.kind = CreaseKind::kValley;
      sign = 1;
    } else if (is(255, 255, 0)) {
      line.colour = "yellow (flat)";
      line.kind = CreaseKind::kFlat;
    } else if (is(255, 0, 255)) {
      fail(element, fmt::format("the {} is magenta, Origami Simulator's undriven hinge, which has "
                                "no fold angle: each hinge is printed to fold by its angle; make "
                                "it red (mountain) or blue (valley) with opacity = |angle| / "
                                "180°, or give it data-fold-angle, and save again",
                                line.what));
    } else {
      fail(element, fmt::format("the {} has stroke \"{}\", which is no crease colour: use "
                                "Origami Simulator's black #000000 (outline), red #ff0000 "
                                "(mountain), blue #0000ff (valley), yellow #ffff00 (flat) or "
                                "green #00ff00 (cut), and save again",
                                line.what, printable(stroke)));
    }
    const std::string* given = element.find("data-fold-angle");
    if (given != nullptr) {
      const std::optional<double> degrees = svg::number(*given);
      if (!degrees || std::abs(*degrees) > 180) {
        fail(element, fmt::format("data-fold-angle=\"{}\" of the {} is not an angle in degrees "
                                  "from -180 to 180: fix it, and save again",
                                  printable(*given), line.what));
      }
      const bool agrees = line.kind == CreaseKind::kMountain ? *degrees <= 0
                          : line.kind == CreaseKind::kValley ? *degrees >= 0
                                                             : *degrees == 0;
      if (!agrees) {
        fail(element,
             fmt::format("the {} is {} but its data-fold-angle is {:g}°: a valley folds by a "
                         "positive angle, a mountain by a negative one, the outline and flat "
                         "creases by 0; fix the colour or the angle, and save again",
                         line.what, line.colour, *degrees));
      }
      line.fold_angle = *degrees * kPi / 180;
    } else if (sign != 0) {
      // Origami Simulator's getOpacity: the element's opacity first, then its stroke-opacity.
      std::optional<std::string> opacity = svg::property(shape, "opacity", false);
      if (!opacity) opacity = svg::property(shape, "stroke-opacity", true);
      double value = 1;
      if (opacity) {
        std::string_view text = *opacity;
        const bool percent = !text.empty() && text.back() == '%';
        if (percent) text.remove_suffix(1);
        const std::optional<double> v = svg::number(text);
        if (v) value = percent ? *v / 100 : *v;
        if (!v || value < 0 || value > 1) {
          fail(element, fmt::format("the {}'s opacity \"{}\" is not a number from 0 to 1 (the "
                                    "fold angle / 180°): fix it, and save again",
                                    line.what, printable(*opacity)));
        }
      }
      line.fold_angle = sign * value * kPi;
    }
    if (line.kind != CreaseKind::kBorder && std::abs(line.fold_angle) < options_.flat_angle) {
      line.kind = CreaseKind::kFlat;
      line.fold_angle = 0;
    }
    return line;
  }

  void read_rect(const Element& element, const svg::Affine& map, int index) {
    const double x = length(element, "x").value_or(0), y = length(element, "y").value_or(0);
    const std::optional<double> w = length(element, "width"), h = length(element, "height");
    if (!w || !h || !(*w > 0) || !(*h > 0)) {
      fail(element,
           fmt::format("the {} needs a positive width and height: fix it or delete it, and save "
                       "again",
                       describe(element)),
           ErrorCategory::kGeometry);
    }
    if (length(element, "rx").value_or(0) > 0 || length(element, "ry").value_or(0) > 0) {
      fail(element, fmt::format("the {} has rounded corners: a crease pattern is straight lines; "
                                "give it square corners, and save again",
                                describe(element)));
    }
    const Point corners[4] = {map(Point(x, y)), map(Point(x + *w, y)), map(Point(x + *w, y + *h)),
                              map(Point(x, y + *h))};
    for (int k = 0; k < 4; ++k) add(corners[k], corners[(k + 1) % 4], index, element);
  }

  void add(const Point& a, const Point& b, int index, const Element& element) {
    for (const Point& p : {a, b}) {
      if (!(std::abs(p.x()) <= kMaxCoordinate && std::abs(p.y()) <= kMaxCoordinate)) {
        fail(element,
             fmt::format("a point of the {} lies at ({:g}, {:g}) mm, more than 1e+06 mm (1 km) "
                         "from the origin: check the drawing's units and coordinates",
                         describe(element), p.x(), p.y()),
             ErrorCategory::kGeometry);
      }
    }
    if (a == b) return;
    if (segments.size() >= options_.max_segments) {
      fail(element,
           fmt::format("the drawing has more than {} straight segments: simplify it",
                       options_.max_segments),
           ErrorCategory::kResource);
    }
    segments.push_back({a, b, index});
  }

  const std::string& file_;
  const CreasePatternReadOptions& options_;
};

// --- The arrangement: vertices, edges, faces -----------------------------------------------------

// Points within `tolerance` of an earlier one are that one (the earliest, so the result follows
// the drawing's order). More than `max` points (lines crossing each other everywhere) are refused.
class Welder {
 public:
  Welder(double tolerance, size_t max, const std::string& file)
      : tolerance_(tolerance), max_(max), file_(file) {}

  std::vector<Point> points;

  int vertex(const Point& p) {
    const long long cx = cell(p.x()), cy = cell(p.y());
    int found = -1;
    for (long long dx = -1; dx <= 1; ++dx) {
      for (long long dy = -1; dy <= 1; ++dy) {
        const auto it = cells_.find({cx + dx, cy + dy});
        if (it == cells_.end()) continue;
        for (int v : it->second) {
          if ((points[v] - p).norm() <= tolerance_ && (found < 0 || v < found)) found = v;
        }
      }
    }
    if (found >= 0) return found;
    if (points.size() >= max_) {
      throw UserError(ErrorCategory::kResource,
                      fmt::format("{}: the lines cross each other in more than {} points: "
                                  "simplify the drawing",
                                  file_, max_));
    }
    points.push_back(p);
    cells_[{cx, cy}].push_back(static_cast<int>(points.size()) - 1);
    return static_cast<int>(points.size()) - 1;
  }

 private:
  long long cell(double x) const { return static_cast<long long>(std::floor(x / tolerance_)); }

  double tolerance_;
  size_t max_;
  const std::string& file_;
  std::map<std::pair<long long, long long>, std::vector<int>> cells_;
};

struct Edge {
  int u = 0, v = 0;        // vertices, u < v
  std::vector<int> lines;  // the drawn lines along it, in drawing order
  bool alive = true;       // false: a dangling piece, pruned
};

struct Arrangement {
  std::vector<Point> points;
  std::vector<Edge> edges;
};

// The drawn segments cut where they cross or where one ends on another, welded within
// `tolerance`.
Arrangement arrange(const std::vector<Segment>& segments, double tolerance, size_t max_segments,
                    const std::string& file) {
  const size_t max_points = 25 * max_segments + 16;
  Welder welder(tolerance, max_points, file);
  struct Piece {
    int a, b, line;
    std::vector<int> on;  // vertices along it, its ends excepted
  };
  std::vector<Piece> pieces;
  for (const Segment& s : segments) {
    const int a = welder.vertex(s.a), b = welder.vertex(s.b);
    if (a != b) pieces.push_back({a, b, s.line, {}});
  }
  const auto& P = welder.points;
  std::vector<int> order(pieces.size());
  std::iota(order.begin(), order.end(), 0);
  const auto min_x = [&](int i) { return std::min(P[pieces[i].a].x(), P[pieces[i].b].x()); };
  const auto max_x = [&](int i) { return std::max(P[pieces[i].a].x(), P[pieces[i].b].x()); };
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return min_x(i) < min_x(j); });
  // A line's end that stops within the tolerance of another line moves onto it (the first such
  // line in the sweep), so that the line it meets stays straight.
  std::map<int, std::pair<int, int>> t_junctions;
  // Vertices made at crossings are appended to P while this runs: copy what is compared.
  for (size_t oi = 0; oi < order.size(); ++oi) {
    const int i = order[oi];
    for (size_t oj = oi + 1; oj < order.size() && min_x(order[oj]) <= max_x(i) + tolerance; ++oj) {
      const int j = order[oj];
      const Point pa = P[pieces[i].a], pb = P[pieces[i].b];
      const Point qa = P[pieces[j].a], qb = P[pieces[j].b];
      if (std::max(pa.y(), pb.y()) + tolerance < std::min(qa.y(), qb.y()) ||
          std::max(qa.y(), qb.y()) + tolerance < std::min(pa.y(), pb.y())) {
        continue;
      }
      // A line ending on another (T-junction), or lying along it.
      bool touch = false;
      for (const auto& [self, other] : {std::pair{i, j}, std::pair{j, i}}) {
        const Piece& s = pieces[self];
        for (int v : {pieces[other].a, pieces[other].b}) {
          if (v == s.a || v == s.b) {
            touch = true;
            continue;
          }
          if (segment_distance(P[v], P[s.a], P[s.b]) <= tolerance) {
            pieces[self].on.push_back(v);
            t_junctions.try_emplace(v, s.a, s.b);
            touch = true;
          }
        }
      }
      if (touch) continue;
      const Point r = pb - pa, s = qb - qa;
      const double d = cross2(r, s);
      if (d == 0) continue;  // parallel and apart
      const double t = cross2(qa - pa, s) / d, u = cross2(qa - pa, r) / d;
      if (t > 0 && t < 1 && u > 0 && u < 1) {
        const int v = welder.vertex(pa + t * r);
        for (int k : {i, j}) {
          if (v != pieces[k].a && v != pieces[k].b) pieces[k].on.push_back(v);
        }
      }
    }
  }
  for (const auto& [v, line] : t_junctions) {
    const Point a = welder.points[line.first], ab = welder.points[line.second] - a;
    welder.points[v] = a + (welder.points[v] - a).dot(ab) / ab.squaredNorm() * ab;
  }
  // Ends moved onto a line may have come within the tolerance of each other: one point again.
  Welder again(tolerance, max_points, file);
  std::vector<int> final_vertex(P.size());
  for (size_t v = 0; v < P.size(); ++v) final_vertex[v] = again.vertex(P[v]);
  Arrangement out;
  std::map<std::pair<int, int>, int> edge_of;
  for (Piece& piece : pieces) {
    const Point a = P[piece.a], direction = P[piece.b] - a;
    std::vector<int>& on = piece.on;
    std::sort(on.begin(), on.end(), [&](int x, int y) {
      return std::make_tuple((P[x] - a).dot(direction), x) <
             std::make_tuple((P[y] - a).dot(direction), y);
    });
    on.erase(std::unique(on.begin(), on.end()), on.end());
    on.insert(on.begin(), piece.a);
    on.push_back(piece.b);
    for (size_t k = 0; k + 1 < on.size(); ++k) {
      const int a = final_vertex[on[k]], b = final_vertex[on[k + 1]];
      const int u = std::min(a, b), v = std::max(a, b);
      if (u == v) continue;
      const auto [it, added] = edge_of.try_emplace({u, v}, static_cast<int>(out.edges.size()));
      if (added) out.edges.push_back({u, v, {}, true});
      std::vector<int>& lines = out.edges[it->second].lines;
      if (std::find(lines.begin(), lines.end(), piece.line) == lines.end()) {
        lines.push_back(piece.line);
      }
    }
  }
  out.points = again.points;
  return out;
}

// The closed walks around the regions the living edges bound: half-edge 2e runs u → v along edge
// e, 2e + 1 back; each walk keeps its region on the left.
struct Walks {
  std::vector<int> walk_of;             // per half-edge
  std::vector<std::vector<int>> walks;  // half-edges in order
  std::vector<double> area;             // mm², > 0: a bounded region (a face); else an outer walk
};

Walks walk(const Arrangement& arrangement) {
  const auto& P = arrangement.points;
  const auto& E = arrangement.edges;
  const auto origin = [&](int h) { return h % 2 == 0 ? E[h / 2].u : E[h / 2].v; };
  std::vector<std::vector<int>> out(P.size());
  for (size_t e = 0; e < E.size(); ++e) {
    if (!E[e].alive) continue;
    out[E[e].u].push_back(static_cast<int>(2 * e));
    out[E[e].v].push_back(static_cast<int>(2 * e + 1));
  }
  std::vector<int> slot(2 * E.size(), -1);
  for (std::vector<int>& around : out) {
    std::vector<double> angle;
    for (int h : around) {
      const Point d = P[origin(h ^ 1)] - P[origin(h)];
      angle.push_back(std::atan2(d.y(), d.x()));
    }
    std::vector<size_t> by_angle(around.size());
    std::iota(by_angle.begin(), by_angle.end(), 0);
    std::sort(by_angle.begin(), by_angle.end(), [&](size_t a, size_t b) {
      return std::make_pair(angle[a], around[a]) < std::make_pair(angle[b], around[b]);
    });
    std::vector<int> sorted;
    for (size_t k : by_angle) sorted.push_back(around[k]);
    around = sorted;
    for (size_t k = 0; k < around.size(); ++k) slot[around[k]] = static_cast<int>(k);
  }
  // Arriving along h at its end, the walk leaves by the half-edge just clockwise of the way back.
  const auto next = [&](int h) {
    const std::vector<int>& around = out[origin(h ^ 1)];
    const int n = static_cast<int>(around.size());
    return around[(slot[h ^ 1] + n - 1) % n];
  };
  Walks w;
  w.walk_of.assign(2 * E.size(), -1);
  for (int h = 0; h < static_cast<int>(2 * E.size()); ++h) {
    if (!E[h / 2].alive || w.walk_of[h] >= 0) continue;
    const int id = static_cast<int>(w.walks.size());
    std::vector<int> halves;
    std::vector<Point> loop;
    for (int g = h; w.walk_of[g] < 0; g = next(g)) {
      w.walk_of[g] = id;
      halves.push_back(g);
      loop.push_back(P[origin(g)]);
    }
    w.walks.push_back(std::move(halves));
    w.area.push_back(signed_area(loop));
  }
  return w;
}

// --- The pattern ---------------------------------------------------------------------------------

class PatternBuilder {
 public:
  PatternBuilder(const std::string& file, const CreasePatternReadOptions& options,
                 const std::vector<DrawnLine>& lines, Arrangement arrangement,
                 std::vector<std::string>& warnings)
      : file_(file),
        options_(options),
        lines_(lines),
        a_(std::move(arrangement)),
        warnings_(warnings) {}

  CreasePattern build() {
    resolve_kinds();
    const std::vector<int> dangling = prune();
    walks_ = walk(a_);
    for (size_t w = 0; w < walks_.walks.size(); ++w) {
      std::vector<Point> points;
      for (int h : walks_.walks[w]) points.push_back(a_.points[origin(h)]);
      Bounds bounds{points[0], points[0]};
      for (const Point& p : points) {
        bounds.lo = bounds.lo.cwiseMin(p);
        bounds.hi = bounds.hi.cwiseMax(p);
      }
      loops_.push_back(std::move(points));
      bounds_.push_back(bounds);
    }
    check_pieces();
    check_dangling(dangling);
    return pattern();
  }

 private:
  [[noreturn]] void fail(int line, const std::string& message,
                         ErrorCategory category = ErrorCategory::kTopology) const {
    throw UserError(category, fmt::format("{}:{}: {}", file_, lines_[line].line, message));
  }

  std::string name(int line) const {
    return fmt::format("{} {}", lines_[line].colour, lines_[line].what);
  }

  Point middle(const Edge& e) const { return (a_.points[e.u] + a_.points[e.v]) / 2; }

  int origin(int h) const { return h % 2 == 0 ? a_.edges[h / 2].u : a_.edges[h / 2].v; }

  bool is_face(int walk) const { return walks_.area[walk] > 0; }

  // Whether `p` lies inside the bounded region walk `walk` goes around.
  bool in_face(int walk, const Point& p) const {
    const Bounds& b = bounds_[walk];
    return is_face(walk) && (p.array() >= b.lo.array()).all() &&
           (p.array() <= b.hi.array()).all() && point_in_polygon(loops_[walk], p);
  }

  // Lines drawn over each other must say the same.
  void resolve_kinds() {
    for (const Edge& e : a_.edges) {
      const DrawnLine& first = lines_[e.lines[0]];
      for (size_t k = 1; k < e.lines.size(); ++k) {
        const DrawnLine& other = lines_[e.lines[k]];
        if (other.kind != first.kind || std::abs(other.fold_angle - first.fold_angle) > 1e-9) {
          fail(e.lines[k],
               fmt::format("the {} lies on the {} at line {} around {}, and they say different "
                           "things ({:g}° and {:g}°): a side is one crease or the outline; "
                           "delete one of them, and save again",
                           name(e.lines[k]), name(e.lines[0]), first.line, format_point(middle(e)),
                           other.fold_angle * 180 / kPi, first.fold_angle * 180 / kPi));
        }
      }
    }
  }

  // Pieces of lines with a free end (repeatedly: a free end's edge off, its other end may be
  // free next). Returns them.
  std::vector<int> prune() {
    std::vector<int> degree(a_.points.size(), 0);
    std::vector<std::vector<int>> edges_at(a_.points.size());
    for (size_t e = 0; e < a_.edges.size(); ++e) {
      for (int v : {a_.edges[e].u, a_.edges[e].v}) {
        ++degree[v];
        edges_at[v].push_back(static_cast<int>(e));
      }
    }
    std::vector<int> free_ends, dangling;
    for (size_t v = 0; v < degree.size(); ++v) {
      if (degree[v] == 1) free_ends.push_back(static_cast<int>(v));
    }
    while (!free_ends.empty()) {
      const int v = free_ends.back();
      free_ends.pop_back();
      for (int e : edges_at[v]) {
        Edge& edge = a_.edges[e];
        if (!edge.alive) continue;
        edge.alive = false;
        dangling.push_back(e);
        for (int w : {edge.u, edge.v}) {
          if (--degree[w] == 1) free_ends.push_back(w);
        }
      }
    }
    std::sort(dangling.begin(), dangling.end());
    return dangling;
  }

  // One connected sheet without holes, every face a simple polygon.
  void check_pieces() {
    int faces = 0;
    for (size_t w = 0; w < walks_.walks.size(); ++w) faces += is_face(static_cast<int>(w));
    if (faces == 0) {
      throw UserError(ErrorCategory::kTopology,
                      fmt::format("{}: no closed outline: draw the sheet's outline as a closed "
                                  "black path, polygon or rectangle (or black lines that meet), "
                                  "its folds red (mountain) and blue (valley) from side to side, "
                                  "and save again",
                                  file_));
    }
    // Outer boundaries: one per connected part of the drawing.
    std::vector<int> outer;
    for (size_t w = 0; w < walks_.walks.size(); ++w) {
      if (!is_face(static_cast<int>(w))) outer.push_back(static_cast<int>(w));
    }
    if (outer.size() > 1) {
      std::vector<int> part(a_.points.size());
      std::iota(part.begin(), part.end(), 0);
      for (const Edge& e : a_.edges) {
        if (e.alive) part[component_root(part, e.u)] = component_root(part, e.v);
      }
      const auto part_of = [&](int walk) {
        return component_root(part, origin(walks_.walks[walk][0]));
      };
      for (int o : outer) {
        const int h = walks_.walks[o][0];
        const Point p = a_.points[origin(h)];
        for (size_t f = 0; f < walks_.walks.size(); ++f) {
          const int face = static_cast<int>(f);
          if (part_of(face) != part_of(o) && in_face(face, p)) {
            fail(a_.edges[h / 2].lines[0],
                 fmt::format("the {} lies inside a face (around {}) without meeting its sides: "
                             "a face cannot have a hole or an island; extend its lines to the "
                             "face's sides so that they cut the face, or delete it, and save "
                             "again",
                             name(a_.edges[h / 2].lines[0]), format_point(p)));
          }
        }
      }
      const int second = a_.edges[walks_.walks[outer[1]][0] / 2].lines[0];
      fail(second,
           fmt::format("the {} belongs to a second sheet, apart from the one drawn at "
                       "line {} ({} sheets in all): flatmorph folds one sheet per file; "
                       "put each sheet in its own file, and save again",
                       name(second), lines_[a_.edges[walks_.walks[outer[0]][0] / 2].lines[0]].line,
                       outer.size()));
    }
    for (size_t e = 0; e < a_.edges.size(); ++e) {
      const Edge& edge = a_.edges[e];
      if (!edge.alive) continue;
      const int left = walks_.walk_of[2 * e], right = walks_.walk_of[2 * e + 1];
      if (left != right) continue;
      fail(edge.lines[0],
           is_face(left)
               ? fmt::format("the {} runs inside a face around {} without cutting it in two: a "
                             "fold or a cut runs from side to side of its face; extend it, or "
                             "delete it, and save again",
                             name(edge.lines[0]), format_point(middle(edge)))
               : fmt::format("the {} joins parts of the sheet outside it around {}: the sheet "
                             "would be in pieces; flatmorph folds one sheet per file; delete it, "
                             "and save again",
                             name(edge.lines[0]), format_point(middle(edge))));
    }
  }

  // A free end inside the sheet is a fold that stops short; outside, an overshoot.
  void check_dangling(const std::vector<int>& dangling) {
    std::vector<bool> warned(lines_.size(), false);
    for (int e : dangling) {
      const Edge& edge = a_.edges[e];
      const Point m = middle(edge);
      for (size_t f = 0; f < walks_.walks.size(); ++f) {
        if (in_face(static_cast<int>(f), m)) {
          fail(edge.lines[0],
               fmt::format("the {} ends inside a face around {}, short of the outline or another "
                           "crease: a fold runs from side to side of its face; extend it to meet "
                           "a line (within {:g} mm), or delete it, and save again",
                           name(edge.lines[0]), format_point(m), options_.snap_tolerance));
        }
      }
      for (int line : edge.lines) {
        if (warned[line]) continue;
        warned[line] = true;
        warnings_.push_back(
            fmt::format("{}:{}: a piece of the {} outside the sheet (around {}) "
                        "is not read",
                        file_, lines_[line].line, name(line), format_point(m)));
      }
    }
  }

  CreasePattern pattern() {
    CreasePattern out;
    out.name = options_.name.empty() ? file_ : options_.name;
    std::vector<int> face_of_walk(walks_.walks.size(), -1);
    std::vector<int> vertex(a_.points.size(), -1);
    std::vector<Point> corners;
    for (size_t w = 0; w < walks_.walks.size(); ++w) {
      if (!is_face(static_cast<int>(w))) continue;
      face_of_walk[w] = out.num_faces();
      std::vector<int> face;
      for (int h : walks_.walks[w]) {
        const int v = origin(h);
        if (vertex[v] < 0) {
          vertex[v] = static_cast<int>(corners.size());
          corners.push_back(a_.points[v]);
        }
        face.push_back(vertex[v]);
      }
      std::vector<int> sorted = face;
      std::sort(sorted.begin(), sorted.end());
      const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
      if (twice != sorted.end()) {
        // The walk passes a corner twice: lines meeting the rest at that one point only.
        const int line = a_.edges[walks_.walks[w][0] / 2].lines[0];
        fail(line, fmt::format("the face along the {} touches itself at {}: lines that meet the "
                               "others at one point only do not cut a face apart; extend them "
                               "across the face, or delete them, and save again",
                               name(line), format_point(corners[*twice])));
      }
      out.faces.push_back(std::move(face));
    }
    out.V.resize(static_cast<Eigen::Index>(corners.size()), 2);
    for (size_t v = 0; v < corners.size(); ++v)
      out.V.row(static_cast<Eigen::Index>(v)) = corners[v];

    std::vector<int> piece(out.faces.size());
    std::iota(piece.begin(), piece.end(), 0);
    for (size_t e = 0; e < a_.edges.size(); ++e) {
      const Edge& edge = a_.edges[e];
      if (!edge.alive) continue;
      const DrawnLine& drawn = lines_[edge.lines[0]];
      const int left = face_of_walk[walks_.walk_of[2 * e]];
      const int right = face_of_walk[walks_.walk_of[2 * e + 1]];
      Crease crease;
      crease.kind = drawn.kind;
      crease.fold_angle = drawn.fold_angle;
      const bool two = left >= 0 && right >= 0;
      if (drawn.kind == CreaseKind::kBorder && two) {
        fail(edge.lines[0],
             fmt::format("the {} runs between two faces around {}: a printed sheet cannot have "
                         "a cut of no width; for a fold make it red (mountain) or blue (valley), "
                         "for a cut leave a gap between the faces' outlines, and save again",
                         name(edge.lines[0]), format_point(middle(edge))));
      }
      if (drawn.kind != CreaseKind::kBorder && !two) {
        fail(edge.lines[0],
             fmt::format("the {} lies on the sheet's outline around {}: a fold needs a face on "
                         "both sides; draw the outline around it, or make it black, and save "
                         "again",
                         name(edge.lines[0]), format_point(middle(edge))));
      }
      // v0 → v1 runs counter-clockwise around `left`: the lower face number when there are two.
      const bool forward = two ? left < right : left >= 0;
      crease.v0 = vertex[forward ? edge.u : edge.v];
      crease.v1 = vertex[forward ? edge.v : edge.u];
      crease.left = forward ? left : right;
      crease.right = two ? std::max(left, right) : -1;
      if (two) piece[component_root(piece, left)] = component_root(piece, right);
      out.creases.push_back(crease);
    }
    for (int f = 1; f < out.num_faces(); ++f) {
      if (component_root(piece, f) != component_root(piece, 0)) {
        throw UserError(ErrorCategory::kTopology,
                        fmt::format("{}: the sheet's faces meet only at corners in places (faces "
                                    "1 and {} are not joined by a crease): it would fall apart; "
                                    "flatmorph folds one sheet per file; join the parts by a "
                                    "crease, or put each in its own file, and save again",
                                    file_, f + 1));
      }
    }
    fold_tree(out);
    return out;
  }

  // A maximum spanning tree on crease length from the largest face (Prim; ties to the lower
  // crease index): long hinges are strong, as for a solid's nets.
  static void fold_tree(CreasePattern& pattern) {
    const int n = pattern.num_faces();
    std::vector<double> area(n, 0);
    for (int f = 0; f < n; ++f) {
      std::vector<Point> loop;
      for (int v : pattern.faces[f]) loop.push_back(pattern.V.row(v).transpose());
      area[f] = signed_area(loop);
    }
    pattern.root = static_cast<int>(std::max_element(area.begin(), area.end()) - area.begin());
    std::vector<std::vector<int>> creases_of(n);
    for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
      const Crease& crease = pattern.creases[c];
      if (crease.right < 0) continue;
      creases_of[crease.left].push_back(c);
      creases_of[crease.right].push_back(c);
    }
    pattern.parent_crease.assign(n, -1);
    pattern.solid_face.assign(n, -1);
    pattern.fold_order.clear();
    std::vector<bool> placed(n, false);
    std::priority_queue<std::pair<double, int>> candidates;  // (length, −crease)
    const auto place = [&](int f) {
      placed[f] = true;
      pattern.fold_order.push_back(f);
      for (int c : creases_of[f]) {
        if (placed[pattern.other_face(c, f)]) continue;
        const Crease& crease = pattern.creases[c];
        candidates.push({(pattern.V.row(crease.v1) - pattern.V.row(crease.v0)).norm(), -c});
      }
    };
    place(pattern.root);
    while (!candidates.empty()) {
      const int c = -candidates.top().second;
      candidates.pop();
      const Crease& crease = pattern.creases[c];
      const int child = placed[crease.left] ? crease.right : crease.left;
      if (placed[child]) continue;
      pattern.parent_crease[child] = c;
      place(child);
    }
  }

  const std::string& file_;
  const CreasePatternReadOptions& options_;
  const std::vector<DrawnLine>& lines_;
  Arrangement a_;
  std::vector<std::string>& warnings_;
  Walks walks_;
  struct Bounds {
    Point lo, hi;
  };
  std::vector<std::vector<Point>> loops_;  // per walk, its corners
  std::vector<Bounds> bounds_;             // per walk
};

}  // namespace

CreasePattern read_crease_pattern_svg(std::string_view text, const std::string& source,
                                      const CreasePatternReadOptions& options,
                                      std::vector<std::string>* warnings) {
  if (!(options.snap_tolerance > 0) || !std::isfinite(options.snap_tolerance) ||
      !(options.flat_angle >= 0) || !(options.flat_angle < kPi)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("reading {}: the snap tolerance must be a positive length (mm) "
                                "and the flat angle from 0 to 180°",
                                source));
  }
  if (text.size() > options.max_bytes) {
    throw UserError(ErrorCategory::kResource,
                    fmt::format("{}: the file has {} bytes, more than the {} read: simplify the "
                                "drawing",
                                source, text.size(), options.max_bytes));
  }
  std::vector<std::string> found;
  PatternDrawing drawing(source, options);
  svg::read_drawing(
      text, source, "the crease pattern", [&](const svg::Shape& shape) { drawing.read(shape); },
      found);
  if (drawing.unstroked > 0) {
    found.push_back(
        fmt::format("{}: {} elements without a stroke (fills, backgrounds) are not "
                    "read",
                    source, drawing.unstroked));
  }
  if (drawing.segments.empty()) {
    throw UserError(ErrorCategory::kTopology,
                    fmt::format("{}: no lines: draw the sheet's outline in black and its folds "
                                "red (mountain) and blue (valley), and save as SVG",
                                source));
  }
  PatternBuilder builder(
      source, options, drawing.lines,
      arrange(drawing.segments, options.snap_tolerance, options.max_segments, source), found);
  CreasePattern pattern = builder.build();
  if (warnings != nullptr) warnings->insert(warnings->end(), found.begin(), found.end());
  return pattern;
}

}  // namespace flatmorph
