#include "methods/tiles/svg_outlines.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "common/angles.h"
#include "common/error.h"
#include "common/svg_drawing.h"

namespace flatmorph {
namespace {

using outline_loops::DrawnLoop;
using outline_loops::Origin;
using outline_loops::Point;
using svg::Affine;
using svg::describe;
using svg::Element;

// The tiles' shapes: each closed loop in plate mm.
class OutlineShapes {
 public:
  OutlineShapes(const std::string& file, const OutlineReadOptions& options)
      : file_(file), options_(options) {
    budget_.max = options.max_points;
  }

  std::vector<DrawnLoop> loops() && { return std::move(loops_); }

  void read(const svg::Shape& shape) {
    const Element& element = shape.element;
    const std::string_view name = shape.name;
    if (name == "polygon" || name == "polyline") {
      read_poly(element, shape.map, name == "polygon");
    } else if (name == "circle" || name == "ellipse") {
      read_ellipse(element, shape.map, name == "circle");
    } else if (name == "rect") {
      read_rect(element, shape.map);
    } else if (name == "path") {
      read_path(element, shape.map);
    } else if (name == "use") {
      fail(element,
           "<use> elements (clones) are not read: unlink the clone (Inkscape: Edit > "
           "Clone > Unlink Clone) or draw the shape itself, and save again");
    } else if (name == "image") {
      fail(element,
           "<image> elements are not read (a picture has no outline): trace it into a "
           "path (Inkscape: Path > Trace Bitmap) or delete it, and save again");
    } else if (name == "line") {
      fail(element,
           "a <line> is one segment, not a closed outline: draw the outline as a closed "
           "path or a polygon, and save again");
    } else if (name == "svg") {
      fail(element,
           "nested <svg> elements are not read: put the outlines directly into the "
           "drawing, and save again");
    } else {
      fail(element, fmt::format("<{}> elements are not read: only polygon, polyline, circle, "
                                "ellipse, rect and path are; delete it or convert it to a path, "
                                "and save again",
                                printable(element.name)));
    }
  }

 private:
  [[noreturn]] void fail(const Element& element, const std::string& message,
                         ErrorCategory category = ErrorCategory::kFormat) const {
    svg::fail(file_, element, message, category);
  }

  std::optional<double> length(const Element& element, std::string_view key) const {
    return svg::length(element, key, file_);
  }

  // A loop being drawn: mm, plate coordinates.
  struct Pen {
    std::vector<Point> points;
    Origin origin;
  };

  void add_point(Pen& pen, const Point& mm, const Element& element) {
    // The messages are made only for a refusal: paths may have millions of points.
    if (budget_.used >= budget_.max || !outline_loops::acceptable(mm)) {
      const std::string at = outline_loops::where(file_, element.line);
      outline_loops::take_points(budget_, 1, at);
      outline_loops::check_point(mm, at, fmt::format("a point of the {}", pen.origin.what));
    }
    ++budget_.used;
    pen.points.push_back(mm);
  }

  void add_arc(Pen& pen, const outline_loops::EllipseArc& arc, const Element& element) {
    outline_loops::append_arc_interior(
        arc, options_, budget_, outline_loops::where(file_, element.line),
        fmt::format("an arc of the {}", pen.origin.what), pen.points);
  }

  // Ends the loop: closed if `closed` (Z, a polygon) or if it ends where it started; refuses an
  // open one.
  void finish_loop(Pen& pen, bool closed, const Element& element, const char* advice) {
    const double tolerance = options_.join_tolerance;
    if (pen.points.size() >= 2 && (pen.points.back() - pen.points.front()).norm() <= tolerance) {
      pen.points.pop_back();
    } else if (!closed && pen.points.size() >= 2) {
      fail(element,
           fmt::format("the {} is open: it ends at {}, not where it starts, {}: {}",
                       pen.origin.what, outline_loops::format_point(pen.points.back()),
                       outline_loops::format_point(pen.points.front()), advice),
           ErrorCategory::kTopology);
    }
    loops_.push_back({std::move(pen.points), std::move(pen.origin)});
    pen = Pen{};
  }

  void read_poly(const Element& element, const Affine& map, bool polygon) {
    Pen pen{{}, {describe(element), element.line}};
    svg::read_points(element, file_, [&](const Point& p) { add_point(pen, map(p), element); });
    finish_loop(pen, polygon, element,
                "make it a polygon, or end it at its first point, and save again");
  }

  double positive_length(const Element& element, std::string_view key,
                         std::optional<double> value) const {
    if (!value || !(*value > 0)) {
      fail(element,
           fmt::format("the {} has {}: give it a positive {}, or delete it, and save again",
                       describe(element),
                       value ? fmt::format("{} = {:g}", printable(key), *value)
                             : fmt::format("no {}", printable(key)),
                       printable(key)),
           ErrorCategory::kGeometry);
    }
    return *value;
  }

  void read_ellipse(const Element& element, const Affine& map, bool circle) {
    Pen pen{{}, {describe(element), element.line}};
    const Point centre(length(element, "cx").value_or(0), length(element, "cy").value_or(0));
    double rx = 0, ry = 0;
    if (circle) {
      rx = ry = positive_length(element, "r", length(element, "r"));
    } else {
      // SVG 2: a missing radius is the other one.
      std::optional<double> x = length(element, "rx"), y = length(element, "ry");
      rx = positive_length(element, "rx", x ? x : y);
      ry = positive_length(element, "ry", y ? y : x);
    }
    outline_loops::EllipseArc arc;
    arc.centre = map(centre);
    arc.axes = map.linear * Point(rx, ry).asDiagonal();
    arc.sweep = 2 * kPi;
    add_point(pen, map(centre + Point(rx, 0)), element);
    add_arc(pen, arc, element);
    finish_loop(pen, true, element, "");
  }

  void read_rect(const Element& element, const Affine& map) {
    Pen pen{{}, {describe(element), element.line}};
    const double x = length(element, "x").value_or(0), y = length(element, "y").value_or(0);
    const double w = positive_length(element, "width", length(element, "width"));
    const double h = positive_length(element, "height", length(element, "height"));
    std::optional<double> rx = length(element, "rx"), ry = length(element, "ry");
    if ((rx && *rx < 0) || (ry && *ry < 0)) {
      fail(element,
           fmt::format("the {} has a negative corner radius: fix it, and save again",
                       describe(element)),
           ErrorCategory::kGeometry);
    }
    // SVG: a missing corner radius is the other one; neither more than half the side.
    double cx = std::min(rx ? *rx : ry.value_or(0), w / 2);
    double cy = std::min(ry ? *ry : rx.value_or(0), h / 2);
    if (cx == 0 || cy == 0) cx = cy = 0;  // square corners
    // Clockwise on screen from the top left corner's end: each corner a quarter ellipse.
    const Point corners[4] = {
        {x + w - cx, y + cy}, {x + w - cx, y + h - cy}, {x + cx, y + h - cy}, {x + cx, y + cy}};
    for (int k = 0; k < 4; ++k) {
      const double start = (k - 1) * kPi / 2;
      const Point& c = corners[k];
      add_point(pen, map(c + Point(cx * std::cos(start), cy * std::sin(start))), element);
      if (cx > 0 && cy > 0) {
        outline_loops::EllipseArc arc;
        arc.centre = map(c);
        arc.axes = map.linear * Point(cx, cy).asDiagonal();
        arc.start = start;
        arc.sweep = kPi / 2;
        add_arc(pen, arc, element);
        add_point(pen,
                  map(c + Point(cx * std::cos(start + kPi / 2), cy * std::sin(start + kPi / 2))),
                  element);
      }
    }
    finish_loop(pen, true, element, "");
  }

  // An elliptical arc command (SVG 1.1 F.6.5, endpoint to centre parametrisation), worked in
  // units of the radii so that no square overflows.
  void arc_to(Pen& pen, const Point& from, const Point& to, const svg::ArcCommand& command,
              const Affine& map, const Element& element) {
    if (from == to) return;  // SVG: such an arc is omitted
    double rx = std::abs(command.rx), ry = std::abs(command.ry);
    const Point end = map(to);
    if (rx == 0 || ry == 0) {
      add_point(pen, end, element);
      return;
    }
    const double phi = command.rotation * kPi / 180;
    Eigen::Matrix2d rotation;
    rotation << std::cos(phi), -std::sin(phi), std::sin(phi), std::cos(phi);
    const Point half = rotation.transpose() * (from - to) / 2;
    Point u(half.x() / rx, half.y() / ry);  // the start on the unit circle, from the middle
    double lambda = u.squaredNorm();
    if (!(lambda > 1e-30) || !std::isfinite(lambda)) {
      if (command.large) {
        fail(element,
             fmt::format("an arc of the {} has radii ({:g}, {:g}) so large beside the "
                         "distance between its ends that its long way round leaves the "
                         "drawing: fix the path, and save again",
                         pen.origin.what, rx, ry),
             ErrorCategory::kGeometry);
      }
      add_point(pen, end, element);  // the short way round is its chord
      return;
    }
    if (lambda > 1) {
      // Radii too small to reach: scaled up until they just do (SVG's correction).
      const double s = std::sqrt(lambda);
      rx *= s;
      ry *= s;
      u /= s;
      lambda = u.squaredNorm();
    }
    double k = std::sqrt(std::max(0.0, (1 - lambda) / lambda));
    if (command.large == command.sweep) k = -k;
    const Point centre_unit(k * u.y(), -k * u.x());
    const Point v1 = u - centre_unit, v2 = -u - centre_unit;
    double delta = std::atan2(v1.x() * v2.y() - v1.y() * v2.x(), v1.dot(v2));
    if (command.sweep && delta < 0) delta += 2 * kPi;
    if (!command.sweep && delta > 0) delta -= 2 * kPi;
    const Eigen::Matrix2d axes = rotation * Point(rx, ry).asDiagonal();
    outline_loops::EllipseArc arc;
    arc.centre = map(axes * centre_unit + (from + to) / 2);
    arc.axes = map.linear * axes;
    arc.start = std::atan2(v1.y(), v1.x());
    arc.sweep = delta;
    add_arc(pen, arc, element);
    add_point(pen, end, element);
  }

  // Each subpath a loop.
  void read_path(const Element& element, const Affine& map) {
    const std::string what = describe(element);
    Pen pen;
    svg::PathCallbacks callbacks;
    callbacks.begin = [&](const Point& start, int subpath) {
      pen = Pen{{},
                {subpath == 1 ? what : fmt::format("{} subpath {}", what, subpath), element.line}};
      add_point(pen, map(start), element);
    };
    callbacks.line_to = [&](const Point& to) { add_point(pen, map(to), element); };
    callbacks.arc_to = [&](const Point& from, const Point& to, const svg::ArcCommand& arc) {
      arc_to(pen, from, to, arc, map, element);
    };
    callbacks.end = [&](bool closed) {
      if (pen.points.size() == 1 && !closed) return;  // a lone moveto draws nothing
      finish_loop(pen, closed, element,
                  "close it (Z) or end it at its first point in the drawing, and save again");
    };
    svg::read_path(element, file_, callbacks);
  }

  const std::string& file_;
  const OutlineReadOptions& options_;
  outline_loops::PointBudget budget_;
  std::vector<DrawnLoop> loops_;
};

}  // namespace

std::vector<TileOutline> read_svg_outlines(std::string_view text, const std::string& source,
                                           const OutlineReadOptions& options,
                                           std::vector<std::string>* warnings) {
  outline_loops::check_options(options);
  outline_loops::check_size(text.size(), options, source);
  std::vector<std::string> found;
  OutlineShapes shapes(source, options);
  svg::read_drawing(
      text, source, "the outlines", [&](const svg::Shape& shape) { shapes.read(shape); }, found);
  std::vector<TileOutline> tiles = outline_loops::nest_loops(
      std::move(shapes).loops(), source, options, found,
      "draw each tile as a closed path, a polygon, a circle, an ellipse or a rectangle, and save "
      "as SVG");
  if (warnings != nullptr) warnings->insert(warnings->end(), found.begin(), found.end());
  return tiles;
}

}  // namespace flatmorph
