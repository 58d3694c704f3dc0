// The small kernels of plane geometry that several stages share: points, segments and triangles of
// the plate's plane as Eigen::Vector2d, mm (areas mm²). The smallest are inline: they sit in the
// inner loops of the path checks and the flattening.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <optional>

namespace flatmorph {

// The z component of the cross product a × b, mm²: positive when b turns counter-clockwise from a.
inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// The signed area of triangle (a, b, c), mm²: positive when it runs counter-clockwise.
inline double triangle_signed_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                   const Eigen::Vector2d& c) {
  return 0.5 * cross2(b - a, c - a);
}

// The distance from p to the segment ab, mm; `t` receives where along ab (in [0, 1]) its closest
// point a + t (b − a) lies. A segment of zero length is its point a (t = 0).
inline double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                               const Eigen::Vector2d& b, double& t) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

inline double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                               const Eigen::Vector2d& b) {
  double t;
  return segment_distance(p, a, b, t);
}

// One step of the even-odd point-in-polygon test: whether the side from a to b crosses the ray
// from p towards +x. Half-open in y, so that a corner on the ray's height counts once over its
// two sides.
inline bool side_crosses_ray(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                             const Eigen::Vector2d& b) {
  return (a.y() > p.y()) != (b.y() > p.y()) &&
         p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
}

// A point the closed segments pq and rs share, if any: where they cross, else an end of one that
// lies on the other (touching, or overlapping along one line). Exact signs: no tolerance.
std::optional<Eigen::Vector2d> segment_intersection(const Eigen::Vector2d& p,
                                                    const Eigen::Vector2d& q,
                                                    const Eigen::Vector2d& r,
                                                    const Eigen::Vector2d& s);

}  // namespace flatmorph
