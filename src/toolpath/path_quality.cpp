#include "toolpath/path_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "mesh/plane_geometry.h"
#include "mesh/topology.h"
#include "toolpath/line_field.h"

namespace flatmorph {
namespace {

// Items bucketed by the cells their bounding boxes overlap.
class Grid {
 public:
  Grid(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double cell) : lo_(lo), cell_(cell) {
    nx_ = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)) + 1);
    ny_ = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)) + 1);
    cells_.resize(static_cast<size_t>(nx_) * ny_);
  }
  void insert(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int item) {
    int x0, y0, x1, y1;
    range(lo, hi, x0, y0, x1, y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) cells_[static_cast<size_t>(y) * nx_ + x].push_back(item);
    }
  }
  template <typename Visit>
  void visit(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, Visit&& visit_item) const {
    int x0, y0, x1, y1;
    range(lo, hi, x0, y0, x1, y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        for (int item : cells_[static_cast<size_t>(y) * nx_ + x]) visit_item(item);
      }
    }
  }

 private:
  void range(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int& x0, int& y0, int& x1,
             int& y1) const {
    const auto clamp_x = [&](double v) {
      return std::clamp(static_cast<int>(std::floor((v - lo_.x()) / cell_)), 0, nx_ - 1);
    };
    const auto clamp_y = [&](double v) {
      return std::clamp(static_cast<int>(std::floor((v - lo_.y()) / cell_)), 0, ny_ - 1);
    };
    x0 = clamp_x(lo.x());
    x1 = clamp_x(hi.x());
    y0 = clamp_y(lo.y());
    y1 = clamp_y(hi.y());
  }
  Eigen::Vector2d lo_;
  double cell_;
  int nx_, ny_;
  std::vector<std::vector<int>> cells_;
};

// Barycentric coordinates of p in triangle (a, b, c).
Eigen::Vector3d barycentric(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  const double l1 = ((p - a).x() * (c - a).y() - (p - a).y() * (c - a).x()) / det;
  const double l2 = ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x()) / det;
  return {1 - l1 - l2, l1, l2};
}

struct Location {
  int face = -1;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
  double distance = std::numeric_limits<double>::infinity();  // 0 inside
};

class PlateLocator {
 public:
  PlateLocator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector2d& lo,
               const Eigen::Vector2d& hi, double cell)
      : V_(V), F_(F), grid_(lo, hi, cell) {
    for (int f = 0; f < F.rows(); ++f) {
      Eigen::Vector2d a = corner(f, 0), b = a;
      for (int k = 1; k < 3; ++k) {
        a = a.cwiseMin(corner(f, k));
        b = b.cwiseMax(corner(f, k));
      }
      grid_.insert(a, b, f);
    }
  }
  Eigen::Vector2d corner(int f, int k) const { return V_.row(F_(f, k)).head<2>(); }
  Location locate(const Eigen::Vector2d& p) const {
    Location best;
    grid_.visit(p, p, [&](int f) {
      if (best.distance == 0) return;
      const Eigen::Vector2d a = corner(f, 0), b = corner(f, 1), c = corner(f, 2);
      const Eigen::Vector3d l = barycentric(p, a, b, c);
      double distance = 0;
      if (l.minCoeff() < 0) {
        distance = std::min(
            {segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
      }
      if (distance < best.distance) {
        best.face = f;
        best.distance = distance;
        best.bary = l.cwiseMax(0.0) / l.cwiseMax(0.0).sum();
      }
    });
    return best;
  }

 private:
  const Eigen::MatrixXd& V_;
  const Eigen::MatrixXi& F_;
  Grid grid_;
};

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

PathQuality evaluate_path_quality(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                  const Eigen::VectorXd& theta_vertex,
                                  const std::vector<PathPolyline>& paths,
                                  const std::vector<Eigen::Vector2d>& singular_points,
                                  const PathQualityOptions& options,
                                  std::vector<PathSample>* samples) {
  const double s = options.spacing;
  Eigen::Vector2d lo = V.leftCols<2>().colwise().minCoeff().transpose();
  Eigen::Vector2d hi = V.leftCols<2>().colwise().maxCoeff().transpose();
  for (const PathPolyline& path : paths) {
    for (int i = 0; i < path.points.rows(); ++i) {
      lo = lo.cwiseMin(path.points.row(i).head<2>().transpose());
      hi = hi.cwiseMax(path.points.row(i).head<2>().transpose());
    }
  }
  lo.array() -= 2 * s;
  hi.array() += 2 * s;
  PathQuality q;

  // Path pieces no longer than a spacing, bucketed, for nearest-path queries.
  // Each piece remembers its path and where it starts along it (arc length, mm), so that the far
  // parts of the same path (the next turn of a spiral, the other side of a hairpin) count as
  // neighbours too.
  std::vector<Eigen::Vector2d> piece_a, piece_b;
  std::vector<int> piece_path;
  std::vector<double> piece_arc;
  std::vector<double> path_length(paths.size(), 0);
  for (size_t p = 0; p < paths.size(); ++p) {
    const auto& P = paths[p].points;
    for (int i = 0; i + 1 < P.rows(); ++i) {
      const Eigen::Vector2d a = P.row(i).head<2>(), b = P.row(i + 1).head<2>();
      const double length = (b - a).norm();
      const int pieces = std::max(1, static_cast<int>(std::ceil(length / s)));
      for (int k = 0; k < pieces; ++k) {
        piece_a.push_back(a + (b - a) * (static_cast<double>(k) / pieces));
        piece_b.push_back(a + (b - a) * (static_cast<double>(k + 1) / pieces));
        piece_path.push_back(static_cast<int>(p));
        piece_arc.push_back(path_length[p] + length * k / pieces);
      }
      path_length[p] += length;
    }
  }
  // Own-path pieces closer than this along the path are the sample's own stretch of path.
  const double own_stretch = 3 * s;
  Grid pieces(lo, hi, s);
  for (size_t k = 0; k < piece_a.size(); ++k) {
    pieces.insert(piece_a[k].cwiseMin(piece_b[k]), piece_a[k].cwiseMax(piece_b[k]),
                  static_cast<int>(k));
  }
  const PlateLocator locator(V, F, lo, hi, std::max(2 * s, 1.0));
  const double exclusion = options.singular_exclusion_mm;
  Grid singular(lo, hi, std::max(exclusion, s));
  for (size_t k = 0; k < singular_points.size(); ++k) {
    singular.insert(singular_points[k], singular_points[k], static_cast<int>(k));
  }

  // (c) path points outside the plate; their distance is to the nearest boundary edge.
  const EdgeTopology topology = edge_topology(F);
  for (const PathPolyline& path : paths) {
    for (int i = 0; i < path.points.rows(); ++i) {
      const Eigen::Vector2d x = path.points.row(i).head<2>();
      if (locator.locate(x).distance <= options.outside_tolerance_mm) continue;
      ++q.points_outside;
      double distance = std::numeric_limits<double>::infinity();
      for (int e = 0; e < topology.num_edges(); ++e) {
        if (!topology.is_boundary_edge(e)) continue;
        distance = std::min(distance, segment_distance(x, V.row(topology.edges(e, 0)).head<2>(),
                                                       V.row(topology.edges(e, 1)).head<2>()));
      }
      q.max_outside_mm = std::max(q.max_outside_mm, distance);
    }
  }

  // (a) and (d) on samples every sample_step spacings along each path.
  const double step = options.sample_step * s, reach = 2 * s;
  std::vector<double> nearest, angles;
  for (size_t p = 0; p < paths.size(); ++p) {
    const auto& P = paths[p].points;
    double next_sample = 0, walked = 0;
    for (int i = 0; i + 1 < P.rows(); ++i) {
      const Eigen::Vector2d a = P.row(i).head<2>(), b = P.row(i + 1).head<2>();
      const double length = (b - a).norm();
      if (length == 0) continue;
      const double tangent = std::atan2(b.y() - a.y(), b.x() - a.x());
      while (next_sample <= walked + length) {
        const Eigen::Vector2d x = a + (b - a) * ((next_sample - walked) / length);
        next_sample += step;
        double d = std::numeric_limits<double>::infinity();
        const double arc = next_sample - step;
        pieces.visit(x.array() - reach, x.array() + reach, [&](int k) {
          if (piece_path[k] == static_cast<int>(p)) {
            const double piece_length = (piece_b[k] - piece_a[k]).norm();
            double along = std::max({0.0, piece_arc[k] - arc, arc - piece_arc[k] - piece_length});
            if (paths[p].closed) along = std::min(along, path_length[p] - along - piece_length);
            if (along <= own_stretch) return;
          }
          d = std::min(d, segment_distance(x, piece_a[k], piece_b[k]));
        });
        nearest.push_back(d / s);
        if (samples) samples->push_back({x, d / s, -1});
        bool near_singularity = false;
        singular.visit(x.array() - exclusion, x.array() + exclusion, [&](int k) {
          if ((singular_points[k] - x).norm() < exclusion) near_singularity = true;
        });
        if (near_singularity) continue;
        const Location at = locator.locate(x);
        if (at.face < 0) continue;
        const double theta =
            interpolate_line_field(theta_vertex(F(at.face, 0)), theta_vertex(F(at.face, 1)),
                                   theta_vertex(F(at.face, 2)), at.bary);
        angles.push_back(line_angle_difference(tangent, theta) * 180 / std::numbers::pi);
        if (samples) samples->back().angle_deg = angles.back();
      }
      walked += length;
    }
  }
  q.samples = static_cast<int>(nearest.size());
  int in_range = 0;
  for (double d : nearest) in_range += d >= options.spacing_low && d <= options.spacing_high;
  q.spacing_in_range = q.samples ? static_cast<double>(in_range) / q.samples : 0;
  q.spacing_median = quantile(nearest, 0.5);
  q.angle_samples = static_cast<int>(angles.size());
  q.angle_median_deg = quantile(angles, 0.5);
  q.angle_p95_deg = quantile(angles, 0.95);

  // (b) coverage on a raster of pixel centres inside the plate.
  const double pixel = options.raster_step * s, radius = options.coverage_radius * s;
  const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / pixel));
  const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / pixel));
  std::vector<unsigned char> raster(static_cast<size_t>(nx) * ny, 0);  // 1 plate, 2 covered
  const auto centre = [&](int ix, int iy) {
    return Eigen::Vector2d(lo.x() + (ix + 0.5) * pixel, lo.y() + (iy + 0.5) * pixel);
  };
  const auto pixel_range = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, int& x0, int& y0,
                               int& x1, int& y1) {
    x0 = std::max(0, static_cast<int>(std::floor((a.x() - lo.x()) / pixel - 0.5)));
    y0 = std::max(0, static_cast<int>(std::floor((a.y() - lo.y()) / pixel - 0.5)));
    x1 = std::min(nx - 1, static_cast<int>(std::ceil((b.x() - lo.x()) / pixel - 0.5)));
    y1 = std::min(ny - 1, static_cast<int>(std::ceil((b.y() - lo.y()) / pixel - 0.5)));
  };
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector2d a = locator.corner(f, 0), b = locator.corner(f, 1),
                          c = locator.corner(f, 2);
    int x0, y0, x1, y1;
    pixel_range(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), x0, y0, x1, y1);
    for (int iy = y0; iy <= y1; ++iy) {
      for (int ix = x0; ix <= x1; ++ix) {
        if (barycentric(centre(ix, iy), a, b, c).minCoeff() >= 0) {
          raster[static_cast<size_t>(iy) * nx + ix] = 1;
        }
      }
    }
  }
  for (size_t k = 0; k < piece_a.size(); ++k) {
    int x0, y0, x1, y1;
    pixel_range(piece_a[k].cwiseMin(piece_b[k]).array() - radius,
                piece_a[k].cwiseMax(piece_b[k]).array() + radius, x0, y0, x1, y1);
    for (int iy = y0; iy <= y1; ++iy) {
      for (int ix = x0; ix <= x1; ++ix) {
        unsigned char& r = raster[static_cast<size_t>(iy) * nx + ix];
        if (r == 1 && segment_distance(centre(ix, iy), piece_a[k], piece_b[k]) <= radius) r = 2;
      }
    }
  }
  long long plate_pixels = 0, covered = 0;
  for (unsigned char r : raster) {
    plate_pixels += r > 0;
    covered += r == 2;
  }
  q.covered_area = plate_pixels ? static_cast<double>(covered) / plate_pixels : 0;
  return q;
}

}  // namespace flatmorph
