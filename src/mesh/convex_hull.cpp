#include "mesh/convex_hull.h"

#include <algorithm>
#include <vector>

namespace flatmorph {

Eigen::MatrixX2d convex_hull(const Eigen::MatrixX2d& points) {
  std::vector<Eigen::Vector2d> p(points.rows());
  for (Eigen::Index i = 0; i < points.rows(); ++i) p[i] = points.row(i).transpose();
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> hull;
  if (p.size() < 3) {
    hull = p;
  } else {
    hull.resize(2 * p.size());
    size_t k = 0;
    for (size_t i = 0; i < p.size(); ++i) {  // lower chain
      while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
      hull[k++] = p[i];
    }
    for (size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
      while (k >= lower && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
      hull[k++] = p[i];
    }
    hull.resize(k - 1);
  }
  Eigen::MatrixX2d out(hull.size(), 2);
  for (size_t i = 0; i < hull.size(); ++i) out.row(i) = hull[i].transpose();
  return out;
}

}  // namespace flatmorph
