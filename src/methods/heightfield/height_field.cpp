#include "methods/heightfield/height_field.h"

#include <fmt/core.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <queue>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common/angles.h"
#include "common/error.h"
#include "mesh/plane_geometry.h"
#include "mesh/topology.h"
#include "mesh/validate.h"

namespace flatmorph {

std::string at_xy(const Eigen::Vector2d& p) {
  return fmt::format("({:.1f}, {:.1f}) mm", p.x(), p.y());
}

namespace {

Eigen::Vector2d xy(const Eigen::MatrixXd& V, int v) { return Eigen::Vector2d(V(v, 0), V(v, 1)); }

// Twice the signed area of face f seen from above (positive when counter-clockwise).
double signed_area2_xy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const Eigen::Vector2d a = xy(V, F(f, 0));
  return cross2(xy(V, F(f, 1)) - a, xy(V, F(f, 2)) - a);
}

// Twice the signed area enclosed by a loop seen from above.
double loop_area2_xy(const Eigen::MatrixXd& V, const std::vector<int>& loop) {
  double sum = 0.0;
  for (size_t i = 0; i < loop.size(); ++i) {
    sum += cross2(xy(V, loop[i]), xy(V, loop[(i + 1) % loop.size()]));
  }
  return sum;
}

Eigen::Vector3d face_centroid(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  return (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3.0;
}

Eigen::Vector2d mean_xy(const Eigen::MatrixXd& V, const std::vector<int>& vertices) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int v : vertices) sum += xy(V, v);
  return sum / static_cast<double>(vertices.size());
}

[[noreturn]] void refuse(ErrorCategory category, const std::string& source,
                         const std::string& problem, const std::string& fix) {
  throw UserError(category, fmt::format("{}: {}; {}", source, problem, fix));
}

// Several pieces, closure, holes and handles, each with where it is.
void check_disk(const HeightField& field, const std::vector<std::vector<int>>& loops,
                const std::string& source) {
  const Eigen::MatrixXd& V = field.V;
  const Eigen::MatrixXi& F = field.F;
  Eigen::VectorXi component;
  const int pieces = face_components(F, component);
  if (pieces > 1) {
    std::vector<int> second;
    for (int f = 0; f < F.rows(); ++f) {
      if (component[f] == 1) second.insert(second.end(), {F(f, 0), F(f, 1), F(f, 2)});
    }
    refuse(
        ErrorCategory::kTopology, source,
        fmt::format("{} separate pieces, the second around {}", pieces, at_xy(mean_xy(V, second))),
        "a height field is one sheet with one outer boundary: keep one piece (e.g. MeshLab: "
        "Remove Isolated pieces)");
  }
  if (loops.empty()) {
    std::vector<int> used(F.data(), F.data() + F.size());
    refuse(ErrorCategory::kTopology, source,
           fmt::format("a closed surface (no boundary) around {}", at_xy(mean_xy(V, used))),
           "a height field is an open sheet rising from its outer boundary: keep only the top "
           "surface (delete the bottom and the sides)");
  }
  if (loops.size() > 1) {
    int outer = 0;
    for (int i = 1; i < static_cast<int>(loops.size()); ++i) {
      if (std::abs(loop_area2_xy(V, loops[i])) > std::abs(loop_area2_xy(V, loops[outer]))) {
        outer = i;
      }
    }
    const int hole = outer == 0 ? 1 : 0;
    refuse(ErrorCategory::kTopology, source,
           fmt::format("{} boundary loops: a hole around {} ({} edges)", loops.size(),
                       at_xy(mean_xy(V, loops[hole])), loops[hole].size()),
           "a height field has one outer boundary and no holes (a hole cuts the printed paths, "
           "paper §8): fill the hole (e.g. MeshLab: Close Holes)");
  }
  const int chi = euler_characteristic(F);
  if (chi != 1) {
    const Eigen::Vector2d lo = V.leftCols<2>().colwise().minCoeff().transpose();
    const Eigen::Vector2d hi = V.leftCols<2>().colwise().maxCoeff().transpose();
    refuse(ErrorCategory::kTopology, source,
           fmt::format("not a disk: Euler characteristic {} (a disk has 1), {} handle(s) somewhere "
                       "between {} and {}",
                       chi, (1 - chi) / 2, at_xy(lo), at_xy(hi)),
           "a height field is one sheet without tunnels or handles: cut them away");
  }
}

// Where the boundary loop crosses or touches itself seen from above, if it does. A sweep over x:
// only edges whose x ranges overlap are compared.
std::optional<Eigen::Vector2d> boundary_crossing(const Eigen::MatrixXd& V,
                                                 const std::vector<int>& loop) {
  const int n = static_cast<int>(loop.size());
  auto end = [&](int e, int k) { return xy(V, loop[(e + k) % n]); };
  std::vector<int> order(n);
  for (int e = 0; e < n; ++e) order[e] = e;
  auto min_x = [&](int e) { return std::min(end(e, 0).x(), end(e, 1).x()); };
  auto max_x = [&](int e) { return std::max(end(e, 0).x(), end(e, 1).x()); };
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return min_x(a) != min_x(b) ? min_x(a) < min_x(b) : a < b; });
  for (int i = 0; i < n; ++i) {
    const int a = order[i];
    for (int j = i + 1; j < n && min_x(order[j]) <= max_x(a); ++j) {
      const int b = order[j];
      // Consecutive edges share a corner, which is no crossing.
      if ((a + 1) % n == b || (b + 1) % n == a) continue;
      if (auto point = segment_intersection(end(a, 0), end(a, 1), end(b, 0), end(b, 1))) {
        return point;
      }
    }
  }
  return std::nullopt;
}

// Overhangs: the surface must be the graph of a function over its footprint. Seen from above, its
// faces must all turn the same way and none may stand on edge, the faces around each vertex must
// go round once (at most once at the boundary), and the boundary must not cross itself; together
// these make the projection one-to-one.
void check_graph(const HeightField& field, const std::vector<int>& boundary,
                 const std::string& source) {
  const Eigen::MatrixXd& V = field.V;
  const Eigen::MatrixXi& F = field.F;
  const int nf = static_cast<int>(F.rows());
  double total = 0.0;
  for (int f = 0; f < nf; ++f) total += signed_area2_xy(V, F, f);
  const double up = total >= 0.0 ? 1.0 : -1.0;

  int bad = 0, first = -1;
  bool first_is_wall = false;
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double area2 = (b - a).cross(c - a).norm();
    const double turn = up * signed_area2_xy(V, F, f);
    if (turn > kWallNormalZ * area2) continue;
    if (bad++ == 0) {
      first = f;
      first_is_wall = std::abs(turn) <= kWallNormalZ * area2;
    }
  }
  if (bad > 0) {
    const Eigen::Vector3d c = face_centroid(V, F, first);
    refuse(ErrorCategory::kGeometry, source,
           fmt::format(
               "an overhang (not a graph z = h(x, y)): face {} centred at {}, z = {:.1f} "
               "mm, {} ({} such faces)",
               first, at_xy(c.head<2>()), c.z(),
               first_is_wall ? "stands vertical" : "is folded under its neighbours seen from above",
               bad),
           "a height field has one height over every point of its footprint: remove the "
           "overhang, or turn the model so that it rises along +z");
  }

  // Seen from above, the corner angles around an interior vertex add up to 2 pi times the number
  // of times the faces go round it; around a boundary vertex to less than 2 pi.
  std::vector<double> angle(V.rows(), 0.0);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d o = xy(V, F(f, k));
      const Eigen::Vector2d u = xy(V, F(f, (k + 1) % 3)) - o, w = xy(V, F(f, (k + 2) % 3)) - o;
      angle[F(f, k)] += std::atan2(std::abs(cross2(u, w)), u.dot(w));
    }
  }
  std::vector<char> on_boundary(V.rows(), 0);
  for (int v : boundary) on_boundary[v] = 1;
  for (int v = 0; v < V.rows(); ++v) {
    const double limit = on_boundary[v] ? kTwoPi + 1e-9 : 1.5 * kTwoPi;
    if (angle[v] <= limit) continue;
    // Round the turns of an interior vertex; a boundary one only has to turn less than once.
    const std::string turns =
        on_boundary[v] ? "more than once"
                       : fmt::format("{} times", std::max(2L, std::lround(angle[v] / kTwoPi)));
    refuse(ErrorCategory::kGeometry, source,
           fmt::format("an overhang (not a graph z = h(x, y)): the surface winds {} round {} seen "
                       "from above, z = {:.1f} mm",
                       turns, at_xy(xy(V, v)), V(v, 2)),
           "a height field has one height over every point of its footprint: remove the "
           "overlapping part");
  }
  if (const auto crossing = boundary_crossing(V, boundary)) {
    refuse(
        ErrorCategory::kGeometry, source,
        fmt::format("an overhang (not a graph z = h(x, y)): the boundary passes over itself at {} "
                    "seen from above",
                    at_xy(*crossing)),
        "a height field has one height over every point of its footprint: remove the "
        "overlapping part");
  }
}

// Depressions by flooding from the boundary (priority flood): the level of a vertex is the lowest,
// over all paths along edges to the boundary, of the highest height on the path; water poured on
// the vertex stands at that level, and the vertex lies in a depression when the level is above it.
void check_depressions(const HeightField& field, const std::vector<int>& boundary,
                       const std::string& source) {
  const Eigen::MatrixXd& V = field.V;
  const int nv = static_cast<int>(V.rows());
  const EdgeTopology topology = edge_topology(field.F);
  std::vector<std::vector<int>> neighbours(nv);
  for (int e = 0; e < topology.num_edges(); ++e) {
    neighbours[topology.edges(e, 0)].push_back(topology.edges(e, 1));
    neighbours[topology.edges(e, 1)].push_back(topology.edges(e, 0));
  }
  std::vector<double> level(nv, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (int v : boundary) {
    level[v] = V(v, 2);
    queue.emplace(level[v], v);
  }
  while (!queue.empty()) {
    const auto [current, v] = queue.top();
    queue.pop();
    if (current > level[v]) continue;  // reached lower since it was queued
    for (int u : neighbours[v]) {
      const double candidate = std::max(current, V(u, 2));
      if (candidate < level[u]) {
        level[u] = candidate;
        queue.emplace(candidate, u);
      }
    }
  }

  // The depressions: groups of connected vertices deeper than the tolerance.
  std::vector<int> basin(nv, -1);
  int basins = 0, deepest = -1;
  for (int v = 0; v < nv; ++v) {
    if (neighbours[v].empty() || basin[v] >= 0 || level[v] - V(v, 2) <= kDepressionToleranceMm) {
      continue;
    }
    std::vector<int> stack{v};
    basin[v] = basins;
    while (!stack.empty()) {
      const int w = stack.back();
      stack.pop_back();
      if (deepest < 0 || level[w] - V(w, 2) > level[deepest] - V(deepest, 2)) deepest = w;
      for (int u : neighbours[w]) {
        if (basin[u] < 0 && level[u] - V(u, 2) > kDepressionToleranceMm) {
          basin[u] = basins;
          stack.push_back(u);
        }
      }
    }
    ++basins;
  }
  if (basins == 0) return;
  refuse(ErrorCategory::kGeometry, source,
         fmt::format("a depression {:.3f} mm deep at {} (its lowest point, z = {:.2f} mm; its rim "
                     "is at z = {:.2f} mm){}: the sheet has no preferred direction to sink into it "
                     "(paper §8)",
                     level[deepest] - V(deepest, 2), at_xy(xy(V, deepest)), V(deepest, 2),
                     level[deepest], basins > 1 ? fmt::format(", the deepest of {}", basins) : ""),
         "a height field must rise from its boundary to its peaks with no pits: fill the pit up "
         "to its rim");
}

}  // namespace

void check_height_field(const HeightField& field, const std::string& source) {
  if (field.colors.size() > 0 &&
      (field.colors.rows() != field.V.rows() || field.colors.cols() != 3)) {
    throw std::invalid_argument("check_height_field: colors must be empty or #V x 3");
  }
  const Mesh mesh{field.V, field.F};
  for (const MeshProblem& problem : diagnose_mesh(mesh).problems) {
    // Worded below with where they are.
    if (problem.kind == MeshProblemKind::kSeveralPieces ||
        problem.kind == MeshProblemKind::kClosed || problem.kind == MeshProblemKind::kHoles) {
      continue;
    }
    throw UserError(problem.category, problem_line(source, problem));
  }
  // diagnose_mesh found the mesh manifold, oriented and with valid indices: topology.h applies.
  const std::vector<std::vector<int>> loops = boundary_loops(field.F);
  check_disk(field, loops, source);
  check_graph(field, loops.front(), source);
  check_depressions(field, loops.front(), source);
}

HeightField height_field_from_mesh(const Mesh& mesh, const std::string& source) {
  Mesh repaired = mesh;
  repair_mesh(repaired);
  double total = 0.0;
  for (int f = 0; f < repaired.num_faces(); ++f)
    total += signed_area2_xy(repaired.V, repaired.F, f);
  if (total < 0.0) repaired.F.col(1).swap(repaired.F.col(2));
  HeightField field{std::move(repaired.V), std::move(repaired.F), {}};
  check_height_field(field, source);
  return field;
}

HeightField height_field_from_image(const GrayImage& image, double width_mm, double depth_mm,
                                    double height_mm, double resolution_mm,
                                    const std::string& source) {
  if (image.samples.size() != static_cast<size_t>(image.width) * image.height || image.width < 0 ||
      image.height < 0) {
    throw std::invalid_argument("height_field_from_image: samples do not match width x height");
  }
  for (const auto& [name, value] : {std::pair<const char*, double>{"width", width_mm},
                                    {"depth", depth_mm},
                                    {"height", height_mm},
                                    {"resolution", resolution_mm}}) {
    if (!(std::isfinite(value) && value > 0.0)) {
      throw UserError(ErrorCategory::kOption,
                      fmt::format("{}: the height field's {} must be a positive number of "
                                  "millimetres, not {}",
                                  source, name, value));
    }
  }
  if (image.width < 2 || image.height < 2) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: {} x {} pixels: a height map needs at least 2 x 2 pixels",
                                source, image.width, image.height));
  }
  const double cells_x = std::ceil(width_mm / resolution_mm);
  const double cells_y = std::ceil(depth_mm / resolution_mm);
  if ((cells_x + 1.0) * (cells_y + 1.0) > static_cast<double>(kMaxHeightFieldVertices)) {
    // The spacing that gives the most vertices, with 1 % for the extra row and column.
    const double finest =
        1.01 * std::sqrt(width_mm * depth_mm / static_cast<double>(kMaxHeightFieldVertices));
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("{}: a resolution of {} mm over {} x {} mm makes {:.0f} vertices, "
                    "more than the {} flatmorph handles: choose a resolution of at "
                    "least {:.2f} mm",
                    source, resolution_mm, width_mm, depth_mm, (cells_x + 1.0) * (cells_y + 1.0),
                    kMaxHeightFieldVertices, std::ceil(finest * 100.0) / 100.0));
  }
  const int nx = static_cast<int>(cells_x), ny = static_cast<int>(cells_y);
  const int w = image.width, h = image.height;
  // Bilinear in pixel coordinates (px, py), both from 0 to size - 1.
  auto sample = [&](double px, double py) {
    const int x0 = std::min(static_cast<int>(px), w - 2),
              y0 = std::min(static_cast<int>(py), h - 2);
    const double fx = px - x0, fy = py - y0;
    return (1 - fy) * ((1 - fx) * image.at(x0, y0) + fx * image.at(x0 + 1, y0)) +
           fy * ((1 - fx) * image.at(x0, y0 + 1) + fx * image.at(x0 + 1, y0 + 1));
  };
  HeightField field;
  field.V.resize(static_cast<Eigen::Index>(nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j) {
    // Row j = 0 is the bottom edge (y = -depth / 2), the image's last row. Products before the
    // division, so that grid points on pixels land on them exactly.
    const double py = static_cast<double>(ny - j) * (h - 1) / ny;
    for (int i = 0; i <= nx; ++i) {
      const double px = static_cast<double>(i) * (w - 1) / nx;
      field.V.row(static_cast<Eigen::Index>(j) * (nx + 1) + i)
          << -0.5 * width_mm + width_mm * i / nx,
          -0.5 * depth_mm + depth_mm * j / ny, height_mm * sample(px, py) / image.max_value();
    }
  }
  field.F.resize(2 * static_cast<Eigen::Index>(nx) * ny, 3);
  Eigen::Index f = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      // Alternating diagonals keep the mesh as symmetric as the image.
      if ((i + j) % 2 == 0) {
        field.F.row(f++) << a, b, d;
        field.F.row(f++) << a, d, c;
      } else {
        field.F.row(f++) << a, b, c;
        field.F.row(f++) << b, d, c;
      }
    }
  }
  check_height_field(field, source);
  return field;
}

}  // namespace flatmorph
