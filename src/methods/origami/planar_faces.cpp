#include "methods/origami/planar_faces.h"

#include <fmt/core.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <set>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "common/error.h"

namespace flatmorph {
namespace {

using Triangle = std::array<int, 3>;
using Points = std::vector<Eigen::Vector3d>;

// Zero area: below this fraction of the squared bounding-box diagonal (as mesh/validate.cpp).
constexpr double kZeroAreaRelative = 1e-14;
// Weight of the planes that hold an open mesh's border in place, against the surface's own
// (Garland & Heckbert 1997, "boundary preservation").
constexpr double kBorderWeight = 1e3;
// Weight of a plane the mesh already has, per mm² of it, against its triangles' own (1 per mm²).
constexpr double kHeldPlaneWeight = 1e3;

// "12", "12 and 40", "12, 40 and 41", "1, 2, 3, 4, 5 and 9 more".
std::string list_numbers(const std::vector<int>& items) {
  constexpr size_t kShown = 5;
  std::string out;
  const size_t shown = items.size() > kShown + 1 ? kShown : items.size();
  for (size_t i = 0; i < shown; ++i) {
    if (i > 0) out += i + 1 == shown && shown == items.size() ? " and " : ", ";
    out += std::to_string(items[i]);
  }
  if (shown < items.size()) out += fmt::format(" and {} more", items.size() - shown);
  return out;
}

Eigen::Vector3d area_vector(const Points& X, const Triangle& t) {
  return (X[t[1]] - X[t[0]]).cross(X[t[2]] - X[t[0]]);
}

double diagonal(const Points& X, const std::vector<Triangle>& T) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Triangle& t : T) {
    for (int v : t) {
      lo = lo.cwiseMin(X[v]);
      hi = hi.cwiseMax(X[v]);
    }
  }
  return (hi - lo).norm();
}

// The smallest label of each set, path-halving union-find.
struct Sets {
  std::vector<int> parent;
  explicit Sets(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// Per triangle, the triangle across each edge k (F(t,k) → F(t,k+1)), or −1 on the border.
// Requires a manifold, consistently oriented mesh.
std::vector<Triangle> triangle_neighbours(const std::vector<Triangle>& T) {
  std::vector<std::pair<std::pair<int, int>, int>> directed;
  directed.reserve(3 * T.size());
  for (size_t t = 0; t < T.size(); ++t) {
    for (int k = 0; k < 3; ++k) directed.push_back({{T[t][k], T[t][(k + 1) % 3]}, int(t)});
  }
  std::sort(directed.begin(), directed.end());
  std::vector<Triangle> out(T.size(), Triangle{-1, -1, -1});
  for (size_t t = 0; t < T.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> twin{T[t][(k + 1) % 3], T[t][k]};
      const auto it = std::lower_bound(directed.begin(), directed.end(),
                                       std::make_pair(twin, std::numeric_limits<int>::min()));
      if (it != directed.end() && it->first == twin) out[t][k] = it->second;
    }
  }
  return out;
}

// ---- Validation: what a folded sheet cannot be made of, named by triangle -------------------

std::vector<Triangle> validated_triangles(const Mesh& mesh, const std::string& source) {
  if (mesh.F.cols() != 3 || mesh.V.cols() != 3) {
    throw std::invalid_argument("planar_faces: V and F need three columns");
  }
  const int num_triangles = mesh.num_faces(), num_vertices = mesh.num_vertices();
  if (num_triangles == 0) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: the mesh has no triangles; give a surface mesh", source));
  }
  std::vector<Triangle> T(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(t, k);
      if (v < 0 || v >= num_vertices) {
        throw UserError(ErrorCategory::kGeometry,
                        fmt::format("{}: triangle {} names vertex {}, but the mesh has {} "
                                    "vertices; repair or re-export the mesh",
                                    source, t, v, num_vertices));
      }
      if (!mesh.V.row(v).allFinite()) {
        throw UserError(ErrorCategory::kGeometry,
                        fmt::format("{}: vertex {} (of triangle {}) has a NaN or infinite "
                                    "coordinate; repair or re-export the mesh",
                                    source, v, t));
      }
      T[t][k] = v;
    }
  }
  Points X(num_vertices);
  for (int v = 0; v < num_vertices; ++v) X[v] = mesh.V.row(v).transpose();

  const double min_area = kZeroAreaRelative * std::pow(diagonal(X, T), 2);
  std::vector<int> zero_area;
  for (int t = 0; t < num_triangles; ++t) {
    if (!(0.5 * area_vector(X, T[t]).norm() > min_area)) zero_area.push_back(t);
  }
  if (!zero_area.empty()) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: triangle{} {} {} zero area (a repeated or collinear corner); "
                                "remove degenerate faces (e.g. MeshLab's 'Remove Zero Area "
                                "Faces') and try again",
                                source, zero_area.size() > 1 ? "s" : "", list_numbers(zero_area),
                                zero_area.size() > 1 ? "have" : "has"));
  }

  // Every undirected edge with the triangles using it, in triangle order.
  std::map<std::pair<int, int>, std::vector<int>> users;
  for (int t = 0; t < num_triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      users[std::minmax(T[t][k], T[t][(k + 1) % 3])].push_back(t);
    }
  }
  const auto runs_forward = [&](int t, int a, int b) {
    for (int k = 0; k < 3; ++k) {
      if (T[t][k] == a && T[t][(k + 1) % 3] == b) return true;
    }
    return false;
  };
  int non_manifold = 0;
  const std::pair<const std::pair<int, int>, std::vector<int>>* first = nullptr;
  for (const auto& entry : users) {
    if (entry.second.size() <= 2) continue;
    if (non_manifold++ == 0) first = &entry;
  }
  if (first != nullptr) {
    throw UserError(
        ErrorCategory::kTopology,
        fmt::format("{}: edge {}-{} is shared by triangles {}{}; a folded sheet joins "
                    "at most two faces at an edge: remove the extra triangles",
                    source, first->first.first, first->first.second, list_numbers(first->second),
                    non_manifold > 1 ? fmt::format(" ({} such edges in all)", non_manifold) : ""));
  }
  for (const auto& [edge, ts] : users) {
    if (ts.size() == 2 && runs_forward(ts[0], edge.first, edge.second) ==
                              runs_forward(ts[1], edge.first, edge.second)) {
      throw UserError(ErrorCategory::kTopology,
                      fmt::format("{}: triangles {} and {} run their shared edge {}-{} the same "
                                  "way, so the mesh is not consistently oriented (or not "
                                  "orientable); re-orient its faces coherently (e.g. MeshLab's "
                                  "'Re-Orient all faces coherently')",
                                  source, ts[0], ts[1], edge.first, edge.second));
    }
  }

  // Around each vertex, its triangles must form one fan (a disk or a half-disk).
  std::vector<std::vector<int>> around(num_vertices);
  for (int t = 0; t < num_triangles; ++t) {
    for (int v : T[t]) around[v].push_back(t);
  }
  for (int v = 0; v < num_vertices; ++v) {
    const std::vector<int>& fan = around[v];
    Sets fans(static_cast<int>(fan.size()));
    for (size_t i = 0; i < fan.size(); ++i) {
      for (size_t j = i + 1; j < fan.size(); ++j) {
        int shared = 0;
        for (int a : T[fan[i]]) {
          shared += a != v && std::count(T[fan[j]].begin(), T[fan[j]].end(), a);
        }
        if (shared > 0) fans.join(int(i), int(j));
      }
    }
    for (size_t i = 1; i < fan.size(); ++i) {
      if (fans.find(int(i)) != 0) {
        throw UserError(ErrorCategory::kTopology,
                        fmt::format("{}: vertex {} joins separate fans of triangles (triangles "
                                    "{} and {} meet only there); split the vertex or remove one "
                                    "fan",
                                    source, v, fan[0], fan[i]));
      }
    }
  }
  return T;
}

// Per triangle its piece (triangles joined through edges), and which pieces are closed.
struct Pieces {
  std::vector<int> of_triangle;
  std::vector<char> closed;
};

Pieces pieces(const std::vector<Triangle>& T, const std::vector<Triangle>& neighbours) {
  Sets sets(static_cast<int>(T.size()));
  for (size_t t = 0; t < T.size(); ++t) {
    for (int n : neighbours[t]) {
      if (n >= 0) sets.join(int(t), n);
    }
  }
  Pieces out;
  out.of_triangle.assign(T.size(), -1);
  std::map<int, int> index;  // smallest triangle → piece, numbered in order of first triangle
  for (size_t t = 0; t < T.size(); ++t) {
    const int root = sets.find(int(t));
    const auto [it, added] = index.emplace(root, int(out.closed.size()));
    if (added) out.closed.push_back(1);
    out.of_triangle[t] = it->second;
    for (int n : neighbours[t]) {
      if (n < 0) out.closed[it->second] = 0;
    }
  }
  return out;
}

// ---- Quadric-error edge collapse (Garland & Heckbert 1997) ------------------------------------

struct Candidate {
  long long key;  // the quadric error, quantized so that rounding does not reorder equal costs
  int a, b;       // a < b
  int version_a, version_b;
  Eigen::Vector3d x;
  bool operator>(const Candidate& o) const {
    return std::tie(key, a, b) > std::tie(o.key, o.a, o.b);
  }
};

struct Decimation {
  Points X;
  std::vector<Triangle> T;
  std::vector<char> alive;               // per triangle
  std::vector<std::vector<int>> around;  // per vertex, its live triangles
  std::vector<Eigen::Matrix4d> quadric;  // per vertex
  std::vector<char> on_border;           // per vertex
  std::vector<int> version;              // per vertex, bumped when it moves
  int triangles = 0;
  double scale = 1;  // the bounding-box diagonal, mm
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue;
};

Eigen::Matrix4d plane_quadric(const Eigen::Vector3d& n, const Eigen::Vector3d& p, double weight) {
  Eigen::Vector4d plane;
  plane << n, -n.dot(p);
  return weight * plane * plane.transpose();
}

std::vector<int> neighbours_of(const Decimation& d, int v) {
  std::vector<int> out;
  for (int t : d.around[v]) {
    for (int u : d.T[t]) {
      if (u != v) out.push_back(u);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<int> edge_triangles(const Decimation& d, int a, int b) {
  std::vector<int> out;
  for (int t : d.around[a]) {
    if (std::count(d.T[t].begin(), d.T[t].end(), b)) out.push_back(t);
  }
  return out;
}

double error_at(const Eigen::Matrix4d& Q, const Eigen::Vector3d& x) {
  Eigen::Vector4d h;
  h << x, 1;
  return std::max(0.0, h.dot(Q * h));
}

// Where the merged vertex goes: border vertices stay where they are (an inner vertex joins a
// border one; of two border vertices, the one that costs less stays), so the cuts of an open mesh
// keep to its border; otherwise the quadric's minimum nearest the edge's midpoint (small
// eigenvalues ignored, as in a flat or cylindrical neighbourhood the minimum is a plane or a
// line), or the best of the ends and the midpoint when that minimum lies far off.
Candidate plan(const Decimation& d, int a, int b) {
  if (a > b) std::swap(a, b);
  const Eigen::Matrix4d Q = d.quadric[a] + d.quadric[b];
  Eigen::Vector3d x;
  if (d.on_border[a] != d.on_border[b]) {
    x = d.on_border[a] ? d.X[a] : d.X[b];
  } else if (d.on_border[a]) {
    x = error_at(Q, d.X[b]) < error_at(Q, d.X[a]) ? d.X[b] : d.X[a];
  } else {
    const Eigen::Vector3d mid = 0.5 * (d.X[a] + d.X[b]);
    const Eigen::Matrix3d A = Q.topLeftCorner<3, 3>();
    const Eigen::Vector3d rhs = -Q.topRightCorner<3, 1>() - A * mid;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(A);
    const double largest = eigen.eigenvalues().cwiseAbs().maxCoeff();
    x = mid;
    for (int i = 0; i < 3; ++i) {
      const double lambda = eigen.eigenvalues()(i);
      if (lambda > 1e-3 * largest) {
        x += eigen.eigenvectors().col(i) * (eigen.eigenvectors().col(i).dot(rhs) / lambda);
      }
    }
    if ((x - mid).norm() > (d.X[a] - d.X[b]).norm()) {
      x = mid;
      for (const Eigen::Vector3d& y : {d.X[a], d.X[b]}) {
        if (error_at(Q, y) < error_at(Q, x)) x = y;
      }
    }
  }
  const double unit = 1e-13 * std::pow(d.scale, 4);  // the error is mm² × mm²
  const double key = std::min(error_at(Q, x) / unit, 1e18);
  return {std::llround(key), a, b, d.version[a], d.version[b], x};
}

// The link condition (the collapse keeps the surface manifold), no vertex left with too few
// triangles, no triangle turned over or squashed flat.
bool can_collapse(const Decimation& d, int a, int b, const Eigen::Vector3d& x) {
  const std::vector<int> shared = edge_triangles(d, a, b);
  if (shared.empty()) return false;
  const bool border_edge = shared.size() == 1;
  if (!border_edge && d.on_border[a] && d.on_border[b]) return false;  // would pinch the sheet
  const std::vector<int> na = neighbours_of(d, a), nb = neighbours_of(d, b);
  std::vector<int> common;
  std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
  if (common.size() != shared.size()) return false;
  const auto least = [&](int v) { return d.on_border[v] ? 1 : 3; };
  for (int t : shared) {
    for (int c : d.T[t]) {
      if (c != a && c != b && int(d.around[c].size()) - 1 < least(c)) return false;
    }
  }
  const int merged = int(d.around[a].size() + d.around[b].size() - 2 * shared.size());
  if (merged < std::max(least(a), least(b))) return false;
  const double min_area = kZeroAreaRelative * d.scale * d.scale;
  for (int v : {a, b}) {
    for (int t : d.around[v]) {
      if (std::count(shared.begin(), shared.end(), t)) continue;
      const Eigen::Vector3d before = area_vector(d.X, d.T[t]);
      Triangle moved = d.T[t];
      for (int& u : moved) {
        if (u == v) u = -1;
      }
      Eigen::Vector3d p[3];
      for (int k = 0; k < 3; ++k) p[k] = moved[k] < 0 ? x : d.X[moved[k]];
      const Eigen::Vector3d after = (p[1] - p[0]).cross(p[2] - p[0]);
      if (0.5 * after.norm() <= min_area || after.dot(before) <= 0) return false;
    }
  }
  return true;
}

void push_edges_of(Decimation& d, int v) {
  for (int u : neighbours_of(d, v)) d.queue.push(plan(d, v, u));
}

// Vertex b merges into a (into b instead when only b is on the border) at x.
void collapse(Decimation& d, int a, int b, const Eigen::Vector3d& x) {
  if (d.on_border[b] && !d.on_border[a]) std::swap(a, b);
  const std::vector<int> from_b = d.around[b];
  for (int t : from_b) {
    if (std::count(d.T[t].begin(), d.T[t].end(), a)) {
      d.alive[t] = 0;
      --d.triangles;
      for (int u : d.T[t]) {
        if (u == b) continue;
        std::vector<int>& list = d.around[u];
        list.erase(std::find(list.begin(), list.end(), t));
      }
    } else {
      for (int& u : d.T[t]) {
        if (u == b) u = a;
      }
      d.around[a].push_back(t);
    }
  }
  d.around[b].clear();
  d.X[a] = x;
  d.quadric[a] += d.quadric[b];
  d.on_border[a] = d.on_border[a] || d.on_border[b];
  ++d.version[a];
  ++d.version[b];
  push_edges_of(d, a);
}

void refill_queue(Decimation& d) {
  d.queue = {};
  for (int v = 0; v < int(d.X.size()); ++v) {
    for (int u : neighbours_of(d, v)) {
      if (v < u) d.queue.push(plan(d, v, u));
    }
  }
}

// The mesh to simplify; `region` (from grow_regions) names the planes it already has: those as
// large as half a face of the result are held (their plane's quadric, heavily weighted, on each of
// their vertices), so that a flat base or a cube's side stays one flat face when its rim
// vertices merge with the curved surface beside it.
Decimation start_decimation(const Points& X, const std::vector<Triangle>& T,
                            const std::vector<Triangle>& neighbours, const std::vector<int>& region,
                            int num_regions, int max_faces) {
  Decimation d;
  d.X = X;
  d.T = T;
  d.alive.assign(T.size(), 1);
  d.triangles = int(T.size());
  d.around.resize(X.size());
  d.quadric.assign(X.size(), Eigen::Matrix4d::Zero());
  d.on_border.assign(X.size(), 0);
  d.version.assign(X.size(), 0);
  d.scale = diagonal(X, T);
  for (size_t t = 0; t < T.size(); ++t) {
    const Eigen::Vector3d area = area_vector(X, T[t]);
    const Eigen::Vector3d n = area.normalized();
    // Area-weighted planes: a large triangle holds its plane more firmly than a sliver.
    const Eigen::Matrix4d K = plane_quadric(n, X[T[t][0]], 0.5 * area.norm());
    for (int k = 0; k < 3; ++k) {
      const int u = T[t][k], v = T[t][(k + 1) % 3];
      d.around[u].push_back(int(t));
      d.quadric[u] += K;
      if (neighbours[t][k] >= 0) continue;
      d.on_border[u] = d.on_border[v] = 1;
      const Eigen::Vector3d along = X[v] - X[u];
      const Eigen::Matrix4d B =
          plane_quadric(along.cross(n).normalized(), X[u], kBorderWeight * along.squaredNorm());
      d.quadric[u] += B;
      d.quadric[v] += B;
    }
  }
  std::vector<Eigen::Vector3d> area(num_regions, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> moment(num_regions, Eigen::Vector3d::Zero());
  std::vector<int> size(num_regions, 0);
  double total = 0;
  for (size_t t = 0; t < T.size(); ++t) {
    const Eigen::Vector3d a = area_vector(X, T[t]);
    area[region[t]] += a;
    moment[region[t]] += a.norm() * (X[T[t][0]] + X[T[t][1]] + X[T[t][2]]) / 3;
    ++size[region[t]];
    total += 0.5 * a.norm();
  }
  for (int r = 0; r < num_regions; ++r) {
    const double a = 0.5 * area[r].norm();
    if (size[r] < 2 || a < 0.5 * total / max_faces) continue;
    const Eigen::Matrix4d K =
        plane_quadric(area[r].normalized(), moment[r] / (2 * a), kHeldPlaneWeight * a);
    std::vector<char> seen(X.size(), 0);
    for (size_t t = 0; t < T.size(); ++t) {
      if (region[t] != r) continue;
      for (int v : T[t]) {
        if (!seen[v]) d.quadric[v] += K;
        seen[v] = 1;
      }
    }
  }
  refill_queue(d);
  return d;
}

// Collapses the cheapest valid edges until at most `target` triangles are left; returns how many
// collapses it made. Edges refused once are tried again when the queue runs dry, since their
// neighbourhood may have changed since.
int collapse_until(Decimation& d, int target) {
  int done = 0;
  bool refilled = false;  // and nothing collapsed since
  while (d.triangles > target) {
    if (d.queue.empty()) {
      if (refilled) break;
      refill_queue(d);
      refilled = true;
      continue;
    }
    const Candidate c = d.queue.top();
    d.queue.pop();
    if (d.version[c.a] != c.version_a || d.version[c.b] != c.version_b) continue;
    if (!can_collapse(d, c.a, c.b, c.x)) continue;
    collapse(d, c.a, c.b, c.x);
    ++done;
    refilled = false;
  }
  return done;
}

// ---- Merging triangles into planar polygons ----------------------------------------------------

// Each triangle's region: grown from the largest triangle not yet taken, over edges, taking a
// triangle when its normal is within coplanar_angle of the first triangle's and its corners lie
// near that triangle's plane (so tilt does not accumulate along the region), and only when the
// region stays a disk whose boundary visits each vertex once: a triangle joining along one edge
// must bring a new vertex, and one joining along two fills the last gap at their shared vertex.
std::vector<int> grow_regions(const Points& X, const std::vector<Triangle>& T,
                              const std::vector<Triangle>& neighbours,
                              const PlanarFacesOptions& options, int& count) {
  const int num_triangles = int(T.size());
  std::vector<Eigen::Vector3d> normal(num_triangles);
  std::vector<double> area(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    const Eigen::Vector3d a = area_vector(X, T[t]);
    area[t] = a.norm();
    normal[t] = a / area[t];
  }
  // Largest first; areas within a billionth of the largest count as equal and keep index order,
  // so that a turned mesh grows the same regions.
  const double largest = *std::max_element(area.begin(), area.end());
  std::vector<long long> key(num_triangles);
  for (int t = 0; t < num_triangles; ++t) key[t] = std::llround(area[t] / (1e-9 * largest));
  std::vector<int> seeds(num_triangles);
  std::iota(seeds.begin(), seeds.end(), 0);
  std::stable_sort(seeds.begin(), seeds.end(), [&](int a, int b) { return key[a] > key[b]; });

  const double cos_angle = std::cos(options.coplanar_angle);
  std::vector<int> region(num_triangles, -1);
  std::vector<int> stamp(X.size(), -1);  // the region a vertex was last taken into
  count = 0;
  for (int seed : seeds) {
    if (region[seed] >= 0) continue;
    const int r = count++;
    region[seed] = r;
    const Eigen::Vector3d n0 = normal[seed];
    const Eigen::Vector3d p0 = X[T[seed][0]];
    Eigen::Vector3d lo = X[T[seed][0]], hi = lo;
    for (int v : T[seed]) {
      stamp[v] = r;
      lo = lo.cwiseMin(X[v]);
      hi = hi.cwiseMax(X[v]);
    }
    std::deque<int> queue(neighbours[seed].begin(), neighbours[seed].end());
    while (!queue.empty()) {
      const int t = queue.front();
      queue.pop_front();
      if (t < 0 || region[t] >= 0 || normal[t].dot(n0) < cos_angle) continue;
      int joined = 0, edge = -1;
      for (int k = 0; k < 3; ++k) {
        if (neighbours[t][k] >= 0 && region[neighbours[t][k]] == r) ++joined, edge = k;
      }
      if (joined == 3) continue;
      if (joined == 1 && stamp[T[t][(edge + 2) % 3]] == r) continue;
      Eigen::Vector3d lo_t = lo, hi_t = hi;
      for (int v : T[t]) {
        lo_t = lo_t.cwiseMin(X[v]);
        hi_t = hi_t.cwiseMax(X[v]);
      }
      // A quarter of the tolerance against the bounding box's diagonal (at most √3 diameters),
      // so the finished face passes the planarity check about its own plane.
      const double tolerance = 0.25 * options.planarity * (hi_t - lo_t).norm();
      bool near = true;
      for (int v : T[t]) near = near && std::abs(n0.dot(X[v] - p0)) <= tolerance;
      if (!near) continue;
      region[t] = r;
      lo = lo_t, hi = hi_t;
      for (int v : T[t]) stamp[v] = r;
      for (int n : neighbours[t]) {
        if (n >= 0 && region[n] < 0) queue.push_back(n);
      }
    }
  }
  return region;
}

// The boundary loop of each region, counter-clockwise as its triangles, from its smallest vertex.
std::vector<std::vector<int>> region_loops(const std::vector<Triangle>& T,
                                           const std::vector<Triangle>& neighbours,
                                           const std::vector<int>& region, int count) {
  std::vector<std::map<int, int>> next(count);
  for (size_t t = 0; t < T.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int n = neighbours[t][k];
      if (n >= 0 && region[n] == region[t]) continue;
      next[region[t]].emplace(T[t][k], T[t][(k + 1) % 3]);
    }
  }
  std::vector<std::vector<int>> loops(count);
  for (int r = 0; r < count; ++r) {
    const int start = next[r].begin()->first;
    int v = start;
    do {
      loops[r].push_back(v);
      const auto it = next[r].find(v);
      v = it == next[r].end() ? -1 : it->second;
    } while (v >= 0 && v != start && loops[r].size() <= next[r].size());
    if (v != start || loops[r].size() != next[r].size()) {
      throw std::logic_error("planar_faces: a merged region is not a simple polygon");
    }
  }
  return loops;
}

// Drops each corner that only two faces share (one on an open border), where their common side
// runs straight on (turning by less than coplanar_angle): the faces then meet edge to edge without
// it. Returns how many it dropped.
int drop_straight_corners(const Points& X, std::vector<std::vector<int>>& faces,
                          double coplanar_angle) {
  std::map<int, std::set<int>> adjacent;  // the polygon graph
  std::map<int, std::vector<int>> faces_at;
  for (size_t f = 0; f < faces.size(); ++f) {
    for (size_t i = 0; i < faces[f].size(); ++i) {
      const int a = faces[f][i], b = faces[f][(i + 1) % faces[f].size()];
      adjacent[a].insert(b);
      adjacent[b].insert(a);
      faces_at[a].push_back(int(f));
    }
  }
  const double sin_angle = std::sin(coplanar_angle);
  int dropped = 0;
  for (bool changed = true; changed;) {
    changed = false;
    for (auto& [v, around] : adjacent) {
      if (around.size() != 2) continue;
      const int u = *around.begin(), w = *around.rbegin();
      const Eigen::Vector3d in = X[v] - X[u], out = X[w] - X[v];
      if (in.dot(out) <= 0 || in.cross(out).norm() > sin_angle * in.norm() * out.norm()) continue;
      if (adjacent[u].count(w)) continue;  // u-w is already a side elsewhere
      bool small = false;
      for (int f : faces_at[v]) small = small || faces[f].size() <= 3;
      if (small) continue;
      for (int f : faces_at[v]) {
        faces[f].erase(std::find(faces[f].begin(), faces[f].end(), v));
      }
      adjacent[u].erase(v);
      adjacent[w].erase(v);
      adjacent[u].insert(w);
      adjacent[w].insert(u);
      around.clear();
      ++dropped;
      changed = true;
    }
  }
  return dropped;
}

// Faces whose corners stray from their plane (Newell normal through their mean corner) by more
// than `planarity` of their diameter.
void require_planar(const Polyhedron& solid, double planarity) {
  std::vector<int> bent;
  double worst = 0;
  for (size_t f = 0; f < solid.faces.size(); ++f) {
    const std::vector<int>& face = solid.faces[f];
    const Eigen::Vector3d n = face_normal(solid, int(f));
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int v : face) centre += solid.V.row(v).transpose();
    centre /= double(face.size());
    double diameter = 0, off = 0;
    for (int v : face) {
      off = std::max(off, std::abs(n.dot(solid.V.row(v).transpose() - centre)));
      for (int u : face) diameter = std::max(diameter, (solid.V.row(v) - solid.V.row(u)).norm());
    }
    if (off > planarity * diameter) {
      bent.push_back(int(f));
      worst = std::max(worst, off / diameter);
    }
  }
  if (!bent.empty()) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: face{} {} {} not planar within {:g} % of {} diameter "
                                "(worst: {:.2f} %); smooth the mesh or allow more faces",
                                solid.source, bent.size() > 1 ? "s" : "", list_numbers(bent),
                                bent.size() > 1 ? "are" : "is", 100 * planarity,
                                bent.size() > 1 ? "their" : "its", 100 * worst));
  }
}

// The live triangles of a decimation, with its vertices (unused ones kept, so indices stay).
std::vector<Triangle> live_triangles(const Decimation& d) {
  std::vector<Triangle> out;
  for (size_t t = 0; t < d.T.size(); ++t) {
    if (d.alive[t]) out.push_back(d.T[t]);
  }
  return out;
}

}  // namespace

Polyhedron planar_faces(const Mesh& mesh, const std::string& source,
                        const PlanarFacesOptions& options, std::vector<std::string>* notes) {
  const auto note = [&](const std::string& line) {
    if (notes != nullptr) notes->push_back(line);
  };
  if (!(options.coplanar_angle >= 0 && options.coplanar_angle < std::numbers::pi / 2) ||
      !(options.planarity >= 0 && options.planarity < 1)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: coplanar angle {} rad and planarity {} out of range; give "
                                "an angle in [0, π/2) and a planarity in [0, 1)",
                                source, options.coplanar_angle, options.planarity));
  }
  std::vector<Triangle> T = validated_triangles(mesh, source);
  Points X(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) X[v] = mesh.V.row(v).transpose();
  std::vector<Triangle> neighbours = triangle_neighbours(T);

  // Outward: a closed piece encloses a positive volume with its triangles.
  const Pieces piece = pieces(T, neighbours);
  const int num_pieces = int(piece.closed.size());
  std::vector<double> volume(num_pieces, 0.0);
  for (size_t t = 0; t < T.size(); ++t) {
    volume[piece.of_triangle[t]] += X[T[t][0]].dot(X[T[t][1]].cross(X[T[t][2]])) / 6;
  }
  for (int p = 0; p < num_pieces; ++p) {
    if (!piece.closed[p] || volume[p] >= 0) continue;
    for (size_t t = 0; t < T.size(); ++t) {
      if (piece.of_triangle[t] == p) std::swap(T[t][1], T[t][2]);
    }
    note(num_pieces == 1
             ? fmt::format("{}: the triangles faced inward; turned them outward", source)
             : fmt::format("{}: the triangles of piece {} faced inward; turned them outward",
                           source, p + 1));
  }
  neighbours = triangle_neighbours(T);

  const int num_closed = int(std::count(piece.closed.begin(), piece.closed.end(), 1));
  const int fewest = 4 * num_closed + (num_pieces - num_closed);
  if (options.max_faces < fewest) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("{}: at most {} faces asked, but the mesh has {} closed piece{} (4 faces at "
                    "least each) and {} open one{} (1 at least): allow at least {} faces",
                    source, options.max_faces, num_closed, num_closed == 1 ? "" : "s",
                    num_pieces - num_closed, num_pieces - num_closed == 1 ? "" : "s", fewest));
  }

  int count = 0;
  std::vector<int> region = grow_regions(X, T, neighbours, options, count);
  if (count > options.max_faces) {
    const int before = int(T.size());
    Decimation d = start_decimation(X, T, neighbours, region, count, options.max_faces);
    while (count > options.max_faces) {
      // Collapse at least as many triangles as there are faces too many; more while the mesh
      // still has many more triangles than faces (flat parts cost nothing to collapse).
      const int step = std::max({1, count - options.max_faces, (d.triangles - count) / 4});
      if (collapse_until(d, d.triangles - step) == 0) {
        throw UserError(ErrorCategory::kInfeasible,
                        fmt::format("{}: the mesh simplifies to no fewer than {} planar faces "
                                    "(no further edge collapse keeps it manifold without "
                                    "turning a triangle over); allow at least {} faces",
                                    source, count, count));
      }
      T = live_triangles(d);
      X = d.X;
      neighbours = triangle_neighbours(T);
      region = grow_regions(X, T, neighbours, options, count);
    }
    note(fmt::format("{}: simplified {} triangles to {} by quadric-error edge collapse", source,
                     before, T.size()));
  }

  std::vector<std::vector<int>> faces = region_loops(T, neighbours, region, count);
  const int dropped = drop_straight_corners(X, faces, options.coplanar_angle);
  note(fmt::format("{}: merged {} triangles into {} planar faces{}", source, T.size(), faces.size(),
                   dropped > 0 ? fmt::format(", dropping {} corners in the middle of straight "
                                             "sides",
                                             dropped)
                               : ""));

  // Only the corners the faces use, in the mesh's vertex order.
  std::vector<int> index(X.size(), -1);
  for (const std::vector<int>& face : faces) {
    for (int v : face) index[v] = 0;
  }
  int used = 0;
  for (int& i : index) {
    if (i == 0) i = used++;
  }
  Polyhedron solid;
  solid.source = source;
  solid.V.resize(used, 3);
  for (size_t v = 0; v < X.size(); ++v) {
    if (index[v] >= 0) solid.V.row(index[v]) = X[v].transpose();
  }
  for (std::vector<int>& face : faces) {
    for (int& v : face) v = index[v];
  }
  solid.faces = std::move(faces);
  polyhedron_edges(solid);
  require_planar(solid, options.planarity);
  return solid;
}

}  // namespace flatmorph
