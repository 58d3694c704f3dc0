#include "toolpath/isolines.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/angles.h"
#include "mesh/plane_geometry.h"

namespace flatmorph {
namespace {

// Segments of all polylines bucketed in square cells, for distance queries within a radius.
class SegmentGrid {
 public:
  SegmentGrid(const std::vector<Polyline2>& polylines, double cell) : cell_(cell) {
    lo_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo_;
    for (const Polyline2& line : polylines) {
      for (int i = 0; i < line.points.rows(); ++i) {
        lo_ = lo_.cwiseMin(line.points.row(i).transpose());
        hi = hi.cwiseMax(line.points.row(i).transpose());
      }
    }
    if (!(lo_.x() <= hi.x())) lo_ = hi = Eigen::Vector2d::Zero();
    nx_ = static_cast<int>((hi.x() - lo_.x()) / cell_) + 1;
    ny_ = static_cast<int>((hi.y() - lo_.y()) / cell_) + 1;
    cells_.resize(static_cast<size_t>(nx_) * ny_);
    for (size_t p = 0; p < polylines.size(); ++p) {
      const auto& P = polylines[p].points;
      for (int i = 0; i + 1 < P.rows(); ++i) {
        a_.push_back(P.row(i).transpose());
        b_.push_back(P.row(i + 1).transpose());
        owner_.push_back(static_cast<int>(p));
        const int s = static_cast<int>(a_.size()) - 1;
        int x0, y0, x1, y1;
        range(a_[s].cwiseMin(b_[s]), a_[s].cwiseMax(b_[s]), x0, y0, x1, y1);
        for (int y = y0; y <= y1; ++y) {
          for (int x = x0; x <= x1; ++x) cells_[static_cast<size_t>(y) * nx_ + x].push_back(s);
        }
      }
    }
  }
  // Distance from x to the nearest segment not of polyline `skip`, or `radius` if none is closer.
  double distance(const Eigen::Vector2d& x, int skip, double radius) const {
    int x0, y0, x1, y1;
    range(x.array() - radius, x.array() + radius, x0, y0, x1, y1);
    double best = radius;
    for (int y = y0; y <= y1; ++y) {
      for (int gx = x0; gx <= x1; ++gx) {
        for (int s : cells_[static_cast<size_t>(y) * nx_ + gx]) {
          if (owner_[s] != skip) best = std::min(best, segment_distance(x, a_[s], b_[s]));
        }
      }
    }
    return best;
  }

 private:
  void range(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int& x0, int& y0, int& x1,
             int& y1) const {
    x0 = std::clamp(static_cast<int>(std::floor((lo.x() - lo_.x()) / cell_)), 0, nx_ - 1);
    y0 = std::clamp(static_cast<int>(std::floor((lo.y() - lo_.y()) / cell_)), 0, ny_ - 1);
    x1 = std::clamp(static_cast<int>(std::floor((hi.x() - lo_.x()) / cell_)), 0, nx_ - 1);
    y1 = std::clamp(static_cast<int>(std::floor((hi.y() - lo_.y()) / cell_)), 0, ny_ - 1);
  }
  double cell_;
  Eigen::Vector2d lo_;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<int>> cells_;
  std::vector<Eigen::Vector2d> a_, b_;
  std::vector<int> owner_;
};

}  // namespace

void trim_converging_ends(std::vector<Polyline2>& polylines, double min_gap_mm) {
  if (!(min_gap_mm > 0) || polylines.empty()) return;
  const SegmentGrid grid(polylines, min_gap_mm);
  const auto far_enough = [&](const Eigen::Vector2d& x, int p) {
    return grid.distance(x, p, min_gap_mm) >= min_gap_mm;
  };
  std::vector<Polyline2> kept;
  for (size_t p = 0; p < polylines.size(); ++p) {
    Polyline2& line = polylines[p];
    const int n = static_cast<int>(line.points.rows());
    if (line.closed || n < 2) {
      kept.push_back(std::move(line));
      continue;
    }
    const int id = static_cast<int>(p);
    // Cut position from one end: the first point far enough, refined on the segment before it.
    const auto cut = [&](bool from_start, Eigen::Vector2d& point) -> int {
      for (int k = 0; k < n; ++k) {
        const int i = from_start ? k : n - 1 - k;
        if (!far_enough(line.points.row(i).transpose(), id)) continue;
        point = line.points.row(i).transpose();
        if (k == 0) return i;
        Eigen::Vector2d near = line.points.row(from_start ? i - 1 : i + 1).transpose();
        for (int b = 0; b < 20; ++b) {  // bisection between a close point and a far one
          const Eigen::Vector2d mid = 0.5 * (near + point);
          (far_enough(mid, id) ? point : near) = mid;
        }
        return from_start ? i - 1 : i + 1;  // the point before the cut, replaced by `point`
      }
      return -1;
    };
    Eigen::Vector2d start_point, end_point;
    const int first = cut(true, start_point);
    const int last = cut(false, end_point);
    if (first < 0 || last < 0 || last < first) continue;
    Polyline2 trimmed;
    trimmed.points.resize(last - first + 1, 2);
    trimmed.points = line.points.middleRows(first, last - first + 1);
    trimmed.points.row(0) = start_point.transpose();
    trimmed.points.row(trimmed.points.rows() - 1) = end_point.transpose();
    if (trimmed.points.rows() >= 2) kept.push_back(std::move(trimmed));
  }
  polylines = std::move(kept);
}

int drop_short_polylines(std::vector<Polyline2>& polylines, double min_length_mm,
                         double* removed_length) {
  int removed = 0;
  std::vector<Polyline2> kept;
  for (Polyline2& line : polylines) {
    const double length = polyline_length(line.points);
    if (length < min_length_mm) {
      ++removed;
      if (removed_length) *removed_length += length;
    } else {
      kept.push_back(std::move(line));
    }
  }
  polylines = std::move(kept);
  return removed;
}

double polyline_length(const Eigen::MatrixX2d& points) {
  double length = 0;
  for (int i = 0; i + 1 < points.rows(); ++i) length += (points.row(i + 1) - points.row(i)).norm();
  return length;
}

std::vector<Polyline2> stripe_isolines(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const EdgeTopology& topology, const StripePattern& pattern,
                                       double min_length_mm) {
  // Crossing points, edge by edge, ordered from edges(e, 0) to edges(e, 1).
  const int ne = topology.num_edges();
  std::vector<int> offset(ne + 1, 0);
  for (int e = 0; e < ne; ++e) {
    const double a = pattern.vertex_phase(topology.edges(e, 0));
    offset[e + 1] = offset[e] + count_phase_levels(a, a + pattern.edge_phase(e));
  }
  const int num_nodes = offset[ne];
  Eigen::MatrixX2d node(num_nodes, 2);
  for (int e = 0; e < ne; ++e) {
    const int i = topology.edges(e, 0), j = topology.edges(e, 1);
    const double a = pattern.vertex_phase(i), b = a + pattern.edge_phase(e);
    const int n = offset[e + 1] - offset[e];
    const double first = b > a ? std::floor(a / kTwoPi) + 1 : std::ceil(a / kTwoPi) - 1;
    const double step = b > a ? 1 : -1;
    for (int m = 0; m < n; ++m) {
      const double t = (kTwoPi * (first + step * m) - a) / (b - a);
      node.row(offset[e] + m) = (1 - t) * V.row(i).head<2>() + t * V.row(j).head<2>();
    }
  }

  // Segments inside faces: each node has at most one per adjacent face, so at most two.
  std::vector<std::array<int, 2>> adjacent(num_nodes, {-1, -1});
  const auto link = [&](int p, int q) {
    (adjacent[p][0] < 0 ? adjacent[p][0] : adjacent[p][1]) = q;
    (adjacent[q][0] < 0 ? adjacent[q][0] : adjacent[q][1]) = p;
  };
  for (int f = 0; f < F.rows(); ++f) {
    if (!pattern.usable[f]) continue;
    // The phase along the face's boundary, lifted: corner k at alpha[k], back at corner 0 with
    // alpha[3], 2 pi stripe_index higher than alpha[0] (a fork: the phase winds around its zero).
    double alpha[4];
    for (int k = 0; k < 3; ++k) alpha[k] = pattern.corner_phase(f, k);
    alpha[3] = alpha[0] + kTwoPi * pattern.stripe_index(f);
    const double lo = *std::min_element(alpha, alpha + 4), hi = *std::max_element(alpha, alpha + 4);
    const int k_lo = static_cast<int>(std::floor(lo / kTwoPi)) + 1;
    const int k_hi = static_cast<int>(std::ceil(hi / kTwoPi)) - 1;
    for (int level = k_lo; level <= k_hi; ++level) {
      const double L = kTwoPi * level;
      // Crossings in boundary order. Where the phase is linear a level crosses twice or not at
      // all; at a fork one level crosses once or three times, and one of its crossings is the
      // end of the branch that stops at the fork.
      int ends[3], found = 0;
      for (int k = 0; k < 3; ++k) {
        const double au = alpha[k], av = alpha[k + 1];
        if (!((au < L && L < av) || (av < L && L < au))) continue;
        const int e = topology.face_edges(f, k);
        const int n = offset[e + 1] - offset[e];
        int index = static_cast<int>(std::floor(std::abs(L - au) / kTwoPi));
        if (topology.edges(e, 0) != F(f, k)) index = n - 1 - index;
        index = std::clamp(index, 0, n - 1);
        ends[found++] = offset[e] + index;
      }
      if (found == 3) {
        // Join the two closer crossings; the third ends at the fork.
        const auto length = [&](int a, int b) { return (node.row(a) - node.row(b)).norm(); };
        if (length(ends[1], ends[2]) < length(ends[0], ends[1])) ends[0] = ends[2];
        found = 2;
      }
      if (found == 2 && ends[0] != ends[1]) link(ends[0], ends[1]);
    }
  }

  // Chains: open ones from their ends first, then the closed loops that remain.
  std::vector<Polyline2> polylines;
  std::vector<bool> visited(num_nodes, false);
  const auto degree = [&](int p) { return (adjacent[p][0] >= 0) + (adjacent[p][1] >= 0); };
  const auto walk = [&](int start) {
    std::vector<int> chain{start};
    visited[start] = true;
    int previous = -1, current = start;
    while (true) {
      int next = -1;
      for (int q : adjacent[current]) {
        if (q >= 0 && q != previous && !visited[q]) {
          next = q;
          break;
        }
      }
      if (next < 0) break;
      visited[next] = true;
      chain.push_back(next);
      previous = current;
      current = next;
    }
    Polyline2 line;
    // A loop closes when its last node links back to the first.
    line.closed =
        chain.size() > 2 && (adjacent[current][0] == start || adjacent[current][1] == start);
    if (line.closed) chain.push_back(start);
    line.points.resize(static_cast<int>(chain.size()), 2);
    for (size_t c = 0; c < chain.size(); ++c) line.points.row(c) = node.row(chain[c]);
    if (polyline_length(line.points) >= min_length_mm) polylines.push_back(std::move(line));
  };
  for (int p = 0; p < num_nodes; ++p) {
    if (!visited[p] && degree(p) == 1) walk(p);
  }
  for (int p = 0; p < num_nodes; ++p) {
    if (!visited[p] && degree(p) == 2) walk(p);
  }
  return polylines;
}

}  // namespace flatmorph
