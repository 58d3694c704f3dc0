#include "methods/tiles/tile_rings.h"

#include <fmt/format.h>
#include <clipper.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>

#include "common/error.h"
#include "mesh/clipper_path.h"
#include "mesh/plane_geometry.h"
#include "mesh/polygon.h"

namespace flatmorph {
namespace {

using Point = Eigen::Vector2d;

constexpr double kMaxCoordinate = 1e6;  // mm: anything larger is a unit or export mistake
constexpr int kMaxLevels = 200000;
constexpr double kBisectionTolerance = 1e-3;  // mm: locates the deepest region for max_depth

Point row(const Eigen::MatrixX2d& loop, Eigen::Index i) { return loop.row(i).transpose(); }

double loop_length(const Eigen::MatrixX2d& loop) {
  double length = 0;
  const Eigen::Index n = loop.rows();
  for (Eigen::Index i = 0; i < n; ++i) length += (row(loop, (i + 1) % n) - row(loop, i)).norm();
  return length;
}

// Crossing-number test; orientation does not matter.
bool inside_loop(const Eigen::MatrixX2d& loop, const Point& p) {
  bool inside = false;
  const Eigen::Index n = loop.rows();
  for (Eigen::Index i = 0, j = n - 1; i < n; j = i++) {
    const double yi = loop(i, 1), yj = loop(j, 1);
    if ((yi > p.y()) != (yj > p.y())) {
      const double x = loop(i, 0) + (p.y() - yi) / (yj - yi) * (loop(j, 0) - loop(i, 0));
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

double distance_to_loop(const Eigen::MatrixX2d& loop, const Point& p) {
  double best = std::numeric_limits<double>::infinity();
  const Eigen::Index n = loop.rows();
  for (Eigen::Index i = 0; i < n; ++i) {
    best = std::min(best, segment_distance(p, row(loop, i), row(loop, (i + 1) % n)));
  }
  return best;
}

// The seam's reference point: smallest x, then smallest y.
Eigen::Index reference_vertex(const Eigen::MatrixX2d& loop) {
  Eigen::Index best = 0;
  for (Eigen::Index i = 1; i < loop.rows(); ++i) {
    if (loop(i, 0) < loop(best, 0) || (loop(i, 0) == loop(best, 0) && loop(i, 1) < loop(best, 1))) {
      best = i;
    }
  }
  return best;
}

Eigen::MatrixX2d starting_at(const Eigen::MatrixX2d& loop, Eigen::Index first) {
  const Eigen::Index n = loop.rows();
  Eigen::MatrixX2d out(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) out.row(i) = loop.row((first + i) % n);
  return out;
}

// The other way round, keeping the first point first.
Eigen::MatrixX2d reversed(const Eigen::MatrixX2d& loop) {
  const Eigen::Index n = loop.rows();
  Eigen::MatrixX2d out(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) out.row(i) = loop.row((n - i) % n);
  return out;
}

std::string point_text(const Point& p) { return fmt::format("({:.3f}, {:.3f}) mm", p.x(), p.y()); }

// ---- Options and outline checks ----

struct Resolved {
  double pitch, first_offset, arc_tolerance, min_length, min_area, scale;
};

Resolved resolve(const RingOptions& options) {
  const auto refuse = [](const std::string& message) {
    throw UserError(ErrorCategory::kOption, message);
  };
  if (!std::isfinite(options.pitch) || options.pitch <= 0 || options.pitch > 100) {
    refuse(
        fmt::format("ring pitch {} mm is not a path width; give a positive number of mm, e.g. 0.4",
                    options.pitch));
  }
  for (const auto& [name, value] : {std::pair{"first ring offset", options.first_offset},
                                    std::pair{"minimum ring length", options.min_length},
                                    std::pair{"minimum ring area", options.min_area}}) {
    if (!std::isfinite(value)) {
      refuse(fmt::format("{} {} is not a number; give a value >= 0, or < 0 for the default", name,
                         value));
    }
  }
  if (!std::isfinite(options.arc_tolerance) || options.arc_tolerance <= 0 ||
      options.arc_tolerance >= options.pitch) {
    refuse(fmt::format("ring arc tolerance {} mm must be positive and below the pitch {} mm",
                       options.arc_tolerance, options.pitch));
  }
  if (!std::isfinite(options.scale) || options.scale < 1 || options.scale > 1e9 ||
      options.pitch * options.scale < 10 || options.arc_tolerance * options.scale < 0.25) {
    refuse(
        fmt::format("ring offset scale {} units/mm is out of range: it must be within 1..1e9 and "
                    "give the pitch {} mm at least 10 units and the arc tolerance {} mm at least "
                    "0.25 units",
                    options.scale, options.pitch, options.arc_tolerance));
  }
  Resolved r;
  r.pitch = options.pitch;
  r.first_offset = options.first_offset < 0 ? options.pitch / 2 : options.first_offset;
  r.arc_tolerance = options.arc_tolerance;
  r.min_length = options.min_length < 0 ? std::numbers::pi * options.pitch : options.min_length;
  r.min_area = options.min_area < 0 ? options.pitch * options.pitch : options.min_area;
  r.scale = options.scale;
  return r;
}

struct CheckedOutline {
  Eigen::MatrixX2d boundary;            // counter-clockwise
  std::vector<Eigen::MatrixX2d> holes;  // clockwise
};

std::string source_of(const TileOutline& outline) {
  return outline.source.empty() ? std::string("tile outline") : outline.source;
}

[[noreturn]] void refuse_geometry(const TileOutline& outline, const std::string& problem) {
  throw UserError(ErrorCategory::kGeometry, fmt::format("{}: {}", source_of(outline), problem));
}

std::string loop_name(int loop) {
  return loop == 0 ? std::string("boundary") : fmt::format("hole {}", loop);
}

// Finite coordinates, no repeated consecutive points, at least 3 of them, non-zero area; returned
// counter-clockwise when `outer`, clockwise otherwise.
Eigen::MatrixX2d checked_loop(const TileOutline& outline, const Eigen::MatrixX2d& raw,
                              int loop_index, bool outer) {
  const std::string name = loop_name(loop_index);
  for (Eigen::Index i = 0; i < raw.rows(); ++i) {
    if (!std::isfinite(raw(i, 0)) || !std::isfinite(raw(i, 1)) ||
        std::abs(raw(i, 0)) > kMaxCoordinate || std::abs(raw(i, 1)) > kMaxCoordinate) {
      refuse_geometry(outline, fmt::format("the {}'s point {} is ({}, {}): not a finite coordinate "
                                           "within 1e6 mm; fix the drawing or its units",
                                           name, i + 1, raw(i, 0), raw(i, 1)));
    }
  }
  std::vector<Eigen::Index> kept;
  for (Eigen::Index i = 0; i < raw.rows(); ++i) {
    if (kept.empty() || (raw.row(i) - raw.row(kept.back())).norm() > 1e-9) kept.push_back(i);
  }
  while (kept.size() > 1 && (raw.row(kept.back()) - raw.row(kept.front())).norm() <= 1e-9) {
    kept.pop_back();
  }
  if (kept.size() < 3) {
    const Point at = raw.rows() > 0 ? row(raw, 0) : Point(0, 0);
    refuse_geometry(outline,
                    fmt::format("the {} has {} distinct point(s) (near {}); a tile outline "
                                "needs a closed polygon of at least 3 points",
                                name, kept.size(), point_text(at)));
  }
  Eigen::MatrixX2d loop(static_cast<Eigen::Index>(kept.size()), 2);
  for (size_t i = 0; i < kept.size(); ++i) {
    loop.row(static_cast<Eigen::Index>(i)) = raw.row(kept[i]);
  }
  const double diagonal = (loop.colwise().maxCoeff() - loop.colwise().minCoeff()).norm();
  const double area = signed_area(loop);
  if (std::abs(area) <= 1e-9 * diagonal * diagonal) {
    refuse_geometry(outline,
                    fmt::format("the {} near {} has zero area (its points lie on one line); "
                                "give a closed polygon",
                                name, point_text(row(loop, 0))));
  }
  return (area > 0) == outer ? loop : reversed(loop);
}

struct Edge {
  int loop;
  Eigen::Index index;
  Point a, b;
  double x_min, x_max, y_min, y_max;
};

// Edges of all loops may meet only where consecutive edges of one loop share their vertex (and do
// not fold back over each other). Sort-and-sweep on x.
void check_no_crossings(const TileOutline& outline, const std::vector<Eigen::MatrixX2d>& loops) {
  std::vector<Edge> edges;
  for (int l = 0; l < static_cast<int>(loops.size()); ++l) {
    const Eigen::MatrixX2d& loop = loops[l];
    for (Eigen::Index i = 0; i < loop.rows(); ++i) {
      const Point a = row(loop, i), b = row(loop, (i + 1) % loop.rows());
      edges.push_back({l, i, a, b, std::min(a.x(), b.x()), std::max(a.x(), b.x()),
                       std::min(a.y(), b.y()), std::max(a.y(), b.y())});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& e, const Edge& f) {
    return std::tie(e.x_min, e.loop, e.index) < std::tie(f.x_min, f.loop, f.index);
  });
  for (size_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    for (size_t j = i + 1; j < edges.size() && edges[j].x_min <= e.x_max; ++j) {
      const Edge& f = edges[j];
      if (f.y_min > e.y_max || f.y_max < e.y_min) continue;
      const auto where = [&](const Point& p) {
        return e.loop == f.loop ? fmt::format("the {} crosses or touches itself near {}",
                                              loop_name(e.loop), point_text(p))
                                : fmt::format("the {} and the {} cross or touch near {}",
                                              loop_name(std::min(e.loop, f.loop)),
                                              loop_name(std::max(e.loop, f.loop)), point_text(p));
      };
      if (e.loop == f.loop) {
        const Eigen::Index n = loops[e.loop].rows();
        const bool e_then_f = (e.index + 1) % n == f.index, f_then_e = (f.index + 1) % n == e.index;
        if (e_then_f || f_then_e) {
          // Consecutive edges share a vertex; they overlap only if the second folds back.
          const Edge& first = e_then_f ? e : f;
          const Edge& second = e_then_f ? f : e;
          const Point u = first.b - first.a, v = second.b - second.a;
          if (cross2(u, v) == 0 && u.dot(v) < 0) {
            refuse_geometry(outline, where(first.b) + "; the outline folds back on itself there");
          }
          continue;
        }
      }
      if (const std::optional<Point> p = segment_intersection(e.a, e.b, f.a, f.b)) {
        refuse_geometry(outline,
                        where(*p) + "; fix the drawing so that edges meet only at their ends");
      }
    }
  }
}

CheckedOutline checked_outline(const TileOutline& outline) {
  CheckedOutline checked;
  checked.boundary = checked_loop(outline, outline.boundary, 0, true);
  std::vector<Eigen::MatrixX2d> loops{checked.boundary};
  for (size_t h = 0; h < outline.holes.size(); ++h) {
    checked.holes.push_back(
        checked_loop(outline, outline.holes[h], static_cast<int>(h) + 1, false));
    loops.push_back(checked.holes.back());
  }
  check_no_crossings(outline, loops);
  // Without crossings one vertex tells where a whole loop lies.
  for (size_t h = 0; h < checked.holes.size(); ++h) {
    const Point p = row(checked.holes[h], 0);
    if (!inside_loop(checked.boundary, p)) {
      refuse_geometry(outline, fmt::format("{} at {} lies outside the boundary; a hole must be "
                                           "inside the tile",
                                           loop_name(static_cast<int>(h) + 1), point_text(p)));
    }
    for (size_t k = 0; k < checked.holes.size(); ++k) {
      if (k != h && inside_loop(checked.holes[k], p)) {
        refuse_geometry(outline, fmt::format("{} at {} lies inside {}; remove the inner one",
                                             loop_name(static_cast<int>(h) + 1), point_text(p),
                                             loop_name(static_cast<int>(k) + 1)));
      }
    }
  }
  return checked;
}

// ---- Offsets ----

// Douglas–Peucker on a closed loop: drops vertices within `tolerance` of the chord that replaces
// them. Clipper's inward offsets cross every offset edge with its neighbours' (their spikes back to
// the convex vertices), about n·depth/(inradius − depth) crossings, so a densely chorded arc made
// deep offsets quadratic; a loop simplified to a fraction of the arc tolerance keeps them fast.
Eigen::MatrixX2d simplified(const Eigen::MatrixX2d& loop, double tolerance) {
  const Eigen::Index n = loop.rows();
  Eigen::Index far = 0;
  for (Eigen::Index i = 1; i < n; ++i) {
    if ((loop.row(i) - loop.row(0)).squaredNorm() > (loop.row(far) - loop.row(0)).squaredNorm()) {
      far = i;
    }
  }
  std::vector<bool> keep(static_cast<size_t>(n), false);
  keep[0] = keep[static_cast<size_t>(far)] = true;
  // Spans (first, last) of indices along the loop, last possibly n (= vertex 0 again).
  std::vector<std::pair<Eigen::Index, Eigen::Index>> spans{{0, far}, {far, n}};
  while (!spans.empty()) {
    const auto [first, last] = spans.back();
    spans.pop_back();
    const Point a = row(loop, first), b = row(loop, last % n);
    double worst = -1;
    Eigen::Index worst_at = -1;
    for (Eigen::Index i = first + 1; i < last; ++i) {
      const double distance = segment_distance(row(loop, i), a, b);
      if (distance > worst) {
        worst = distance;
        worst_at = i;
      }
    }
    if (worst > tolerance) {
      keep[static_cast<size_t>(worst_at)] = true;
      spans.push_back({first, worst_at});
      spans.push_back({worst_at, last});
    }
  }
  std::vector<Eigen::Index> kept;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (keep[static_cast<size_t>(i)]) kept.push_back(i);
  }
  if (kept.size() < 3) return loop;
  Eigen::MatrixX2d out(static_cast<Eigen::Index>(kept.size()), 2);
  for (size_t i = 0; i < kept.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) = loop.row(kept[i]);
  return out;
}

// One connected piece of an offset region.
struct Piece {
  Eigen::MatrixX2d outer;               // counter-clockwise
  std::vector<Eigen::MatrixX2d> holes;  // clockwise
  double area = 0;                      // mm², holes subtracted
  double outer_length = 0;
};

bool piece_contains(const Piece& piece, const Point& p) {
  if (!inside_loop(piece.outer, p)) return false;
  for (const Eigen::MatrixX2d& hole : piece.holes) {
    if (inside_loop(hole, p)) return false;
  }
  return true;
}

// The region at distance ≥ depth from the outline. The offset runs on the original outline every
// time (note 4.1): round joins make it the exact distance level set up to the arc tolerance.
std::vector<Piece> offset_pieces(ClipperLib::ClipperOffset& offsetter, double depth, double scale) {
  ClipperLib::Paths paths;
  offsetter.Execute(paths, -depth * scale);
  // Rounding to the integer grid leaves the odd one-unit step backwards.
  ClipperLib::CleanPolygons(paths);
  std::vector<Piece> pieces;
  std::vector<Eigen::MatrixX2d> holes;
  for (const ClipperLib::Path& path : paths) {
    if (path.size() < 3) continue;
    Eigen::MatrixX2d loop = from_clipper_path(path, scale);
    const double area = signed_area(loop);
    if (area > 0) {
      Piece piece;
      piece.outer = std::move(loop);
      piece.area = area;
      piece.outer_length = loop_length(piece.outer);
      pieces.push_back(std::move(piece));
    } else if (area < 0) {
      holes.push_back(std::move(loop));
    }
  }
  // A hole belongs to the smallest outer loop around it (an island inside a hole has its own).
  for (Eigen::MatrixX2d& hole : holes) {
    int owner = -1;
    for (int p = 0; p < static_cast<int>(pieces.size()); ++p) {
      if (inside_loop(pieces[p].outer, row(hole, 0)) &&
          (owner < 0 || pieces[p].area < pieces[owner].area)) {
        owner = p;
      }
    }
    if (owner < 0) continue;  // not expected from Clipper; such a loop bounds nothing printable
    pieces[owner].area += signed_area(hole);
    pieces[owner].holes.push_back(std::move(hole));
  }
  return pieces;
}

// Compass search for a local maximum of the exact depth from `p`, steps from `step` down to 1e-6
// mm. Moves p to the deepest point found and returns its depth.
double climb_depth(const TileOutline& outline, Point& p, double step) {
  double best = outline_depth(outline, p);
  const double diagonal = std::sqrt(0.5);
  const Point directions[] = {{1, 0},
                              {-1, 0},
                              {0, 1},
                              {0, -1},
                              {diagonal, diagonal},
                              {-diagonal, diagonal},
                              {diagonal, -diagonal},
                              {-diagonal, -diagonal}};
  for (int moves = 0; step > 1e-6 && moves < 10000; ++moves) {
    bool moved = false;
    for (const Point& direction : directions) {
      const Point q = p + step * direction;
      const double depth = outline_depth(outline, q);
      if (depth > best) {
        best = depth;
        p = q;
        moved = true;
      }
    }
    if (!moved) step /= 2;
  }
  return std::max(best, 0.0);
}

struct KeptPiece {
  Piece piece;
  int outer_ring = -1;
  std::vector<int> hole_rings;
};

struct Candidate {
  Eigen::MatrixX2d points;  // starting at the reference vertex
  int parent = -1;
  bool around_hole = false;
  int piece = 0;  // index among this level's kept pieces
  int hole = -1;  // index among the piece's holes
};

}  // namespace

TileRings tile_rings(const TileOutline& outline, const RingOptions& options) {
  const Resolved o = resolve(options);
  const CheckedOutline checked = checked_outline(outline);

  const Eigen::RowVector2d extent =
      checked.boundary.colwise().maxCoeff() - checked.boundary.colwise().minCoeff();
  if (extent.minCoeff() / 2 / o.pitch > kMaxLevels) {
    throw UserError(ErrorCategory::kResource,
                    fmt::format("{}: a tile {:.1f} x {:.1f} mm at pitch {} mm could need more than "
                                "{} rings; use a larger pitch",
                                source_of(outline), extent.x(), extent.y(), o.pitch, kMaxLevels));
  }

  // Half the arc tolerance goes to simplifying the outline, half to the chords of round joins.
  // Clipper spaces a round join's vertices evenly but ends it with a chord up to 1.5 steps long,
  // whose gap to the arc is up to 2.25 times its nominal tolerance.
  const double simplification = o.arc_tolerance / 2;
  const double arc_units = o.arc_tolerance / 2 * o.scale / 2.25;
  ClipperLib::ClipperOffset offsetter(2.0, arc_units);
  offsetter.AddPath(to_clipper_path(simplified(checked.boundary, simplification), o.scale),
                    ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  for (const Eigen::MatrixX2d& hole : checked.holes) {
    offsetter.AddPath(to_clipper_path(simplified(hole, simplification), o.scale),
                      ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  }

  TileRings result;
  std::vector<KeptPiece> previous;
  // Bracket of the region's maximal depth: non-empty at `deepest`, empty at `empty_at`.
  double deepest = 0, empty_at = -1;
  std::vector<Piece> deepest_pieces;
  const auto note_deepest = [&](const std::vector<Piece>& pieces, double depth) {
    deepest = depth;
    deepest_pieces = pieces;
  };

  for (int level = 0; level <= kMaxLevels; ++level) {
    const double depth = o.first_offset + level * o.pitch;
    std::vector<Piece> pieces = offset_pieces(offsetter, depth, o.scale);
    if (pieces.empty()) {
      empty_at = depth;
      break;
    }
    note_deepest(pieces, depth);

    std::vector<KeptPiece> kept;
    std::vector<Candidate> candidates;
    for (Piece& piece : pieces) {
      if (piece.outer_length < o.min_length || piece.area < o.min_area) continue;
      int container = -1;
      if (level > 0) {
        for (int p = 0; p < static_cast<int>(previous.size()); ++p) {
          if (piece_contains(previous[p].piece, row(piece.outer, 0))) {
            container = p;
            break;
          }
        }
        if (container < 0) continue;  // what it grew from was too small to print
      }
      const int index = static_cast<int>(kept.size());
      Candidate outer;
      outer.points = starting_at(piece.outer, reference_vertex(piece.outer));
      outer.parent = container < 0 ? -1 : previous[container].outer_ring;
      outer.piece = index;
      candidates.push_back(std::move(outer));
      for (int h = 0; h < static_cast<int>(piece.holes.size()); ++h) {
        Candidate around;
        around.points = starting_at(piece.holes[h], reference_vertex(piece.holes[h]));
        around.around_hole = true;
        around.piece = index;
        around.hole = h;
        if (container >= 0) {
          // Distance level sets gain no new holes, so some ring around a hole one level out lies
          // inside this one: the hole it grew from (the first, where holes merged).
          around.parent = previous[container].outer_ring;
          for (const int ring : previous[container].hole_rings) {
            if (inside_loop(piece.holes[h], row(result.rings[ring].points, 0))) {
              around.parent = ring;
              break;
            }
          }
        }
        candidates.push_back(std::move(around));
      }
      KeptPiece k;
      k.piece = std::move(piece);
      k.hole_rings.assign(k.piece.holes.size(), -1);
      kept.push_back(std::move(k));
    }
    if (kept.empty()) break;

    std::stable_sort(
        candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
          return std::make_tuple(a.parent, a.around_hole, a.points(0, 0), a.points(0, 1)) <
                 std::make_tuple(b.parent, b.around_hole, b.points(0, 0), b.points(0, 1));
        });
    for (Candidate& candidate : candidates) {
      const int index = static_cast<int>(result.rings.size());
      if (candidate.around_hole) {
        kept[candidate.piece].hole_rings[candidate.hole] = index;
      } else {
        kept[candidate.piece].outer_ring = index;
      }
      result.rings.push_back({std::move(candidate.points), level, depth, candidate.parent});
    }
    previous = std::move(kept);
  }

  // Pieces too small to print can still be deep enough to hold points: go on to an empty offset.
  for (int step = 0; empty_at < 0 && step <= kMaxLevels; ++step) {
    const double depth = deepest + o.pitch;
    const std::vector<Piece> pieces = offset_pieces(offsetter, depth, o.scale);
    if (pieces.empty()) {
      empty_at = depth;
    } else {
      note_deepest(pieces, depth);
    }
  }
  // Locate the deepest points by bisection on the deepest region found, coarsely simplified,
  // rather than on the outline (the same region: erosions by discs add up): near the inradius
  // Clipper's offsets of the outline cost ~n² crossings. Then climb the exact depth from there.
  if (deepest_pieces.empty()) deepest_pieces = offset_pieces(offsetter, 0, o.scale);
  ClipperLib::ClipperOffset deeper(2.0, arc_units);
  for (const Piece& piece : deepest_pieces) {
    deeper.AddPath(to_clipper_path(simplified(piece.outer, o.arc_tolerance), o.scale),
                   ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    for (const Eigen::MatrixX2d& hole : piece.holes) {
      deeper.AddPath(to_clipper_path(simplified(hole, o.arc_tolerance), o.scale),
                     ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    }
  }
  Point deepest_point = deepest_pieces.empty()
                            ? row(checked.boundary, 0)
                            : Point(deepest_pieces.front().outer.colwise().mean().transpose());
  double low = 0, high = empty_at - deepest;
  while (high - low > kBisectionTolerance) {
    const double middle = (low + high) / 2;
    const std::vector<Piece> pieces = offset_pieces(deeper, middle, o.scale);
    if (pieces.empty()) {
      high = middle;
    } else {
      deepest_point = pieces.front().outer.colwise().mean().transpose();
      low = middle;
    }
  }
  const TileOutline exact{checked.boundary, checked.holes, outline.source};
  result.max_depth = climb_depth(exact, deepest_point, 2 * o.arc_tolerance);

  if (result.rings.empty()) {
    // A disc holds one ring when its radius reaches first_offset plus the smallest ring radius
    // that passes min_length and min_area.
    const double smallest_ring_radius =
        std::max(o.min_length / (2 * std::numbers::pi), std::sqrt(o.min_area / std::numbers::pi));
    const double needed = 2 * (o.first_offset + smallest_ring_radius);
    refuse_geometry(outline,
                    fmt::format("the tile is too small for one ring: its widest inscribed circle "
                                "has a diameter of about {:.3g} mm (near {}), and a tile needs a "
                                "diameter of at least {:.3g} mm for one ring at pitch {} mm; "
                                "enlarge the tile or print a finer pitch",
                                2 * result.max_depth, point_text(deepest_point), needed, o.pitch));
  }
  return result;
}

double outline_depth(const TileOutline& outline, const Eigen::Vector2d& p) {
  if (outline.boundary.rows() < 3) {
    throw std::invalid_argument("outline_depth: the boundary has fewer than 3 points");
  }
  double distance = distance_to_loop(outline.boundary, p);
  bool inside = inside_loop(outline.boundary, p);
  for (const Eigen::MatrixX2d& hole : outline.holes) {
    if (hole.rows() < 2) continue;
    distance = std::min(distance, distance_to_loop(hole, p));
    if (inside_loop(hole, p)) inside = false;
  }
  return inside ? distance : -distance;
}

std::vector<std::vector<int>> ring_chains(const TileRings& rings) {
  const int count = static_cast<int>(rings.rings.size());
  std::vector<std::vector<int>> children(static_cast<size_t>(count));
  std::vector<int> roots;
  for (int i = 0; i < count; ++i) {
    const Ring& ring = rings.rings[i];
    if (ring.parent < 0) {
      roots.push_back(i);
      continue;
    }
    if (ring.parent >= i || rings.rings[ring.parent].level != ring.level - 1) {
      throw std::invalid_argument(fmt::format(
          "ring_chains: ring {} (level {}) has parent {}, which is not an earlier ring one level "
          "out",
          i, ring.level, ring.parent));
    }
    children[ring.parent].push_back(i);
  }
  std::vector<std::vector<int>> chains;
  std::vector<int> stack(roots.rbegin(), roots.rend());
  while (!stack.empty()) {
    int ring = stack.back();
    stack.pop_back();
    std::vector<int> chain{ring};
    while (children[ring].size() == 1) {
      ring = children[ring].front();
      chain.push_back(ring);
    }
    chains.push_back(std::move(chain));
    stack.insert(stack.end(), children[ring].rbegin(), children[ring].rend());
  }
  return chains;
}

namespace {

// A ring as the nozzle travels it: counter-clockwise, from its reference point, by arc length.
struct Track {
  Eigen::MatrixX2d points;
  std::vector<double> at_vertex;  // arc length at each vertex, then the total
  double length = 0;
  double level = 0;

  double wrap(double s) const { return s - length * std::floor(s / length); }

  Point at(double s) const {
    s = wrap(s);
    const auto next = std::upper_bound(at_vertex.begin(), at_vertex.end(), s);
    const Eigen::Index i =
        std::clamp<Eigen::Index>(next - at_vertex.begin() - 1, 0, points.rows() - 1);
    const double span = at_vertex[i + 1] - at_vertex[i];
    const double t = span > 0 ? (s - at_vertex[i]) / span : 0.0;
    return (1 - t) * row(points, i) + t * row(points, (i + 1) % points.rows());
  }

  // Arc length of the point nearest p.
  double nearest(const Point& p) const {
    double best = std::numeric_limits<double>::infinity(), best_s = 0;
    const Eigen::Index n = points.rows();
    for (Eigen::Index i = 0; i < n; ++i) {
      const Point a = row(points, i), ab = row(points, (i + 1) % n) - a;
      const double length2 = ab.squaredNorm();
      const double t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
      const double distance = (a + t * ab - p).squaredNorm();
      if (distance < best) {
        best = distance;
        best_s = at_vertex[i] + t * (at_vertex[i + 1] - at_vertex[i]);
      }
    }
    return best_s;
  }

  // Arc lengths of the vertices strictly between s0 and s1 (s0 < s1, unwrapped).
  void vertices_between(double s0, double s1, std::vector<double>& out) const {
    const double base = length * std::floor(s0 / length);
    for (int lap = 0; base + lap * length < s1; ++lap) {
      for (Eigen::Index i = 0; i < points.rows(); ++i) {
        const double s = base + lap * length + at_vertex[i];
        if (s > s0 && s < s1) out.push_back(s);
      }
    }
  }
};

Track make_track(const Ring& ring) {
  Track track;
  track.points = starting_at(ring.points, reference_vertex(ring.points));
  if (signed_area(track.points) < 0) track.points = reversed(track.points);
  const Eigen::Index n = track.points.rows();
  track.at_vertex.assign(static_cast<size_t>(n) + 1, 0.0);
  for (Eigen::Index i = 0; i < n; ++i) {
    track.at_vertex[i + 1] =
        track.at_vertex[i] + (row(track.points, (i + 1) % n) - row(track.points, i)).norm();
  }
  track.length = track.at_vertex.back();
  track.level = ring.level;
  return track;
}

struct PathBuilder {
  std::vector<Point> points;
  std::vector<double> coordinates;
  double spacing;  // ≤ 0: no resampling

  void add(const Point& p, double coordinate) {
    if (!points.empty() && (p - points.back()).norm() < 1e-9) return;
    points.push_back(p);
    coordinates.push_back(coordinate);
  }

  // Along a ring from arc length s0 to s1 (unwrapped, s0 ≤ s1).
  void walk(const Track& track, double s0, double s1) {
    std::vector<double> stops{s0};
    track.vertices_between(s0, s1, stops);
    stops.push_back(s1);
    for (size_t k = 0; k + 1 < stops.size(); ++k) {
      const int parts =
          spacing > 0
              ? std::max(1, static_cast<int>(std::ceil((stops[k + 1] - stops[k]) / spacing)))
              : 1;
      for (int j = 0; j < parts; ++j) {
        add(track.at(stops[k] + (stops[k + 1] - stops[k]) * j / parts), track.level);
      }
    }
    add(track.at(s1), track.level);
  }
};

}  // namespace

RingPath join_rings(const TileRings& rings, const std::vector<int>& sequence,
                    const JoinOptions& options) {
  for (const auto& [name, value] :
       {std::pair{"blend length", options.blend_length}, std::pair{"seam", options.seam},
        std::pair{"point spacing", options.point_spacing}}) {
    if (!std::isfinite(value)) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format("ring path {} {} is not a number; give a finite value", name, value));
    }
  }
  if (!(options.max_blend_fraction > 0 && options.max_blend_fraction <= 1)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("ring path maximum blend fraction {} must lie in (0, 1]",
                                options.max_blend_fraction));
  }
  if (sequence.empty()) throw std::invalid_argument("join_rings: the ring sequence is empty");
  const int count = static_cast<int>(rings.rings.size());
  for (size_t k = 0; k < sequence.size(); ++k) {
    const int i = sequence[k];
    if (i < 0 || i >= count) {
      throw std::invalid_argument(
          fmt::format("join_rings: ring index {} is out of range (there are {} rings)", i, count));
    }
    if (rings.rings[i].points.rows() < 3) {
      throw std::invalid_argument(fmt::format("join_rings: ring {} has fewer than 3 points", i));
    }
    if (k == 0) continue;
    const int j = sequence[k - 1];
    const Ring &a = rings.rings[j], &b = rings.rings[i];
    const bool nested =
        (b.parent == j && b.level == a.level + 1) || (a.parent == i && a.level == b.level + 1);
    if (!nested) {
      throw std::invalid_argument(fmt::format(
          "join_rings: rings {} (level {}) and {} (level {}) follow each other but are not parent "
          "and child",
          j, a.level, i, b.level));
    }
  }

  PathBuilder path{{}, {}, options.point_spacing};
  Track current = make_track(rings.rings[sequence.front()]);
  double start = current.length * (options.seam - std::floor(options.seam));
  for (size_t k = 0; k < sequence.size(); ++k) {
    if (k + 1 == sequence.size()) {
      path.walk(current, start, start + current.length);
      break;
    }
    Track next = make_track(rings.rings[sequence[k + 1]]);
    const double spacing =
        std::abs(rings.rings[sequence[k + 1]].depth - rings.rings[sequence[k]].depth);
    const double requested = options.blend_length < 0 ? 8 * spacing : options.blend_length;
    const double blend = std::min(requested, options.max_blend_fraction * current.length);
    if (blend <= 0) {
      // Paper mode: the whole ring, then a straight jog to the nearest point of the next.
      path.walk(current, start, start + current.length);
      start = next.nearest(current.at(start));
      current = std::move(next);
      continue;
    }
    const double blend_from = start + current.length - blend;
    path.walk(current, start, blend_from);
    // The point on the next ring starts nearest the blend's beginning and runs along the next ring
    // as far as the nozzle runs along this one: the next blend then begins where this one's target
    // began, and the two connectors lie side by side a pitch apart (note 4.3b). On small rings that
    // would put the target far ahead of (or behind) the nozzle's nearest point and pull the
    // connector across the inner ring: keep the lead within spacing × (shorter / longer ring),
    // which for a disc keeps every point between the two rings.
    const double target_from = next.nearest(current.at(blend_from));
    double projected = next.nearest(current.at(blend_from + blend)) - target_from;
    projected -= next.length * std::round(projected / next.length);
    const double lead =
        spacing * std::min(current.length, next.length) / std::max(current.length, next.length);
    const double target_run = std::max(0.0, std::clamp(blend, projected - lead, projected + lead));
    const auto connector = [&](double t) -> Point {
      return (1 - t) * current.at(blend_from + t * blend) +
             t * next.at(target_from + t * target_run);
    };
    // Parameters t in [0, 1]: where either ring has a vertex, and evenly in between.
    std::vector<double> stops, on_next;
    current.vertices_between(blend_from, blend_from + blend, stops);
    for (double& s : stops) s = (s - blend_from) / blend;
    if (target_run > 0) {
      next.vertices_between(target_from, target_from + target_run, on_next);
      for (const double s : on_next) stops.push_back((s - target_from) / target_run);
    }
    const int uniform = 16;
    for (int j = 0; j <= uniform; ++j) stops.push_back(static_cast<double>(j) / uniform);
    std::sort(stops.begin(), stops.end());
    const auto coordinate = [&](double t) { return (1 - t) * current.level + t * next.level; };
    for (size_t j = 0; j < stops.size(); ++j) {
      const double t = std::clamp(stops[j], 0.0, 1.0);
      if (j > 0 && options.point_spacing > 0) {
        // The connector is nearly straight between stops: subdivide until short enough.
        const double t0 = std::clamp(stops[j - 1], 0.0, 1.0);
        const auto longest_part = [&](int parts) {
          double longest = 0;
          for (int i = 0; i < parts; ++i) {
            longest = std::max(longest, (connector(t0 + (t - t0) * (i + 1) / parts) -
                                         connector(t0 + (t - t0) * i / parts))
                                            .norm());
          }
          return longest;
        };
        int parts = 1;
        while (parts < 1 << 12 && longest_part(parts) > options.point_spacing) parts *= 2;
        for (int i = 1; i < parts; ++i) {
          const double u = t0 + (t - t0) * i / parts;
          path.add(connector(u), coordinate(u));
        }
      }
      path.add(connector(t), coordinate(t));
    }
    start = target_from + target_run;
    current = std::move(next);
  }

  RingPath result;
  const Eigen::Index n = static_cast<Eigen::Index>(path.points.size());
  result.points.resize(n, 2);
  result.ring_coordinate.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    result.points.row(i) = path.points[static_cast<size_t>(i)].transpose();
    result.ring_coordinate(i) = path.coordinates[static_cast<size_t>(i)];
  }
  return result;
}

}  // namespace flatmorph
