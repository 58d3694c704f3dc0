#include "toolpath/toolpath.h"

namespace flatmorph {

double extrusion_length(const ToolpathLayer& layer) {
  double total = 0;
  for (const PathPolyline& path : layer.paths) {
    for (size_t i = 0; i < path.segments.size(); ++i) {
      if (!path.segments[i].travel) total += (path.points.row(i + 1) - path.points.row(i)).norm();
    }
  }
  return total;
}

double travel_length(const ToolpathLayer& layer) {
  double total = 0;
  for (size_t p = 0; p < layer.paths.size(); ++p) {
    const PathPolyline& path = layer.paths[p];
    for (size_t i = 0; i < path.segments.size(); ++i) {
      if (path.segments[i].travel) {
        total += (path.points.row(i + 1) - path.points.row(i)).head<2>().norm();
      }
    }
    if (p + 1 < layer.paths.size() && path.points.rows() > 0 &&
        layer.paths[p + 1].points.rows() > 0) {
      total += (layer.paths[p + 1].points.row(0) - path.points.row(path.points.rows() - 1))
                   .head<2>()
                   .norm();
    }
  }
  return total;
}

double extrusion_volume(const ToolpathLayer& layer) {
  double total = 0;
  for (const PathPolyline& path : layer.paths) {
    for (size_t i = 0; i < path.segments.size(); ++i) {
      const SegmentStyle& s = path.segments[i];
      if (!s.travel) {
        total += (path.points.row(i + 1) - path.points.row(i)).norm() * s.width * s.layer_height;
      }
    }
  }
  return total;
}

}  // namespace flatmorph
