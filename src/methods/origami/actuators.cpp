#include "methods/origami/actuators.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "common/error.h"
#include "mesh/plane_geometry.h"
#include "mesh/polygon.h"
#include "methods/origami/fold_simulation.h"

namespace flatmorph {
namespace {

// Beyond this an actuator's L = 2 r tan(|θ|/2) outgrows any face (notes §4, degenerate cases).
constexpr double kLargestFold = 170 * std::numbers::pi / 180;

Eigen::MatrixX2d face_corners(const CreasePattern& pattern, int f) {
  const std::vector<int>& face = pattern.faces[f];
  Eigen::MatrixX2d out(static_cast<Eigen::Index>(face.size()), 2);
  for (size_t k = 0; k < face.size(); ++k) {
    out.row(static_cast<Eigen::Index>(k)) = pattern.V.row(face[k]);
  }
  return out;
}

// Per face, per side k (corner k to k + 1): its crease.
std::vector<std::vector<int>> side_creases(const CreasePattern& pattern) {
  std::map<std::pair<int, int>, int> crease_of;  // (from, to) as the face runs it
  for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
    const Crease& crease = pattern.creases[c];
    crease_of[{crease.v0, crease.v1}] = c;
    if (crease.right >= 0) crease_of[{crease.v1, crease.v0}] = c;
  }
  std::vector<std::vector<int>> out(pattern.num_faces());
  for (int f = 0; f < pattern.num_faces(); ++f) {
    const std::vector<int>& face = pattern.faces[f];
    for (size_t k = 0; k < face.size(); ++k) {
      const auto it = crease_of.find({face[k], face[(k + 1) % face.size()]});
      if (it == crease_of.end()) {
        throw std::invalid_argument(
            fmt::format("actuate: side {} of face {} of {} has no crease", k, f, pattern.name));
      }
      out[f].push_back(it->second);
    }
  }
  return out;
}

// A face with each side's supporting line moved inward by its inset (notes §4, the general rule).
struct Trim {
  Eigen::MatrixX2d corners;
  std::vector<int> side_start;   // per side of the face: the trimmed corner it starts at
  std::vector<int> from_corner;  // per trimmed corner: the face's corner it comes from
};

Trim trim_face(const Eigen::MatrixX2d& face, const std::vector<double>& inset) {
  const int n = static_cast<int>(face.rows());
  std::vector<Eigen::Vector2d> direction(n), normal(n), base(n);  // normal: outward
  for (int k = 0; k < n; ++k) {
    direction[k] = (face.row((k + 1) % n) - face.row(k)).transpose().normalized();
    normal[k] = Eigen::Vector2d(direction[k].y(), -direction[k].x());
    base[k] = face.row(k).transpose() - inset[k] * normal[k];
  }
  std::vector<Eigen::Vector2d> corners;
  Trim out;
  for (int k = 0; k < n; ++k) {
    const int before = (k + n - 1) % n;
    const double turn = cross2(direction[before], direction[k]);
    const Eigen::Vector2d corner = face.row(k).transpose();
    if (std::abs(turn) > 1e-9) {
      const double along = cross2(base[before] - base[k], direction[before]) /
                           cross2(direction[k], direction[before]);
      corners.push_back(base[k] + along * direction[k]);
    } else if (direction[before].dot(direction[k]) < 0) {
      throw std::invalid_argument("actuate: a face turns back on itself at a corner");
    } else if (inset[before] != inset[k]) {
      // A straight corner between sides of different insets: a step from one line to the other.
      corners.push_back(corner - inset[before] * normal[before]);
      out.from_corner.push_back(k);
      corners.push_back(corner - inset[k] * normal[k]);
    } else {
      corners.push_back(corner - inset[k] * normal[k]);
    }
    out.from_corner.push_back(k);
    out.side_start.push_back(static_cast<int>(corners.size()) - 1);
  }
  out.corners.resize(static_cast<Eigen::Index>(corners.size()), 2);
  for (size_t i = 0; i < corners.size(); ++i) {
    out.corners.row(static_cast<Eigen::Index>(i)) = corners[i].transpose();
  }
  return out;
}

// The smallest caliper width of a polygon: over the sides of its convex hull, the farthest corner.
double caliper_width(const Eigen::MatrixX2d& polygon, double tolerance) {
  const Eigen::Index n = polygon.rows();
  double width = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const Eigen::Vector2d side = (polygon.row(j) - polygon.row(i)).transpose();
      const double length = side.norm();
      if (length <= tolerance) continue;
      double farthest = 0;
      bool hull = true;
      for (Eigen::Index p = 0; p < n && hull; ++p) {
        const double distance =
            cross2(side, (polygon.row(p) - polygon.row(i)).transpose()) / length;
        hull = distance >= -tolerance;
        farthest = std::max(farthest, distance);
      }
      if (hull) width = std::min(width, farthest);
    }
  }
  return std::isfinite(width) ? width : 0;
}

// What is wrong with a trimmed face, if anything (notes §4, degenerate cases).
std::optional<std::string> trim_problem(const Eigen::MatrixX2d& face, const Trim& trim,
                                        double min_width) {
  const double size = (face.colwise().maxCoeff() - face.colwise().minCoeff()).norm();
  const double tolerance = 1e-9 * size;
  const Eigen::MatrixX2d& c = trim.corners;
  const Eigen::Index m = c.rows();
  for (size_t k = 0; k < trim.side_start.size(); ++k) {
    const Eigen::Index from = trim.side_start[k];
    const Eigen::Vector2d side = (c.row((from + 1) % m) - c.row(from)).transpose();
    const Eigen::Vector2d before =
        (face.row((k + 1) % face.rows()) - face.row(static_cast<Eigen::Index>(k))).transpose();
    if (side.dot(before.normalized()) < -tolerance) return "turned inside out";
  }
  if (signed_area(c) <= tolerance * tolerance) return "empty";
  // Sides that cross without being neighbours (sides shrunk to a point are dropped first).
  std::vector<Eigen::Vector2d> loop;
  for (Eigen::Index i = 0; i < m; ++i) {
    if ((c.row(i) - c.row((i + 1) % m)).norm() > tolerance) loop.push_back(c.row(i).transpose());
  }
  const size_t q = loop.size();
  for (size_t i = 0; i < q; ++i) {
    for (size_t j = i + 2; j < q; ++j) {
      if (i == 0 && j == q - 1) continue;
      const Eigen::Vector2d a = loop[i], b = loop[(i + 1) % q], p = loop[j], r = loop[(j + 1) % q];
      const double d1 = cross2(b - a, p - a), d2 = cross2(b - a, r - a);
      const double d3 = cross2(r - p, a - p), d4 = cross2(r - p, b - p);
      const double zero = tolerance * size;
      if (((d1 > zero && d2 < -zero) || (d1 < -zero && d2 > zero)) &&
          ((d3 > zero && d4 < -zero) || (d3 < -zero && d4 > zero))) {
        return "self-intersecting";
      }
    }
  }
  const double width = caliper_width(c, tolerance);
  if (width < min_width) {
    return fmt::format("{:.2f} mm wide (at least {:.2f} mm needed)", width, min_width);
  }
  return std::nullopt;
}

// Bisection on a feasibility that holds at `good` and fails at `bad`: the last good value.
template <typename Works>
double boundary(double good, double bad, Works works) {
  for (int i = 0; i < 60; ++i) {
    const double middle = (good + bad) / 2;
    (works(middle) ? good : bad) = middle;
  }
  return good;
}

struct FaceFailure {
  int face = 0;
  std::string problem;
  std::optional<double> scale;   // the smallest uniform scale of the pattern that works
  std::optional<double> radius;  // the largest factor on the arc radii that works unscaled
};

FaceFailure face_failure(int f, const Eigen::MatrixX2d& face, const std::vector<double>& inset,
                         const std::string& problem, double min_width) {
  FaceFailure out{f, problem, std::nullopt, std::nullopt};
  std::vector<double> less(inset.size());
  // Scaled by s the face grows while its trims stay: the same as trims divided by s, widths by s.
  const auto works_scaled = [&](double s) {
    const Eigen::MatrixX2d grown = s * face;
    return !trim_problem(grown, trim_face(grown, inset), min_width);
  };
  double bad = 1, good = 2;
  while (!works_scaled(good) && good < 1e6) bad = good, good *= 2;
  if (works_scaled(good)) out.scale = boundary(good, bad, works_scaled);
  const auto works_radius = [&](double factor) {
    for (size_t k = 0; k < inset.size(); ++k) less[k] = factor * inset[k];
    return !trim_problem(face, trim_face(face, less), min_width);
  };
  if (works_radius(0)) out.radius = boundary(0, 1, works_radius);
  return out;
}

// The hinges' designs by crease (−1: none), checked against the pattern, and every face trimmed
// by the corner rule, with the faces that do not survive their trims.
struct Trims {
  std::vector<int> design_of;
  std::vector<std::vector<int>> side_crease;
  std::vector<Trim> trims;
  std::vector<FaceFailure> failures;
};

Trims trim_faces(const CreasePattern& pattern, const std::vector<HingeDesign>& hinges,
                 const ActuateOptions& options) {
  check_fold_tree(pattern);
  const int num_faces = pattern.num_faces();
  const int num_creases = static_cast<int>(pattern.creases.size());
  Trims out;
  std::vector<int>& design_of = out.design_of;
  design_of.assign(num_creases, -1);
  for (size_t h = 0; h < hinges.size(); ++h) {
    const int c = hinges[h].crease;
    if (c < 0 || c >= num_creases || !pattern.is_hinge(c) || design_of[c] >= 0 ||
        hinges[h].fold_angle * pattern.creases[c].fold_angle <= 0) {
      throw std::invalid_argument(
          fmt::format("actuate: design {} is not the only one of a hinge of {} folding its way", h,
                      pattern.name));
    }
    design_of[c] = static_cast<int>(h);
  }
  for (int c = 0; c < num_creases; ++c) {
    if (pattern.is_hinge(c) && design_of[c] < 0) {
      throw std::invalid_argument(
          fmt::format("actuate: hinge {} of {} has no design", c, pattern.name));
    }
  }
  for (int c = 0; c < num_creases; ++c) {
    if (design_of[c] < 0) continue;
    const double angle = hinges[design_of[c]].fold_angle;
    if (std::abs(angle) > kLargestFold) {
      throw UserError(
          ErrorCategory::kInfeasible,
          fmt::format(
              "{}: the hinge between faces {} and {} folds {:.1f}°; an actuator folds at most "
              "170° (its faces would give up 2 r tan(θ/2) without bound): blunt that edge "
              "of the model or cut it",
              pattern.name, pattern.creases[c].left + 1, pattern.creases[c].right + 1,
              angle * 180 / std::numbers::pi));
    }
  }

  // Trim every face; refuse the ones that do not survive, with what would save them.
  out.side_crease = side_creases(pattern);
  const std::vector<std::vector<int>>& side_crease = out.side_crease;
  std::vector<Trim>& trims = out.trims;
  trims.resize(num_faces);
  std::vector<FaceFailure>& failures = out.failures;
  for (int f = 0; f < num_faces; ++f) {
    const Eigen::MatrixX2d face = face_corners(pattern, f);
    std::vector<double> inset(face.rows(), 0.0);
    for (size_t k = 0; k < inset.size(); ++k) {
      const int c = side_crease[f][k];
      if (design_of[c] >= 0) inset[k] = hinges[design_of[c]].cut / 2;
    }
    trims[f] = trim_face(face, inset);
    if (const auto problem = trim_problem(face, trims[f], options.min_face_width)) {
      failures.push_back(face_failure(f, face, inset, *problem, options.min_face_width));
    }
  }
  return out;
}

}  // namespace

HingeDesign hinge_design(int crease, double fold_angle, double radius, bool pla_on_bed,
                         double pla_speed) {
  if (!(radius > 0) || !std::isfinite(radius)) {
    throw std::invalid_argument("hinge_design: the arc radius must be positive and finite");
  }
  HingeDesign out;
  out.crease = crease;
  out.fold_angle = fold_angle;
  out.radius = radius;
  out.width = radius * std::abs(fold_angle);
  out.cut = 2 * radius * std::tan(std::abs(fold_angle) / 2);
  out.shift = out.cut - out.width;
  out.pla_on_bed = pla_on_bed;
  out.pla_speed = pla_speed;
  return out;
}

ActuatedSheet actuate(const CreasePattern& pattern, const std::vector<HingeDesign>& hinges,
                      const ActuateOptions& options) {
  const int num_faces = pattern.num_faces();
  Trims trimmed = trim_faces(pattern, hinges, options);
  const std::vector<int>& design_of = trimmed.design_of;
  const std::vector<std::vector<int>>& side_crease = trimmed.side_crease;
  const std::vector<Trim>& trims = trimmed.trims;
  const std::vector<FaceFailure>& failures = trimmed.failures;
  if (!failures.empty()) {
    // The face that needs the most, and what saves them all.
    const FaceFailure* worst = &failures[0];
    std::optional<double> radius = failures[0].radius;
    std::vector<int> names;
    for (const FaceFailure& failure : failures) {
      names.push_back(failure.face + 1);  // numbered from 1, as net.svg shows them
      // Equal needs within rounding name the first such face.
      const double need = failure.scale.value_or(std::numeric_limits<double>::infinity());
      if (need > worst->scale.value_or(std::numeric_limits<double>::infinity()) * (1 + 1e-9)) {
        worst = &failure;
      }
      radius = radius && failure.radius ? std::optional(std::min(*radius, *failure.radius))
                                        : std::nullopt;
    }
    double largest_radius = 0;
    for (const HingeDesign& hinge : hinges) largest_radius = std::max(largest_radius, hinge.radius);
    std::string fix;
    if (worst->scale) {
      fix = fmt::format("scale the pattern by at least {:.2f} (the trims do not grow with it)",
                        std::ceil(*worst->scale * 100) / 100);
    }
    if (radius) {
      fix += fmt::format(
          "{}bend the hinges on arcs of at most {:.2f} times their radius ({:.2f} mm "
          "for the largest, {:.2f} mm; print their active PLA faster)",
          fix.empty() ? "" : ", or ", std::floor(*radius * 100) / 100,
          std::floor(*radius * largest_radius * 100) / 100, largest_radius);
    }
    if (fix.empty()) fix = "redraw the face: it is not a simple polygon";
    throw UserError(
        ErrorCategory::kInfeasible,
        fmt::format("{}: face {} is {} once its hinges take their actuators' L/2 from it{}: {}",
                    pattern.name, worst->face + 1, worst->problem,
                    names.size() > 1 ? fmt::format(" (faces {} fail)", fmt::join(names, ", ")) : "",
                    fix));
  }

  // Algorithm 1's shifts: each child and its subtree move by δ toward the parent.
  std::vector<Eigen::Vector2d> shift(num_faces, Eigen::Vector2d::Zero());
  std::vector<Eigen::Vector2d> across(num_faces, Eigen::Vector2d::Zero());
  for (int f : pattern.fold_order) {
    const int c = pattern.parent_crease[f];
    if (c < 0) continue;
    const Crease& crease = pattern.creases[c];
    // The crease as the child runs it: the child lies to its left, across it from the parent.
    const Eigen::Vector2d along = (crease.left == f ? 1.0 : -1.0) *
                                  (pattern.V.row(crease.v1) - pattern.V.row(crease.v0)).transpose();
    across[f] = Eigen::Vector2d(-along.y(), along.x()).normalized();
    shift[f] = shift[pattern.other_face(c, f)];
    if (design_of[c] >= 0) shift[f] -= hinges[design_of[c]].shift * across[f];
  }

  ActuatedSheet out;
  out.name = pattern.name;
  for (int f = 0; f < num_faces; ++f) {
    out.faces.push_back(trims[f].corners.rowwise() + shift[f].transpose());
  }
  const auto trimmed_side = [&](int f, int c) {
    const int k = static_cast<int>(std::find(side_crease[f].begin(), side_crease[f].end(), c) -
                                   side_crease[f].begin());
    const Eigen::Index from = trims[f].side_start[k];
    const Eigen::Index to = (from + 1) % out.faces[f].rows();
    return std::pair<Eigen::Vector2d, Eigen::Vector2d>(out.faces[f].row(from).transpose(),
                                                       out.faces[f].row(to).transpose());
  };
  for (int f : pattern.fold_order) {
    const int c = pattern.parent_crease[f];
    if (c < 0 || design_of[c] < 0) continue;
    Actuator actuator;
    actuator.hinge = hinges[design_of[c]];
    actuator.parent_face = pattern.other_face(c, f);
    actuator.child_face = f;
    actuator.across = across[f];
    // The parent runs the hinge the other way: its side's end comes first on the quad.
    const auto [parent_from, parent_to] = trimmed_side(actuator.parent_face, c);
    const auto [child_from, child_to] = trimmed_side(f, c);
    // Along the hinge the strip spans only what both trimmed sides and the hinge itself span: a
    // side that a corner wider than 90° lengthened (by (L/2)|cot α|) would flare the strip past
    // the solid's corner, and bent, that flare pokes through the face beyond it.
    const Eigen::Vector2d along(across[f].y(), -across[f].x());
    const Crease& crease = pattern.creases[c];
    const Eigen::Vector2d shift_parent = shift[actuator.parent_face];
    const double h0 = along.dot(pattern.V.row(crease.v0).transpose() + shift_parent);
    const double h1 = along.dot(pattern.V.row(crease.v1).transpose() + shift_parent);
    const double lo =
        std::max({std::min(h0, h1), std::min(along.dot(parent_from), along.dot(parent_to)),
                  std::min(along.dot(child_from), along.dot(child_to))});
    const double hi =
        std::min({std::max(h0, h1), std::max(along.dot(parent_from), along.dot(parent_to)),
                  std::max(along.dot(child_from), along.dot(child_to))});
    // The end of side from → to (parallel to the hinge) at its `to` end, or its `from` end.
    const auto end = [&](const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool at_to) {
      const bool upper = (along.dot(to) >= along.dot(from)) == at_to;
      return Eigen::Vector2d(from + ((upper ? hi : lo) - along.dot(from)) * along);
    };
    actuator.quad.row(0) = end(parent_from, parent_to, true).transpose();
    actuator.quad.row(1) = end(parent_from, parent_to, false).transpose();
    actuator.quad.row(2) = end(child_from, child_to, true).transpose();
    actuator.quad.row(3) = end(child_from, child_to, false).transpose();
    out.actuators.push_back(actuator);
  }
  return out;
}

std::vector<int> faces_too_narrow(const CreasePattern& pattern,
                                  const std::vector<HingeDesign>& hinges,
                                  const ActuateOptions& options) {
  std::vector<int> faces;
  for (const FaceFailure& failure : trim_faces(pattern, hinges, options).failures) {
    faces.push_back(failure.face);
  }
  return faces;
}

std::vector<std::pair<int, int>> sheet_overlaps(const ActuatedSheet& sheet) {
  const int num_faces = static_cast<int>(sheet.faces.size());
  std::vector<Eigen::MatrixX2d> pieces = sheet.faces;
  for (const Actuator& actuator : sheet.actuators) pieces.push_back(actuator.quad);
  std::vector<std::pair<int, int>> out;
  for (int a = 0; a < static_cast<int>(pieces.size()); ++a) {
    for (int b = a + 1; b < static_cast<int>(pieces.size()); ++b) {
      if (b >= num_faces) {
        const Actuator& actuator = sheet.actuators[b - num_faces];
        if (a == actuator.parent_face || a == actuator.child_face) continue;
      }
      if (polygons_overlap(pieces[a], pieces[b])) out.emplace_back(a, b);
    }
  }
  return out;
}

double largest_corner_gap(const CreasePattern& pattern, const ActuatedSheet& sheet) {
  const FoldedSheet folded = fold_curved(pattern, sheet, 1.0, 1);
  std::vector<double> inset_of(pattern.creases.size(), 0.0);
  std::vector<int> hinges_at(pattern.V.rows(), 0);
  for (const Actuator& actuator : sheet.actuators) {
    const Crease& crease = pattern.creases[actuator.hinge.crease];
    inset_of[actuator.hinge.crease] = actuator.hinge.cut / 2;
    ++hinges_at[crease.v0];
    ++hinges_at[crease.v1];
  }
  const std::vector<std::vector<int>> side_crease = side_creases(pattern);
  std::vector<std::vector<Eigen::Vector3d>> corners_at(pattern.V.rows());
  for (int f = 0; f < pattern.num_faces(); ++f) {
    std::vector<double> inset;
    for (int c : side_crease[f]) inset.push_back(inset_of[c]);
    const Trim trim = trim_face(face_corners(pattern, f), inset);
    if (trim.corners.rows() != folded.faces[f].rows()) {
      throw std::invalid_argument("largest_corner_gap: the sheet is not the pattern actuated");
    }
    for (size_t i = 0; i < trim.from_corner.size(); ++i) {
      const int v = pattern.faces[f][trim.from_corner[i]];
      if (hinges_at[v] >= 2) {
        corners_at[v].push_back(folded.faces[f].row(static_cast<Eigen::Index>(i)).transpose());
      }
    }
  }
  double widest = 0;
  for (const std::vector<Eigen::Vector3d>& corners : corners_at) {
    for (size_t i = 0; i < corners.size(); ++i) {
      for (size_t j = i + 1; j < corners.size(); ++j) {
        widest = std::max(widest, (corners[i] - corners[j]).norm());
      }
    }
  }
  return widest;
}

}  // namespace flatmorph
