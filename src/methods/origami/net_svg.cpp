#include "methods/origami/net_svg.h"

#include <fmt/core.h>
#include <clipper.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <stdexcept>

#include "common/angles.h"
#include "common/markup.h"
#include "mesh/clipper_path.h"
#include "mesh/plane_geometry.h"
#include "mesh/polygon.h"

namespace flatmorph {
namespace {

constexpr double kMargin = 5;  // mm around the drawing

// Origami Simulator's pattern colours (its pattern importer's typeForStroke).
const char* stroke_colour(CreaseKind kind) {
  switch (kind) {
    case CreaseKind::kBorder:
      return "#000000";
    case CreaseKind::kMountain:
      return "#ff0000";
    case CreaseKind::kValley:
      return "#0000ff";
    case CreaseKind::kFlat:
      return "#ffff00";
  }
  return "#000000";
}

constexpr const char* kCaseAFill = "#fdae61";
constexpr const char* kCaseBFill = "#abd9e9";

// The picture's frame: plate mm → SVG user units (mm), y turned down.
struct Box {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;

  void add(double x, double y) {
    min_x = std::min(min_x, x);
    max_x = std::max(max_x, x);
    min_y = std::min(min_y, y);
    max_y = std::max(max_y, y);
  }
  bool empty() const { return !(min_x <= max_x); }
};

// SVG's y of plate y: +0 rather than −0 on the axis.
double down(double y) { return 0.0 - y; }

// The root element: the box with margins around it, at least `min_width` mm wide and with
// `extra_bottom` mm below it; its title; and a white background when asked.
std::string root(const Box& box, double min_width, double extra_bottom, const std::string& title,
                 bool background) {
  const double x = box.min_x - kMargin, y = down(box.max_y) - kMargin;
  const double w = std::max(box.max_x - box.min_x + 2 * kMargin, min_width);
  const double h = box.max_y - box.min_y + 2 * kMargin + extra_bottom;
  std::string out = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.3f}mm\" height=\"{:.3f}mm\" "
      "viewBox=\"{:.3f} {:.3f} {:.3f} {:.3f}\">\n<title>{}</title>\n",
      w, h, x, y, w, h, xml_escape(title));
  if (background) {
    out += fmt::format(
        "<rect x=\"{:.3f}\" y=\"{:.3f}\" width=\"{:.3f}\" height=\"{:.3f}\" fill=\"white\"/>\n", x,
        y, w, h);
  }
  return out;
}

std::string points_attribute(const Eigen::MatrixX2d& polygon) {
  std::string out;
  for (Eigen::Index i = 0; i < polygon.rows(); ++i) {
    out += fmt::format("{}{:.4f},{:.4f}", i == 0 ? "" : " ", polygon(i, 0), down(polygon(i, 1)));
  }
  return out;
}

// --- Where a face's number goes ------------------------------------------------------------------

// Distance from p to the polygon's sides, positive inside (even-odd).
double signed_distance(const Eigen::MatrixX2d& polygon, const Eigen::Vector2d& p) {
  bool inside = false;
  double best = std::numeric_limits<double>::infinity();
  const Eigen::Index n = polygon.rows();
  for (Eigen::Index i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d a = polygon.row(i).transpose(), b = polygon.row(j).transpose();
    if (side_crosses_ray(p, a, b)) inside = !inside;
    best = std::min(best, segment_distance(p, a, b));
  }
  return inside ? best : -best;
}

// The point of the polygon farthest from its sides (its pole of inaccessibility), found by
// subdividing square cells best first until none can beat the best by `precision` mm; with that
// distance. A face's number there stays clear of its sides even in a thin or bent face.
std::pair<Eigen::Vector2d, double> pole(const Eigen::MatrixX2d& polygon, double precision) {
  struct Cell {
    Eigen::Vector2d centre;
    double half, distance, bound;
  };
  const auto cell = [&](const Eigen::Vector2d& centre, double half) {
    const double d = signed_distance(polygon, centre);
    return Cell{centre, half, d, d + half * std::numbers::sqrt2};
  };
  const auto lower = [](const Cell& a, const Cell& b) { return a.bound < b.bound; };
  std::priority_queue<Cell, std::vector<Cell>, decltype(lower)> queue(lower);
  const Eigen::Vector2d lo = polygon.colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = polygon.colwise().maxCoeff().transpose();
  const double size = std::max((hi - lo).minCoeff(), precision);
  const double half = size / 2;
  for (double x = lo.x(); x < hi.x(); x += size) {
    for (double y = lo.y(); y < hi.y(); y += size) queue.push(cell({x + half, y + half}, half));
  }
  Cell best = cell(polygon.colwise().mean().transpose(), 0);
  for (int steps = 0; !queue.empty() && steps < 100000; ++steps) {
    const Cell c = queue.top();
    queue.pop();
    if (c.distance > best.distance) best = c;
    if (c.bound - best.distance <= precision) continue;
    const double h = c.half / 2;
    for (const Eigen::Vector2d& d : {Eigen::Vector2d(-h, -h), Eigen::Vector2d(h, -h),
                                     Eigen::Vector2d(-h, h), Eigen::Vector2d(h, h)}) {
      queue.push(cell(c.centre + d, h));
    }
  }
  return {best.centre, best.distance};
}

// --- The outline to cut -------------------------------------------------------------------------

constexpr double kClipperScale = 1e6;  // 1 nm per unit

// The union of the pieces, closed by 1 µm so that pieces meeting to rounding make one outline.
ClipperLib::Paths cut_outline(const std::vector<Eigen::MatrixX2d>& pieces) {
  ClipperLib::Paths paths;
  for (const Eigen::MatrixX2d& piece : pieces) {
    ClipperLib::Path path = to_clipper_path(piece, kClipperScale);
    if (!ClipperLib::Orientation(path)) std::reverse(path.begin(), path.end());
    paths.push_back(std::move(path));
  }
  ClipperLib::Paths united;
  ClipperLib::Clipper clipper;
  clipper.AddPaths(paths, ClipperLib::ptSubject, true);
  clipper.Execute(ClipperLib::ctUnion, united, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  const double closing = 1e-3 * kClipperScale;
  for (const double delta : {closing, -closing}) {
    ClipperLib::ClipperOffset offset;
    offset.AddPaths(united, ClipperLib::jtMiter, ClipperLib::etClosedPolygon);
    offset.Execute(united, delta);
  }
  return united;
}

}  // namespace

std::string crease_pattern_svg(const CreasePattern& pattern) {
  Box box;
  for (Eigen::Index v = 0; v < pattern.V.rows(); ++v) box.add(pattern.V(v, 0), pattern.V(v, 1));
  if (box.empty()) box.add(0, 0);
  std::string svg = root(box, 0, 0, pattern.name, false);
  for (const Crease& crease : pattern.creases) {
    const Eigen::RowVector2d a = pattern.V.row(crease.v0), b = pattern.V.row(crease.v1);
    const bool folds = crease.kind == CreaseKind::kMountain || crease.kind == CreaseKind::kValley;
    const double degrees = folds ? crease.fold_angle * kDegreesPerRadian : 0.0;
    svg += fmt::format(
        "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-opacity=\"{}\" "
        "stroke-width=\"0.3\"",
        a.x() + 0.0, down(a.y()), b.x() + 0.0, down(b.y()), stroke_colour(crease.kind),
        folds ? std::abs(degrees) / 180 : 1.0);
    if (crease.kind != CreaseKind::kBorder) {
      svg += fmt::format(" data-fold-angle=\"{}\"", degrees + 0.0);
    }
    svg += "/>\n";
  }
  return svg + "</svg>\n";
}

std::string net_svg(const CreasePattern& pattern, const ActuatedSheet& sheet) {
  if (sheet.faces.size() != pattern.faces.size()) {
    throw std::invalid_argument("net_svg: the sheet's faces are not the pattern's");
  }
  for (const Actuator& actuator : sheet.actuators) {
    if (actuator.hinge.crease < 0 ||
        actuator.hinge.crease >= static_cast<int>(pattern.creases.size())) {
      throw std::invalid_argument("net_svg: an actuator on a crease the pattern does not have");
    }
  }
  Box box;
  std::vector<Eigen::MatrixX2d> pieces;
  for (const Eigen::MatrixX2d& face : sheet.faces) {
    for (Eigen::Index i = 0; i < face.rows(); ++i) box.add(face(i, 0), face(i, 1));
    if (face.rows() >= 3) pieces.push_back(face);
  }
  for (const Actuator& actuator : sheet.actuators) {
    for (int i = 0; i < 4; ++i) box.add(actuator.quad(i, 0), actuator.quad(i, 1));
    pieces.push_back(actuator.quad);
  }
  if (box.empty()) box.add(0, 0);
  // The legend: three rows of about 40 characters below the sheet.
  constexpr double kFont = 3.5, kRow = 1.5 * kFont;
  std::string svg = root(box, 8 + 40 * 0.6 * kFont + 2 * kMargin, 3 * kRow + kMargin,
                         sheet.name.empty() ? pattern.name : sheet.name, true);

  svg += "<g id=\"faces\" fill=\"#eeeeee\" stroke=\"#999999\" stroke-width=\"0.2\">\n";
  for (size_t f = 0; f < sheet.faces.size(); ++f) {
    svg += fmt::format("<polygon data-face=\"{}\" points=\"{}\"/>\n", f,
                       points_attribute(sheet.faces[f]));
  }
  svg += "</g>\n<g id=\"actuators\" stroke=\"none\">\n";
  for (const Actuator& actuator : sheet.actuators) {
    svg += fmt::format("<polygon data-crease=\"{}\" data-case=\"{}\" fill=\"{}\" points=\"{}\"/>\n",
                       actuator.hinge.crease, actuator.hinge.pla_on_bed ? 'A' : 'B',
                       actuator.hinge.pla_on_bed ? kCaseAFill : kCaseBFill,
                       points_attribute(actuator.quad));
  }
  svg += "</g>\n<g id=\"hinges\" stroke-width=\"0.4\">\n";
  for (const Actuator& actuator : sheet.actuators) {
    // Corners 0, 1 on the parent's side, 2, 3 on the child's: the centre line joins the middles
    // of the strip's ends.
    const Eigen::RowVector2d a = (actuator.quad.row(0) + actuator.quad.row(3)) / 2;
    const Eigen::RowVector2d b = (actuator.quad.row(1) + actuator.quad.row(2)) / 2;
    const CreaseKind kind = pattern.creases[actuator.hinge.crease].kind;
    svg += fmt::format(
        "<line data-crease=\"{}\" x1=\"{:.4f}\" y1=\"{:.4f}\" x2=\"{:.4f}\" y2=\"{:.4f}\" "
        "stroke=\"{}\"/>\n",
        actuator.hinge.crease, a.x(), down(a.y()), b.x(), down(b.y()),
        kind == CreaseKind::kValley ? "#0000ff" : "#ff0000");
  }
  svg += "</g>\n<g id=\"cut\" fill=\"none\" stroke=\"#000000\" stroke-width=\"0.3\">\n";
  for (const ClipperLib::Path& path : cut_outline(pieces)) {
    std::string d;
    for (size_t i = 0; i < path.size(); ++i) {
      d += fmt::format("{}{:.4f},{:.4f} ", i == 0 ? "M" : "L",
                       static_cast<double>(path[i].X) / kClipperScale,
                       down(static_cast<double>(path[i].Y) / kClipperScale));
    }
    svg += fmt::format("<path d=\"{}Z\"/>\n", d);
  }
  svg +=
      "</g>\n<g id=\"face-numbers\" font-family=\"sans-serif\" text-anchor=\"middle\" "
      "dominant-baseline=\"central\" fill=\"#333333\">\n";
  for (size_t f = 0; f < sheet.faces.size(); ++f) {
    const Eigen::MatrixX2d& face = sheet.faces[f];
    if (face.rows() < 3 || !(std::abs(signed_area(face)) > 0)) continue;
    const auto [at, room] = pole(face, 0.05);
    // As large as the face leaves room for, within what reads on a printed sheet.
    const double size = std::clamp(room, 1.0, 8.0);
    svg += fmt::format(
        "<text data-face=\"{}\" x=\"{:.3f}\" y=\"{:.3f}\" font-size=\"{:.2f}\">{}</text>\n", f,
        at.x(), down(at.y()), size, f + 1);
  }
  int count[2] = {0, 0};  // case A, case B
  for (const Actuator& actuator : sheet.actuators) ++count[actuator.hinge.pla_on_bed ? 0 : 1];
  const double x = box.min_x, y = down(box.min_y) + kMargin;
  svg +=
      fmt::format("</g>\n<g id=\"legend\" font-family=\"sans-serif\" font-size=\"{}\">\n", kFont);
  const std::string rows[3][2] = {
      {fmt::format("fill=\"{}\"", kCaseAFill),
       fmt::format("case A (PLA on the bed): mountain, {} hinge{}", count[0],
                   count[0] == 1 ? "" : "s")},
      {fmt::format("fill=\"{}\"", kCaseBFill),
       fmt::format("case B (TPU on the bed): valley, {} hinge{}", count[1],
                   count[1] == 1 ? "" : "s")},
      {"fill=\"none\" stroke=\"#000000\" stroke-width=\"0.3\"", "the outline to cut"}};
  for (int k = 0; k < 3; ++k) {
    const double row_y = y + k * kRow;
    svg += fmt::format(
        "<rect x=\"{:.3f}\" y=\"{:.3f}\" width=\"6\" height=\"{}\" {}/>"
        "<text x=\"{:.3f}\" y=\"{:.3f}\">{}</text>\n",
        x, row_y, kFont, rows[k][0], x + 8, row_y + 0.85 * kFont, rows[k][1]);
  }
  return svg + "</g>\n</svg>\n";
}

}  // namespace flatmorph
