#include "methods/origami/fold_simulation.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "mesh/plane_geometry.h"
#include "mesh/polygon.h"

namespace flatmorph {
namespace {

// A face's place in 3D: sheet point p (z = 0) ↦ R p + t.
struct Frame {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator()(const Eigen::Vector3d& p) const { return R * p + t; }
};

Eigen::Vector3d lift(const Eigen::Vector2d& p) { return {p.x(), p.y(), 0}; }

Eigen::MatrixX3d place(const Frame& frame, const Eigen::MatrixX2d& corners) {
  Eigen::MatrixX3d out(corners.rows(), 3);
  for (Eigen::Index i = 0; i < corners.rows(); ++i) {
    out.row(i) = frame(lift(corners.row(i).transpose())).transpose();
  }
  return out;
}

std::vector<Frame> sharp_frames(const CreasePattern& pattern, double progress) {
  check_fold_tree(pattern);
  std::vector<Frame> frame(pattern.num_faces());
  for (int f : pattern.fold_order) {
    const int c = pattern.parent_crease[f];
    if (c < 0) continue;
    const Crease& crease = pattern.creases[c];
    const Frame& parent = frame[pattern.other_face(c, f)];
    // The crease as the child runs it (counter-clockwise from +z): the child lies to its left, so
    // a turn by +α about it lifts the child toward +z, a valley (notes §3).
    const bool left = crease.left == f;
    const Eigen::Vector3d start = lift(pattern.V.row(left ? crease.v0 : crease.v1).transpose());
    const Eigen::Vector3d end = lift(pattern.V.row(left ? crease.v1 : crease.v0).transpose());
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(progress * crease.fold_angle, (end - start).normalized())
            .toRotationMatrix();
    frame[f].R = parent.R * turn;
    frame[f].t = parent.R * (start - turn * start) + parent.t;
  }
  return frame;
}

// The arc of a strip bent by `angle` over its width `width`: the point s along it, as
// (across, up) = (sin(κs)/κ, (1 − cos(κs))/κ) with κ = angle / width (notes §7), written so that
// a flat strip (κ → 0) loses no digits.
Eigen::Vector2d arc_point(double s, double angle, double width) {
  if (std::abs(angle) < 1e-12) return {s, 0};
  const double kappa = angle / width;
  const double half = std::sin(kappa * s / 2);
  return {std::sin(kappa * s) / kappa, 2 * half * half / kappa};
}

// The actuator of each hinge of the tree, by crease; checks that `sheet` actuates `pattern`.
std::vector<int> actuator_of_crease(const CreasePattern& pattern, const ActuatedSheet& sheet) {
  check_fold_tree(pattern);
  if (static_cast<int>(sheet.faces.size()) != pattern.num_faces()) {
    throw std::invalid_argument(
        "fold_curved: the sheet has another number of faces than the pattern");
  }
  std::vector<int> out(pattern.creases.size(), -1);
  for (size_t a = 0; a < sheet.actuators.size(); ++a) {
    const Actuator& actuator = sheet.actuators[a];
    const int c = actuator.hinge.crease;
    if (c < 0 || c >= static_cast<int>(pattern.creases.size()) || !pattern.is_hinge(c) ||
        out[c] >= 0 || actuator.child_face < 0 || actuator.child_face >= pattern.num_faces() ||
        pattern.parent_crease[actuator.child_face] != c ||
        pattern.other_face(c, actuator.child_face) != actuator.parent_face) {
      throw std::invalid_argument(
          fmt::format("fold_curved: actuator {} is not on a hinge of the pattern's tree", a));
    }
    out[c] = static_cast<int>(a);
  }
  for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
    if (pattern.is_hinge(c) && out[c] < 0) {
      throw std::invalid_argument(fmt::format("fold_curved: hinge {} has no actuator", c));
    }
  }
  return out;
}

// The curved fold with each actuator at its own progress (bent to progress·θ over its width).
FoldedSheet fold_with(const CreasePattern& pattern, const ActuatedSheet& sheet,
                      const std::vector<double>& progress, int arc_steps) {
  const std::vector<int> actuator = actuator_of_crease(pattern, sheet);
  const Eigen::Vector3d up(0, 0, 1);
  std::vector<Frame> frame(pattern.num_faces());
  FoldedSheet out;
  out.faces.resize(pattern.num_faces());
  out.actuators.resize(sheet.actuators.size());
  for (int f : pattern.fold_order) {
    const int c = pattern.parent_crease[f];
    if (c >= 0) {
      frame[f] = frame[pattern.other_face(c, f)];  // a flat crease keeps the faces together
    }
    if (c >= 0 && actuator[c] >= 0) {
      const int a = actuator[c];
      const Actuator& strip = sheet.actuators[a];
      const Frame parent = frame[strip.parent_face];
      const double width = strip.hinge.width;
      const double angle = progress[a] * strip.hinge.fold_angle;
      // The strip's own axes: `along` the hinge, the child to its left, so that a turn by +angle
      // about it takes `across` toward +z (a valley, as in the sharp fold).
      const Eigen::Vector3d edge = lift(strip.quad.row(0).transpose());
      const Eigen::Vector3d across = lift(strip.across);
      const Eigen::Vector3d along(strip.across.y(), -strip.across.x(), 0);
      const auto bent = [&](const Eigen::Vector2d& p) {
        const Eigen::Vector3d q = lift(p) - edge;
        const Eigen::Vector2d arc = arc_point(q.dot(across), angle, width);
        return parent(edge + q.dot(along) * along + arc.x() * across + arc.y() * up);
      };
      const Eigen::Vector2d end = arc_point(width, angle, width);
      const Eigen::Matrix3d turn = Eigen::AngleAxisd(angle, along).toRotationMatrix();
      frame[f].R = parent.R * turn;
      frame[f].t =
          parent.R * (edge + end.x() * across + end.y() * up - turn * (edge + width * across)) +
          parent.t;
      ActuatorStrip& folded = out.actuators[a];
      folded.side0.resize(arc_steps + 1, 3);
      folded.side1.resize(arc_steps + 1, 3);
      for (int i = 0; i <= arc_steps; ++i) {
        const double w = static_cast<double>(i) / arc_steps;
        folded.side0.row(i) =
            bent((1 - w) * strip.quad.row(0).transpose() + w * strip.quad.row(3).transpose())
                .transpose();
        folded.side1.row(i) =
            bent((1 - w) * strip.quad.row(1).transpose() + w * strip.quad.row(2).transpose())
                .transpose();
      }
    }
    out.faces[f] = place(frame[f], sheet.faces[f]);
  }
  return out;
}

// A triangle shrunk toward its incentre so that each side moves in by `by`; nothing when it is
// not wider than that.
std::optional<Eigen::Matrix3d> shrunk(const Eigen::Matrix3d& t, double by) {
  const Eigen::Vector3d side(  // opposite each corner
      (t.row(1) - t.row(2)).norm(), (t.row(2) - t.row(0)).norm(), (t.row(0) - t.row(1)).norm());
  const double perimeter = side.sum();
  const double area = (t.row(1) - t.row(0)).cross(t.row(2) - t.row(0)).norm() / 2;
  const double inradius = perimeter > 0 ? 2 * area / perimeter : 0;
  if (inradius <= by) return std::nullopt;
  const Eigen::RowVector3d centre = (side.transpose() * t) / perimeter;
  const double keep = (inradius - by) / inradius;
  return ((t.rowwise() - centre) * keep).rowwise() + centre;
}

bool inside_triangle(const Eigen::Matrix<double, 3, 2>& t, const Eigen::Vector2d& x) {
  double sign[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d a = t.row(k).transpose(), b = t.row((k + 1) % 3).transpose();
    sign[k] = cross2(b - a, x - a);
  }
  return (sign[0] >= 0 && sign[1] >= 0 && sign[2] >= 0) ||
         (sign[0] <= 0 && sign[1] <= 0 && sign[2] <= 0);
}

// Two triangles of one plane (normal n) share a point: a side crosses a side, or one holds the
// other.
bool coplanar_meet(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, const Eigen::Vector3d& n) {
  int drop;
  n.cwiseAbs().maxCoeff(&drop);
  const int x = (drop + 1) % 3, y = (drop + 2) % 3;
  Eigen::Matrix<double, 3, 2> a2, b2;
  a2 << a.col(x), a.col(y);
  b2 << b.col(x), b.col(y);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (segment_intersection(a2.row(i).transpose(), a2.row((i + 1) % 3).transpose(),
                               b2.row(j).transpose(), b2.row((j + 1) % 3).transpose())
              .has_value()) {
        return true;
      }
    }
  }
  return inside_triangle(b2, a2.row(0).transpose()) || inside_triangle(a2, b2.row(0).transpose());
}

// The part of triangle t on a plane (signed distances `d` of its corners, none all of one sign):
// its extent along `line`.
Eigen::Vector2d extent_on_plane(const Eigen::Matrix3d& t, const Eigen::Vector3d& d,
                                const Eigen::Vector3d& line) {
  Eigen::Vector2d out(std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity());
  const auto add = [&](const Eigen::Vector3d& p) {
    const double x = p.dot(line);
    out = Eigen::Vector2d(std::min(out.x(), x), std::max(out.y(), x));
  };
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (d(i) == 0) add(t.row(i).transpose());
    if ((d(i) > 0 && d(j) < 0) || (d(i) < 0 && d(j) > 0)) {
      add((t.row(i) + (t.row(j) - t.row(i)) * (d(i) / (d(i) - d(j)))).transpose());
    }
  }
  return out;
}

// Closed triangles share a point (Möller's interval test: where each crosses the other's plane,
// both pieces lie on the planes' common line, and they meet where their extents there overlap).
bool triangles_meet(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  if ((a.colwise().maxCoeff().array() < b.colwise().minCoeff().array()).any() ||
      (b.colwise().maxCoeff().array() < a.colwise().minCoeff().array()).any()) {
    return false;
  }
  const Eigen::Vector3d na = (a.row(1) - a.row(0)).cross(a.row(2) - a.row(0)).transpose();
  const Eigen::Vector3d nb = (b.row(1) - b.row(0)).cross(b.row(2) - b.row(0)).transpose();
  const double size = std::max((a.colwise().maxCoeff() - a.colwise().minCoeff()).maxCoeff(),
                               (b.colwise().maxCoeff() - b.colwise().minCoeff()).maxCoeff());
  // Signed distances to the other's plane (times its normal's length), 0 within rounding.
  const auto distances = [&](const Eigen::Matrix3d& t, const Eigen::Matrix3d& other,
                             const Eigen::Vector3d& n) {
    Eigen::Vector3d d = (t.rowwise() - other.row(0)) * n;
    const double zero = 1e-12 * n.norm() * size;
    for (int i = 0; i < 3; ++i) d(i) = std::abs(d(i)) <= zero ? 0 : d(i);
    return d;
  };
  const Eigen::Vector3d da = distances(a, b, nb), db = distances(b, a, na);
  const auto one_side = [](const Eigen::Vector3d& d) {
    return (d.array() > 0).all() || (d.array() < 0).all();
  };
  if (one_side(da) || one_side(db)) return false;
  const Eigen::Vector3d line = na.cross(nb);
  if ((da.array() == 0).all() || line.norm() <= 1e-12 * na.norm() * nb.norm()) {
    return coplanar_meet(a, b, na);
  }
  const Eigen::Vector2d ea = extent_on_plane(a, da, line), eb = extent_on_plane(b, db, line);
  return ea.y() >= eb.x() && eb.y() >= ea.x();
}

// A piece's triangles shrunk by the tolerance (as triangles_intersect does, once per piece), and
// their bounding box.
struct Piece {
  std::vector<Eigen::Matrix3d> triangles;
  Eigen::Array3d low, high;
};

Piece make_piece(const std::vector<Eigen::Matrix3d>& triangles, double tolerance) {
  Piece piece;
  for (const Eigen::Matrix3d& t : triangles) {
    if (const std::optional<Eigen::Matrix3d> inner = shrunk(t, tolerance)) {
      piece.triangles.push_back(*inner);
    }
  }
  piece.low = Eigen::Array3d::Constant(std::numeric_limits<double>::infinity());
  piece.high = -piece.low;
  for (const Eigen::Matrix3d& t : piece.triangles) {
    piece.low = piece.low.min(t.colwise().minCoeff().transpose().array());
    piece.high = piece.high.max(t.colwise().maxCoeff().transpose().array());
  }
  return piece;
}

bool boxes_meet(const Piece& a, const Piece& b) {
  return !((a.high < b.low).any() || (b.high < a.low).any());
}

}  // namespace

void check_fold_tree(const CreasePattern& pattern) {
  const int num_faces = pattern.num_faces();
  const int num_creases = static_cast<int>(pattern.creases.size());
  if (static_cast<int>(pattern.parent_crease.size()) != num_faces ||
      static_cast<int>(pattern.fold_order.size()) != num_faces || num_faces == 0 ||
      pattern.fold_order[0] != pattern.root) {
    throw std::invalid_argument(pattern.name + ": the fold tree does not cover the faces");
  }
  std::vector<char> seen(num_faces, 0);
  for (int f : pattern.fold_order) {
    if (f < 0 || f >= num_faces || seen[f]) {
      throw std::invalid_argument(pattern.name + ": the fold order lists a face twice or none");
    }
    const int c = pattern.parent_crease[f];
    const bool joined = c >= 0 && c < num_creases && pattern.creases[c].right >= 0 &&
                        (pattern.creases[c].left == f || pattern.creases[c].right == f) &&
                        seen[pattern.other_face(c, f)];
    if ((f == pattern.root) != (c < 0) || (c >= 0 && !joined)) {
      throw std::invalid_argument(fmt::format(
          "{}: face {} is not joined to an earlier face by its parent crease", pattern.name, f));
    }
    seen[f] = 1;
  }
}

std::vector<Eigen::MatrixX3d> fold_sharp(const CreasePattern& pattern, double progress) {
  const std::vector<Frame> frame = sharp_frames(pattern, progress);
  std::vector<Eigen::MatrixX3d> out(pattern.num_faces());
  for (int f = 0; f < pattern.num_faces(); ++f) {
    const std::vector<int>& face = pattern.faces[f];
    out[f].resize(static_cast<Eigen::Index>(face.size()), 3);
    for (size_t k = 0; k < face.size(); ++k) {
      out[f].row(static_cast<Eigen::Index>(k)) =
          frame[f](lift(pattern.V.row(face[k]).transpose())).transpose();
    }
  }
  return out;
}

double loop_closure_error(const CreasePattern& pattern) {
  const std::vector<Frame> frame = sharp_frames(pattern, 1.0);
  double worst = 0;
  for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
    const Crease& crease = pattern.creases[c];
    if (crease.right < 0 || pattern.parent_crease[crease.left] == c ||
        pattern.parent_crease[crease.right] == c) {
      continue;
    }
    for (int v : {crease.v0, crease.v1}) {
      const Eigen::Vector3d p = lift(pattern.V.row(v).transpose());
      worst = std::max(worst, (frame[crease.left](p) - frame[crease.right](p)).norm());
    }
  }
  return worst;
}

FoldedSheet fold_curved(const CreasePattern& pattern, const ActuatedSheet& sheet, double progress,
                        int arc_steps) {
  if (!(progress >= 0 && progress <= 1) || arc_steps < 1) {
    throw std::invalid_argument("fold_curved: progress outside [0, 1] or arc_steps below 1");
  }
  return fold_with(pattern, sheet, std::vector<double>(sheet.actuators.size(), progress),
                   arc_steps);
}

Mesh folded_mesh(const FoldedSheet& folded) {
  std::vector<Eigen::RowVector3d> vertices;
  std::vector<Eigen::RowVector3i> triangles;
  for (const Eigen::MatrixX3d& face : folded.faces) {
    // In the face's own plane (Newell's normal: the sheet's upper side), where ear clipping keeps
    // the counter-clockwise sense.
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (Eigen::Index i = 0; i < face.rows(); ++i) {
      normal += face.row(i).cross(face.row((i + 1) % face.rows())).transpose();
    }
    normal.normalize();
    const Eigen::Vector3d x = normal.unitOrthogonal();
    const Eigen::Vector3d y = normal.cross(x);
    Eigen::MatrixX2d flat(face.rows(), 2);
    flat.col(0) = face * x;
    flat.col(1) = face * y;
    const Eigen::MatrixX3i cut = triangulate_polygon(flat);
    const int first = static_cast<int>(vertices.size());
    for (Eigen::Index i = 0; i < face.rows(); ++i) vertices.push_back(face.row(i));
    for (Eigen::Index t = 0; t < cut.rows(); ++t) {
      triangles.push_back(cut.row(t).array() + first);
    }
  }
  for (const ActuatorStrip& strip : folded.actuators) {
    const int first = static_cast<int>(vertices.size());
    const int n = static_cast<int>(strip.side0.rows());
    for (int i = 0; i < n; ++i) {
      vertices.push_back(strip.side0.row(i));
      vertices.push_back(strip.side1.row(i));
    }
    for (int i = 0; i + 1 < n; ++i) {
      const int a = first + 2 * i;  // side0[i]; a + 1 is side1[i], a + 2 and a + 3 the next pair
      triangles.push_back({a, a + 1, a + 3});
      triangles.push_back({a, a + 3, a + 2});
    }
  }
  Mesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  mesh.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (size_t i = 0; i < vertices.size(); ++i)
    mesh.V.row(static_cast<Eigen::Index>(i)) = vertices[i];
  for (size_t i = 0; i < triangles.size(); ++i) {
    mesh.F.row(static_cast<Eigen::Index>(i)) = triangles[i];
  }
  return mesh;
}

bool triangles_intersect(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, double tolerance) {
  const std::optional<Eigen::Matrix3d> inner_a = shrunk(a, tolerance);
  const std::optional<Eigen::Matrix3d> inner_b = shrunk(b, tolerance);
  return inner_a && inner_b && triangles_meet(*inner_a, *inner_b);
}

std::optional<FoldCollision> first_collision(const CreasePattern& pattern,
                                             const ActuatedSheet& sheet, int steps,
                                             bool in_fold_order) {
  if (steps < 1) throw std::invalid_argument("first_collision: steps below 1");
  const int num_faces = static_cast<int>(sheet.faces.size());
  const int num_actuators = static_cast<int>(sheet.actuators.size());
  const int num_pieces = num_faces + num_actuators;

  // Neighbours touch by construction: a face and its actuators, faces joined along the tree.
  std::vector<std::vector<char>> neighbours(num_pieces, std::vector<char>(num_pieces, 0));
  const auto join = [&](int a, int b) { neighbours[a][b] = neighbours[b][a] = 1; };
  for (int f = 0; f < pattern.num_faces(); ++f) {
    if (pattern.parent_crease[f] >= 0) join(f, pattern.other_face(pattern.parent_crease[f], f));
  }
  for (int a = 0; a < num_actuators; ++a) {
    join(num_faces + a, sheet.actuators[a].parent_face);
    join(num_faces + a, sheet.actuators[a].child_face);
  }

  std::vector<Eigen::MatrixX3i> face_triangles(num_faces);
  Eigen::Array2d low = Eigen::Array2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Array2d high = -low;
  double largest_angle = 0;
  for (int f = 0; f < num_faces; ++f) {
    face_triangles[f] = triangulate_polygon(sheet.faces[f]);
    low = low.min(sheet.faces[f].colwise().minCoeff().transpose().array());
    high = high.max(sheet.faces[f].colwise().maxCoeff().transpose().array());
  }
  for (const Actuator& actuator : sheet.actuators) {
    largest_angle = std::max(largest_angle, std::abs(actuator.hinge.fold_angle));
  }
  const double tolerance = 1e-6 * (high - low).matrix().norm();
  // A segment per 10° of arc: chords then stay within 0.4 % of the radius of their arc.
  const int arc_steps =
      std::max(2, static_cast<int>(std::ceil(largest_angle / (std::numbers::pi / 18))));

  const auto collision_at =
      [&](const std::vector<double>& progress) -> std::optional<std::pair<int, int>> {
    const FoldedSheet folded = fold_with(pattern, sheet, progress, arc_steps);
    std::vector<Piece> pieces;
    pieces.reserve(num_pieces);
    for (int f = 0; f < num_faces; ++f) {
      std::vector<Eigen::Matrix3d> triangles;
      for (Eigen::Index t = 0; t < face_triangles[f].rows(); ++t) {
        Eigen::Matrix3d triangle;
        for (int k = 0; k < 3; ++k) triangle.row(k) = folded.faces[f].row(face_triangles[f](t, k));
        triangles.push_back(triangle);
      }
      pieces.push_back(make_piece(triangles, tolerance));
    }
    for (const ActuatorStrip& strip : folded.actuators) {
      std::vector<Eigen::Matrix3d> triangles;
      for (Eigen::Index i = 0; i + 1 < strip.side0.rows(); ++i) {
        Eigen::Matrix3d triangle;
        triangle << strip.side0.row(i), strip.side1.row(i), strip.side1.row(i + 1);
        triangles.push_back(triangle);
        triangle << strip.side0.row(i), strip.side1.row(i + 1), strip.side0.row(i + 1);
        triangles.push_back(triangle);
      }
      pieces.push_back(make_piece(triangles, tolerance));
    }
    for (int a = 0; a < num_pieces; ++a) {
      for (int b = a + 1; b < num_pieces; ++b) {
        if (neighbours[a][b] || !boxes_meet(pieces[a], pieces[b])) continue;
        for (const Eigen::Matrix3d& ta : pieces[a].triangles) {
          for (const Eigen::Matrix3d& tb : pieces[b].triangles) {
            if (triangles_meet(ta, tb)) return std::pair(a, b);
          }
        }
      }
    }
    return std::nullopt;
  };

  // The flat sheet itself is sheet_overlaps' to judge (exact polygon clipping): all its pieces
  // lie in one plane, where touching and crossing differ by rounding alone.
  std::vector<double> progress(num_actuators, 0.0);
  if (!in_fold_order) {
    for (int k = 1; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      std::fill(progress.begin(), progress.end(), t);
      if (const auto hit = collision_at(progress)) return FoldCollision{hit->first, hit->second, t};
    }
    return std::nullopt;
  }
  for (int a = 0; a < num_actuators; ++a) {
    for (int k = 1; k <= steps; ++k) {
      progress[a] = static_cast<double>(k) / steps;
      if (const auto hit = collision_at(progress)) {
        return FoldCollision{hit->first, hit->second, (a + progress[a]) / num_actuators, a};
      }
    }
  }
  return std::nullopt;
}

std::string piece_name(const ActuatedSheet& sheet, int piece) {
  const int num_faces = static_cast<int>(sheet.faces.size());
  // Numbered from 1, as net.svg and design.json show them.
  if (piece < num_faces) return fmt::format("face {}", piece + 1);
  const Actuator& actuator = sheet.actuators.at(piece - num_faces);
  return fmt::format("actuator {} (faces {}–{})", piece - num_faces + 1, actuator.parent_face + 1,
                     actuator.child_face + 1);
}

}  // namespace flatmorph
