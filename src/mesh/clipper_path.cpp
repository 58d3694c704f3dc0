#include "mesh/clipper_path.h"

#include <algorithm>
#include <cmath>

namespace flatmorph {

ClipperLib::Path to_clipper_path(const Eigen::MatrixX2d& polygon, double scale) {
  ClipperLib::Path path;
  path.reserve(static_cast<size_t>(polygon.rows()));
  for (Eigen::Index i = 0; i < polygon.rows(); ++i) {
    path.emplace_back(static_cast<ClipperLib::cInt>(std::llround(polygon(i, 0) * scale)),
                      static_cast<ClipperLib::cInt>(std::llround(polygon(i, 1) * scale)));
  }
  return path;
}

Eigen::MatrixX2d from_clipper_path(const ClipperLib::Path& path, double scale) {
  Eigen::MatrixX2d polygon(static_cast<Eigen::Index>(path.size()), 2);
  for (size_t i = 0; i < path.size(); ++i) {
    polygon(static_cast<Eigen::Index>(i), 0) = static_cast<double>(path[i].X) / scale;
    polygon(static_cast<Eigen::Index>(i), 1) = static_cast<double>(path[i].Y) / scale;
  }
  return polygon;
}

ClipperLib::Paths clip_open_path(const ClipperLib::Path& line, const ClipperLib::Paths& area) {
  ClipperLib::Clipper clipper;
  clipper.AddPath(line, ClipperLib::ptSubject, false);
  clipper.AddPaths(area, ClipperLib::ptClip, true);
  ClipperLib::PolyTree tree;
  clipper.Execute(ClipperLib::ctIntersection, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  ClipperLib::Paths pieces;
  ClipperLib::OpenPathsFromPolyTree(tree, pieces);
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(),
                              [](const ClipperLib::Path& piece) { return piece.size() < 2; }),
               pieces.end());
  return pieces;
}

}  // namespace flatmorph
