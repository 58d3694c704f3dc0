// What the DXF and SVG tile-outline readers share (Geodesy CHI 2019 §6: outlines drawn in CAD;
// notes §6.4): the reading options, curves cut into chords, open pieces chained end to end, and
// closed loops nested even-odd into TileOutlines. Millimetres and radians; plate coordinates (y up,
// seen from +z).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.h"
#include "methods/tiles/tile_outline.h"

namespace flatmorph {

struct OutlineReadOptions {
  // mm: the largest distance between a curve (circle, arc, bulge) and its chords: w/20 for a
  // 0.4 mm bead (notes §6.4).
  double chord_tolerance = 0.02;
  // mm: ends and points closer than this are one point (chains of lines and arcs, closed
  // polylines, repeated points); a point this close to another outline touches it.
  double join_tolerance = 1e-3;
  size_t max_bytes = 64 << 20;    // larger files are refused (kResource)
  size_t max_points = 2'000'000;  // so are drawings with more points, chords included
};

namespace outline_loops {

// mm: points farther from the origin in x or y are refused (a unit mistake, or garbage).
inline constexpr double kMaxCoordinate = 1e6;

using Point = Eigen::Vector2d;

// Where a loop or piece is drawn, for TileOutline::source and messages.
struct Origin {
  std::string what;  // "LWPOLYLINE", "<circle id=\"c2\">"
  long long line = 0;
};

// A closed loop as drawn: mm, plate coordinates, either orientation, the first point not repeated.
struct DrawnLoop {
  std::vector<Point> points;
  Origin origin;
};

// An open piece of outline (a LINE, an ARC, an open polyline), chained to others by its ends.
struct OpenPiece {
  std::vector<Point> points;  // mm, at least 2: the first and the last are its ends
  Origin origin;
};

// Counts the points read against OutlineReadOptions::max_points.
struct PointBudget {
  size_t used = 0;
  size_t max = 0;
};

// The arc centre + axes (cos t, sin t) for t from `start` over `sweep` (radians, negative =
// clockwise in the axes' frame): a circle when axes is r times a rotation, an ellipse otherwise.
struct EllipseArc {
  Point centre;          // mm
  Eigen::Matrix2d axes;  // mm
  double start = 0;
  double sweep = 0;
};

using ::flatmorph::printable;  // common/error.h

// "file:line", the start of every message about one entity or element.
std::string where(const std::string& file, long long line);
// "(x, y) mm" for messages.
std::string format_point(const Point& p);
// "file: LWPOLYLINE at line 12", the TileOutline::source of a loop.
std::string source_of(const std::string& file, const Origin& origin);

// Throws UserError(kOption) for options that are not positive finite numbers.
void check_options(const OutlineReadOptions& options);
// Throws UserError(kResource) when `size` bytes exceed options.max_bytes.
void check_size(size_t size, const OutlineReadOptions& options, const std::string& file);

// Counts `count` more points, throwing UserError(kResource) past the budget; `at` is "file:line".
void take_points(PointBudget& budget, double count, const std::string& at);

// Whether a point is finite and within kMaxCoordinate (check_point's test, without the message).
inline bool acceptable(const Point& p) {
  return std::abs(p.x()) <= kMaxCoordinate && std::abs(p.y()) <= kMaxCoordinate;
}

// Throws UserError(kGeometry) for a point that is not finite or lies beyond kMaxCoordinate; `at`
// is "file:line", `what` names the point ("the LWPOLYLINE's vertex 3").
void check_point(const Point& p, const std::string& at, const std::string& what);

// Appends the points strictly between the ends of `arc`, spaced so that no chord is farther than
// options.chord_tolerance from the curve (and at most 90 degrees of the parameter apart): the
// caller adds the ends itself, exactly. Throws UserError(kGeometry) when the arc reaches beyond
// kMaxCoordinate, kResource past the budget.
void append_arc_interior(const EllipseArc& arc, const OutlineReadOptions& options,
                         PointBudget& budget, const std::string& at, const std::string& what,
                         std::vector<Point>& out);

// Chains pieces whose ends lie within options.join_tolerance of each other into closed loops (a
// piece may be walked backwards), in the order of each loop's first piece. A piece whose own ends
// meet is a loop by itself. Throws UserError(kTopology) naming the place (mm) of the first free
// end (an open outline) or of three or more ends meeting (a branch or a duplicate). Pieces whose
// points all lie within the tolerance of one point are dropped, with a warning.
std::vector<DrawnLoop> chain_pieces(const std::vector<OpenPiece>& pieces, const std::string& file,
                                    const OutlineReadOptions& options,
                                    std::vector<std::string>& warnings);

// The tiles drawn by `loops` (given in file order), nested even-odd: a loop inside no other, or
// inside an even number of them, is a tile's boundary (made counter-clockwise); a loop inside an
// odd number is a hole (clockwise) of the innermost loop around it. Repeated points (closer than
// join_tolerance) are removed; loops thinner than join_tolerance (zero area) are dropped with a
// warning. Loops may touch (tiles side by side share edges, §6.3; a hole may touch its tile) but
// not cross: throws UserError(kGeometry) with the place (mm) when a loop crosses itself or
// another, also where they only meet at a corner but pass through each other there; when a loop
// is drawn twice; when no loop is left (`what_to_draw` then says what to draw); kResource when the
// checks would take too long (thousands of loops on top of each other). Tiles come in the order
// of their boundaries in `loops`, holes likewise.
std::vector<TileOutline> nest_loops(std::vector<DrawnLoop> loops, const std::string& file,
                                    const OutlineReadOptions& options,
                                    std::vector<std::string>& warnings,
                                    const std::string& what_to_draw);

}  // namespace outline_loops
}  // namespace flatmorph
