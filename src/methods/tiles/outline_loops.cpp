#include "methods/tiles/outline_loops.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include "common/angles.h"
#include "common/error.h"
#include "mesh/plane_geometry.h"

namespace flatmorph {
namespace outline_loops {
namespace {

// Segment pairs, cell entries and point-in-loop steps the crossing and nesting checks may spend:
// a drawing of a few hundred tiles needs well under 1 %, and a hostile one (thousands of loops
// drawn on top of each other) stops within a second.
constexpr double kMaxWork = 2e7;
// Cell entries of the crossing grid (8 bytes each), and pairs of loops that touch.
constexpr double kMaxGridEntries = 2e7;
constexpr double kMaxTouchingPairs = 1e5;

struct Work {
  double used = 0;
  const std::string& file;

  void add(double units) {
    used += units;
    if (used > kMaxWork) {
      throw UserError(ErrorCategory::kResource,
                      fmt::format("{}: checking the outlines for crossings and nesting takes too "
                                  "long (too many points, or loops nested too deep): split the "
                                  "drawing, or draw curves with fewer points",
                                  file));
    }
  }
};

// Twice the signed area, measured from the first point so that far-off loops keep their digits.
double twice_area(const std::vector<Point>& p) {
  double sum = 0;
  for (size_t i = 1; i + 1 < p.size(); ++i) sum += cross2(p[i] - p[0], p[i + 1] - p[0]);
  return sum;
}

double perimeter(const std::vector<Point>& p) {
  double sum = 0;
  for (size_t i = 0; i < p.size(); ++i) sum += (p[(i + 1) % p.size()] - p[i]).norm();
  return sum;
}

std::vector<Point> without_repeated_points(const std::vector<Point>& points, double tolerance) {
  std::vector<Point> out;
  out.reserve(points.size());
  for (const Point& p : points) {
    if (out.empty() || (p - out.back()).norm() > tolerance) out.push_back(p);
  }
  while (out.size() > 1 && (out.back() - out.front()).norm() <= tolerance) out.pop_back();
  return out;
}

std::string describe(const Origin& origin) {
  return fmt::format("the {} at line {}", origin.what, origin.line);
}

// The largest factor by which `m` stretches a vector (its largest singular value).
double stretch(const Eigen::Matrix2d& matrix) {
  // Scaled to its largest entry first, so that huge radii do not overflow the squares.
  const double scale = matrix.cwiseAbs().maxCoeff();
  if (!(scale > 0) || !std::isfinite(scale)) return scale;
  const Eigen::Matrix2d m = matrix / scale;
  const double sum = m.squaredNorm();
  const double det = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
  return scale * std::sqrt((sum + std::sqrt(std::max(0.0, sum * sum - 4 * det * det))) / 2);
}

// Whether some angle a + 2 pi k lies in [lo, hi].
bool angle_in(double a, double lo, double hi) {
  const double k = std::ceil((lo - a) / (2 * kPi));
  return a + 2 * kPi * k <= hi;
}

struct Box {
  Point min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Point max = -min;
  void add(const Point& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

// --- Crossings -------------------------------------------------------------------------------

struct LoopRef {
  const std::vector<Point>* points;
  const Origin* origin;
};

enum class Side { kInside, kOutside, kOn };

Side side_of(const Point& p, const std::vector<Point>& loop, double eps, Work& work) {
  work.add(static_cast<double>(loop.size()));
  bool inside = false;
  for (size_t i = 0; i < loop.size(); ++i) {
    const Point& a = loop[i];
    const Point& b = loop[i + 1 == loop.size() ? 0 : i + 1];
    // Only an edge whose box, widened by eps, holds p can be within eps of it.
    if (p.y() >= std::min(a.y(), b.y()) - eps && p.y() <= std::max(a.y(), b.y()) + eps &&
        p.x() >= std::min(a.x(), b.x()) - eps && p.x() <= std::max(a.x(), b.x()) + eps &&
        segment_distance(p, a, b) <= eps) {
      return Side::kOn;
    }
    // Even-odd count of the edges a ray towards +x crosses.
    if (side_crosses_ray(p, a, b)) inside = !inside;
  }
  return inside ? Side::kInside : Side::kOutside;
}

enum class Meeting { kApart, kCross, kTouch };

// How segments ab and cd meet. kCross: each passes through the other's inside, its ends more than
// `eps` away on both sides; `at` is the crossing. kTouch: otherwise within eps of each other
// (touching ends, a corner on an edge, overlapping collinear edges as of tiles side by side,
// §6.3); `at` is the first end that touches, `ends` has a bit for each end that does (a, b, c, d)
// or none when the segments touch only inside both.
Meeting meeting(const Point& a, const Point& b, const Point& c, const Point& d, double eps,
                Point& at, unsigned& ends) {
  const Point ab = b - a, cd = d - c;
  const double lab = ab.norm();
  const double dc = cross2(ab, c - a) / lab, dd = cross2(ab, d - a) / lab;
  // Both ends of one segment farther than eps on one side of the other's line: apart. Most pairs
  // sharing a grid cell end here.
  if ((dc > eps && dd > eps) || (dc < -eps && dd < -eps)) return Meeting::kApart;
  const double lcd = cd.norm();
  const double da = cross2(cd, a - c) / lcd, db = cross2(cd, b - c) / lcd;
  if ((da > eps && db > eps) || (da < -eps && db < -eps)) return Meeting::kApart;
  if (((dc > eps && dd < -eps) || (dc < -eps && dd > eps)) &&
      ((da > eps && db < -eps) || (da < -eps && db > eps))) {
    at = c + cd * (dc / (dc - dd));
    return Meeting::kCross;
  }
  ends = 0;
  const Point* end_points[4] = {&a, &b, &c, &d};
  for (unsigned k = 0; k < 4; ++k) {
    const Point& p = *end_points[k];
    const double distance = k < 2 ? segment_distance(p, c, d) : segment_distance(p, a, b);
    if (distance <= eps) {
      if (ends == 0) at = p;
      ends |= 1u << k;
    }
  }
  return ends != 0 ? Meeting::kTouch : Meeting::kApart;
}

// Whether two passes of outline through the point x cross there: the pass from p0 to p1 (through
// x) and the pass from q0 to q1 cross when q0 and q1 lie on different sides of it, i.e. exactly
// one of them is in the angle swept counter-clockwise from p0 to p1. Directions that coincide
// (edges running along each other) decide nothing.
bool passes_cross(const Point& x, const Point& p0, const Point& p1, const Point& q0,
                  const Point& q1) {
  const auto angle = [&](const Point& p) { return std::atan2(p.y() - x.y(), p.x() - x.x()); };
  const auto from_p0 = [&](const Point& p) {
    double a = angle(p) - angle(p0);
    while (a < 0) a += 2 * kPi;
    while (a >= 2 * kPi) a -= 2 * kPi;
    return a;
  };
  const double sweep = from_p0(p1), a0 = from_p0(q0), a1 = from_p0(q1);
  constexpr double kSame = 1e-9;  // radians
  for (double a : {a0, a1}) {
    if (a < kSame || a > 2 * kPi - kSame || std::abs(a - sweep) < kSame) return false;
  }
  return (a0 < sweep) != (a1 < sweep);
}

[[noreturn]] void refuse_crossing(const std::string& file, const Origin& first,
                                  const Origin& second, bool same, const Point& at) {
  if (same) {
    throw UserError(
        ErrorCategory::kGeometry,
        fmt::format("{}: the {} crosses itself at {}: a tile outline must be a simple closed "
                    "loop; fix the drawing",
                    where(file, first.line), first.what, format_point(at)));
  }
  const Origin& early = first.line <= second.line ? first : second;
  const Origin& late = first.line <= second.line ? second : first;
  throw UserError(
      ErrorCategory::kGeometry,
      fmt::format("{}: the {} and {} cross at {}: tile outlines must not overlap, "
                  "and a hole must lie inside its tile; fix the drawing",
                  where(file, early.line), early.what, describe(late), format_point(at)));
}

[[noreturn]] void refuse_duplicate(const std::string& file, const Origin& first,
                                   const Origin& second) {
  const Origin& early = first.line <= second.line ? first : second;
  const Origin& late = first.line <= second.line ? second : first;
  throw UserError(ErrorCategory::kGeometry,
                  fmt::format("{}: the {} and {} are the same outline drawn twice: delete one of "
                              "them",
                              where(file, early.line), early.what, describe(late)));
}

// A loop touching itself (a vertex on one of its own edges or vertices, found at `first` of
// segment `i` near segment `j`): refused if its two passes through the place cross, as in a
// figure eight through one of its vertices.
void check_self_touch(const std::vector<Point>& p, size_t i, size_t j, unsigned ends, double eps,
                      const std::string& file, const Origin& origin) {
  const size_t n = p.size();
  const auto at = [&](size_t k) -> const Point& { return p[k % n]; };
  // The touching end, as the vertex v of one segment, and the other segment (s, s + 1).
  size_t v, s;
  if ((ends & 3u) != 0) {
    v = (ends & 1u) != 0 ? i : i + 1;
    s = j;
  } else {
    v = (ends & 4u) != 0 ? j : j + 1;
    s = i;
  }
  const Point& x = at(v);
  const Point &p0 = at(v + n - 1), &p1 = at(v + 1);
  // The other pass: through the segment's end when x is at it, else straight along it.
  Point q0 = at(s), q1 = at(s + 1);
  if ((x - at(s)).norm() <= eps) {
    q0 = at(s + n - 1);
  } else if ((x - at(s + 1)).norm() <= eps) {
    q1 = at(s + 2);
  }
  if (passes_cross(x, p0, p1, q0, q1)) refuse_crossing(file, origin, origin, true, x);
}

// Two loops that touch (found at `at`) may still pass through each other there, at a corner or
// along a shared edge. Points of `b` near the places where it touches other loops (the touching
// vertices, their neighbours, the middles of edges between two touching vertices) must then lie
// all inside `a` or all outside it, ignoring those on `a`; likewise with `a` and `b` swapped.
void check_touching_pair(const LoopRef& a, const LoopRef& b, const std::vector<char>& touches_a,
                         const std::vector<char>& touches_b, const Point& at,
                         const std::string& file, double eps, Work& work) {
  const auto one_way = [&](const std::vector<Point>& inner, const std::vector<char>& touches,
                           const std::vector<Point>& outer) {
    const size_t n = inner.size();
    work.add(static_cast<double>(n));
    bool inside = false, outside = false;
    const auto ask = [&](const Point& p) {
      const Side side = side_of(p, outer, eps, work);
      inside = inside || side == Side::kInside;
      outside = outside || side == Side::kOutside;
    };
    for (size_t k = 0; k < n && !(inside && outside); ++k) {
      const bool here = touches[k] != 0, next = touches[(k + 1) % n] != 0;
      if (here || next || touches[(k + n - 1) % n] != 0) ask(inner[k]);
      if (here && next) ask((inner[k] + inner[(k + 1) % n]) / 2);
    }
    return inside && outside;
  };
  if (one_way(*b.points, touches_b, *a.points) || one_way(*a.points, touches_a, *b.points)) {
    refuse_crossing(file, *a.origin, *b.origin, false, at);
  }
}

// Refuses the first proper crossing between two segments of the loops (a loop's neighbouring
// segments excepted), then loops that touch and overlap. The segments go into the cells of a
// uniform grid they pass near, so that only segments sharing a cell are compared.
void check_crossings(const std::vector<LoopRef>& loops, const std::string& file, double eps,
                     Work& work) {
  std::vector<std::pair<uint32_t, uint32_t>> segments;  // loop, first point
  Box box;
  for (uint32_t l = 0; l < loops.size(); ++l) {
    for (uint32_t i = 0; i < loops[l].points->size(); ++i) {
      segments.emplace_back(l, i);
      box.add((*loops[l].points)[i]);
    }
  }
  if (segments.empty()) return;
  // About as many cells as segments, but none smaller than twice the mean segment: loops drawn
  // on top of one another then share cells instead of each segment filling dozens.
  double total_length = 0;
  for (const auto& s : segments) {
    const std::vector<Point>& p = *loops[s.first].points;
    total_length += (p[(s.second + 1) % p.size()] - p[s.second]).norm();
  }
  const double cells_per_side =
      std::clamp(std::ceil(std::sqrt(static_cast<double>(segments.size()))), 1.0, 2048.0);
  const double h = std::max({(box.max - box.min).maxCoeff() / cells_per_side,
                             2 * total_length / static_cast<double>(segments.size()), eps, 1e-9});
  const auto cell_count = [&](double extent) {
    return static_cast<int64_t>(std::min(cells_per_side, std::floor(extent / h) + 1));
  };
  const int64_t columns = cell_count(box.max.x() - box.min.x());
  const int64_t rows = cell_count(box.max.y() - box.min.y());
  const auto cell_of = [&](double v, double lo, int64_t count) {
    return std::clamp(static_cast<int64_t>(std::floor((v - lo) / h)), int64_t{0}, count - 1);
  };
  const auto segment_ends = [&](const std::pair<uint32_t, uint32_t>& s) {
    const std::vector<Point>& p = *loops[s.first].points;
    return std::make_pair(p[s.second], p[(s.second + 1) % p.size()]);
  };

  std::vector<uint64_t> entries;  // cell << 32 | segment
  for (uint32_t s = 0; s < segments.size(); ++s) {
    const auto [a, b] = segment_ends(segments[s]);
    const double x_min = std::min(a.x(), b.x()), x_max = std::max(a.x(), b.x());
    const int64_t c0 = cell_of(x_min - eps, box.min.x(), columns);
    const int64_t c1 = cell_of(x_max + eps, box.min.x(), columns);
    for (int64_t c = c0; c <= c1; ++c) {
      // The cells of this column the segment passes within eps of: its y over the column's x
      // (widened by eps), widened by eps.
      double y_lo = std::min(a.y(), b.y()), y_hi = std::max(a.y(), b.y());
      if (x_max - x_min > 1e-12) {
        // Captured by value: clang 14 cannot capture structured bindings.
        const Eigen::Vector2d from = a, to = b;
        const auto y_at = [&, from, to](double x) {
          x = std::clamp(x, x_min, x_max);
          return from.y() + (to.y() - from.y()) * (x - from.x()) / (to.x() - from.x());
        };
        const double ya = y_at(box.min.x() + c * h - eps);
        const double yb = y_at(box.min.x() + (c + 1) * h + eps);
        y_lo = std::min(ya, yb);
        y_hi = std::max(ya, yb);
      }
      const int64_t r0 = cell_of(y_lo - eps, box.min.y(), rows);
      const int64_t r1 = cell_of(y_hi + eps, box.min.y(), rows);
      work.add(static_cast<double>(r1 - r0 + 1));
      if (static_cast<double>(entries.size() + (r1 - r0 + 1)) > kMaxGridEntries) {
        work.add(kMaxWork);  // the same refusal
      }
      for (int64_t r = r0; r <= r1; ++r) {
        entries.push_back(static_cast<uint64_t>(c * rows + r) << 32 | s);
      }
    }
  }
  std::sort(entries.begin(), entries.end());

  // Pairs of loops found touching (where first found), and each loop's vertices that touch
  // another loop.
  std::map<std::pair<uint32_t, uint32_t>, Point> touching_pairs;
  std::vector<std::vector<char>> touches(loops.size());
  for (size_t l = 0; l < loops.size(); ++l) touches[l].assign(loops[l].points->size(), 0);
  for (size_t begin = 0; begin < entries.size();) {
    size_t end = begin + 1;
    while (end < entries.size() && entries[end] >> 32 == entries[begin] >> 32) ++end;
    for (size_t i = begin; i < end; ++i) {
      work.add(static_cast<double>(end - i - 1));
      const auto& si = segments[static_cast<uint32_t>(entries[i])];
      const auto [a, b] = segment_ends(si);
      for (size_t j = i + 1; j < end; ++j) {
        const auto& sj = segments[static_cast<uint32_t>(entries[j])];
        const bool same = si.first == sj.first;
        const size_t n = loops[si.first].points->size();
        if (same) {
          const size_t di = (si.second + n - sj.second) % n;
          if (di == 1 || di == n - 1) continue;  // neighbours share a point
        }
        const auto [c, d] = segment_ends(sj);
        Point at;
        unsigned ends = 0;
        const Meeting how = meeting(a, b, c, d, eps, at, ends);
        if (how == Meeting::kCross) {
          refuse_crossing(file, *loops[si.first].origin, *loops[sj.first].origin, same, at);
        }
        if (how != Meeting::kTouch) continue;
        work.add(4);  // the distances cost more than a pair kept apart
        if (same) {
          check_self_touch(*loops[si.first].points, si.second, sj.second, ends, eps, file,
                           *loops[si.first].origin);
          continue;
        }
        const size_t m = loops[sj.first].points->size();
        if ((ends & 1u) != 0) touches[si.first][si.second] = 1;
        if ((ends & 2u) != 0) touches[si.first][(si.second + 1) % n] = 1;
        if ((ends & 4u) != 0) touches[sj.first][sj.second] = 1;
        if ((ends & 8u) != 0) touches[sj.first][(sj.second + 1) % m] = 1;
        touching_pairs.emplace(std::minmax(si.first, sj.first), at);
        if (static_cast<double>(touching_pairs.size()) > kMaxTouchingPairs) work.add(kMaxWork);
      }
    }
    begin = end;
  }
  // Loops of zero area are dropped later, whatever they touch.
  std::vector<bool> thin(loops.size());
  for (size_t l = 0; l < loops.size(); ++l) {
    const std::vector<Point>& p = *loops[l].points;
    thin[l] = std::abs(twice_area(p)) <= eps * perimeter(p);
  }
  for (const auto& [pair, at] : touching_pairs) {
    if (thin[pair.first] || thin[pair.second]) continue;
    check_touching_pair(loops[pair.first], loops[pair.second], touches[pair.first],
                        touches[pair.second], at, file, eps, work);
  }
}

// --- Nesting ---------------------------------------------------------------------------------

// Whether `inner` lies inside `outer` (they do not cross): its first point clearly inside or
// outside says so; points on `outer` (shared corners and edges) say nothing, then the midpoints
// of its edges are asked. kOn: every point and midpoint lies on `outer`.
Side loop_side(const std::vector<Point>& inner, const std::vector<Point>& outer, double eps,
               Work& work) {
  for (const Point& p : inner) {
    const Side side = side_of(p, outer, eps, work);
    if (side != Side::kOn) return side;
  }
  for (size_t i = 0; i < inner.size(); ++i) {
    const Point mid = (inner[i] + inner[(i + 1) % inner.size()]) / 2;
    const Side side = side_of(mid, outer, eps, work);
    if (side != Side::kOn) return side;
  }
  return Side::kOn;
}

Eigen::MatrixX2d to_matrix(const std::vector<Point>& points, bool counter_clockwise) {
  const bool reverse = (twice_area(points) > 0) != counter_clockwise;
  const Eigen::Index n = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixX2d m(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    // Reversed from the same first point.
    m.row(i) = points[static_cast<size_t>(reverse ? (n - i) % n : i)].transpose();
  }
  return m;
}

}  // namespace

std::string where(const std::string& file, long long line) {
  return fmt::format("{}:{}", file, line);
}

std::string format_point(const Point& p) {
  // Four decimals (0.1 um) for a drawing's coordinates, exponents for absurd ones.
  const auto coordinate = [](double v) {
    return std::abs(v) < 1e9 ? fmt::format("{:.4f}", v) : fmt::format("{:.6g}", v);
  };
  return fmt::format("({}, {}) mm", coordinate(p.x()), coordinate(p.y()));
}

std::string source_of(const std::string& file, const Origin& origin) {
  return fmt::format("{}: {} at line {}", file, origin.what, origin.line);
}

void check_options(const OutlineReadOptions& options) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(options.chord_tolerance) || !positive(options.join_tolerance)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("the chord tolerance ({} mm) and the join tolerance ({} mm) of "
                                "the outline reader must be positive numbers of millimetres",
                                options.chord_tolerance, options.join_tolerance));
  }
  if (options.max_points < 3) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("the outline reader's point limit ({}) must allow at least one "
                                "triangle",
                                options.max_points));
  }
}

void check_size(size_t size, const OutlineReadOptions& options, const std::string& file) {
  if (size > options.max_bytes) {
    throw UserError(ErrorCategory::kResource,
                    fmt::format("{}: {} bytes is more than flatmorph reads for tile outlines ({} "
                                "bytes): remove everything but the outlines from the drawing",
                                file, size, options.max_bytes));
  }
}

void take_points(PointBudget& budget, double count, const std::string& at) {
  if (!(count <= static_cast<double>(budget.max - budget.used))) {
    throw UserError(ErrorCategory::kResource,
                    fmt::format("{}: the drawing has more than {} points (curves included, cut "
                                "into chords): simplify it, or draw fewer tiles per file",
                                at, budget.max));
  }
  budget.used += static_cast<size_t>(count);
}

void check_point(const Point& p, const std::string& at, const std::string& what) {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: {} is not a finite point ({}, {}): fix the drawing", at, what,
                                p.x(), p.y()));
  }
  if (std::abs(p.x()) > kMaxCoordinate || std::abs(p.y()) > kMaxCoordinate) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: {} lies at {}, more than {:g} mm (1 km) from the origin: "
                                "check the drawing's units and coordinates",
                                at, what, format_point(p), kMaxCoordinate));
  }
}

void append_arc_interior(const EllipseArc& arc, const OutlineReadOptions& options,
                         PointBudget& budget, const std::string& at, const std::string& what,
                         std::vector<Point>& out) {
  const double sigma = stretch(arc.axes);
  if (!arc.axes.allFinite() || !std::isfinite(sigma) || !arc.centre.allFinite() ||
      !std::isfinite(arc.start) || !std::isfinite(arc.sweep)) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: {} is too large to compute (its centre, radius or angles are "
                                "not finite numbers): fix the drawing",
                                at, what));
  }
  // A chord of parameter step phi strays at most sigma (1 - cos(phi / 2)) = 2 sigma
  // sin^2(phi / 4) from the curve: the unit circle's sagitta, stretched at most sigma times.
  const double ratio = options.chord_tolerance / (2 * sigma);
  const double phi = ratio >= 0.5 ? kPi / 2 : std::min(kPi / 2, 4 * std::asin(std::sqrt(ratio)));
  const double chords = std::ceil(std::abs(arc.sweep) / phi);
  if (!(chords > 1)) return;

  // The arc's extent, before any point is made: x(t) = cx + R cos(t - alpha) peaks where
  // t = alpha (mod 2 pi) if the arc reaches that angle, else at an end.
  const double lo = std::min(arc.start, arc.start + arc.sweep);
  const double hi = std::max(arc.start, arc.start + arc.sweep);
  for (int k = 0; k < 2; ++k) {
    const double radius = std::hypot(arc.axes(k, 0), arc.axes(k, 1));
    const double alpha = std::atan2(arc.axes(k, 1), arc.axes(k, 0));
    const auto value = [&](double t) {
      return arc.centre(k) + arc.axes(k, 0) * std::cos(t) + arc.axes(k, 1) * std::sin(t);
    };
    double top = std::max(value(lo), value(hi)), bottom = std::min(value(lo), value(hi));
    if (angle_in(alpha, lo, hi)) top = arc.centre(k) + radius;
    if (angle_in(alpha + kPi, lo, hi)) bottom = arc.centre(k) - radius;
    if (top > kMaxCoordinate || bottom < -kMaxCoordinate) {
      const double reach = top > kMaxCoordinate ? top : bottom;
      throw UserError(ErrorCategory::kGeometry,
                      fmt::format("{}: {} reaches {} = {:.6g} mm, more than {:g} mm (1 km) from "
                                  "the origin: check its radius (or bulge) and the drawing's "
                                  "units",
                                  at, what, k == 0 ? "x" : "y", reach, kMaxCoordinate));
    }
  }
  take_points(budget, chords - 1, at);
  const int n = static_cast<int>(chords);
  for (int i = 1; i < n; ++i) {
    const double t = arc.start + arc.sweep * i / n;
    out.push_back(arc.centre + arc.axes * Point(std::cos(t), std::sin(t)));
  }
}

std::vector<DrawnLoop> chain_pieces(const std::vector<OpenPiece>& pieces, const std::string& file,
                                    const OutlineReadOptions& options,
                                    std::vector<std::string>& warnings) {
  const double tolerance = options.join_tolerance;
  std::vector<DrawnLoop> loops;
  std::vector<size_t> open;  // pieces to chain
  size_t dropped = 0;
  long long dropped_line = 0;
  for (size_t k = 0; k < pieces.size(); ++k) {
    const std::vector<Point>& p = pieces[k].points;
    if (p.size() < 2) throw std::invalid_argument("chain_pieces: a piece with fewer than 2 points");
    double reach = 0;
    for (const Point& q : p) reach = std::max(reach, (q - p.front()).norm());
    if (reach <= tolerance) {
      if (dropped++ == 0) dropped_line = pieces[k].origin.line;
      continue;
    }
    if ((p.back() - p.front()).norm() <= tolerance) {
      // Closed by itself (an arc of 360 degrees less a hair).
      loops.push_back({std::vector<Point>(p.begin(), p.end() - 1), pieces[k].origin});
      continue;
    }
    open.push_back(k);
  }
  if (dropped > 0) {
    warnings.push_back(
        fmt::format("{}: {} LINE, ARC or polyline piece(s) of zero length (the "
                    "first at line {}) are not read",
                    file, dropped, dropped_line));
  }

  // Ends on a grid of cells `tolerance` wide: an end's partners lie in the 3 x 3 cells around it.
  const size_t ends = 2 * open.size();
  const auto end_point = [&](size_t e) -> const Point& {
    const std::vector<Point>& p = pieces[open[e / 2]].points;
    return e % 2 == 0 ? p.front() : p.back();
  };
  const auto cell = [&](double v) { return static_cast<int64_t>(std::floor(v / tolerance)); };
  std::vector<std::tuple<int64_t, int64_t, size_t>> sorted;
  sorted.reserve(ends);
  for (size_t e = 0; e < ends; ++e) {
    sorted.emplace_back(cell(end_point(e).x()), cell(end_point(e).y()), e);
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<size_t> partner(ends, SIZE_MAX);
  const auto describe_end = [&](size_t e) {
    return fmt::format("the {} at line {}", pieces[open[e / 2]].origin.what,
                       pieces[open[e / 2]].origin.line);
  };
  for (size_t e = 0; e < ends; ++e) {
    const Point& p = end_point(e);
    std::vector<size_t> near;
    for (int64_t dx = -1; dx <= 1 && near.size() < 2; ++dx) {
      for (int64_t dy = -1; dy <= 1 && near.size() < 2; ++dy) {
        const auto key = std::make_tuple(cell(p.x()) + dx, cell(p.y()) + dy, size_t{0});
        for (auto it = std::lower_bound(sorted.begin(), sorted.end(), key);
             it != sorted.end() && std::get<0>(*it) == std::get<0>(key) &&
             std::get<1>(*it) == std::get<1>(key) && near.size() < 2;
             ++it) {
          const size_t other = std::get<2>(*it);
          if (other / 2 != e / 2 && (end_point(other) - p).norm() <= tolerance) {
            near.push_back(other);
          }
        }
      }
    }
    if (near.size() >= 2) {
      std::sort(near.begin(), near.end());
      throw UserError(
          ErrorCategory::kTopology,
          fmt::format("{}: three or more ends of lines and arcs meet at {} ({}, {} and {}): an "
                      "outline must be one closed loop without branches; remove the duplicate or "
                      "extra entities",
                      where(file, pieces[open[e / 2]].origin.line), format_point(p),
                      describe_end(e), describe_end(near[0]), describe_end(near[1])));
    }
    if (!near.empty()) partner[e] = near[0];
  }
  for (size_t e = 0; e < ends; ++e) {
    if (partner[e] != SIZE_MAX) continue;
    // The other side of the gap: the nearest end that is loose too.
    const Point& p = end_point(e);
    size_t nearest = SIZE_MAX;
    for (size_t o = 0; o < ends; ++o) {
      if (o != e && partner[o] == SIZE_MAX &&
          (nearest == SIZE_MAX || (end_point(o) - p).norm() < (end_point(nearest) - p).norm())) {
        nearest = o;
      }
    }
    const std::string closest =
        nearest == SIZE_MAX
            ? std::string("no other end is loose")
            : fmt::format("the nearest loose end is {:.4g} mm away, at {}",
                          (end_point(nearest) - p).norm(), format_point(end_point(nearest)));
    throw UserError(
        ErrorCategory::kTopology,
        fmt::format("{}: the outline is open: the {} ends at {} and no other line or "
                    "arc ends within {:g} mm of it ({}): close the gap in the drawing "
                    "(join the pieces into one closed polyline) and save again",
                    where(file, pieces[open[e / 2]].origin.line), pieces[open[e / 2]].origin.what,
                    format_point(p), tolerance, closest));
  }

  std::vector<bool> used(open.size(), false);
  for (size_t first = 0; first < open.size(); ++first) {
    if (used[first]) continue;
    DrawnLoop loop;
    loop.origin = pieces[open[first]].origin;
    size_t count = 0;
    size_t end = 2 * first;  // the end the walk enters the piece by
    do {
      const size_t k = end / 2;
      used[k] = true;
      ++count;
      const std::vector<Point>& p = pieces[open[k]].points;
      // Each piece but its last point: that is the next piece's first.
      if (end % 2 == 0) {
        loop.points.insert(loop.points.end(), p.begin(), p.end() - 1);
      } else {
        loop.points.insert(loop.points.end(), p.rbegin(), p.rend() - 1);
      }
      end = partner[end ^ 1];
    } while (end / 2 != first);
    if (count > 1) {
      loop.origin.what =
          fmt::format("chain of {} pieces from the {}", count, pieces[open[first]].origin.what);
    }
    loops.push_back(std::move(loop));
  }
  std::stable_sort(loops.begin(), loops.end(), [](const DrawnLoop& a, const DrawnLoop& b) {
    return a.origin.line < b.origin.line;
  });
  return loops;
}

std::vector<TileOutline> nest_loops(std::vector<DrawnLoop> loops, const std::string& file,
                                    const OutlineReadOptions& options,
                                    std::vector<std::string>& warnings,
                                    const std::string& what_to_draw) {
  const double eps = options.join_tolerance;
  for (DrawnLoop& loop : loops) loop.points = without_repeated_points(loop.points, eps);
  // Crossings first: the lobes of a figure eight cancel in the area, which is no reason to drop
  // it. Loops of zero area cannot cross anything (proper crossings only).
  Work work{0, file};
  std::vector<LoopRef> refs;
  for (const DrawnLoop& loop : loops) {
    if (loop.points.size() >= 3) refs.push_back({&loop.points, &loop.origin});
  }
  check_crossings(refs, file, eps, work);

  std::vector<DrawnLoop> kept;
  for (DrawnLoop& loop : loops) {
    // A loop thinner than the tolerance on average (area <= tolerance x half the perimeter)
    // encloses nothing a nozzle could fill.
    if (loop.points.size() < 3 ||
        std::abs(twice_area(loop.points)) <= eps * perimeter(loop.points)) {
      warnings.push_back(
          fmt::format("{}: {} encloses no area (its points repeat or lie on a "
                      "line); it is not read",
                      where(file, loop.origin.line), describe(loop.origin)));
      continue;
    }
    kept.push_back(std::move(loop));
  }
  if (kept.empty()) {
    throw UserError(
        ErrorCategory::kGeometry,
        fmt::format("{}: no closed outline with an area is drawn: {}", file, what_to_draw));
  }

  // Which loops hold which: only a loop whose box holds another's box (and is larger) is asked.
  const size_t n = kept.size();
  std::vector<Box> boxes(n);
  std::vector<double> areas(n);
  for (size_t i = 0; i < n; ++i) {
    for (const Point& p : kept[i].points) boxes[i].add(p);
    areas[i] = std::abs(twice_area(kept[i].points)) / 2;
  }
  std::vector<size_t> by_left(n);
  std::iota(by_left.begin(), by_left.end(), size_t{0});
  std::stable_sort(by_left.begin(), by_left.end(),
                   [&](size_t a, size_t b) { return boxes[a].min.x() < boxes[b].min.x(); });
  std::vector<std::vector<size_t>> holders(n);
  for (size_t inner = 0; inner < n; ++inner) {
    for (size_t outer : by_left) {
      if (boxes[outer].min.x() > boxes[inner].min.x() + eps) break;
      work.add(1);
      if (outer == inner || areas[outer] < areas[inner] - eps * eps ||
          (boxes[inner].min - boxes[outer].min).minCoeff() < -eps ||
          (boxes[outer].max - boxes[inner].max).minCoeff() < -eps) {
        continue;
      }
      const Side side = loop_side(kept[inner].points, kept[outer].points, eps, work);
      if (side == Side::kInside) holders[inner].push_back(outer);
      if (side == Side::kOn) refuse_duplicate(file, kept[inner].origin, kept[outer].origin);
    }
  }

  // Even-odd: the number of loops around a loop decides what it is; a hole belongs to the
  // innermost loop around it, the one with one loop fewer around it.
  std::vector<size_t> tile_of(n, SIZE_MAX);
  std::vector<TileOutline> tiles;
  for (size_t i = 0; i < n; ++i) {
    if (holders[i].size() % 2 != 0) continue;
    tile_of[i] = tiles.size();
    tiles.push_back({to_matrix(kept[i].points, true), {}, source_of(file, kept[i].origin)});
  }
  for (size_t i = 0; i < n; ++i) {
    if (holders[i].size() % 2 == 0) continue;
    size_t parent = SIZE_MAX;
    for (size_t h : holders[i]) {
      if (holders[h].size() + 1 == holders[i].size()) parent = h;
    }
    if (parent == SIZE_MAX || tile_of[parent] == SIZE_MAX) {
      // Loops around one another must be nested like rings; otherwise two of them overlap,
      // touching or crossing only at corners.
      const Origin& a = kept[holders[i].front()].origin;
      throw UserError(
          ErrorCategory::kGeometry,
          fmt::format("{}: the {} lies partly inside {} and partly outside: the "
                      "outlines overlap (crossing at a corner); fix the drawing",
                      where(file, kept[i].origin.line), kept[i].origin.what, describe(a)));
    }
    tiles[tile_of[parent]].holes.push_back(to_matrix(kept[i].points, false));
  }
  return tiles;
}

}  // namespace outline_loops
}  // namespace flatmorph
