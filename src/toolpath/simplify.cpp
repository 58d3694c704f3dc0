#include "toolpath/simplify.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "mesh/plane_geometry.h"

namespace flatmorph {

Eigen::MatrixXd simplify_polyline(const Eigen::MatrixXd& points, double tolerance_mm) {
  const int n = static_cast<int>(points.rows());
  if (n <= 2) return points;
  std::vector<bool> keep(n, false);
  keep[0] = keep[n - 1] = true;
  std::vector<std::pair<int, int>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [first, last] = stack.back();
    stack.pop_back();
    const Eigen::Vector2d a = points.row(first).head<2>(), b = points.row(last).head<2>();
    double farthest = -1;
    int index = -1;
    for (int i = first + 1; i < last; ++i) {
      const double d = segment_distance(points.row(i).head<2>(), a, b);
      if (d > farthest) {
        farthest = d;
        index = i;
      }
    }
    if (index >= 0 && farthest > tolerance_mm) {
      keep[index] = true;
      stack.emplace_back(first, index);
      stack.emplace_back(index, last);
    }
  }
  int count = 0;
  for (bool k : keep) count += k;
  Eigen::MatrixXd out(count, points.cols());
  for (int i = 0, r = 0; i < n; ++i) {
    if (keep[i]) out.row(r++) = points.row(i);
  }
  return out;
}

}  // namespace flatmorph
