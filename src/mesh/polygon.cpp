#include "mesh/polygon.h"

#include <clipper.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "mesh/clipper_path.h"
#include "mesh/plane_geometry.h"

namespace flatmorph {
namespace {

// Clipper's integer plane: 1 nm per unit keeps every net of a printer's bed far inside its range.
constexpr double kClipperScale = 1e6;

template <typename Corners>
double shoelace_area(const Eigen::MatrixBase<Corners>& polygon) {
  double twice = 0;
  for (Eigen::Index i = 0; i < polygon.rows(); ++i) {
    const Eigen::Index j = (i + 1) % polygon.rows();
    twice += polygon(i, 0) * polygon(j, 1) - polygon(j, 0) * polygon(i, 1);
  }
  return twice / 2;
}

template <typename Corners>
bool even_odd_inside(const Eigen::MatrixBase<Corners>& polygon, const Eigen::Vector2d& p) {
  bool inside = false;
  for (Eigen::Index i = 0, j = polygon.rows() - 1; i < polygon.rows(); j = i++) {
    if (side_crosses_ray(p, polygon.row(i).transpose(), polygon.row(j).transpose())) {
      inside = !inside;
    }
  }
  return inside;
}

// The corners of a loop as the rows of one array, read in place.
Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>> corner_rows(
    const std::vector<Eigen::Vector2d>& polygon) {
  return {polygon.empty() ? nullptr : polygon.front().data(),
          static_cast<Eigen::Index>(polygon.size()), 2};
}

}  // namespace

double signed_area(const Eigen::MatrixX2d& polygon) { return shoelace_area(polygon); }

double signed_area(const std::vector<Eigen::Vector2d>& polygon) {
  return shoelace_area(corner_rows(polygon));
}

bool point_in_polygon(const Eigen::MatrixX2d& polygon, const Eigen::Vector2d& p) {
  return even_odd_inside(polygon, p);
}

bool point_in_polygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p) {
  return even_odd_inside(corner_rows(polygon), p);
}

// Overlapping by more than a sliver: rounding to Clipper's grid leaves slivers of about 1e-6 mm
// along a shared side, which are no overlap.
bool polygons_overlap(const Eigen::MatrixX2d& a, const Eigen::MatrixX2d& b) {
  const Eigen::Array2d a_min = a.colwise().minCoeff(), a_max = a.colwise().maxCoeff();
  const Eigen::Array2d b_min = b.colwise().minCoeff(), b_max = b.colwise().maxCoeff();
  if ((a_max < b_min).any() || (b_max < a_min).any()) return false;
  ClipperLib::Clipper clipper;
  clipper.AddPath(to_clipper_path(a, kClipperScale), ClipperLib::ptSubject, true);
  clipper.AddPath(to_clipper_path(b, kClipperScale), ClipperLib::ptClip, true);
  ClipperLib::Paths common;
  clipper.Execute(ClipperLib::ctIntersection, common, ClipperLib::pftNonZero,
                  ClipperLib::pftNonZero);
  double area = 0;
  for (const ClipperLib::Path& path : common) area += std::abs(ClipperLib::Area(path));
  area /= kClipperScale * kClipperScale;
  return area > 1e-4 * std::min(std::abs(signed_area(a)), std::abs(signed_area(b)));
}

Eigen::MatrixX3i triangulate_polygon(const Eigen::MatrixX2d& polygon) {
  const int n = static_cast<int>(polygon.rows());
  if (n < 3) throw std::invalid_argument("triangulate_polygon: fewer than three corners");
  const double sense = signed_area(polygon) < 0 ? -1.0 : 1.0;
  // Twice the area of (a, b, c), positive when it turns the polygon's way.
  const auto turn = [&](int a, int b, int c) {
    const Eigen::Vector2d ab = (polygon.row(b) - polygon.row(a)).transpose();
    const Eigen::Vector2d ac = (polygon.row(c) - polygon.row(a)).transpose();
    return sense * cross2(ab, ac);
  };
  std::vector<int> left(n);
  for (int i = 0; i < n; ++i) left[i] = i;
  Eigen::MatrixX3i out(n - 2, 3);
  for (int t = 0; t < n - 3; ++t) {
    const int m = static_cast<int>(left.size());
    // The first ear: a corner turning the polygon's way whose triangle holds no other corner
    // (closed test, so that a reflex corner on its side also blocks it). A polygon with straight
    // corners only (or not simple) has none: its most convex corner is cut instead.
    int ear = -1, best = 0;
    double best_turn = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < m && ear < 0; ++i) {
      const int a = left[(i + m - 1) % m], b = left[i], c = left[(i + 1) % m];
      const double abc = turn(a, b, c);
      if (abc > best_turn) best_turn = abc, best = i;
      if (abc <= 0) continue;
      bool empty = true;
      for (int j = 0; j < m && empty; ++j) {
        const int p = left[j];
        if (p == a || p == b || p == c) continue;
        empty = !(turn(a, b, p) >= 0 && turn(b, c, p) >= 0 && turn(c, a, p) >= 0);
      }
      if (empty) ear = i;
    }
    if (ear < 0) ear = best;
    out.row(t) << left[(ear + m - 1) % m], left[ear], left[(ear + 1) % m];
    left.erase(left.begin() + ear);
  }
  out.row(n - 3) << left[0], left[1], left[2];
  return out;
}

}  // namespace flatmorph
