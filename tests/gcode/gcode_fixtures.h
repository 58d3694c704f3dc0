// Synthetic toolpaths for the G-code tests: what the trajectory stage will produce, without it.
#pragma once

#include <cmath>
#include <numbers>

#include "toolpath/toolpath.h"

namespace flatmorph::testing {

// A polyline from `a` to `b` (mm) at height z, cut into segments of about `step` mm whose widths
// and bead heights vary from segment to segment around `height`.
inline PathPolyline line_path(Eigen::Vector2d a, Eigen::Vector2d b, double z, double height,
                              double step, int seed, PathType type) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
  PathPolyline path;
  path.type = type;
  path.points.resize(n + 1, 3);
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / n);
    path.points.row(i) << p.x(), p.y(), z;
  }
  for (int i = 0; i < n; ++i) {
    SegmentStyle s;
    s.width = 0.35 + 0.05 * ((i + seed) % 4);
    s.layer_height = height * (1.0 + 0.1 * ((i + seed) % 3 - 1));
    s.feed_rate = (i + seed) % 5 == 0 ? 25.0 : 0.0;
    path.segments.push_back(s);
  }
  return path;
}

// An arc of radius r around `c` from angle a0 over `sweep` (radians), in steps of 3 degrees.
inline PathPolyline arc_path(Eigen::Vector2d c, double r, double a0, double sweep, double z,
                             double height, int seed) {
  const int n = std::max(2, static_cast<int>(std::ceil(std::abs(sweep) / (std::numbers::pi / 60))));
  PathPolyline path;
  path.type = seed % 2 ? PathType::kPerimeter : PathType::kExternalPerimeter;
  path.points.resize(n + 1, 3);
  for (int i = 0; i <= n; ++i) {
    const double a = a0 + sweep * i / n;
    path.points.row(i) << c.x() + r * std::cos(a), c.y() + r * std::sin(a), z;
  }
  for (int i = 0; i < n; ++i) {
    SegmentStyle s;
    s.width = 0.4 + 0.02 * ((i + seed) % 3);
    s.layer_height = height;
    s.feed_rate = 0;
    path.segments.push_back(s);
  }
  return path;
}

// `layers` layers over a disk of `radius` mm centred at `center` (plate frame): even layers are
// parallel lines (zig-zag, a different angle per layer), odd layers concentric 300-degree arcs.
// Layer heights vary (0.06 to 0.09 mm) and so do widths and bead heights per segment; the first
// layer has one path with a travel segment in its middle.
inline Toolpath disk_toolpath(double radius = 50, int layers = 10,
                              Eigen::Vector2d center = Eigen::Vector2d(37, -12),
                              double spacing = 1.6) {
  Toolpath toolpath;
  double z = 0;
  for (int k = 0; k < layers; ++k) {
    ToolpathLayer layer;
    layer.height = 0.06 + 0.01 * (k % 4);
    z += layer.height;
    layer.z = z;
    if (k % 2 == 0) {
      const double angle = k * 17.0 * std::numbers::pi / 180;
      const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
      const Eigen::Vector2d v(-u.y(), u.x());
      int index = 0;
      for (double t = -radius + spacing / 2; t < radius; t += spacing, ++index) {
        const double half = std::sqrt(radius * radius - t * t) - 0.2;
        if (half < 1) continue;
        Eigen::Vector2d a = center + t * v - half * u, b = center + t * v + half * u;
        if (index % 2) std::swap(a, b);
        layer.paths.push_back(
            line_path(a, b, z, layer.height, 2.0, index + k, PathType::kSolidInfill));
      }
    } else {
      int index = 0;
      for (double r = radius - 0.5; r > 2; r -= spacing, ++index) {
        layer.paths.push_back(arc_path(center, r, 0.3 * index + k, 300 * std::numbers::pi / 180, z,
                                       layer.height, index));
      }
    }
    toolpath.layers.push_back(std::move(layer));
  }
  // A travel inside a path: lift the pen halfway along the first line.
  PathPolyline& first = toolpath.layers[0].paths[toolpath.layers[0].paths.size() / 2];
  first.segments[first.segments.size() / 2].travel = true;
  return toolpath;
}

}  // namespace flatmorph::testing
