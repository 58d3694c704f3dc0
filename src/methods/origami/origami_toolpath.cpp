#include "methods/origami/origami_toolpath.h"

#include <fmt/core.h>
#include <clipper.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "mesh/clipper_path.h"

namespace flatmorph {
namespace {

namespace cl = ClipperLib;

constexpr double kScale = 1e4;  // Clipper units per mm
// Lines lying exactly on the edge of the area they fill are kept inside it by this much (mm), so
// that clipping never has to decide about a line on a polygon's edge.
constexpr double kInside = 1e-3;

cl::Paths offset(const cl::Paths& paths, double delta_mm) {
  cl::ClipperOffset offsetter;
  offsetter.MiterLimit = 10;  // faces keep their corners: a solid fill reaches into them
  offsetter.AddPaths(paths, cl::jtMiter, cl::etClosedPolygon);
  cl::Paths out;
  offsetter.Execute(out, delta_mm * kScale);
  return out;
}

cl::Paths boolean(const cl::Paths& a, const cl::Paths& b, cl::ClipType type) {
  cl::Clipper clipper;
  clipper.AddPaths(a, cl::ptSubject, true);
  clipper.AddPaths(b, cl::ptClip, true);
  cl::Paths out;
  clipper.Execute(type, out, cl::pftNonZero, cl::pftNonZero);
  return out;
}

// A bead's centre line, and how it is printed.
struct Line {
  Eigen::MatrixX2d points;
  bool closed = false;
  PathType type = PathType::kSolidInfill;
};

// Parallel lines along `dir` (unit) filling `area` with touching beads `width` wide: the centre
// lines lie in the area shrunk by width/2, `width` apart, as many as fit across it, centred; in a
// serpentine order. Pieces shorter than a bead width are left out.
std::vector<Line> hatch(const cl::Paths& area, const Eigen::Vector2d& dir, double width) {
  const cl::Paths inner = offset(area, -(width / 2 - kInside));
  std::vector<Line> lines;
  if (inner.empty()) return lines;
  const Eigen::Vector2d normal(-dir.y(), dir.x());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  double along_lo = lo, along_hi = hi;
  for (const cl::Path& path : inner) {
    const Eigen::MatrixX2d p = from_clipper_path(path, kScale);
    const Eigen::VectorXd across = p * normal, along = p * dir;
    lo = std::min(lo, across.minCoeff());
    hi = std::max(hi, across.maxCoeff());
    along_lo = std::min(along_lo, along.minCoeff());
    along_hi = std::max(along_hi, along.maxCoeff());
  }
  // The area is hi − lo + width − 2·kInside wide across the lines (to Clipper's rounding).
  const int count = 1 + static_cast<int>(std::floor((hi - lo - 2 * kInside) / width + 1e-3));
  const double first = (lo + hi) / 2 - (count - 1) * width / 2;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector2d c = (first + i * width) * normal;
    Eigen::MatrixX2d ends(2, 2);
    ends.row(0) = (c + (along_lo - 1) * dir).transpose();
    ends.row(1) = (c + (along_hi + 1) * dir).transpose();
    std::vector<Eigen::MatrixX2d> row;
    for (const cl::Path& piece : clip_open_path(to_clipper_path(ends, kScale), inner)) {
      Eigen::MatrixX2d p = from_clipper_path(piece, kScale);
      if ((p.row(p.rows() - 1) - p.row(0)).dot(dir.transpose()) < 0)
        p = p.colwise().reverse().eval();
      if ((p.row(p.rows() - 1) - p.row(0)).norm() < width) continue;
      row.push_back(std::move(p));
    }
    std::sort(row.begin(), row.end(), [&](const Eigen::MatrixX2d& a, const Eigen::MatrixX2d& b) {
      return a.row(0).dot(dir.transpose()) < b.row(0).dot(dir.transpose());
    });
    if (i % 2 == 1) {
      std::reverse(row.begin(), row.end());
      for (Eigen::MatrixX2d& p : row) p = p.colwise().reverse().eval();
    }
    for (Eigen::MatrixX2d& p : row) lines.push_back({std::move(p), false, PathType::kSolidInfill});
  }
  return lines;
}

// A face: one loop half a bead inside its outline, then lines along `dir` inside the loop's bead.
std::vector<Line> solid_face(const cl::Paths& area, const Eigen::Vector2d& dir, double width) {
  std::vector<Line> lines;
  for (const cl::Path& loop : offset(area, -width / 2)) {
    if (loop.size() < 3) continue;
    Eigen::MatrixX2d p(loop.size() + 1, 2);
    p.topRows(static_cast<Eigen::Index>(loop.size())) = from_clipper_path(loop, kScale);
    p.row(p.rows() - 1) = p.row(0);
    lines.push_back({std::move(p), true, PathType::kExternalPerimeter});
  }
  for (Line& line : hatch(offset(area, -width), dir, width)) lines.push_back(std::move(line));
  return lines;
}

void check_settings(const ActuatedSheet& sheet, const OrigamiPrintSettings& s) {
  if (const std::string problem = hinge_stack_problem(s.stack); !problem.empty()) {
    throw std::invalid_argument("origami_toolpath: " + problem);
  }
  if (!(s.line_width > 0) || !(s.face_speed > 0) || !std::isfinite(s.line_width) ||
      !std::isfinite(s.face_speed) || s.pla_tool < 0 || s.tpu_tool < 0 ||
      s.pla_tool == s.tpu_tool) {
    throw std::invalid_argument(
        fmt::format("origami_toolpath: settings line width {}, face speed {}, tools {} and {}",
                    s.line_width, s.face_speed, s.pla_tool, s.tpu_tool));
  }
  if (sheet.faces.empty()) throw std::invalid_argument("origami_toolpath: the sheet has no face");
  for (const Eigen::MatrixX2d& face : sheet.faces) {
    if (face.rows() < 3 || !face.allFinite()) {
      throw std::invalid_argument("origami_toolpath: a face with fewer than 3 finite corners");
    }
  }
  for (const Actuator& a : sheet.actuators) {
    const int faces = static_cast<int>(sheet.faces.size());
    if (!(a.hinge.pla_speed > 0) || !std::isfinite(a.hinge.pla_speed) || !a.quad.allFinite() ||
        std::abs(a.across.norm() - 1) > 1e-6 || a.parent_face < 0 || a.parent_face >= faces ||
        a.child_face < 0 || a.child_face >= faces) {
      throw std::invalid_argument(fmt::format(
          "origami_toolpath: the actuator of crease {} has PLA speed {}, faces {} and "
          "{}, |across| {}",
          a.hinge.crease, a.hinge.pla_speed, a.parent_face, a.child_face, a.across.norm()));
    }
  }
}

// Whether actuator `a` prints active PLA (rather than TPU) in layer k (0 on the bed): notes §8.
bool active_in(const Actuator& a, int k, const OrigamiPrintSettings& s) {
  return a.hinge.pla_on_bed ? k < s.stack.pla_layers : k >= s.stack.tpu_layers;
}

// Per layer, whether it starts with PLA: every layer prints PLA (the faces) and some TPU too, one
// material after the other, starting with the one the layer below ended with; the first layer
// starts with the one that makes the print change material fewest times (ties: PLA).
std::vector<bool> layers_start_with_pla(const std::vector<bool>& uses_tpu) {
  auto run = [&](bool pla, int& changes) {
    std::vector<bool> starts;
    changes = 0;
    for (const bool tpu : uses_tpu) {
      if (!pla && !tpu) {
        pla = true;
        ++changes;
      }
      starts.push_back(pla);
      if (tpu) {
        pla = !pla;
        ++changes;
      }
    }
    return starts;
  };
  int with_pla = 0, with_tpu = 0;
  const std::vector<bool> pla_first = run(true, with_pla);
  const std::vector<bool> tpu_first = run(false, with_tpu);
  return with_tpu < with_pla ? tpu_first : pla_first;
}

PathPolyline path_of(const Line& line, double z, double height, double width, double speed,
                     int tool) {
  PathPolyline path;
  path.type = line.type;
  path.closed = line.closed;
  path.points.resize(line.points.rows(), 3);
  path.points.leftCols<2>() = line.points;
  path.points.col(2).setConstant(z);
  SegmentStyle style;
  style.width = width;
  style.layer_height = height;
  style.feed_rate = speed;
  style.tool = tool;
  path.segments.assign(static_cast<size_t>(line.points.rows() - 1), style);
  return path;
}

}  // namespace

bool face_lines_along_y(int k, int num_layers) { return std::min(k, num_layers - 1 - k) % 2 == 1; }

Toolpath origami_toolpath(const ActuatedSheet& sheet, const OrigamiPrintSettings& settings) {
  check_settings(sheet, settings);
  const double w = settings.line_width;
  const double m = settings.stack.overlap;

  // Each actuator's area: its quad grown by the margin across the hinge into both faces, and no
  // further than the quad and those faces reach (a face narrowing at a corner).
  std::vector<cl::Paths> area;
  cl::Paths taken;  // the areas of the actuators before
  for (const Actuator& a : sheet.actuators) {
    Eigen::Matrix<double, 4, 2> grown = a.quad;
    for (int i = 0; i < 4; ++i) {
      grown.row(i) += (i < 2 ? -m : m) * a.across.transpose();
    }
    const cl::Paths sheet_part = {to_clipper_path(a.quad, kScale),
                                  to_clipper_path(sheet.faces[a.parent_face], kScale),
                                  to_clipper_path(sheet.faces[a.child_face], kScale)};
    const cl::Paths own = boolean({to_clipper_path(grown, kScale)}, sheet_part, cl::ctIntersection);
    area.push_back(boolean(own, taken, cl::ctDifference));
    taken = boolean(taken, own, cl::ctUnion);
  }

  // What each layer prints, by material, in the sheet's order: faces, then actuators.
  std::array<std::vector<std::vector<Line>>, 2> face_lines;  // along x, along y; per face
  for (const Eigen::MatrixX2d& face : sheet.faces) {
    const cl::Paths rest = boolean({to_clipper_path(face, kScale)}, taken, cl::ctDifference);
    face_lines[0].push_back(solid_face(rest, Eigen::Vector2d::UnitX(), w));
    face_lines[1].push_back(solid_face(rest, Eigen::Vector2d::UnitY(), w));
  }
  std::vector<std::vector<Line>> active_lines, constraint_lines;
  for (size_t i = 0; i < sheet.actuators.size(); ++i) {
    const Eigen::Vector2d across = sheet.actuators[i].across;
    active_lines.push_back(hatch(area[i], across, w));
    constraint_lines.push_back(hatch(area[i], Eigen::Vector2d(-across.y(), across.x()), w));
  }

  const int layers = settings.stack.pla_layers + settings.stack.tpu_layers;
  std::vector<bool> uses_tpu(static_cast<size_t>(layers), false);
  for (const Actuator& a : sheet.actuators) {
    for (int k = 0; k < layers; ++k) {
      if (!active_in(a, k, settings)) uses_tpu[static_cast<size_t>(k)] = true;
    }
  }
  const std::vector<bool> pla_first = layers_start_with_pla(uses_tpu);

  Toolpath toolpath;
  for (int k = 0; k < layers; ++k) {
    ToolpathLayer layer;
    layer.height = settings.stack.layer_height;
    layer.z = (k + 1) * settings.stack.layer_height;
    std::vector<PathPolyline> pla, tpu;
    for (const std::vector<Line>& lines : face_lines[face_lines_along_y(k, layers) ? 1 : 0]) {
      for (const Line& line : lines) {
        pla.push_back(
            path_of(line, layer.z, layer.height, w, settings.face_speed, settings.pla_tool));
      }
    }
    for (size_t i = 0; i < sheet.actuators.size(); ++i) {
      const Actuator& a = sheet.actuators[i];
      if (active_in(a, k, settings)) {
        for (const Line& line : active_lines[i]) {
          pla.push_back(
              path_of(line, layer.z, layer.height, w, a.hinge.pla_speed, settings.pla_tool));
        }
      } else {
        for (const Line& line : constraint_lines[i]) {
          tpu.push_back(
              path_of(line, layer.z, layer.height, w, settings.stack.tpu_speed, settings.tpu_tool));
        }
      }
    }
    std::vector<PathPolyline>& first = pla_first[static_cast<size_t>(k)] ? pla : tpu;
    std::vector<PathPolyline>& second = pla_first[static_cast<size_t>(k)] ? tpu : pla;
    layer.paths = std::move(first);
    layer.paths.insert(layer.paths.end(), std::make_move_iterator(second.begin()),
                       std::make_move_iterator(second.end()));
    toolpath.layers.push_back(std::move(layer));
  }
  return toolpath;
}

}  // namespace flatmorph
