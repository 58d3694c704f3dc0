#include "methods/tiles/tile_lattice.h"

#include <fmt/core.h>
#include <clipper.hpp>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "mesh/clipper_path.h"
#include "mesh/convex_hull.h"

namespace flatmorph {
namespace {

namespace cl = ClipperLib;

constexpr double kScale = 1e4;  // Clipper units per mm

cl::Paths offset(const cl::Paths& paths, double delta_mm) {
  cl::ClipperOffset offsetter;
  offsetter.ArcTolerance = 0.01 * kScale;
  offsetter.AddPaths(paths, cl::jtRound, cl::etClosedPolygon);
  cl::Paths out;
  offsetter.Execute(out, delta_mm * kScale);
  return out;
}

}  // namespace

TileLattice tile_lattice(const std::vector<TileOutline>& tiles, const LatticeSpec& spec,
                         double pitch, int tool) {
  if (!(spec.spacing_mm >= pitch)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("lattice spacing {} mm is below the path width {} mm: the lines "
                                "would merge into a solid sheet; give a spacing of at least {} mm",
                                spec.spacing_mm, pitch, pitch));
  }
  cl::Paths tile_paths;
  Eigen::MatrixX2d all_points(0, 2);
  for (const TileOutline& tile : tiles) {
    tile_paths.push_back(to_clipper_path(tile.boundary, kScale));
    all_points.conservativeResize(all_points.rows() + tile.boundary.rows(), 2);
    all_points.bottomRows(tile.boundary.rows()) = tile.boundary;
  }
  cl::Paths sheet;
  if (spec.outline.rows() >= 3) {
    sheet.push_back(to_clipper_path(spec.outline, kScale));
  } else {
    sheet = offset({to_clipper_path(convex_hull(all_points), kScale)}, spec.margin_mm);
  }

  TileLattice out;
  out.fill = std::min(1.0, pitch / spec.spacing_mm);
  // The area between the tiles, for the mesh: the sheet with the tiles' own outlines as holes (the
  // very points of the tiles' regions, so that the mesh conforms to both).
  if (sheet.size() != 1) {
    throw UserError(ErrorCategory::kGeometry,
                    "the lattice's sheet outline is not one loop: give one closed outline");
  }
  TileOutline region;
  region.boundary = from_clipper_path(sheet[0], kScale);
  if (!cl::Orientation(sheet[0])) region.boundary = region.boundary.colwise().reverse().eval();
  region.source = "lattice";
  for (size_t t = 0; t < tiles.size(); ++t) {
    for (Eigen::Index i = 0; i < tiles[t].boundary.rows(); ++i) {
      const cl::IntPoint p{static_cast<cl::cInt>(std::llround(tiles[t].boundary(i, 0) * kScale)),
                           static_cast<cl::cInt>(std::llround(tiles[t].boundary(i, 1) * kScale))};
      if (cl::PointInPolygon(p, sheet[0]) != 1) {
        throw UserError(
            ErrorCategory::kGeometry,
            fmt::format("{}: the tile reaches ({:.2f}, {:.2f}) mm, outside the "
                        "lattice's sheet outline: enlarge the outline or the margin",
                        tiles[t].source, tiles[t].boundary(i, 0), tiles[t].boundary(i, 1)));
      }
    }
    region.holes.push_back(tiles[t].boundary.colwise().reverse());
  }
  out.regions.push_back(std::move(region));
  // The lines' area: the sheet minus the tiles shrunk by the overlap, so lines enter each rim.
  const double overlap = spec.overlap_mm >= 0 ? spec.overlap_mm : pitch / 2;
  cl::Paths area;
  {
    cl::Clipper clipper;
    clipper.AddPaths(offset(sheet, -pitch / 2), cl::ptSubject, true);
    clipper.AddPaths(offset(tile_paths, -overlap), cl::ptClip, true);
    clipper.Execute(cl::ctDifference, area, cl::pftNonZero, cl::pftNonZero);
  }
  cl::Clipper for_bounds;
  for_bounds.AddPaths(area, cl::ptSubject, true);
  const cl::IntRect bounds = for_bounds.GetBounds();
  const cl::cInt min_x = std::min(bounds.left, bounds.right) - 1;
  const cl::cInt max_x = std::max(bounds.left, bounds.right) + 1;
  const cl::cInt min_y = std::min(bounds.top, bounds.bottom) - 1;
  const cl::cInt max_y = std::max(bounds.top, bounds.bottom) + 1;
  const double step = spec.spacing_mm * kScale;
  for (int l = 1; l <= spec.layers; ++l) {
    const bool along_x = l % 2 == 1;
    LatticePass pass;
    pass.z = l * spec.layer_height_mm;
    const double lo = static_cast<double>(along_x ? min_y : min_x);
    const double hi = static_cast<double>(along_x ? max_y : max_x);
    // Lines on a grid anchored at 0, so neighbouring layers and sheets agree.
    int index = 0;
    for (double c = std::ceil(lo / step) * step; c <= hi; c += step, ++index) {
      cl::Path line;
      const cl::cInt at = static_cast<cl::cInt>(std::llround(c));
      if (along_x) {
        line = {{min_x, at}, {max_x, at}};
      } else {
        line = {{at, min_y}, {at, max_y}};
      }
      // Along the line, in a serpentine order: every other line runs back.
      std::vector<Eigen::MatrixX2d> segments;
      for (const cl::Path& piece : clip_open_path(line, area)) {
        Eigen::MatrixX2d points = from_clipper_path(piece, kScale);
        const int axis = along_x ? 0 : 1;
        if (points(0, axis) > points(points.rows() - 1, axis))
          points = points.colwise().reverse().eval();
        if ((points.row(points.rows() - 1) - points.row(0)).norm() < 2 * pitch) continue;
        segments.push_back(points);
      }
      const int axis = along_x ? 0 : 1;
      std::sort(segments.begin(), segments.end(),
                [axis](const Eigen::MatrixX2d& a, const Eigen::MatrixX2d& b) {
                  return a(0, axis) < b(0, axis);
                });
      if (index % 2 == 1) {
        std::reverse(segments.begin(), segments.end());
        for (Eigen::MatrixX2d& s : segments) s = s.colwise().reverse().eval();
      }
      for (const Eigen::MatrixX2d& s : segments) {
        PathPolyline path;
        path.type = PathType::kSolidInfill;
        path.points.resize(s.rows(), 3);
        path.points.leftCols(2) = s;
        path.points.col(2).setConstant(pass.z);
        SegmentStyle style;
        style.width = pitch;
        style.layer_height = spec.layer_height_mm;
        style.feed_rate = spec.feed_rate;
        style.tool = tool;
        path.segments.assign(s.rows() - 1, style);
        pass.lines.push_back(std::move(path));
        ++out.lines;
      }
    }
    out.passes.push_back(std::move(pass));
  }
  return out;
}

}  // namespace flatmorph
