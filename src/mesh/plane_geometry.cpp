#include "mesh/plane_geometry.h"

namespace flatmorph {

std::optional<Eigen::Vector2d> segment_intersection(const Eigen::Vector2d& p,
                                                    const Eigen::Vector2d& q,
                                                    const Eigen::Vector2d& r,
                                                    const Eigen::Vector2d& s) {
  const double d1 = cross2(q - p, r - p), d2 = cross2(q - p, s - p);
  const double d3 = cross2(s - r, p - r), d4 = cross2(s - r, q - r);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    return p + (q - p) * (d3 / (d3 - d4));
  }
  // Touching: an end on the other segment's line and inside its box.
  const auto in_box = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                         const Eigen::Vector2d& x) {
    return x.x() >= std::min(a.x(), b.x()) && x.x() <= std::max(a.x(), b.x()) &&
           x.y() >= std::min(a.y(), b.y()) && x.y() <= std::max(a.y(), b.y());
  };
  if (d1 == 0 && in_box(p, q, r)) return r;
  if (d2 == 0 && in_box(p, q, s)) return s;
  if (d3 == 0 && in_box(r, s, p)) return p;
  if (d4 == 0 && in_box(r, s, q)) return q;
  return std::nullopt;
}

}  // namespace flatmorph
