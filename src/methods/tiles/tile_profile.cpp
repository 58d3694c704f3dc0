#include "methods/tiles/tile_profile.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include "common/error.h"
#include "mesh/plane_geometry.h"

namespace flatmorph {
namespace {

// A first point this close to the axis is on it (mm).
constexpr double kAxisTolerance = 1e-9;
// Coordinates beyond this are unit mistakes (mm).
constexpr double kAbsurdCoordinate = 1e6;
constexpr int kMaxCsvRows = 100000;
// Library curves: the largest distance of a chord from the curve, relative to the flat radius (so
// that the sampling, and Sh, do not depend on the tile's size, note A11) and at most 1e-3 mm; and
// the finest sampling.
constexpr double kRelativeChordTolerance = 1e-7;
constexpr double kChordTolerance = 1e-3;
constexpr int kMaxSegments = 1 << 16;
// A wanted shrink this close to the reachable range is printed as wanted, not reported as clamped.
constexpr double kClampTolerance = 1e-9;
// Geodesy Fig. 2a: the least and the most shrink of the paper's PLA (0.30 and 0.05 mm layers).
constexpr double kSubtleConeShrinkage = 0.0793;
constexpr double kDramaticConeShrinkage = 0.3727;
// The polar angle θ at which a spherical cap's height over meridian length, (1 − cos θ)/θ, peaks
// (θ sin θ = 1 − cos θ): 0.7246. Beyond it a taller cap needs a longer meridian.
constexpr double kCapMaxAngle = 2.3311223704144224;

// ---------------------------------------------------------------------------------------------
// Arc length along a meridian.

std::vector<double> cumulative_length(const Eigen::MatrixX2d& m) {
  std::vector<double> cum(static_cast<size_t>(m.rows()), 0.0);
  for (Eigen::Index i = 1; i < m.rows(); ++i) {
    cum[i] = cum[i - 1] + (m.row(i) - m.row(i - 1)).norm();
  }
  return cum;
}

void require_within(const TileProfile& profile, const std::vector<double>& cum, double s) {
  if (!(s >= 0)) {
    throw std::invalid_argument(
        fmt::format("arc length {} along profile {} is negative or NaN", s, profile.name));
  }
  const double length = cum.back();
  if (s > length * (1 + 1e-9) + 1e-12) {
    throw UserError(
        ErrorCategory::kGeometry,
        fmt::format("profile {} is {:.3f} mm long along its meridian, but a ring sits at "
                    "flat radius {:.3f} mm; the meridian must be as long as the tile's "
                    "flat radius: scale the profile to the tile or make the tile smaller",
                    profile.name, length, s));
  }
}

Eigen::Vector2d point_at(const Eigen::MatrixX2d& m, const std::vector<double>& cum, double s) {
  if (s <= 0) return m.row(0).transpose();
  if (s >= cum.back()) return m.row(m.rows() - 1).transpose();
  const size_t i =
      static_cast<size_t>(std::upper_bound(cum.begin(), cum.end(), s) - cum.begin()) - 1;
  const double t = (s - cum[i]) / (cum[i + 1] - cum[i]);
  const Eigen::Index r = static_cast<Eigen::Index>(i);
  return ((1 - t) * m.row(r) + t * m.row(r + 1)).transpose();
}

// CHI 2019 §7: Sh = 1 − F(G(s))/s. The first point counts as the axis even when it sits a hair off.
double shrinkage_at(const Eigen::MatrixX2d& m, const std::vector<double>& cum, double s) {
  if (s <= 0) return 1 - (m(1, 0) - m(0, 0)) / cum[1];
  return 1 - (point_at(m, cum, s)(0) - m(0, 0)) / s;
}

// ---------------------------------------------------------------------------------------------
// The library's curved shapes: a unit shape with one aspect parameter p, rescaled per tile.

struct Shape {
  const char* name;
  // The point at parameter u ∈ [0, 1] (u = 0 the apex on the axis) of the shape with aspect p.
  Eigen::Vector2d (*point)(double p, double u);
  // The range of p over which height / meridian length grows monotonically.
  double p_lo;
  double p_hi;
};

Eigen::Vector2d spherical_cap_point(double theta, double u) {
  // Unit sphere, polar angle θ at the rim; rim at z = 0.
  return {std::sin(u * theta), std::cos(u * theta) - std::cos(theta)};
}
Eigen::Vector2d paraboloid_point(double p, double u) { return {u, p * (1 - u * u)}; }
Eigen::Vector2d gaussian_point(double p, double u) {
  // exp(−r²/(2σ²)) out to r = 3σ, shifted so that the rim is at z = 0 and scaled to height p.
  const double foot = std::exp(-4.5);
  return {u, p * (std::exp(-4.5 * u * u) - foot) / (1 - foot)};
}
Eigen::Vector2d concave_point(double p, double u) { return {u, p * (1 - u) * (1 - u)}; }
Eigen::Vector2d transition_point(double p, double u) {
  // Slope magnitude p(0.8 − 2u + 2.4u²)/0.6: falling from the pointed apex (concave top) to a least
  // at u = 0.42, then rising (convex steep skirt), so Sh has a minimum in between (note A5).
  return {u, p * (1 - (0.8 * u - u * u + 0.8 * u * u * u) / 0.6)};
}

constexpr Shape kShapes[] = {
    {"spherical-cap", spherical_cap_point, 1e-6, kCapMaxAngle},
    {"paraboloid", paraboloid_point, 1e-6, 1e6},
    {"gaussian", gaussian_point, 1e-6, 1e6},
    {"concave", concave_point, 1e-6, 1e6},
    {"transition", transition_point, 1e-6, 1e6},
};

Eigen::MatrixX2d sample(const Shape& shape, double p, int segments) {
  Eigen::MatrixX2d m(segments + 1, 2);
  for (int i = 0; i <= segments; ++i) {
    m.row(i) = shape.point(p, static_cast<double>(i) / segments).transpose();
  }
  return m;
}

double polyline_length(const Eigen::MatrixX2d& m) {
  double length = 0;
  for (Eigen::Index i = 1; i < m.rows(); ++i) length += (m.row(i) - m.row(i - 1)).norm();
  return length;
}

double height_of(const Eigen::MatrixX2d& m) { return m.col(1).maxCoeff() - m.col(1).minCoeff(); }

double aspect_ratio(const Shape& shape, double p, int segments) {
  const Eigen::MatrixX2d m = sample(shape, p, segments);
  return height_of(m) / polyline_length(m);
}

// The largest distance (in the unit shape's coordinates) of a chord's midpoint parameter from it.
double chord_error(const Shape& shape, double p, int segments) {
  double worst = 0;
  Eigen::Vector2d a = shape.point(p, 0);
  for (int i = 1; i <= segments; ++i) {
    const Eigen::Vector2d b = shape.point(p, static_cast<double>(i) / segments);
    const Eigen::Vector2d mid = shape.point(p, (i - 0.5) / segments);
    worst = std::max(worst, segment_distance(mid, a, b));
    a = b;
  }
  return worst;
}

// The aspect p at which the sampled shape's height / length is `ratio`, by bisection on log p (the
// ratio grows with p on [p_lo, p_hi]).
double solve_aspect(const Shape& shape, double ratio, int segments) {
  double lo = std::log(shape.p_lo);
  double hi = std::log(shape.p_hi);
  for (int it = 0; it < 100 && hi - lo > 1e-15; ++it) {
    const double mid = 0.5 * (lo + hi);
    (aspect_ratio(shape, std::exp(mid), segments) < ratio ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

TileProfile cone(const std::string& name, double flat_radius, double slope) {
  TileProfile profile{name, Eigen::MatrixX2d(2, 2)};
  profile.meridian << 0, flat_radius * std::sin(slope), flat_radius * std::cos(slope), 0;
  return profile;
}

std::string degrees(double radians) {
  return fmt::format("{:.1f}°", radians * 180 / std::numbers::pi);
}

// ---------------------------------------------------------------------------------------------
// CSV.

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

bool parse_number(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return false;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end;
}

// ---------------------------------------------------------------------------------------------
// Rings.

std::vector<Eigen::Index> order_by_radius(const Eigen::VectorXd& flat_radii) {
  std::vector<Eigen::Index> order(static_cast<size_t>(flat_radii.size()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  for (Eigen::Index i = 0; i < flat_radii.size(); ++i) {
    if (!(std::isfinite(flat_radii(i)) && flat_radii(i) > 0)) {
      throw std::invalid_argument(fmt::format(
          "ring {} has flat radius {}; radii must be finite and positive", i, flat_radii(i)));
    }
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return flat_radii(a) < flat_radii(b); });
  for (size_t i = 1; i < order.size(); ++i) {
    if (flat_radii(order[i]) == flat_radii(order[i - 1])) {
      throw std::invalid_argument(fmt::format("rings {} and {} share the flat radius {}",
                                              order[i - 1], order[i], flat_radii(order[i])));
    }
  }
  return order;
}

std::string percent(double fraction) { return fmt::format("{:.2f} %", 100 * fraction); }

// "0.2-6.6", or "0.2" when both ends print alike (mm, 0.1 mm).
std::string span(double a, double b) {
  const std::string from = fmt::format("{:.1f}", a);
  const std::string to = fmt::format("{:.1f}", b);
  return from == to ? from : from + "-" + to;
}

// "rings at flat radius 0.2-6.6 mm need 0.00-7.92 % shrink, below the least 7.93 % the material
// gives" for the rings clamped in `direction`; empty when there are none. `order`: by radius.
std::string clamped_rings(const RingShrinkage& rings, const std::vector<Eigen::Index>& order,
                          int direction) {
  std::vector<std::string> ranges;
  int count = 0;
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (size_t i = 0; i < order.size();) {
    if (rings.clamped(order[i]) != direction) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j + 1 < order.size() && rings.clamped(order[j + 1]) == direction) ++j;
    for (size_t k = i; k <= j; ++k) {
      low = std::min(low, rings.wanted(order[k]));
      high = std::max(high, rings.wanted(order[k]));
      ++count;
    }
    ranges.push_back(span(rings.flat_radius(order[i]), rings.flat_radius(order[j])));
    i = j + 1;
  }
  if (count == 0) return {};
  std::string where;
  for (size_t i = 0; i < ranges.size(); ++i) {
    where += (i == 0 ? "" : i + 1 == ranges.size() ? " and " : ", ") + ranges[i];
  }
  const std::string needed = percent(low) == percent(high)
                                 ? percent(low)
                                 : fmt::format("{:.2f}-{}", 100 * low, percent(high));
  return fmt::format("{} at flat radius {} mm {} {} shrink, {} the material gives",
                     count == 1 ? "the ring" : "rings", where, count == 1 ? "needs" : "need",
                     needed,
                     direction < 0 ? "below the least " + percent(rings.least)
                                   : "above the most " + percent(rings.most));
}

}  // namespace

void check_tile_profile(const TileProfile& profile, const std::string& source) {
  const Eigen::MatrixX2d& m = profile.meridian;
  auto fail = [&](Eigen::Index i, const std::string& problem) {
    throw UserError(
        ErrorCategory::kGeometry,
        fmt::format("{}: point {} (r = {}, z = {}): {}", source, i + 1, m(i, 0), m(i, 1), problem));
  };
  if (m.rows() < 2) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: the profile has {} point(s); give the apex on the axis and at "
                                "least one more point toward the rim",
                                source, m.rows()));
  }
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    if (!m.row(i).allFinite()) {
      fail(i, "not a finite number; give every point as two numbers in mm");
    }
    if (m.row(i).cwiseAbs().maxCoeff() > kAbsurdCoordinate) {
      fail(i, "beyond 1e6 mm; give the profile in millimetres");
    }
    if (i == 0 && std::abs(m(0, 0)) > kAxisTolerance) {
      fail(i, "the profile starts off the axis; start it at the apex on the axis (r = 0)");
    }
    if (i > 0 && m(i, 0) < 0) {
      fail(i, "r is negative; r is the distance to the axis (0 or more)");
    }
    if (i > 0 && m.row(i) == m.row(i - 1)) {
      fail(i,
           "repeats the point before it; remove one (the arc length must grow along the profile)");
    }
  }
}

std::vector<std::string> tile_profile_names() {
  return {"spherical-cap", "cone",       "paraboloid",  "gaussian",
          "concave",       "transition", "subtle-cone", "dramatic-cone"};
}

TileProfile tile_profile(const std::string& name, double flat_radius_mm, double height_mm) {
  const std::vector<std::string> names = tile_profile_names();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("unknown tile profile \"{}\"; choose one of {}, or give a CSV "
                                "profile of r,z rows",
                                name, fmt::join(names, ", ")));
  }
  if (!(std::isfinite(flat_radius_mm) && flat_radius_mm > 0)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("tile profile {}: the flat radius {} mm is not a positive size; "
                                "give the tile a positive radius",
                                name, flat_radius_mm));
  }
  // Note §3.2: a cone of uniform shrink Sh slopes acos(1 − Sh).
  if (name == "subtle-cone") {
    return cone(name, flat_radius_mm, std::acos(1 - kSubtleConeShrinkage));
  }
  if (name == "dramatic-cone") {
    return cone(name, flat_radius_mm, std::acos(1 - kDramaticConeShrinkage));
  }
  if (!(std::isfinite(height_mm) && height_mm > 0)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("tile profile {}: the height {} mm is not a positive size; give a "
                                "height above 0 and below the flat radius {} mm",
                                name, height_mm, flat_radius_mm));
  }
  if (height_mm >= flat_radius_mm) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("tile profile {}: a tile of flat radius {} mm cannot rise {} mm (its "
                    "meridian is only {} mm long); lower the height below {} mm or "
                    "widen the tile",
                    name, flat_radius_mm, height_mm, flat_radius_mm, flat_radius_mm));
  }
  if (name == "cone") return cone(name, flat_radius_mm, std::asin(height_mm / flat_radius_mm));

  const Shape& shape = *std::find_if(std::begin(kShapes), std::end(kShapes),
                                     [&](const Shape& s) { return name == s.name; });
  const double ratio = height_mm / flat_radius_mm;
  int segments = 256;
  auto too_high = [&](double most) {
    return UserError(
        ErrorCategory::kOption,
        fmt::format("tile profile {}: a tile of flat radius {} mm rises at most {:.3f} "
                    "mm with this shape, not {} mm; lower the height or widen the tile "
                    "to a flat radius of {:.3f} mm or more",
                    name, flat_radius_mm, most * flat_radius_mm, height_mm,
                    std::ceil(height_mm / most * 1000) / 1000));
  };
  const double most = aspect_ratio(shape, shape.p_hi, segments);
  const double least = aspect_ratio(shape, shape.p_lo, segments);
  if (ratio > most) throw too_high(most);
  if (ratio < least) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("tile profile {}: a height of {} mm is too small for a tile of flat "
                    "radius {} mm; raise it to {:.3g} mm or more",
                    name, height_mm, flat_radius_mm, least * flat_radius_mm));
  }
  // Refine until the chords of the scaled curve stay within the tolerance of it.
  const double tolerance = std::min(kRelativeChordTolerance * flat_radius_mm, kChordTolerance);
  double p = solve_aspect(shape, ratio, segments);
  for (;;) {
    const double scale = flat_radius_mm / polyline_length(sample(shape, p, segments));
    if (chord_error(shape, p, segments) * scale <= tolerance || segments >= kMaxSegments) {
      break;
    }
    while (segments < kMaxSegments && chord_error(shape, p, segments) * scale > tolerance) {
      segments *= 2;
    }
    p = solve_aspect(shape, ratio, segments);
  }
  Eigen::MatrixX2d m = sample(shape, p, segments);
  // The finer polyline is longer: a height just under the coarse limit may now be out of reach.
  if (std::abs(height_of(m) / polyline_length(m) - ratio) > 1e-9 * ratio) {
    throw too_high(aspect_ratio(shape, shape.p_hi, segments));
  }
  m *= flat_radius_mm / polyline_length(m);
  m(0, 0) = 0;
  return {name, m};
}

TileProfile read_profile_csv(std::string_view text, const std::string& source) {
  std::vector<Eigen::Vector2d> points;
  int first_line = 0, previous_line = 0, line = 0;
  bool seen_content = false;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view row = text.substr(start, end - start);
    start = end + 1;
    ++line;
    if (const size_t hash = row.find('#'); hash != std::string_view::npos) {
      row = row.substr(0, hash);
    }
    row = trim(row);
    if (row.empty()) continue;
    auto fail = [&](const std::string& problem) {
      throw UserError(ErrorCategory::kFormat, fmt::format("{}:{}: {}", source, line, problem));
    };
    std::vector<std::string_view> cells;
    for (size_t from = 0;;) {
      const size_t comma = row.find(',', from);
      cells.push_back(
          trim(row.substr(from, comma == std::string_view::npos ? row.npos : comma - from)));
      if (comma == std::string_view::npos) break;
      from = comma + 1;
    }
    double value = 0;
    const bool header = !seen_content && !parse_number(cells[0], value);
    seen_content = true;
    if (header) continue;
    if (cells.size() != 2) {
      fail(
          fmt::format("{} cells where a point has two; write one point per line as r,z in mm "
                      "(r the distance to the axis)",
                      cells.size()));
    }
    Eigen::Vector2d p;
    for (int c = 0; c < 2; ++c) {
      const char* what = c == 0 ? "r" : "z";
      if (!parse_number(cells[c], p(c))) {
        fail(fmt::format("{} = \"{}\" is not a number; write r,z in mm such as 2.5,7.1", what,
                         cells[c]));
      }
      if (!std::isfinite(p(c))) {
        fail(fmt::format("{} = {} is not a finite number; give every point as two numbers in mm",
                         what, cells[c]));
      }
      if (std::abs(p(c)) > kAbsurdCoordinate) {
        fail(fmt::format("{} = {} mm is beyond 1e6 mm; give the profile in millimetres", what,
                         cells[c]));
      }
    }
    if (points.size() >= static_cast<size_t>(kMaxCsvRows)) {
      fail(fmt::format("more than {} points; resample the profile more coarsely", kMaxCsvRows));
    }
    if (points.empty()) {
      if (std::abs(p(0)) > kAxisTolerance) {
        fail(
            fmt::format("the profile starts at r = {} mm, off the axis; start it at the apex on "
                        "the axis (r = 0): a tile with a hole takes the full profile and leaves "
                        "out its inner rings",
                        cells[0]));
      }
      p(0) = 0;
      first_line = line;
    } else {
      if (p(0) < 0) {
        fail(fmt::format("r = {} mm is negative; r is the distance to the axis (0 or more)",
                         cells[0]));
      }
      if (p == points.back()) {
        fail(
            fmt::format("the point ({}, {}) repeats line {}; remove one of them (the arc length "
                        "must grow from point to point)",
                        cells[0], cells[1], previous_line));
      }
    }
    points.push_back(p);
    previous_line = line;
  }
  if (points.size() < 2) {
    throw UserError(ErrorCategory::kFormat,
                    points.empty()
                        ? fmt::format("{}:{}: no points; write the profile as r,z rows in mm from "
                                      "the apex (r = 0) to the rim",
                                      source, std::max(line, 1))
                        : fmt::format("{}:{}: only one point; a profile needs the apex on the axis "
                                      "and at least one more point toward the rim",
                                      source, first_line));
  }
  TileProfile profile{source, Eigen::MatrixX2d(static_cast<Eigen::Index>(points.size()), 2)};
  for (size_t i = 0; i < points.size(); ++i) {
    profile.meridian.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  }
  return profile;
}

TileProfile scale_profile_to_length(const TileProfile& profile, double flat_radius_mm) {
  if (!(std::isfinite(flat_radius_mm) && flat_radius_mm > 0)) {
    throw std::invalid_argument(fmt::format("flat radius {} is not positive", flat_radius_mm));
  }
  return {profile.name, profile.meridian * (flat_radius_mm / profile_length(profile))};
}

double profile_length(const TileProfile& profile) { return polyline_length(profile.meridian); }

double profile_height(const TileProfile& profile) { return height_of(profile.meridian); }

Eigen::Vector2d profile_point_at_length(const TileProfile& profile, double s) {
  const std::vector<double> cum = cumulative_length(profile.meridian);
  require_within(profile, cum, s);
  return point_at(profile.meridian, cum, s);
}

double ring_shrinkage(const TileProfile& profile, double s) {
  const std::vector<double> cum = cumulative_length(profile.meridian);
  require_within(profile, cum, s);
  return shrinkage_at(profile.meridian, cum, s);
}

RingShrinkage tile_ring_shrinkage(const TileProfile& profile, const Eigen::VectorXd& flat_radii,
                                  double least, double most) {
  if (!(std::isfinite(least) && std::isfinite(most) && 0 <= least && least < most && most < 1)) {
    throw std::invalid_argument(
        fmt::format("reachable shrinkage [{}, {}] is not a range within [0, 1)", least, most));
  }
  order_by_radius(flat_radii);
  const std::vector<double> cum = cumulative_length(profile.meridian);
  RingShrinkage rings;
  rings.flat_radius = flat_radii;
  rings.wanted.resize(flat_radii.size());
  rings.printed.resize(flat_radii.size());
  rings.clamped = Eigen::VectorXi::Zero(flat_radii.size());
  rings.least = least;
  rings.most = most;
  for (Eigen::Index i = 0; i < flat_radii.size(); ++i) {
    require_within(profile, cum, flat_radii(i));
    const double wanted = shrinkage_at(profile.meridian, cum, flat_radii(i));
    rings.wanted(i) = wanted;
    rings.printed(i) = std::clamp(wanted, least, most);
    if (wanted < least - kClampTolerance) rings.clamped(i) = -1;
    if (wanted > most + kClampTolerance) rings.clamped(i) = 1;
  }
  return rings;
}

ForwardProfile profile_from_shrinkage(const Eigen::VectorXd& flat_radii,
                                      const Eigen::VectorXd& shrinkage) {
  if (flat_radii.size() != shrinkage.size()) {
    throw std::invalid_argument(
        fmt::format("{} flat radii but {} shrinkage values", flat_radii.size(), shrinkage.size()));
  }
  for (Eigen::Index i = 0; i < shrinkage.size(); ++i) {
    if (!(std::isfinite(shrinkage(i)) && shrinkage(i) <= 1)) {
      throw std::invalid_argument(fmt::format("ring {} has shrinkage {}", i, shrinkage(i)));
    }
  }
  ForwardProfile forward;
  forward.points.resize(flat_radii.size(), 2);
  double r = 0, rho = 0, z = 0;
  for (const Eigen::Index k : order_by_radius(flat_radii)) {
    // Note §3.1: the ring's length sets its radius; the meridian between rings keeps its length.
    const double next_rho = (1 - shrinkage(k)) * flat_radii(k);
    const double dr = flat_radii(k) - r;
    const double drho = next_rho - rho;
    if (std::abs(drho) > dr) {
      ++forward.horizontal_steps;
      forward.stretch += std::abs(drho) - dr;
    } else {
      z -= std::sqrt(dr * dr - drho * drho);
    }
    r = flat_radii(k);
    rho = next_rho;
    forward.points.row(k) << rho, z;
  }
  return forward;
}

PrintabilityReport printability(const TileProfile& profile, const RingShrinkage& rings,
                                bool strict) {
  const Eigen::Index n = rings.flat_radius.size();
  if (n == 0 || rings.wanted.size() != n || rings.printed.size() != n ||
      rings.clamped.size() != n) {
    throw std::invalid_argument("printability needs at least one ring and arrays of one size");
  }
  const std::vector<Eigen::Index> order = order_by_radius(rings.flat_radius);
  const Eigen::Index clamped = (rings.clamped.array() != 0).count();
  const std::string below = clamped_rings(rings, order, -1);
  const std::string above = clamped_rings(rings, order, 1);
  const std::string cones = fmt::format(
      "the material's {:.2f}-{} shrink fits cones of {} to {}", 100 * rings.least,
      percent(rings.most), degrees(std::acos(1 - rings.least)), degrees(std::acos(1 - rings.most)));
  // A smooth summit is the usual reason for the least (note §3.7.1): only a point helps there.
  const bool flat_apex = rings.clamped(order.front()) < 0;
  const std::string steeper =
      flat_apex ? fmt::format("make the apex a point sloping at least {}, or raise the height",
                              degrees(std::acos(1 - rings.least)))
                : std::string("raise the height or narrow the tile");
  std::string advice;
  if (!below.empty() && !above.empty()) {
    advice = fmt::format(
        "{} where it needs too little, and lower the height or widen the tile "
        "where it needs too much ({})",
        steeper, cones);
  } else if (!below.empty()) {
    advice = fmt::format("{} ({})", steeper, cones);
  } else {
    advice = fmt::format("lower the height or widen the tile ({})", cones);
  }
  const std::string parts = below.empty() ? above : above.empty() ? below : below + "; " + above;
  if (clamped == n) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("profile {}: no ring is printable: {}; {}", profile.name, parts, advice));
  }

  PrintabilityReport report;
  report.target_height_mm = profile_height(profile);
  // The forward model of what is printed, out to the rim with the rim's own shrink clamped.
  const double length = profile_length(profile);
  const double outermost = rings.flat_radius(order.back());
  Eigen::VectorXd radii = rings.flat_radius, shrink = rings.printed;
  if (length > outermost * (1 + 1e-12)) {
    radii.conservativeResize(n + 1);
    shrink.conservativeResize(n + 1);
    radii(n) = length;
    shrink(n) = std::clamp(ring_shrinkage(profile, length), rings.least, rings.most);
  }
  const ForwardProfile forward = profile_from_shrinkage(radii, shrink);
  report.clamped_height_mm = -forward.points.col(1).minCoeff();
  report.horizontal_steps = forward.horizontal_steps;
  report.any_clamped = clamped > 0;
  if (!report.any_clamped) return report;

  std::string printed;
  if (!below.empty()) printed += below + ", printed at " + percent(rings.least);
  if (!above.empty()) {
    printed += (printed.empty() ? "" : "; ") + above + ", printed at " + percent(rings.most);
  }
  report.warning = fmt::format(
      "profile {}: {}; the tile rises {:.2f} mm instead of {:.2f} mm{}{}", profile.name, printed,
      report.clamped_height_mm, report.target_height_mm, flat_apex ? " (a pointed apex)" : "",
      forward.horizontal_steps == 0
          ? ""
          : fmt::format("; {} ring step(s) would need the meridian to stretch {:.3f} mm",
                        forward.horizontal_steps, forward.stretch));
  if (strict) {
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("profile {}: {}, and --strict refuses to clamp; {}, or drop --strict",
                    profile.name, parts, advice));
  }
  return report;
}

double polygon_ring_shrinkage(const RingShrinkage& circle, double circle_radius,
                              double depth_fraction) {
  if (!(std::isfinite(circle_radius) && circle_radius > 0) ||
      !(depth_fraction >= -1e-9 && depth_fraction <= 1 + 1e-9) || circle.printed.size() == 0 ||
      circle.printed.size() != circle.flat_radius.size()) {
    throw std::invalid_argument(
        fmt::format("polygon_ring_shrinkage: circle radius {}, depth fraction {}, {} rings",
                    circle_radius, depth_fraction, circle.printed.size()));
  }
  const std::vector<Eigen::Index> order = order_by_radius(circle.flat_radius);
  const double r = (1 - std::clamp(depth_fraction, 0.0, 1.0)) * circle_radius;
  if (r <= circle.flat_radius(order.front())) return circle.printed(order.front());
  if (r >= circle.flat_radius(order.back())) return circle.printed(order.back());
  size_t i = 0;
  while (circle.flat_radius(order[i + 1]) <= r) ++i;
  const double r0 = circle.flat_radius(order[i]), r1 = circle.flat_radius(order[i + 1]);
  const double t = (r - r0) / (r1 - r0);
  return circle.printed(order[i]) + t * (circle.printed(order[i + 1]) - circle.printed(order[i]));
}

Eigen::VectorXd paper_polygon_shrinkage(const RingShrinkage& circle, int polygon_rings) {
  const Eigen::Index n = circle.printed.size();
  if (polygon_rings < 1 || n == 0 || circle.flat_radius.size() != n) {
    throw std::invalid_argument(
        fmt::format("paper_polygon_shrinkage: {} polygon rings, {} circle "
                    "rings",
                    polygon_rings, n));
  }
  const std::vector<Eigen::Index> order = order_by_radius(circle.flat_radius);
  Eigen::VectorXd out(polygon_rings);
  for (int j = 1; j <= polygon_rings; ++j) {
    // CHI 2019 §7: Sh'(j) = Sh(Floor(j N / N')), both counted from the centre.
    const long long k = std::max(1LL, static_cast<long long>(j) * n / polygon_rings);
    out(j - 1) = circle.printed(order[static_cast<size_t>(k - 1)]);
  }
  return out;
}

}  // namespace flatmorph
