// The printing graph of a height field (SCF 2020 §6.1 "Graph generation" and "Triangulation";
// the structure the authors' graphs have, notes §1.1, §1.3, §2). The authors made their graphs by
// hand in Rhino; this builds them from the piecewise-linear (PL) height:
// 1. levels: equidistant, plus a pair around each saddle and one half-way up to a summit; a
//    global set, so that the depth of a loop in the loop tree is the index of its level;
// 2. loops: the isolines of the PL height (marching over the triangles), loop 0 the boundary;
//    the loop tree from the components of the superlevel sets (a sweep from the top);
// 3. gradient lines from samples on every loop, up to its children and down to its parent; their
//    ends, made monotone along both loops, are the anchors of the quad-dominant graph;
// 4. loops resampled at the anchors and upsampled to l_u (§6.1 "Triangulation"; notes §2 step 3);
// 5. each strip between two anchors zipped by the greedy shortest diagonal (notes §2 step 4); where
//    two consecutive anchors reach different children, the strip's upper side is a saddle chain
//    between them (notes §2 step 2) and the polygon the chains close around the saddle is fanned
//    from the saddle vertex (step 6); a top loop is capped by a fan from its summit (step 5).
// Every face is checked (counter-clockwise seen from above); where a strip cannot be zipped
// that way, its anchors move, merge or a new gradient line splits it (see step 5).
#include "methods/heightfield/isoline_mesh.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#include "common/error.h"
#include "mesh/plane_geometry.h"
#include "mesh/polygon.h"
#include "mesh/topology.h"

namespace flatmorph {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// Fractions of the level spacing Δ that shape the levels (documented in the header).
constexpr double kDefaultLevelsPerHeight = 12.0;
constexpr double kSaddleOffset = 0.25;     // saddle band: saddle ± Δ/4
constexpr double kSaddleClearance = 0.25;  // no equidistant level within Δ/4 of a saddle band
constexpr double kPersistence = 0.5;       // peaks rising less than Δ/2 over their saddle: noise
constexpr double kSummitGap = 0.75;        // a summit more than 3/4 Δ above its top level
constexpr double kLevelClearance = 0.25;   // an extra level at least Δ/4 from every other
constexpr double kTopClearance = 0.125;    // no level within Δ/8 below a significant peak
constexpr long long kMaxVertices = 5'000'000;
constexpr double kMinEdgeFraction = 0.25;  // loop vertices at least l_u / 4 apart...
constexpr double kMinLoopPieces = 16.0;    // ...or a sixteenth of a small loop's perimeter

// ---------------------------------------------------------------------------------------------
// The input surface and walking on it.

struct Surface {
  const Eigen::MatrixXi* F = nullptr;
  EdgeTopology topo;
  std::vector<Vector2d> xy;
  Eigen::VectorXd z;
  Eigen::VectorXd area2;                     // twice the xy area of each face (positive)
  Eigen::VectorXd slope;                     // |∇z| of each face
  std::vector<Vector2d> vertex_gradient;     // ∇z averaged over the faces around, by area
  std::vector<std::vector<int>> neighbours;  // per vertex
  std::vector<int> boundary;                 // boundary vertices, counter-clockwise
  std::vector<int> boundary_edge_segment;    // per edge: index along `boundary`, or -1

  int corner(int f, int k) const { return (*F)(f, k); }
};

Surface make_surface(const HeightField& field) {
  Surface s;
  s.F = &field.F;
  s.topo = edge_topology(field.F);
  const int nv = static_cast<int>(field.V.rows());
  const int nf = static_cast<int>(field.F.rows());
  s.xy.resize(nv);
  s.z = field.V.col(2);
  for (int v = 0; v < nv; ++v) s.xy[v] = Vector2d(field.V(v, 0), field.V(v, 1));
  s.area2.resize(nf);
  s.slope.resize(nf);
  s.vertex_gradient.assign(nv, Vector2d::Zero());
  std::vector<double> weight(nv, 0.0);
  for (int f = 0; f < nf; ++f) {
    const int a = field.F(f, 0), b = field.F(f, 1), c = field.F(f, 2);
    const Vector2d e1 = s.xy[b] - s.xy[a], e2 = s.xy[c] - s.xy[a];
    const double A2 = cross2(e1, e2);
    s.area2[f] = A2;
    // z = z_a + g·(p - a): solve [e1 e2]^T g = [dz1 dz2].
    const double dz1 = s.z[b] - s.z[a], dz2 = s.z[c] - s.z[a];
    const Vector2d g((dz1 * e2.y() - dz2 * e1.y()) / A2, (dz2 * e1.x() - dz1 * e2.x()) / A2);
    s.slope[f] = g.norm();
    for (int v : {a, b, c}) {
      s.vertex_gradient[v] += 0.5 * A2 * g;
      weight[v] += 0.5 * A2;
    }
  }
  for (int v = 0; v < nv; ++v) {
    if (weight[v] > 0.0) s.vertex_gradient[v] /= weight[v];
  }
  s.neighbours.assign(nv, {});
  for (int e = 0; e < s.topo.num_edges(); ++e) {
    s.neighbours[s.topo.edges(e, 0)].push_back(s.topo.edges(e, 1));
    s.neighbours[s.topo.edges(e, 1)].push_back(s.topo.edges(e, 0));
  }
  const std::vector<std::vector<int>> loops = boundary_loops(field.F);
  if (loops.empty()) throw std::invalid_argument("isoline_mesh: the field has no boundary");
  s.boundary = loops.front();
  s.boundary_edge_segment.assign(s.topo.num_edges(), -1);
  std::map<std::pair<int, int>, int> edge_of;
  for (int e = 0; e < s.topo.num_edges(); ++e) {
    if (s.topo.is_boundary_edge(e)) edge_of[{s.topo.edges(e, 0), s.topo.edges(e, 1)}] = e;
  }
  const int nb = static_cast<int>(s.boundary.size());
  for (int k = 0; k < nb; ++k) {
    const int a = s.boundary[k], b = s.boundary[(k + 1) % nb];
    const auto it = edge_of.find({std::min(a, b), std::max(a, b)});
    if (it != edge_of.end()) s.boundary_edge_segment[it->second] = k;
  }
  return s;
}

// Barycentric coordinates of p in face f (possibly outside it).
std::array<double, 3> barycentric(const Surface& s, int f, const Vector2d& p) {
  const Vector2d& a = s.xy[s.corner(f, 0)];
  const Vector2d& b = s.xy[s.corner(f, 1)];
  const Vector2d& c = s.xy[s.corner(f, 2)];
  const double l0 = cross2(b - p, c - p) / s.area2[f];
  const double l1 = cross2(c - p, a - p) / s.area2[f];
  return {l0, l1, 1.0 - l0 - l1};
}

double height_in_face(const Surface& s, int f, const Vector2d& p) {
  const std::array<double, 3> l = barycentric(s, f, p);
  return l[0] * s.z[s.corner(f, 0)] + l[1] * s.z[s.corner(f, 1)] + l[2] * s.z[s.corner(f, 2)];
}

// The smoothed gradient at p in face f (vertex gradients interpolated linearly).
Vector2d gradient_in_face(const Surface& s, int f, const Vector2d& p) {
  const std::array<double, 3> l = barycentric(s, f, p);
  return l[0] * s.vertex_gradient[s.corner(f, 0)] + l[1] * s.vertex_gradient[s.corner(f, 1)] +
         l[2] * s.vertex_gradient[s.corner(f, 2)];
}

// A stretch [t0, t1] of a segment p + t (q - p) inside one face.
struct WalkPiece {
  int face;
  double t0, t1;
};

struct Walk {
  int face = -1;        // the face holding the end (or the last face before the boundary)
  bool exited = false;  // the segment leaves the surface through the boundary edge `exit_edge`
  int exit_edge = -1;
  double t_exit = 1.0;
};

// Walks the straight segment from p (in face f) to q across the faces, recording the pieces.
Walk walk_segment(const Surface& s, int f, const Vector2d& p, const Vector2d& q,
                  std::vector<WalkPiece>* pieces) {
  if (pieces) pieces->clear();
  double t = 0.0;
  int entry_local = -1;
  const int limit = static_cast<int>(s.area2.size()) + 8;
  for (int it = 0; it < limit; ++it) {
    const std::array<double, 3> lp = barycentric(s, f, p);
    const std::array<double, 3> lq = barycentric(s, f, q);
    int exit_corner = -1;
    double t_exit = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      if ((k + 1) % 3 == entry_local) continue;  // corner k is opposite edge (k + 1) % 3
      if (lq[k] >= -1e-12) continue;
      const double tk = lp[k] / (lp[k] - lq[k]);
      if (tk < t_exit) t_exit = tk, exit_corner = k;
    }
    if (exit_corner < 0) {
      if (pieces) pieces->push_back({f, t, 1.0});
      return {f, false, -1, 1.0};
    }
    t_exit = std::clamp(t_exit, t, 1.0);
    if (pieces) pieces->push_back({f, t, t_exit});
    const int local = (exit_corner + 1) % 3;
    const int next = s.topo.face_faces(f, local);
    if (next < 0) return {f, true, s.topo.face_edges(f, local), t_exit};
    entry_local = s.topo.face_faces_edge(f, local);
    f = next;
    t = t_exit;
  }
  return {f, false, -1, 1.0};
}

// ---------------------------------------------------------------------------------------------
// Critical points: a sweep of the vertices from the top joins the components of the superlevel
// sets (the join tree). A vertex joining two or more components is a saddle (its one-ring changes
// sign at least four times); a vertex starting one is a peak.

struct UnionFind {
  std::vector<int> parent, top;  // top: the highest vertex of the component (its first)
  explicit UnionFind(int n) : parent(n), top(n) {
    std::iota(parent.begin(), parent.end(), 0);
    std::iota(top.begin(), top.end(), 0);
  }
  int find(int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
};

// Vertices from the highest down; ties by index, so that plateaus have an order.
std::vector<int> descending_order(const Surface& s) {
  std::vector<int> order(s.z.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return s.z[a] != s.z[b] ? s.z[a] > s.z[b] : a < b; });
  return order;
}

struct Saddle {
  int vertex;
  double z;
  double second_peak;  // the second highest peak among the components it joins
};

struct Peak {
  int vertex;
  double z;
  double persistence;  // how far it rises above the saddle where it joins a higher peak
};

struct CriticalPoints {
  std::vector<Saddle> saddles;  // ascending z
  std::vector<Peak> peaks;      // descending z
};

CriticalPoints critical_points(const Surface& s, const std::vector<int>& order,
                               const std::vector<bool>& on_boundary, double z_boundary) {
  const int nv = static_cast<int>(s.z.size());
  UnionFind uf(nv);
  std::vector<int> rank(nv);
  for (int i = 0; i < nv; ++i) rank[order[i]] = i;
  CriticalPoints cp;
  std::vector<double> persistence(nv, -1.0);  // per peak vertex
  std::vector<int> roots;
  for (int v : order) {
    roots.clear();
    for (int u : s.neighbours[v]) {
      if (rank[u] < rank[v]) roots.push_back(uf.find(u));
    }
    std::sort(roots.begin(), roots.end());
    roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
    if (roots.empty()) {
      persistence[v] = std::numeric_limits<double>::infinity();
      continue;
    }
    // The component of the highest peak survives (ties: the lower vertex index).
    std::sort(roots.begin(), roots.end(),
              [&](int a, int b) { return rank[uf.top[a]] < rank[uf.top[b]]; });
    if (roots.size() >= 2 && !on_boundary[v] && s.z[v] > z_boundary) {
      cp.saddles.push_back({v, s.z[v], s.z[uf.top[roots[1]]]});
    }
    for (size_t i = 1; i < roots.size(); ++i) {
      persistence[uf.top[roots[i]]] = s.z[uf.top[roots[i]]] - s.z[v];
      uf.parent[roots[i]] = roots[0];
    }
    uf.parent[v] = roots[0];
  }
  for (int v : order) {
    if (persistence[v] < 0.0) continue;
    const double p = std::isinf(persistence[v]) ? s.z[v] - z_boundary : persistence[v];
    cp.peaks.push_back({v, s.z[v], p});
  }
  std::sort(cp.saddles.begin(), cp.saddles.end(), [](const Saddle& a, const Saddle& b) {
    return a.z != b.z ? a.z < b.z : a.vertex < b.vertex;
  });
  return cp;
}

// ---------------------------------------------------------------------------------------------
// Levels (paper §6.1: equidistant isolines; notes §1.1: extra levels at saddles and summits).

// Ascending heights strictly between the boundary (z_boundary, its highest point z_rim) and the
// top.
std::vector<double> choose_levels(const Surface& s, const CriticalPoints& cp, double z_boundary,
                                  double z_rim, double z_top, double spacing,
                                  const IsolineMeshOptions& options) {
  const double min_persistence = kPersistence * spacing;
  struct Band {
    double low, high;
  };
  std::vector<double> extra;
  std::vector<Band> bands;
  if (options.saddle_levels) {
    // A level just below and one just above each saddle: the loop below pinches towards the
    // saddle from both sides, the two above start right beside it, and the band between them
    // holds only the saddle, where gradient lines bend and the strips must stay small.
    for (const Saddle& saddle : cp.saddles) {
      const double rise = saddle.second_peak - saddle.z;
      if (rise < min_persistence) continue;
      const double offset =
          std::min({kSaddleOffset * spacing, 0.5 * rise, 0.5 * (saddle.z - z_boundary)});
      const Band band{saddle.z - offset, saddle.z + offset};
      // Saddles whose bands (nearly) overlap share one band.
      if (!bands.empty() && band.low - bands.back().high < kLevelClearance * spacing) {
        bands.back().high = std::max(bands.back().high, band.high);
        continue;
      }
      bands.push_back(band);
    }
    for (const Band& band : bands) extra.insert(extra.end(), {band.low, band.high});
  }
  std::vector<double> significant_peaks;
  for (const Peak& peak : cp.peaks) {
    if (peak.persistence >= min_persistence) significant_peaks.push_back(peak.z);
  }
  const auto too_close_to_a_peak = [&](double level) {
    for (double peak : significant_peaks) {
      if (level < peak && peak - level < kTopClearance * spacing) return true;
    }
    return false;
  };
  std::vector<double> levels = extra;
  for (int k = 1;; ++k) {
    const double level = z_boundary + k * spacing;
    if (level >= z_top) break;
    if (too_close_to_a_peak(level)) continue;
    bool clear = true;
    for (const Band& band : bands) {
      if (level > band.low - kSaddleClearance * spacing &&
          level < band.high + kSaddleClearance * spacing) {
        clear = false;
      }
    }
    if (clear) levels.push_back(level);
  }
  std::sort(levels.begin(), levels.end());
  if (options.summit_levels) {
    for (double peak : significant_peaks) {
      double below = z_boundary;
      for (double level : levels) {
        if (level < peak) below = std::max(below, level);
      }
      if (peak - below <= kSummitGap * spacing) continue;
      const double level = 0.5 * (below + peak);
      bool clear = !too_close_to_a_peak(level);
      for (double other : levels) {
        if (std::abs(other - level) < kLevelClearance * spacing) clear = false;
      }
      if (clear) {
        levels.insert(std::upper_bound(levels.begin(), levels.end(), level), level);
      }
    }
  }
  // No level may pass through a vertex: the isoline would touch it and degenerate. Nudge up.
  std::vector<double> zs(s.z.data(), s.z.data() + s.z.size());
  std::sort(zs.begin(), zs.end());
  const double eps = 1e-7 * (z_top - z_boundary);
  for (double& level : levels) {
    for (int guard = 0; guard < 1000; ++guard) {
      const auto it = std::lower_bound(zs.begin(), zs.end(), level - eps);
      if (it == zs.end() || *it > level + eps) break;
      level = *it + 2.0 * eps;
    }
  }
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  // An isoline must not touch the boundary (with a spacing below the boundary's tolerance).
  levels.erase(std::remove_if(levels.begin(), levels.end(),
                              [&](double level) { return level <= z_rim + eps; }),
               levels.end());
  return levels;
}

// ---------------------------------------------------------------------------------------------
// Loops: closed isolines as polylines over the input faces.

struct Loop {
  int level = 0;                  // depth = index into the levels
  std::vector<Vector2d> points;   // closed polyline, counter-clockwise (higher on the left)
  std::vector<int> segment_face;  // the face holding segment k (points k -> k + 1)
  std::vector<double> length;     // arc length at each point; length[n] = perimeter
  int upper_vertex = -1;          // an input vertex above the level, inside the loop
  int parent = -1;
  std::vector<int> children;
  int summit = -1;  // the highest input vertex inside (top loops)
  // Output: the mesh's vertices along the loop, counter-clockwise.
  std::vector<int> vertices;

  double perimeter() const { return length.back(); }
  int num_segments() const { return static_cast<int>(points.size()); }
};

void finish_loop(Loop& loop) {
  const int n = loop.num_segments();
  loop.length.assign(n + 1, 0.0);
  for (int k = 0; k < n; ++k) {
    loop.length[k + 1] = loop.length[k] + (loop.points[(k + 1) % n] - loop.points[k]).norm();
  }
}

double wrap(double s, double period) {
  double r = std::fmod(s, period);
  if (r < 0.0) r += period;
  return r;
}

// The point at arc length s, its segment and the segment's direction.
struct LoopPoint {
  Vector2d p;
  int segment;
  Vector2d tangent;
};

LoopPoint point_at(const Loop& loop, double s) {
  const int n = loop.num_segments();
  s = wrap(s, loop.perimeter());
  int k = static_cast<int>(std::upper_bound(loop.length.begin(), loop.length.end(), s) -
                           loop.length.begin()) -
          1;
  k = std::clamp(k, 0, n - 1);
  const Vector2d a = loop.points[k], b = loop.points[(k + 1) % n];
  const double len = loop.length[k + 1] - loop.length[k];
  const double t = len > 0.0 ? std::clamp((s - loop.length[k]) / len, 0.0, 1.0) : 0.0;
  Vector2d tangent = b - a;
  for (int j = 1; tangent.norm() == 0.0 && j < n; ++j) {
    tangent = loop.points[(k + j + 1) % n] - loop.points[(k + j) % n];
  }
  return {a + t * (b - a), k, tangent.normalized()};
}

// Between arc lengths s0 < s1 (s1 may pass the perimeter): how far the loop strays from the
// chord, and how much room there is (the least of `room` over the segments passed).
void chord_fit(const Loop& loop, const std::vector<double>& room, double s0, double s1,
               double& deviation, double& least_room) {
  const LoopPoint a = point_at(loop, s0), b = point_at(loop, s1);
  const Vector2d d = b.p - a.p;
  const double len = d.norm();
  const int n = loop.num_segments();
  const double per = loop.perimeter();
  deviation = 0.0;
  least_room = room[a.segment];
  for (int k = a.segment, guard = 0; guard <= n; ++guard) {
    least_room = std::min(least_room, room[k]);
    if (k == b.segment && s1 - s0 < per - 1e-12 && guard > 0) break;
    if (k == b.segment && guard == 0 && s1 - s0 < loop.length[k + 1] - loop.length[k]) break;
    k = (k + 1) % n;
    const Vector2d& q = loop.points[k];
    const double off = len > 0.0 ? std::abs(cross2(d, q - a.p)) / len : (q - a.p).norm();
    deviation = std::max(deviation, off);
  }
}

// Per level: which loop and segment lie in each crossed face, sorted by face.
struct LevelIndex {
  std::vector<std::array<int, 3>> face_segment;  // (face, loop, segment)
  std::vector<int> loops;

  bool find(int face, int& loop, int& segment) const {
    const auto it = std::lower_bound(face_segment.begin(), face_segment.end(),
                                     std::array<int, 3>{face, -1, -1});
    if (it == face_segment.end() || (*it)[0] != face) return false;
    loop = (*it)[1];
    segment = (*it)[2];
    return true;
  }
};

// Marches the triangles at `height` and appends the loops (paper §6.1: isolines).
void march(const Surface& s, double height, int level, std::vector<Loop>& loops,
           LevelIndex& index) {
  const Eigen::MatrixXi& F = *s.F;
  const int nf = static_cast<int>(F.rows());
  struct Segment {
    int face, from_edge, to_edge;
  };
  std::vector<Segment> segments;
  std::map<int, int> segment_from_edge;  // crossed edge -> the segment that starts on it
  const auto crossing = [&](int e) {
    const int a = s.topo.edges(e, 0), b = s.topo.edges(e, 1);
    const double t = (height - s.z[a]) / (s.z[b] - s.z[a]);
    return Vector2d(s.xy[a] + t * (s.xy[b] - s.xy[a]));
  };
  for (int f = 0; f < nf; ++f) {
    bool above[3];
    int count = 0;
    for (int k = 0; k < 3; ++k) count += above[k] = s.z[F(f, k)] > height;
    if (count == 0 || count == 3) continue;
    int crossed[2], m = 0, high = -1;
    for (int k = 0; k < 3; ++k) {
      if (above[k] != above[(k + 1) % 3]) crossed[m++] = s.topo.face_edges(f, k);
      if (above[k]) high = F(f, k);
    }
    // Orient the segment with the higher side on its left.
    const Vector2d p0 = crossing(crossed[0]), p1 = crossing(crossed[1]);
    if (cross2(p1 - p0, s.xy[high] - p0) < 0.0) std::swap(crossed[0], crossed[1]);
    segment_from_edge[crossed[0]] = static_cast<int>(segments.size());
    segments.push_back({f, crossed[0], crossed[1]});
  }
  std::vector<bool> used(segments.size(), false);
  for (size_t first = 0; first < segments.size(); ++first) {
    if (used[first]) continue;
    Loop loop;
    loop.level = level;
    const int id = static_cast<int>(loops.size());
    int k = static_cast<int>(first);
    while (!used[k]) {
      used[k] = true;
      index.face_segment.push_back({segments[k].face, id, loop.num_segments()});
      loop.points.push_back(crossing(segments[k].from_edge));
      loop.segment_face.push_back(segments[k].face);
      const auto next = segment_from_edge.find(segments[k].to_edge);
      if (next == segment_from_edge.end()) {
        throw std::logic_error("isoline_mesh: an isoline ends inside the surface");
      }
      k = next->second;
    }
    if (k != static_cast<int>(first)) {
      throw std::logic_error("isoline_mesh: an isoline does not close");
    }
    const int e = segments[first].from_edge;
    const int a = s.topo.edges(e, 0), b = s.topo.edges(e, 1);
    loop.upper_vertex = s.z[a] > height ? a : b;
    finish_loop(loop);
    index.loops.push_back(id);
    loops.push_back(std::move(loop));
  }
  std::sort(index.face_segment.begin(), index.face_segment.end());
}

// ---------------------------------------------------------------------------------------------
// Gradient lines (paper §6.1, after Dong et al. 2005): from a point on a loop, up or down along
// the height's gradient until the next level. On a PL surface the face-wise gradient makes lines
// merge along ridge and valley edges; its average at the vertices, interpolated, does not. Over
// flat ground (a plateau at the boundary's height) a line keeps its direction.

struct Landing {
  int loop = -1;
  double s = 0.0;  // arc length along that loop
};

struct GradientTracer {
  const Surface* surface;
  const std::vector<Loop>* loops;
  const std::vector<LevelIndex>* index;
  const std::vector<double>* heights;  // per level (heights[0]: the boundary)
  double step;
  int max_steps;
  double flat_slope;
};

Vector2d direction(const GradientTracer& t, int f, const Vector2d& p, double sign,
                   const Vector2d& previous) {
  const Vector2d g = gradient_in_face(*t.surface, f, p);
  const double n = g.norm();
  return n > t.flat_slope ? Vector2d(sign * g / n) : previous;
}

// Projects p (in face f, at the height of level `level`) onto that level's loop there.
Landing land(const GradientTracer& t, int level, int f, const Vector2d& p) {
  const LevelIndex& index = (*t.index)[level];
  int loop = -1, segment = -1;
  bool found = index.find(f, loop, segment);
  // p sits on an edge or a corner: try the faces across.
  for (int k = 0; k < 3 && !found; ++k) {
    const int g = t.surface->topo.face_faces(f, k);
    found = g >= 0 && index.find(g, loop, segment);
  }
  if (!found) return {};
  const Loop& l = (*t.loops)[loop];
  const Vector2d a = l.points[segment], b = l.points[(segment + 1) % l.num_segments()];
  const double len2 = (b - a).squaredNorm();
  const double u = len2 > 0.0 ? std::clamp((p - a).dot(b - a) / len2, 0.0, 1.0) : 0.0;
  return {loop, l.length[segment] + u * std::sqrt(len2)};
}

// From p (in face f, at height `origin`) up or down to level `to_level`; `previous` is the
// direction to keep over flat ground.
Landing trace_from(const GradientTracer& t, int f, Vector2d p, double origin, int to_level,
                   double sign, Vector2d previous) {
  const Surface& surface = *t.surface;
  const double target = (*t.heights)[to_level];
  const double retreat = 0.5 * std::abs(target - origin);
  std::vector<WalkPiece> pieces;
  for (int i = 0; i < t.max_steps; ++i) {
    const Vector2d d1 = direction(t, f, p, sign, previous);
    const Vector2d mid = p + 0.5 * t.step * d1;
    const Walk half = walk_segment(surface, f, p, mid, nullptr);
    const Vector2d d2 = half.exited ? d1 : direction(t, half.face, mid, sign, d1);
    const Vector2d q = p + t.step * d2;
    const Walk w = walk_segment(surface, f, p, q, &pieces);
    if (to_level > 0) {
      for (const WalkPiece& piece : pieces) {
        const Vector2d a = p + piece.t0 * (q - p), b = p + piece.t1 * (q - p);
        const double za = height_in_face(surface, piece.face, a);
        const double zb = height_in_face(surface, piece.face, b);
        if (sign * (zb - target) >= 0.0 && sign * (za - target) < 0.0) {
          const double u = (target - za) / (zb - za);
          return land(t, to_level, piece.face, a + u * (b - a));
        }
        if (sign * (origin - za) > retreat) return {};  // went back over its own loop
      }
    }
    if (w.exited) {
      if (to_level != 0) return {};
      // Down to the boundary: land where the line leaves the surface.
      const int segment = surface.boundary_edge_segment[w.exit_edge];
      if (segment < 0) return {};
      const Loop& boundary = (*t.loops)[0];
      const Vector2d x = p + w.t_exit * (q - p);
      const Vector2d a = boundary.points[segment];
      const Vector2d b = boundary.points[(segment + 1) % boundary.num_segments()];
      const double len = (b - a).norm();
      const double u = len > 0.0 ? std::clamp((x - a).dot(b - a) / (len * len), 0.0, 1.0) : 0.0;
      return {0, boundary.length[segment] + u * len};
    }
    previous = d2;
    p = q;
    f = w.face;
  }
  return {};
}

Landing trace(const GradientTracer& t, const Loop& from, double s, int to_level) {
  const LoopPoint start = point_at(from, s);
  const double sign = to_level > from.level ? 1.0 : -1.0;
  // The loop's left side is its higher side.
  return trace_from(t, from.segment_face[start.segment], start.p, (*t.heights)[from.level],
                    to_level, sign, sign * Vector2d(-start.tangent.y(), start.tangent.x()));
}

// ---------------------------------------------------------------------------------------------
// Anchors: the ends of the gradient lines between a parent loop and its children.

struct Anchor {
  double s_parent = 0.0;  // arc length along the parent
  int child = -1;         // loop index
  double s_child = 0.0;
  bool pinned = false;  // on a saddle's separatrix: kept
  // Output vertices and their positions in the loops' vertex lists.
  int parent_vertex = -1, child_vertex = -1;
  int parent_position = -1, child_position = -1;
};

// The longest strictly increasing subsequence of u (indices).
std::vector<int> longest_increasing(const std::vector<double>& u) {
  std::vector<int> tails, previous(u.size(), -1);
  for (int i = 0; i < static_cast<int>(u.size()); ++i) {
    const auto it = std::lower_bound(tails.begin(), tails.end(), u[i],
                                     [&](int j, double value) { return u[j] < value; });
    if (it != tails.begin()) previous[i] = *(it - 1);
    if (it == tails.end()) {
      tails.push_back(i);
    } else {
      *it = i;
    }
  }
  std::vector<int> out;
  for (int i = tails.empty() ? -1 : tails.back(); i >= 0; i = previous[i]) out.push_back(i);
  std::reverse(out.begin(), out.end());
  return out;
}

// Keeps the anchors of `run` (sorted along the parent) whose child positions increase along the
// child too, at least `gap` apart on both loops: gradient lines do not cross, and the strips
// between them must not be slivers. `cyclic`: the run goes all around both loops.
std::vector<Anchor> monotone(const std::vector<Anchor>& run, double parent_perimeter,
                             double child_perimeter, double gap, bool cyclic) {
  const int n = static_cast<int>(run.size());
  std::vector<Anchor> best;
  const int tries = std::min(n, 8);
  for (int r = 0; r < tries; ++r) {
    const int ref = cyclic ? r * n / tries : r;
    std::vector<int> order;
    for (int i = 0; i < n; ++i) order.push_back(cyclic ? (ref + i) % n : i);
    std::vector<double> u;
    for (int i : order) u.push_back(wrap(run[i].s_child - run[ref].s_child, child_perimeter));
    if (!cyclic) {
      // Anchors before the reference come before it on the child too.
      for (int i = 0; i < ref; ++i) u[i] -= child_perimeter;
    }
    std::vector<Anchor> kept;
    double last_p = 0.0, last_c = 0.0, first_p = 0.0, first_c = 0.0;
    for (int j : longest_increasing(u)) {
      const Anchor& a = run[order[j]];
      const double up = wrap(a.s_parent - run[cyclic ? ref : 0].s_parent, parent_perimeter);
      if (!kept.empty() && (up - last_p < gap || u[j] - last_c < gap)) continue;
      if (kept.empty()) first_p = up, first_c = u[j];
      kept.push_back(a);
      last_p = up;
      last_c = u[j];
    }
    if (cyclic) {
      while (kept.size() > 1 && (first_p + parent_perimeter - last_p < gap ||
                                 first_c + child_perimeter - last_c < gap)) {
        kept.pop_back();
        const Anchor& a = kept.back();
        last_p = wrap(a.s_parent - run[ref].s_parent, parent_perimeter);
        last_c = wrap(a.s_child - run[ref].s_child, child_perimeter);
      }
    } else if (!kept.empty() && last_c - first_c >= child_perimeter) {
      continue;  // a run cannot wrap around its child
    }
    if (kept.size() > best.size()) best = std::move(kept);
  }
  return best;
}

struct AnchorRun {
  int begin, end;  // [begin, end) into the annulus' anchors
  int child;
};

// The region between a loop and its children (paper §6.1: quads; polygons at saddles).
struct Annulus {
  int parent = -1;
  std::vector<Anchor> anchors;  // around the parent, counter-clockwise
  std::vector<AnchorRun> runs;  // consecutive anchors reaching one child
  bool cyclic = false;          // one child: the anchors go all around
};

// Sorts, filters and groups the anchors of an annulus with several children into runs, each
// monotone, of at least two anchors.
void organise_runs(Annulus& annulus, const std::vector<Loop>& loops, double gap) {
  const Loop& parent = loops[annulus.parent];
  std::vector<Anchor>& a = annulus.anchors;
  std::sort(a.begin(), a.end(), [](const Anchor& x, const Anchor& y) {
    return x.s_parent != y.s_parent ? x.s_parent < y.s_parent : x.child < y.child;
  });
  if (parent.children.size() == 1) {
    a = monotone(a, parent.perimeter(), loops[parent.children[0]].perimeter(), gap, true);
    annulus.cyclic = true;
    if (a.size() < 3) {
      throw std::logic_error(
          fmt::format("isoline_mesh: only {} gradient lines join the loop at {} to the one above",
                      a.size(), at_xy(parent.points[0])));
    }
    annulus.runs = {{0, static_cast<int>(a.size()), parent.children[0]}};
    return;
  }
  for (int pass = 0; pass < 100; ++pass) {
    const int n = static_cast<int>(a.size());
    int start = -1;
    for (int i = 0; i < n && start < 0; ++i) {
      if (a[i].child != a[(i + n - 1) % n].child) start = i;
    }
    if (start < 0) {
      throw std::logic_error(fmt::format(
          "isoline_mesh: the gradient lines from the loop at {} reach only one of its {} "
          "children",
          at_xy(parent.points[0]), parent.children.size()));
    }
    std::rotate(a.begin(), a.begin() + start, a.end());
    std::vector<Anchor> kept;
    std::vector<AnchorRun> runs;
    bool changed = false;
    for (int i = 0; i < n;) {
      int j = i;
      while (j < n && a[j].child == a[i].child) ++j;
      const std::vector<Anchor> run(a.begin() + i, a.begin() + j);
      std::vector<Anchor> m =
          monotone(run, parent.perimeter(), loops[a[i].child].perimeter(), gap, false);
      if (m.size() != run.size()) changed = true;
      if (m.size() >= 2) {
        const int b = static_cast<int>(kept.size());
        kept.insert(kept.end(), m.begin(), m.end());
        if (!runs.empty() && runs.back().child == a[i].child) {
          runs.back().end = static_cast<int>(kept.size());  // merged with the previous run
        } else {
          runs.push_back({b, static_cast<int>(kept.size()), a[i].child});
        }
      }
      i = j;
    }
    if (runs.size() >= 2 && runs.front().child == runs.back().child) changed = true;
    a = std::move(kept);
    if (!changed) {
      annulus.runs = std::move(runs);
      for (int child : parent.children) {
        bool reached = false;
        for (const AnchorRun& r : annulus.runs) reached = reached || r.child == child;
        if (!reached) {
          throw std::logic_error(
              fmt::format("isoline_mesh: no gradient line joins the loop at {} to its parent",
                          at_xy(loops[child].points[0])));
        }
      }
      return;
    }
    // Re-sort (a run may have been merged across the start) and filter again.
    std::sort(a.begin(), a.end(), [](const Anchor& x, const Anchor& y) {
      return x.s_parent != y.s_parent ? x.s_parent < y.s_parent : x.child < y.child;
    });
  }
  throw std::logic_error("isoline_mesh: the gradient lines of a saddle do not settle");
}

// Where the gradient lines from the parent switch from one child to the next, a saddle's
// separatrix runs down to the parent between them. Bisecting there along the parent brings the two
// last lines to the saddle itself, so that they reach the children right beside it and the saddle
// chain and polygon between them stay small (notes §2 steps 2, 6). Each child keeps at least
// `separation` of its loop free between the runs that reach it (the polygon's side there): the
// bisection backs off where two saddle sides would meet.
void refine_transitions(Annulus& annulus, const std::vector<Loop>& loops,
                        const GradientTracer& tracer, double gap, double separation) {
  if (annulus.cyclic) return;
  const Loop& parent = loops[annulus.parent];
  const double per = parent.perimeter();
  const int nr = static_cast<int>(annulus.runs.size());
  std::vector<std::vector<Anchor>> runs(nr);
  for (int r = 0; r < nr; ++r) {
    runs[r].assign(annulus.anchors.begin() + annulus.runs[r].begin,
                   annulus.anchors.begin() + annulus.runs[r].end);
  }
  // For transition r (run r -> run r + 1): the ends found, closer and closer to the separatrix.
  std::vector<std::vector<Anchor>> ends(nr), starts(nr);
  const double stop = 0.01 * gap;
  for (int r = 0; r < nr; ++r) {
    Anchor a = runs[r].back(), b = runs[(r + 1) % nr].front();
    ends[r] = {a};
    starts[r] = {b};
    double lo = a.s_parent, hi = b.s_parent;
    if (hi < lo) hi += per;
    for (int it = 0; it < 30 && hi - lo > stop; ++it) {
      const double mid = 0.5 * (lo + hi);
      const Landing l = trace(tracer, parent, wrap(mid, per), parent.level + 1);
      if (l.loop == a.child) {
        ends[r].push_back({wrap(mid, per), a.child, l.s});
        lo = mid;
      } else if (l.loop == b.child) {
        starts[r].push_back({wrap(mid, per), b.child, l.s});
        hi = mid;
      } else {
        break;
      }
    }
  }
  // Back off where the free side of a child would be shorter than `separation`.
  std::vector<int> end_pick(nr), start_pick(nr);
  for (int r = 0; r < nr; ++r) {
    end_pick[r] = static_cast<int>(ends[r].size()) - 1;
    start_pick[r] = static_cast<int>(starts[r].size()) - 1;
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (int r = 0; r < nr; ++r) {
      // The end of run r, and the start of the run of the same child that comes next on it
      // (found before refining: refined ends may pass each other).
      const Anchor& e0 = ends[r][0];
      const Anchor& e = ends[r][end_pick[r]];
      const double pc = loops[e.child].perimeter();
      int next = -1;
      double free0 = 2.0 * pc;
      for (int q = 0; q < nr; ++q) {
        if (annulus.runs[(q + 1) % nr].child != e.child) continue;
        const double d = wrap(starts[q][0].s_child - e0.s_child, pc);
        if (d < free0) free0 = d, next = q;
      }
      if (next < 0) continue;
      const auto moved = [&](double from, double to) {  // signed, along the child
        return wrap(to - from + 0.5 * pc, pc) - 0.5 * pc;
      };
      const double free = free0 - moved(e0.s_child, e.s_child) -
                          moved(starts[next][start_pick[next]].s_child, starts[next][0].s_child);
      if (free >= std::min(separation, free0) - 1e-12) continue;
      if (end_pick[r] > 0 && (end_pick[r] >= start_pick[next] || start_pick[next] == 0)) {
        --end_pick[r];
        changed = true;
      } else if (start_pick[next] > 0) {
        --start_pick[next];
        changed = true;
      }
    }
  }
  for (int r = 0; r < nr; ++r) {
    std::vector<Anchor>& left = runs[r];
    std::vector<Anchor>& right = runs[(r + 1) % nr];
    const Anchor a = ends[r][end_pick[r]], b = starts[r][start_pick[r]];
    // The new ends replace the anchors they come too close to (or pass) on either loop.
    const auto too_close = [&](const Anchor& x, const Anchor& y) {  // x before y
      const double pc = loops[x.child].perimeter();
      const double dc = wrap(y.s_child - x.s_child, pc);
      return wrap(y.s_parent - x.s_parent, per) < 0.5 * gap || dc < 0.5 * gap || dc > 0.5 * pc;
    };
    while (left.size() > 2 && too_close(left.back(), a)) left.pop_back();
    if (!too_close(left.back(), a)) {
      left.push_back(a);
    } else {
      left.back() = a;
    }
    while (right.size() > 2 && too_close(b, right.front())) right.erase(right.begin());
    if (!too_close(b, right.front())) {
      right.insert(right.begin(), b);
    } else {
      right.front() = b;
    }
  }
  annulus.anchors.clear();
  for (int r = 0; r < nr; ++r) {
    annulus.runs[r].begin = static_cast<int>(annulus.anchors.size());
    annulus.anchors.insert(annulus.anchors.end(), runs[r].begin(), runs[r].end());
    annulus.runs[r].end = static_cast<int>(annulus.anchors.size());
  }
}

// Adds the anchor f (on a saddle's descending separatrix) to the anchors of one run (in order
// along the parent; `cyclic`: all around both loops), dropping the ones it crosses or comes
// closer than gap / 2 to on either loop. A valley's isolines bend sharply where it runs, and a
// strip can only zip into such a notch from below along the valley. Returns false, changing
// nothing, when f does not fall inside a run or would cross a pinned anchor or a run's end.
bool pin(std::vector<Anchor>& run, const Anchor& f, double parent_perimeter, double child_perimeter,
         double gap, bool cyclic) {
  const auto signed_wrap = [](double d, double period) {
    return wrap(d + 0.5 * period, period) - 0.5 * period;
  };
  const int n = static_cast<int>(run.size());
  std::vector<Anchor> kept;
  for (int i = 0; i < n; ++i) {
    const Anchor& e = run[i];
    double dp, dc;
    if (cyclic) {
      dp = signed_wrap(e.s_parent - f.s_parent, parent_perimeter);
      dc = signed_wrap(e.s_child - f.s_child, child_perimeter);
    } else {
      dp = wrap(e.s_parent - run[0].s_parent, parent_perimeter) -
           wrap(f.s_parent - run[0].s_parent, parent_perimeter);
      dc = wrap(e.s_child - run[0].s_child, child_perimeter) -
           wrap(f.s_child - run[0].s_child, child_perimeter);
    }
    const bool conflict =
        (dp < 0.0) != (dc < 0.0) || std::abs(dp) < 0.5 * gap || std::abs(dc) < 0.5 * gap;
    if (!conflict) {
      kept.push_back(e);
    } else if (e.pinned || (!cyclic && (i == 0 || i == n - 1))) {
      return false;
    }
  }
  if (kept.size() < 2) return false;
  // Insert in order along the parent.
  const double ref = kept[0].s_parent;
  const double uf = wrap(f.s_parent - ref, parent_perimeter);
  auto at = kept.begin() + 1;
  while (at != kept.end() && wrap(at->s_parent - ref, parent_perimeter) < uf) ++at;
  if (!cyclic && at == kept.end()) return false;
  Anchor g = f;
  g.pinned = true;
  kept.insert(at, g);
  run = std::move(kept);
  return true;
}

// ---------------------------------------------------------------------------------------------
// The output mesh under construction.

struct Builder {
  const Surface* surface;
  std::vector<Vector3d> V;
  std::vector<int> level, loop;
  std::vector<int> hint;      // per vertex: an input face holding it (or near it), to walk from
  std::vector<double> param;  // per vertex: its arc length along its loop (-1 off loops)
  std::vector<std::array<int, 3>> faces;
  std::vector<std::pair<int, int>> printing;  // printing and boundary edges (a < b)

  int add_vertex(const Vector3d& p, int lvl, int lp, int face) {
    V.push_back(p);
    hint.push_back(face);
    param.push_back(-1.0);
    level.push_back(lvl);
    loop.push_back(lp);
    return static_cast<int>(V.size()) - 1;
  }
  void add_printing(int a, int b) { printing.push_back({std::min(a, b), std::max(a, b)}); }
  double orient(int a, int b, int c) const {
    const Vector2d pa = V[a].head<2>(), pb = V[b].head<2>(), pc = V[c].head<2>();
    return cross2(pb - pa, pc - pa);
  }
  void add_face(int a, int b, int c) { faces.push_back({a, b, c}); }
};

// A triangle counter-clockwise seen from above, and not a sliver (sine of its angle at a > 1e-9).
bool proper(const Builder& b, int a, int c, int d) {
  const Vector2d pa = b.V[a].head<2>(), pc = b.V[c].head<2>(), pd = b.V[d].head<2>();
  return cross2(pc - pa, pd - pa) > 1e-9 * (pc - pa).norm() * (pd - pa).norm();
}

// Zips a strip (paper §6.1 "Triangulation"; notes §2 step 4): the lower chain runs along one
// level, the upper along the next, both in the same direction, the strip on the left of the lower
// chain; each triangle takes one edge of a chain as its base and its apex on the other. The
// paper's rule is greedy: take the shorter diagonal. Where that would flip a triangle (a strip
// bent around a saddle or a coarse corner), the zip of least total diagonal length among those
// without a flipped triangle is taken instead (dynamic programming over the two chains). Returns
// false when there is none.
bool zip(const Builder& b, const std::vector<int>& lower, const std::vector<int>& upper,
         std::vector<std::array<int, 3>>& faces) {
  faces.clear();
  const int nl = static_cast<int>(lower.size()) - 1, nu = static_cast<int>(upper.size()) - 1;
  const auto diagonal = [&](int i, int j) { return (b.V[lower[i]] - b.V[upper[j]]).norm(); };
  bool greedy_ok = true;
  for (int i = 0, j = 0; i < nl || j < nu;) {
    const bool advance_lower = j == nu || (i < nl && diagonal(i + 1, j) <= diagonal(i, j + 1));
    if (advance_lower) {
      greedy_ok = greedy_ok && proper(b, lower[i], lower[i + 1], upper[j]);
      faces.push_back({lower[i], lower[i + 1], upper[j]});
      ++i;
    } else {
      greedy_ok = greedy_ok && proper(b, lower[i], upper[j + 1], upper[j]);
      faces.push_back({lower[i], upper[j + 1], upper[j]});
      ++j;
    }
  }
  if (greedy_ok) return true;
  faces.clear();
  // cost[i][j]: the least length of diagonals of a proper zip from (0, 0) to (i, j).
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> cost((nl + 1) * (nu + 1), inf);
  std::vector<char> from((nl + 1) * (nu + 1), 0);
  const auto at = [&](int i, int j) { return i * (nu + 1) + j; };
  cost[0] = 0.0;
  for (int i = 0; i <= nl; ++i) {
    for (int j = 0; j <= nu; ++j) {
      if (cost[at(i, j)] == inf) continue;
      if (i < nl && proper(b, lower[i], lower[i + 1], upper[j])) {
        const double c = cost[at(i, j)] + diagonal(i + 1, j);
        if (c < cost[at(i + 1, j)]) cost[at(i + 1, j)] = c, from[at(i + 1, j)] = 'l';
      }
      if (j < nu && proper(b, lower[i], upper[j + 1], upper[j])) {
        const double c = cost[at(i, j)] + diagonal(i, j + 1);
        if (c < cost[at(i, j + 1)]) cost[at(i, j + 1)] = c, from[at(i, j + 1)] = 'u';
      }
    }
  }
  if (cost[at(nl, nu)] == inf) return false;
  for (int i = nl, j = nu; i > 0 || j > 0;) {
    if (from[at(i, j)] == 'l') {
      --i;
      faces.push_back({lower[i], lower[i + 1], upper[j]});
    } else {
      --j;
      faces.push_back({lower[i], upper[j + 1], upper[j]});
    }
  }
  std::reverse(faces.begin(), faces.end());
  return true;
}

// The vertices of a loop from position `from` to `to` (inclusive), counter-clockwise; all the way
// round when they are equal and `full`.
std::vector<int> arc(const Loop& loop, int from, int to, bool full) {
  const int n = static_cast<int>(loop.vertices.size());
  int count = (to - from + n) % n;
  if (count == 0 && full) count = n;
  std::vector<int> out;
  for (int i = 0; i <= count; ++i) out.push_back(loop.vertices[(from + i) % n]);
  return out;
}

// Locates p starting from face f (a face near it); -1 when p is off the surface.
int locate(const Surface& s, int f, const Vector2d& from, const Vector2d& p) {
  const Walk w = walk_segment(s, f, from, p, nullptr);
  return w.exited ? -1 : w.face;
}

// Whether every triangle of the fan from c over the polygon (counter-clockwise) is proper.
bool fans(const std::vector<Vector2d>& polygon, const Vector2d& c) {
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Vector2d p = polygon[k] - c, q = polygon[(k + 1) % polygon.size()] - c;
    if (!(cross2(p, q) > 1e-9 * p.norm() * q.norm())) return false;
  }
  return true;
}

// The centroid of the kernel of a counter-clockwise polygon (the points that see all of it: the
// intersection of the half-planes left of its edges), or nothing when it is (nearly) empty.
std::optional<Vector2d> kernel_centroid(const std::vector<Vector2d>& polygon) {
  Vector2d lo = polygon.front(), hi = polygon.front();
  for (const Vector2d& p : polygon) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  std::vector<Vector2d> kernel = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
  for (size_t k = 0; k < polygon.size() && !kernel.empty(); ++k) {
    const Vector2d a = polygon[k], d = polygon[(k + 1) % polygon.size()] - a;
    if (d.norm() == 0.0) continue;
    std::vector<Vector2d> clipped;
    for (size_t i = 0; i < kernel.size(); ++i) {
      const Vector2d& p = kernel[i];
      const Vector2d& q = kernel[(i + 1) % kernel.size()];
      const double sp = cross2(d, p - a), sq = cross2(d, q - a);
      if (sp >= 0.0) clipped.push_back(p);
      if ((sp >= 0.0) != (sq >= 0.0)) clipped.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    kernel = std::move(clipped);
  }
  if (kernel.size() < 3) return std::nullopt;
  double area = 0.0;
  Vector2d centroid = Vector2d::Zero();
  for (size_t i = 0; i < kernel.size(); ++i) {
    const double w = cross2(kernel[i], kernel[(i + 1) % kernel.size()]);
    area += w;
    centroid += w * (kernel[i] + kernel[(i + 1) % kernel.size()]);
  }
  if (!(area > 0.0)) return std::nullopt;
  return Vector2d(centroid / (3.0 * area));
}

bool inside(const std::vector<Vector2d>& polygon, const Vector2d& p) {
  bool in = false;
  for (size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vector2d& a = polygon[i];
    const Vector2d& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      in = !in;
    }
  }
  return in;
}

// The point of the surface above p, found by walking from vertex `from` of the mesh; its face.
Vector3d on_surface(const Builder& b, int from, const Vector2d& p, int& face) {
  const Surface& s = *b.surface;
  face = locate(s, b.hint[from], b.V[from].head<2>(), p);
  if (face < 0) {
    throw std::logic_error("isoline_mesh: a vertex falls off the surface at " + at_xy(p));
  }
  return Vector3d(p.x(), p.y(), height_in_face(s, face, p));
}

// ---------------------------------------------------------------------------------------------
// The stages of isoline_mesh, in order.

// Refuses options that are negative or not finite (l_u must also be positive).
void check_isoline_mesh_options(const IsolineMeshOptions& options, const std::string& source) {
  for (const auto& [name, value, zero_ok] :
       {std::tuple<const char*, double, bool>{"level spacing", options.level_spacing_mm, true},
        {"upsample length", options.upsample_length_mm, false},
        {"gradient spacing", options.gradient_spacing_mm, true}}) {
    if (!std::isfinite(value) || value < 0.0 || (!zero_ok && value == 0.0)) {
      throw UserError(
          ErrorCategory::kOption,
          fmt::format("{}: the {} must be a {} number of millimetres, not {}", source, name,
                      zero_ok ? "non-negative (0: automatic)" : "positive", value));
    }
  }
}

// The field with its faces turned counter-clockwise seen from +z, when they turn the other way
// (nothing when they already turn that way).
std::optional<HeightField> counter_clockwise_field(const HeightField& field) {
  double area2 = 0.0;
  for (int f = 0; f < field.F.rows(); ++f) {
    const Eigen::Vector2d a = field.V.row(field.F(f, 0)).head<2>();
    area2 += cross2(Vector2d(field.V.row(field.F(f, 1)).head<2>()) - a,
                    Vector2d(field.V.row(field.F(f, 2)).head<2>()) - a);
  }
  if (!(area2 < 0.0)) return std::nullopt;
  HeightField turned;
  turned.V = field.V;
  turned.F = field.F;
  turned.F.col(1).swap(turned.F.col(2));
  return turned;
}

// The heights and lengths the meshing works at, from the field's level boundary and the options.
struct IsolineScales {
  double z_boundary = 0.0;   // the boundary's level: its mean height
  double z_high = 0.0;       // the boundary's highest point
  double z_top = 0.0;        // the field's highest point
  double tolerance = 0.0;    // how far the boundary may stray from level
  double spacing = 0.0;      // Δ, between equidistant levels
  double l_u = 0.0;          // the longest printing edge
  double gap_spacing = 0.0;  // between the gradient lines' starts along a loop
};

// The boundary must be one isoline, the lowest (paper §6.1: loop 0); the surface must rise above
// it; the spacing must not make too many levels.
IsolineScales isoline_scales(const Surface& s, const IsolineMeshOptions& options,
                             const std::string& source) {
  double z_low = std::numeric_limits<double>::infinity(), z_high = -z_low, z_mean = 0.0;
  int highest = s.boundary.front();
  for (int v : s.boundary) {
    z_low = std::min(z_low, s.z[v]);
    if (s.z[v] > z_high) z_high = s.z[v], highest = v;
    z_mean += s.z[v];
  }
  z_mean /= static_cast<double>(s.boundary.size());
  const double z_top = s.z.maxCoeff();
  const double tolerance =
      std::max(kBoundaryLevelTolerance * (z_top - z_low), kBoundaryLevelToleranceMinMm);
  if (z_high - z_low > tolerance) {
    throw UserError(
        ErrorCategory::kGeometry,
        fmt::format("{}: the boundary is not level: its height ranges from {:.3f} to {:.3f} mm "
                    "(highest at {}), more than the {:.3f} mm allowed; the method rises from a "
                    "level rim: lower the border to one height (for an image, paint its border "
                    "black)",
                    source, z_low, z_high, at_xy(s.xy[highest]), tolerance));
  }
  const double z_boundary = z_mean;
  const double height = z_top - z_boundary;
  if (height <= tolerance) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: the surface is flat (it rises {:.3f} mm above its boundary): "
                                "there is nothing to rise; give it some height",
                                source, std::max(height, 0.0)));
  }
  const double spacing =
      options.level_spacing_mm > 0.0 ? options.level_spacing_mm : height / kDefaultLevelsPerHeight;
  if (height / spacing > 10000.0) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: a level spacing of {} mm makes {:.0f} levels over {:.1f} mm; "
                                "choose at least {:.3f} mm",
                                source, spacing, height / spacing, height, height / 10000.0));
  }
  IsolineScales scales;
  scales.z_boundary = z_boundary;
  scales.z_high = z_high;
  scales.z_top = z_top;
  scales.tolerance = tolerance;
  scales.spacing = spacing;
  scales.l_u = options.upsample_length_mm;
  scales.gap_spacing = options.gradient_spacing_mm > 0.0 ? options.gradient_spacing_mm
                                                         : std::max(scales.l_u, 2.0 * spacing);
  return scales;
}

// Step 1, the levels: the boundary's, then the equidistant ones with the saddle and summit
// levels, from the critical points of the sweep from the top.
struct IsolineLevels {
  std::vector<int> order;       // the input vertices from the highest down
  CriticalPoints cp;            // saddles and peaks
  std::vector<double> heights;  // per level, ascending; heights[0] is the boundary's

  int num_levels() const { return static_cast<int>(heights.size()); }
};

IsolineLevels isoline_levels(const Surface& s, const IsolineScales& scales,
                             const IsolineMeshOptions& options) {
  const int nv = static_cast<int>(s.z.size());
  std::vector<bool> on_boundary(nv, false);
  for (int v : s.boundary) on_boundary[v] = true;
  IsolineLevels levels;
  levels.order = descending_order(s);
  levels.cp = critical_points(s, levels.order, on_boundary, scales.z_boundary + scales.tolerance);
  levels.heights = {scales.z_boundary};
  for (double level : choose_levels(s, levels.cp, scales.z_boundary, scales.z_high, scales.z_top,
                                    scales.spacing, options)) {
    levels.heights.push_back(level);
  }
  return levels;
}

// Step 2, the loops: loop 0 is the boundary, then the isolines level by level; per level, which
// loop crosses each face. Refuses a loop that runs the wrong way round (a pit) and isolines too
// long to upsample.
struct IsolineLoops {
  std::vector<Loop> loops;
  std::vector<LevelIndex> index;  // per level
};

IsolineLoops march_isoline_loops(const Surface& s, const std::vector<double>& heights, double l_u,
                                 const std::string& source) {
  const int num_levels = static_cast<int>(heights.size());
  IsolineLoops out;
  std::vector<Loop>& loops = out.loops;
  loops.resize(1);
  out.index.resize(num_levels);
  {
    Loop& boundary = loops[0];
    boundary.segment_face.assign(s.boundary.size(), -1);
    for (int v : s.boundary) boundary.points.push_back(s.xy[v]);
    // The boundary's segments are edges: the face on their inner side holds them.
    for (int e = 0; e < s.topo.num_edges(); ++e) {
      if (s.boundary_edge_segment[e] >= 0) {
        boundary.segment_face[s.boundary_edge_segment[e]] = s.topo.edge_faces(e, 0);
      }
    }
    finish_loop(boundary);
    out.index[0].loops = {0};
  }
  for (int d = 1; d < num_levels; ++d) march(s, heights[d], d, loops, out.index[d]);
  double total_length = 0.0;
  for (const Loop& loop : loops) {
    total_length += loop.perimeter();
    if (loop.level > 0 && signed_area(loop.points) <= 0.0) {
      throw UserError(ErrorCategory::kGeometry,
                      fmt::format("{}: a pit near {} at {:.3f} mm (a loop of the surface's "
                                  "isolines runs the wrong way); fill it",
                                  source, at_xy(loop.points[0]), heights[loop.level]));
    }
  }
  if (total_length / l_u > static_cast<double>(kMaxVertices)) {
    throw UserError(ErrorCategory::kResource,
                    fmt::format("{}: the isolines are {:.0f} mm long: at an upsample length of {} "
                                "mm the mesh would pass {} vertices; choose a larger one",
                                source, total_length, l_u, kMaxVertices));
  }
  return out;
}

// The loop tree: sweep from the top, and at each level find the superlevel component of each
// loop's inside (the loop above a loop one level down is its child). Sets each loop's parent,
// children and summit; refuses two loops bounding one region (a pit).
void build_loop_tree(IsolineLoops& isolines, const Surface& s, const IsolineLevels& levels,
                     const std::string& source) {
  std::vector<Loop>& loops = isolines.loops;
  const std::vector<LevelIndex>& index = isolines.index;
  const std::vector<int>& order = levels.order;
  const std::vector<double>& heights = levels.heights;
  const int num_levels = levels.num_levels();
  const int nv = static_cast<int>(s.z.size());
  UnionFind uf(nv);
  std::vector<bool> done(nv, false);
  int next = 0;
  for (int d = num_levels - 1; d >= 1; --d) {
    for (; next < nv && s.z[order[next]] > heights[d]; ++next) {
      const int v = order[next];
      done[v] = true;
      for (int u : s.neighbours[v]) {
        if (!done[u]) continue;
        int a = uf.find(u), b = uf.find(v);
        if (a == b) continue;
        if (s.z[uf.top[a]] < s.z[uf.top[b]] ||
            (s.z[uf.top[a]] == s.z[uf.top[b]] && uf.top[a] > uf.top[b])) {
          std::swap(a, b);
        }
        uf.parent[b] = a;
      }
    }
    std::map<int, int> loop_of_root;
    for (int id : index[d].loops) {
      const int root = uf.find(loops[id].upper_vertex);
      if (!loop_of_root.emplace(root, id).second) {
        throw UserError(ErrorCategory::kGeometry,
                        fmt::format("{}: a pit near {} (two isolines at {:.3f} mm bound one "
                                    "region); fill it",
                                    source, at_xy(loops[id].points[0]), heights[d]));
      }
      loops[id].summit = uf.top[root];
    }
    if (d + 1 < num_levels) {
      for (int id : index[d + 1].loops) {
        const auto it = loop_of_root.find(uf.find(loops[id].upper_vertex));
        if (it == loop_of_root.end()) {
          throw std::logic_error("isoline_mesh: an isoline has no parent one level below");
        }
        loops[id].parent = it->second;
      }
    }
  }
  if (num_levels > 1) {
    for (int id : index[1].loops) loops[id].parent = 0;
  }
  // The boundary's summit: the highest vertex of all.
  loops[0].summit = order.front();
  for (int id = 1; id < static_cast<int>(loops.size()); ++id) {
    loops[loops[id].parent].children.push_back(id);
  }
}

// The gradient-line tracer over the loops: steps a quarter of the finest length around (input
// edges, l_u, the gradient lines' spacing), at most four times the field's diagonal long.
GradientTracer make_gradient_tracer(const Surface& s, const HeightField& field,
                                    const IsolineLoops& isolines, const IsolineLevels& levels,
                                    const IsolineScales& scales) {
  double mean_edge = 0.0;
  for (int e = 0; e < s.topo.num_edges(); ++e) {
    mean_edge += (s.xy[s.topo.edges(e, 0)] - s.xy[s.topo.edges(e, 1)]).norm();
  }
  mean_edge /= std::max(1, s.topo.num_edges());
  GradientTracer tracer{&s, &isolines.loops, &isolines.index, &levels.heights, 0.0, 0, 1e-4};
  tracer.step = 0.25 * std::min({mean_edge, scales.l_u, scales.gap_spacing});
  const Eigen::Vector2d lo = field.V.leftCols(2).colwise().minCoeff();
  const Eigen::Vector2d hi = field.V.leftCols(2).colwise().maxCoeff();
  tracer.max_steps = static_cast<int>(4.0 * (hi - lo).norm() / tracer.step) + 16;
  return tracer;
}

// Where gradient lines start along a loop: evenly, about gap_spacing apart, at least 8.
std::vector<double> gradient_line_starts(const Loop& loop, double gap_spacing) {
  const int n = std::max(8, static_cast<int>(std::ceil(loop.perimeter() / gap_spacing)));
  std::vector<double> out;
  for (int i = 0; i < n; ++i) out.push_back(loop.perimeter() * i / n);
  return out;
}

// Adds the pinned anchors of `parent` (on saddles' descending separatrices) to the annulus' runs;
// each pinned anchor goes into the first run of its child that takes it.
void pin_separatrix_anchors(Annulus& annulus, const std::vector<Anchor>& pinned,
                            const std::vector<Loop>& loops, double local_gap) {
  const Loop& parent = loops[annulus.parent];
  if (annulus.cyclic) {
    for (const Anchor& f : pinned) {
      pin(annulus.anchors, f, parent.perimeter(), loops[f.child].perimeter(), local_gap, true);
    }
    annulus.runs = {{0, static_cast<int>(annulus.anchors.size()), parent.children[0]}};
    return;
  }
  if (pinned.empty()) return;
  std::vector<std::vector<Anchor>> runs;
  for (const AnchorRun& r : annulus.runs) {
    runs.emplace_back(annulus.anchors.begin() + r.begin, annulus.anchors.begin() + r.end);
  }
  for (const Anchor& f : pinned) {
    for (size_t r = 0; r < runs.size(); ++r) {
      if (annulus.runs[r].child == f.child &&
          pin(runs[r], f, parent.perimeter(), loops[f.child].perimeter(), local_gap, false)) {
        break;
      }
    }
  }
  annulus.anchors.clear();
  for (size_t r = 0; r < runs.size(); ++r) {
    annulus.runs[r].begin = static_cast<int>(annulus.anchors.size());
    annulus.anchors.insert(annulus.anchors.end(), runs[r].begin(), runs[r].end());
    annulus.runs[r].end = static_cast<int>(annulus.anchors.size());
  }
}

// Where the gradient lines switch children, a saddle's descending separatrix leaves the parent:
// follow it down to the boundary, one pinned anchor per strip it crosses (into `pinned`, per
// parent loop).
void follow_separatrices_down(const Annulus& annulus, const std::vector<Loop>& loops,
                              const GradientTracer& tracer,
                              std::vector<std::vector<Anchor>>& pinned) {
  const Loop& parent = loops[annulus.parent];
  for (size_t r = 0; !annulus.cyclic && r < annulus.runs.size(); ++r) {
    const Anchor& x = annulus.anchors[annulus.runs[r].end - 1];
    const Anchor& y = annulus.anchors[annulus.runs[(r + 1) % annulus.runs.size()].begin];
    const double per = parent.perimeter();
    Landing current{annulus.parent,
                    wrap(x.s_parent + 0.5 * wrap(y.s_parent - x.s_parent, per), per)};
    while (current.loop > 0) {
      const Loop& child = loops[current.loop];
      const Landing next = trace(tracer, child, current.s, child.level - 1);
      if (next.loop < 0 || next.loop != child.parent) break;
      Anchor f{next.s, current.loop, current.s};
      f.pinned = true;
      pinned[next.loop].push_back(f);
      current = next;
    }
  }
}

// Step 3, gradient lines between each loop and its children: the anchors of each annulus, traced
// from both loops, made monotone, refined at the saddles and pinned along the separatrices. From
// the top down, so that the separatrices found at a saddle reach the strips below.
std::vector<Annulus> anchor_annuli(const std::vector<Loop>& loops, const GradientTracer& tracer,
                                   const IsolineScales& scales) {
  const double gap = 0.5 * scales.gap_spacing;
  // Pinned anchors per parent loop: the descending separatrices of the saddles (see pin()).
  std::vector<std::vector<Anchor>> pinned(loops.size());
  std::vector<Annulus> annuli;
  std::vector<int> top_down(loops.size());
  std::iota(top_down.begin(), top_down.end(), 0);
  std::stable_sort(top_down.begin(), top_down.end(),
                   [&](int x, int y) { return loops[x].level > loops[y].level; });
  for (int id : top_down) {
    const Loop& parent = loops[id];
    if (parent.children.empty()) continue;
    Annulus annulus;
    annulus.parent = id;
    for (double sp : gradient_line_starts(parent, scales.gap_spacing)) {
      const Landing l = trace(tracer, parent, sp, parent.level + 1);
      if (l.loop >= 0 && loops[l.loop].parent == id) annulus.anchors.push_back({sp, l.loop, l.s});
    }
    for (int child : parent.children) {
      for (double sc : gradient_line_starts(loops[child], scales.gap_spacing)) {
        const Landing l = trace(tracer, loops[child], sc, parent.level);
        if (l.loop == id) annulus.anchors.push_back({l.s, child, sc});
      }
    }
    // Small loops keep at least a few strips.
    double local_gap = std::min(gap, parent.perimeter() / 8.0);
    for (int child : parent.children)
      local_gap = std::min(local_gap, loops[child].perimeter() / 8.0);
    organise_runs(annulus, loops, local_gap);
    refine_transitions(annulus, loops, tracer, local_gap, 0.5 * std::min(scales.l_u, local_gap));
    pin_separatrix_anchors(annulus, pinned[id], loops, local_gap);
    follow_separatrices_down(annulus, loops, tracer, pinned);
    annuli.push_back(std::move(annulus));
  }
  return annuli;
}

// A place on a loop that becomes a vertex: an input boundary vertex or one end of an anchor.
struct LoopMark {
  double s;
  bool fixed;      // an input boundary vertex: keep it where it is
  Anchor* anchor;  // or the anchor it places
  bool as_parent;
};
using LoopMarkGroup = std::pair<double, std::vector<LoopMark*>>;  // a vertex's arc length, marks

bool has_fixed_mark(const LoopMarkGroup& g) {
  return std::any_of(g.second.begin(), g.second.end(), [](const LoopMark* m) { return m->fixed; });
}

// Joins the groups (sorted along a loop of perimeter `per`) closer than `least` apart: first
// into the nearest input boundary vertex (which stays), then each into the one before it, whose
// place the joined vertex takes, so that the vertices kept are `least` apart (input boundary
// vertices closer than that to each other stay as they are).
void space_mark_groups(std::vector<LoopMarkGroup>& groups, double per, double least) {
  std::vector<int> fixed;
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    if (has_fixed_mark(groups[g])) fixed.push_back(g);
  }
  std::vector<LoopMarkGroup> kept;
  if (!fixed.empty()) {
    std::vector<int> into(groups.size(), -1);
    const int nf = static_cast<int>(fixed.size());
    for (int g = 0, next = 0; g < static_cast<int>(groups.size()); ++g) {
      while (next < nf && fixed[next] < g) ++next;
      if (next < nf && fixed[next] == g) continue;
      const int after = fixed[next % nf], before = fixed[(next + nf - 1) % nf];
      const double d_after = wrap(groups[after].first - groups[g].first, per);
      const double d_before = wrap(groups[g].first - groups[before].first, per);
      if (std::min(d_after, d_before) < least) into[g] = d_after < d_before ? after : before;
    }
    for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
      if (into[g] < 0) continue;
      for (LoopMark* mark : groups[g].second) groups[into[g]].second.push_back(mark);
    }
    for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
      if (into[g] < 0) kept.push_back(std::move(groups[g]));
    }
    groups = std::move(kept);
    kept.clear();
  }
  for (LoopMarkGroup& g : groups) {
    if (!kept.empty() && !has_fixed_mark(g) && !has_fixed_mark(kept.back()) &&
        g.first - kept.back().first < least) {
      for (LoopMark* mark : g.second) kept.back().second.push_back(mark);
    } else {
      kept.push_back(std::move(g));
    }
  }
  if (kept.size() > 1 && !has_fixed_mark(kept.front()) && !has_fixed_mark(kept.back()) &&
      kept.front().first + per - kept.back().first < least) {
    for (LoopMark* mark : kept.back().second) kept.front().second.push_back(mark);
    kept.pop_back();
  }
  groups = std::move(kept);
}

// The marks of one loop, sorted (input vertices first at equal arc length), in groups of marks
// closer than `merge`, each one vertex (at a fixed mark if it has one).
std::vector<LoopMarkGroup> group_loop_marks(std::vector<LoopMark>& m, double per, double merge) {
  for (LoopMark& mark : m) mark.s = wrap(mark.s, per);
  std::stable_sort(m.begin(), m.end(), [](const LoopMark& x, const LoopMark& y) {
    return x.s != y.s ? x.s < y.s : x.fixed > y.fixed;
  });
  if (m.empty()) m.push_back({0.0, false, nullptr, false});
  std::vector<LoopMarkGroup> groups;
  for (LoopMark& mark : m) {
    if (!groups.empty() && mark.s - groups.back().second.front()->s < merge &&
        !(mark.fixed && groups.back().second.front()->fixed)) {
      if (mark.fixed) groups.back().first = mark.s;
      groups.back().second.push_back(&mark);
    } else {
      groups.push_back({mark.s, {&mark}});
    }
  }
  if (groups.size() > 1 && groups.front().first + per - groups.back().first < merge &&
      !(groups.front().second.front()->fixed && groups.back().second.front()->fixed)) {
    if (groups.back().second.front()->fixed) groups.front().first = groups.back().first;
    for (LoopMark* mark : groups.back().second) groups.front().second.push_back(mark);
    groups.pop_back();
  }
  return groups;
}

// Per loop segment: the room to the next loops, about the height to the nearer neighbouring level
// over the slope there.
std::vector<std::vector<double>> room_to_next_loops(const std::vector<Loop>& loops,
                                                    const std::vector<double>& heights,
                                                    const Surface& s) {
  const int num_levels = static_cast<int>(heights.size());
  std::vector<std::vector<double>> room(loops.size());
  for (size_t id = 1; id < loops.size(); ++id) {
    const Loop& loop = loops[id];
    double gap_height = heights[loop.level] - heights[loop.level - 1];
    if (loop.level + 1 < num_levels) {
      gap_height = std::min(gap_height, heights[loop.level + 1] - heights[loop.level]);
    }
    for (int k = 0; k < loop.num_segments(); ++k) {
      room[id].push_back(gap_height / std::max(s.slope[loop.segment_face[k]], 1e-6));
    }
  }
  return room;
}

// The vertices of loop `id`, one per group and between them equal pieces no longer than l_u,
// halved where a chord would stray from the isoline by more than a quarter of the room to the
// next (it could cross it). Each anchor learns its vertex and position on the loop.
void place_vertices_on_loop(Builder& b, Loop& loop, int id, std::vector<LoopMarkGroup>& groups,
                            const std::vector<double>& room, double z, double l_u, double min_gap) {
  const double per = loop.perimeter();
  const auto vertex_at = [&](double sv) {
    const LoopPoint lp = point_at(loop, sv);
    const int v = b.add_vertex(Vector3d(lp.p.x(), lp.p.y(), z), loop.level, id,
                               loop.segment_face[lp.segment]);
    b.param[v] = wrap(sv, per);
    return v;
  };
  for (size_t g = 0; g < groups.size(); ++g) {
    const double s0 = groups[g].first;
    double s1 = groups[(g + 1) % groups.size()].first;
    if (s1 <= s0) s1 += per;
    const int position = static_cast<int>(loop.vertices.size());
    const int v = vertex_at(s0);
    loop.vertices.push_back(v);
    for (LoopMark* mark : groups[g].second) {
      if (!mark->anchor) continue;
      if (mark->as_parent) {
        mark->anchor->parent_vertex = v, mark->anchor->parent_position = position;
      } else {
        mark->anchor->child_vertex = v, mark->anchor->child_position = position;
      }
    }
    const int pieces = std::max(1, static_cast<int>(std::ceil((s1 - s0) / l_u - 1e-9)));
    std::vector<std::pair<double, double>> todo;
    for (int i = pieces - 1; i >= 0; --i) {
      todo.push_back({s0 + (s1 - s0) * i / pieces, s0 + (s1 - s0) * (i + 1) / pieces});
    }
    bool first = true;
    while (!todo.empty()) {
      const auto [sa, sb] = todo.back();
      todo.pop_back();
      double deviation = 0.0, least_room = 0.0;
      if (id > 0) chord_fit(loop, room, sa, sb, deviation, least_room);
      if (id > 0 && deviation > 0.25 * least_room && sb - sa >= 2.0 * min_gap) {
        const double mid = 0.5 * (sa + sb);
        todo.push_back({mid, sb});
        todo.push_back({sa, mid});
        continue;
      }
      if (!first) loop.vertices.push_back(vertex_at(sa));
      first = false;
    }
  }
}

// Step 4, the loops' vertices: the anchors (close ones merged), the boundary's own vertices, and
// enough between them that no printing edge is longer than l_u (§6.1 "Triangulation"). Starts
// the output mesh with them.
void place_loop_vertices(Builder& b, std::vector<Loop>& loops, std::vector<Annulus>& annuli,
                         const Surface& s, const std::vector<double>& heights,
                         const std::vector<double>& min_gap, const IsolineScales& scales) {
  std::vector<std::vector<LoopMark>> marks(loops.size());
  for (size_t k = 0; k < s.boundary.size(); ++k) {
    marks[0].push_back({loops[0].length[k], true, nullptr, false});
  }
  for (Annulus& annulus : annuli) {
    for (Anchor& a : annulus.anchors) {
      marks[annulus.parent].push_back({a.s_parent, false, &a, true});
      marks[a.child].push_back({a.s_child, false, &a, false});
    }
  }
  const double merge = 0.02 * std::min(scales.l_u, scales.gap_spacing);
  const std::vector<std::vector<double>> room = room_to_next_loops(loops, heights, s);
  for (int id = 0; id < static_cast<int>(loops.size()); ++id) {
    Loop& loop = loops[id];
    const double per = loop.perimeter();
    std::vector<LoopMarkGroup> groups = group_loop_marks(marks[id], per, merge);
    space_mark_groups(groups, per, min_gap[id]);
    place_vertices_on_loop(b, loop, id, groups, room[id], heights[loop.level], scales.l_u,
                           min_gap[id]);
  }
}

// A centre for a fan over `polygon` when the preferred one does not see all of it: its kernel's
// centroid, on the surface; the preferred one (and a flipped fan, caught at the end) when there is
// no kernel.
Vector3d fan_point(const Builder& b, const std::vector<int>& polygon,
                   const std::vector<Vector2d>& outline, const Vector3d& preferred) {
  const std::optional<Vector2d> k = kernel_centroid(outline);
  if (!k) return preferred;
  int face = -1;
  return on_surface(b, polygon.front(), *k, face);
}

// A saddle chain at `level` from vertex p to vertex q (both on loops; notes §2 step 2): straight,
// or bent at `via`; its inner vertices on the surface, no piece longer than l_u.
std::vector<int> make_saddle_chain(Builder& b, int p, int q, int level, const Vector2d* via,
                                   double l_u) {
  std::vector<int> chain = {p};
  std::vector<Vector2d> corners = {b.V[p].head<2>()};
  if (via) corners.push_back(*via);
  corners.push_back(b.V[q].head<2>());
  for (size_t c = 0; c + 1 < corners.size(); ++c) {
    const Vector2d from = corners[c], to = corners[c + 1];
    const Vector3d end = c + 2 == corners.size() ? b.V[q] : Vector3d::Zero();
    for (int pieces = std::max(1, static_cast<int>(std::ceil((to - from).norm() / l_u)));;
         ++pieces) {
      std::vector<Vector3d> points;
      std::vector<int> point_faces;
      for (int i = 1; i <= pieces; ++i) {
        if (i == pieces && c + 2 == corners.size()) break;
        int face = -1;
        points.push_back(
            on_surface(b, p, from + (to - from) * (static_cast<double>(i) / pieces), face));
        point_faces.push_back(face);
      }
      Vector3d last = b.V[chain.back()];
      double longest = 0.0;
      for (const Vector3d& point : points) {
        longest = std::max(longest, (point - last).norm());
        last = point;
      }
      if (c + 2 == corners.size()) longest = std::max(longest, (end - last).norm());
      if (longest <= l_u || pieces > 100000) {
        for (size_t i = 0; i < points.size(); ++i) {
          chain.push_back(b.add_vertex(points[i], level, -1, point_faces[i]));
        }
        break;
      }
    }
  }
  chain.push_back(q);
  return chain;
}

// Step 5's shared state: the mesh under construction and what its strips are zipped against.
struct StripZipping {
  Builder& b;
  const Surface& s;
  std::vector<Loop>& loops;
  std::vector<Annulus>& annuli;
  const std::vector<double>& heights;
  const CriticalPoints& cp;
  const GradientTracer& tracer;
  const std::vector<double>& min_gap;
  double l_u;
};

// One annulus while its strips are zipped: the anchors in order around the parent, a strip
// between each two consecutive ones. Where the two reach different children, the strip's upper
// side is a saddle chain between them.
struct AnnulusStrips {
  Annulus& annulus;
  std::vector<int> order;                 // into annulus.anchors
  std::vector<std::array<int, 3>> faces;  // of the strip zipped last
};

// Steps forward from position `from` to `to` around a loop of m vertices.
int steps_forward(int from, int to, int m) { return (to - from + m) % m; }

// The saddle a chain from p to q passes: a saddle vertex between the levels of `parent` and its
// children, the nearest to the chain's middle, if one is that close (nullptr if none).
const Saddle* saddle_near(const StripZipping& z, const Loop& parent, int p, int q) {
  const Builder& b = z.b;
  const Vector2d middle = 0.5 * (b.V[p] + b.V[q]).head<2>();
  const Saddle* best = nullptr;
  double best_distance = (b.V[p] - b.V[q]).head<2>().norm();
  for (const Saddle& saddle : z.cp.saddles) {
    if (saddle.z <= z.heights[parent.level] || saddle.z >= z.heights[parent.level + 1]) continue;
    const double d = (z.s.xy[saddle.vertex] - middle).norm();
    if (d < best_distance) best_distance = d, best = &saddle;
  }
  return best;
}

// Drops the vertices added from `mark` on: a saddle chain taken back.
void take_back_vertices(Builder& b, size_t mark) {
  b.V.resize(mark), b.level.resize(mark), b.loop.resize(mark), b.hint.resize(mark);
  b.param.resize(mark);
}

// Zips strip k (order[k] -> order[k + 1]) into st.faces; a saddle strip's chain is made, and kept
// when `commit` (into *chain_out), else taken back.
bool zip_strip(StripZipping& z, AnnulusStrips& st, int k, bool commit,
               std::vector<int>* chain_out) {
  Builder& b = z.b;
  const Loop& parent = z.loops[st.annulus.parent];
  const std::vector<Anchor>& a = st.annulus.anchors;
  const std::vector<int>& order = st.order;
  const int n = static_cast<int>(order.size());
  const Anchor& x = a[order[k]];
  const Anchor& y = a[order[(k + 1) % n]];
  const bool full = n == 1;
  const std::vector<int> lower = arc(parent, x.parent_position, y.parent_position, full);
  if (x.child == y.child) {
    return zip(b, lower, arc(z.loops[x.child], x.child_position, y.child_position, full), st.faces);
  }
  // The chain bends half-way from the saddle towards the parent: straight, it could cut
  // across the parent's pinched waist when the crest between the children rises slowly.
  const size_t mark = b.V.size();
  const Saddle* saddle = saddle_near(z, parent, x.child_vertex, y.child_vertex);
  std::vector<int> chain;
  bool ok = false;
  for (int straight = saddle ? 0 : 1; straight <= 1 && !ok; ++straight) {
    take_back_vertices(b, mark);
    Vector2d via = Vector2d::Zero();
    if (!straight) {
      const Vector2d foot = 0.5 * (b.V[x.parent_vertex] + b.V[y.parent_vertex]).head<2>();
      via = 0.5 * (z.s.xy[saddle->vertex] + foot);
    }
    chain = make_saddle_chain(b, x.child_vertex, y.child_vertex, parent.level + 1,
                              straight ? nullptr : &via, z.l_u);
    ok = zip(b, lower, chain, st.faces);
  }
  if (!commit) {
    take_back_vertices(b, mark);
  } else if (chain_out) {
    *chain_out = chain;
  }
  return ok;
}

// Anchors in the same run (reaching one child) as order[k], counted around.
int anchor_run_size(const AnnulusStrips& st, int k) {
  const std::vector<Anchor>& a = st.annulus.anchors;
  const std::vector<int>& order = st.order;
  const int n = static_cast<int>(order.size());
  int count = 1;
  for (int i = 1; i < n && a[order[(k + i) % n]].child == a[order[k]].child; ++i) ++count;
  for (int i = 1; i < n && a[order[(k - i + n) % n]].child == a[order[k]].child; ++i) ++count;
  return std::min(count, n);
}

// Where strip `failing` does not zip (its gradient lines, drawn straight, cut across a bent
// loop), one of its anchors slides up to three vertices along its loop (along the child only
// between two anchors on the same child) until both strips beside it zip. Marks them to check.
bool slide_anchor(StripZipping& z, AnnulusStrips& st, std::vector<char>& dirty, int failing) {
  const Loop& parent = z.loops[st.annulus.parent];
  std::vector<Anchor>& a = st.annulus.anchors;
  const std::vector<int>& order = st.order;
  const int n = static_cast<int>(order.size());
  bool fixed = false;
  for (int end = 1; end >= 0 && !fixed && n >= 3; --end) {
    const int k = (failing + end) % n;  // the anchor to move
    Anchor& x = a[order[k]];
    const Anchor& w = a[order[(k + n - 1) % n]];
    const Anchor& y = a[order[(k + 1) % n]];
    const Anchor saved = x;
    const int mp = static_cast<int>(parent.vertices.size());
    const Loop& child = z.loops[x.child];
    const int mc = static_cast<int>(child.vertices.size());
    for (int step = 1; step <= 3 && !fixed; ++step) {
      for (int side : {-1, 1}) {
        for (int along_child = 0; along_child <= 1 && !fixed; ++along_child) {
          x = saved;
          if (along_child) {
            // Only between two anchors on the same child.
            if (w.child != x.child || y.child != x.child) continue;
            const int c = (x.child_position + side * step + mc) % mc;
            if (steps_forward(w.child_position, c, mc) >
                    steps_forward(w.child_position, y.child_position, mc) ||
                c == w.child_position || c == y.child_position) {
              continue;
            }
            x.child_position = c;
            x.child_vertex = child.vertices[c];
          } else {
            const int p = (x.parent_position + side * step + mp) % mp;
            if (steps_forward(w.parent_position, p, mp) >
                steps_forward(w.parent_position, y.parent_position, mp)) {
              continue;
            }
            if ((p == w.parent_position && w.child == x.child &&
                 w.child_position == x.child_position) ||
                (p == y.parent_position && y.child == x.child &&
                 y.child_position == x.child_position)) {
              continue;
            }
            x.parent_position = p;
            x.parent_vertex = parent.vertices[p];
          }
          fixed = zip_strip(z, st, (k + n - 1) % n, false, nullptr) &&
                  zip_strip(z, st, k, false, nullptr);
        }
        if (fixed) break;
      }
    }
    if (!fixed) {
      x = saved;
    } else {
      dirty[(k + n - 1) % n] = dirty[k] = 1;
    }
  }
  return fixed;
}

// Splits strip `failing` (both ends on one child) by a new gradient line, down from the upper
// vertex farthest from the parent (the tip of a notch the strip cannot reach into otherwise), to
// a vertex of the parent (an existing one if close, else a new one between, which shifts every
// anchor's position past it, here and in the strips below this loop).
bool split_strip(StripZipping& z, AnnulusStrips& st, std::vector<char>& dirty, int failing) {
  Builder& b = z.b;
  Annulus& annulus = st.annulus;
  std::vector<Anchor>& a = annulus.anchors;
  std::vector<int>& order = st.order;
  const int n = static_cast<int>(order.size());
  if (!(a[order[failing]].child == a[order[(failing + 1) % n]].child && n >= 2)) return false;
  const Anchor x = a[order[failing]], y = a[order[(failing + 1) % n]];
  Loop& child = z.loops[x.child];
  Loop& upper_parent = z.loops[annulus.parent];
  const std::vector<int> upper = arc(child, x.child_position, y.child_position, false);
  const std::vector<int> lower = arc(upper_parent, x.parent_position, y.parent_position, false);
  std::vector<std::pair<double, int>> candidates;  // (-distance, vertex)
  for (size_t i = 1; i + 1 < upper.size(); ++i) {
    double distance = std::numeric_limits<double>::infinity();
    for (int l : lower) distance = std::min(distance, (b.V[upper[i]] - b.V[l]).norm());
    candidates.push_back({-distance, upper[i]});
  }
  std::sort(candidates.begin(), candidates.end());
  const double per = upper_parent.perimeter();
  const double from = b.param[x.parent_vertex];
  const double span =
      x.parent_vertex == y.parent_vertex ? 0.0 : wrap(b.param[y.parent_vertex] - from, per);
  bool split = false;
  for (size_t c = 0; c < std::min<size_t>(candidates.size(), 4) && !split; ++c) {
    const int u = candidates[c].second;
    const Landing l = trace(z.tracer, child, b.param[u], upper_parent.level);
    if (l.loop != annulus.parent) continue;
    const double along = wrap(l.s - from, per);
    if (!(along > 0.0 && along < span)) continue;
    // The parent's vertex there: an existing one if close, else a new one between.
    std::vector<int>& pv = upper_parent.vertices;
    const int mp = static_cast<int>(pv.size());
    int position = x.parent_position;
    while (wrap(b.param[pv[(position + 1) % mp]] - from, per) <= along &&
           (position + 1) % mp != y.parent_position) {
      position = (position + 1) % mp;
    }
    const int next = (position + 1) % mp;
    const double merge_eps = z.min_gap[annulus.parent];
    int vertex = -1;
    if (along - wrap(b.param[pv[position]] - from, per) < merge_eps) {
      vertex = pv[position];
    } else if (wrap(b.param[pv[next]] - from, per) - along < merge_eps) {
      vertex = pv[next];
      position = next;
    } else {
      const LoopPoint lp = point_at(upper_parent, l.s);
      vertex =
          b.add_vertex(Vector3d(lp.p.x(), lp.p.y(), z.heights[upper_parent.level]),
                       upper_parent.level, annulus.parent, upper_parent.segment_face[lp.segment]);
      b.param[vertex] = wrap(l.s, per);
      position = position + 1;
      pv.insert(pv.begin() + position, vertex);
      // Shift every anchor's position past it, here and in the strips below this loop.
      for (Annulus& other : z.annuli) {
        for (Anchor& o : other.anchors) {
          if (other.parent == annulus.parent && o.parent_position >= position) {
            ++o.parent_position;
          }
          if (o.child == annulus.parent && o.child_position >= position) ++o.child_position;
        }
      }
    }
    if (vertex == x.parent_vertex || vertex == y.parent_vertex) continue;
    Anchor na{l.s, x.child, b.param[u]};
    na.pinned = true;
    na.parent_vertex = vertex;
    na.parent_position = position;
    na.child_vertex = u;
    na.child_position = static_cast<int>(
        std::find(child.vertices.begin(), child.vertices.end(), u) - child.vertices.begin());
    a.push_back(na);
    order.insert(order.begin() + failing + 1, static_cast<int>(a.size()) - 1);
    dirty.insert(dirty.begin() + failing + 1, 1);
    dirty[failing] = 1;
    split = true;
  }
  return split;
}

// Drops strip `failing`'s later anchor, else its earlier one, merging two strips; a run keeps two
// anchors, the annulus three.
bool drop_anchor(AnnulusStrips& st, std::vector<char>& dirty, int failing) {
  std::vector<int>& order = st.order;
  const int n = static_cast<int>(order.size());
  for (int end = 1; end >= 0; --end) {
    const int k = (failing + end) % n;
    if (n > 3 && (st.annulus.cyclic || anchor_run_size(st, k) > 2)) {
      order.erase(order.begin() + k);
      dirty.erase(dirty.begin() + k);
      dirty[(k + n - 2) % (n - 1)] = 1;  // the merged strip
      return true;
    }
  }
  return false;
}

// Makes every strip of the annulus zip (paper §6.1 "Triangulation"; notes §2 step 4): a strip
// that does not has an anchor slid, or is split by a new gradient line, or merged with the next.
void make_strips_zip(StripZipping& z, AnnulusStrips& st) {
  const std::vector<Anchor>& a = st.annulus.anchors;
  std::vector<char> dirty(st.order.size(), 1);  // strips to check
  const int work_limit = 8 * static_cast<int>(a.size()) + 20;
  for (int work = 0;; ++work) {
    const int n = static_cast<int>(st.order.size());
    const int failing = [&] {
      for (int k = 0; k < n; ++k) {
        if (!dirty[k]) continue;
        dirty[k] = 0;
        if (!zip_strip(z, st, k, false, nullptr)) return k;
      }
      return -1;
    }();
    if (failing < 0) break;
    if (work > work_limit) {
      throw std::logic_error(
          fmt::format("isoline_mesh: the strip above the loop at {} cannot be zipped",
                      at_xy(z.b.V[a[st.order[failing]].parent_vertex].head<2>())));
    }
    if (slide_anchor(z, st, dirty, failing)) continue;
    if (split_strip(z, st, dirty, failing)) continue;
    if (!drop_anchor(st, dirty, failing)) {
      throw std::logic_error(
          fmt::format("isoline_mesh: the strip above the loop at {} cannot be zipped",
                      at_xy(z.b.V[a[st.order[failing]].parent_vertex].head<2>())));
    }
  }
}

// Emits the strips, making the saddle chains (printing edges); returns per strip k the saddle
// chain after anchor k, if any.
std::vector<std::vector<int>> emit_strips(StripZipping& z, AnnulusStrips& st) {
  const int n = static_cast<int>(st.order.size());
  std::vector<std::vector<int>> chain_after(n);
  for (int k = 0; k < n; ++k) {
    zip_strip(z, st, k, true, &chain_after[k]);
    for (const auto& f : st.faces) z.b.add_face(f[0], f[1], f[2]);
    const std::vector<int>& chain = chain_after[k];
    for (size_t i = 0; i + 1 < chain.size(); ++i) z.b.add_printing(chain[i], chain[i + 1]);
  }
  return chain_after;
}

// The saddle polygon from chain k0 (notes §2 step 6): from each chain's end, back along its child
// (clockwise: the side the strips leave free) to the end of a run, then that run's chain, until
// closed. Marks the chains it takes as used.
std::vector<int> saddle_polygon(const StripZipping& z, const AnnulusStrips& st,
                                const std::vector<std::vector<int>>& chain_after,
                                std::vector<bool>& used, int k0) {
  const std::vector<Anchor>& a = st.annulus.anchors;
  const std::vector<int>& order = st.order;
  const int n = static_cast<int>(order.size());
  std::vector<int> polygon;
  for (int k = k0; !used[k];) {
    used[k] = true;
    const std::vector<int>& chain = chain_after[k];
    polygon.insert(polygon.end(), chain.begin(), chain.end() - 1);
    const Anchor& start_anchor = a[order[(k + 1) % n]];
    const Loop& child = z.loops[start_anchor.child];
    const int m = static_cast<int>(child.vertices.size());
    const int start = start_anchor.child_position;
    // The run end on this child that comes first going clockwise from `start` (all the way
    // round if that is the end of the run starting here, on one vertex).
    int own_end = (k + 1) % n;
    while (chain_after[own_end].empty()) own_end = (own_end + 1) % n;
    int best = -1, best_distance = m + 1;
    for (int q = 0; q < n; ++q) {
      if (chain_after[q].empty() || a[order[q]].child != start_anchor.child) continue;
      int distance = steps_forward(a[order[q]].child_position, start, m);
      if (distance == 0 && q == own_end) distance = m;
      if (distance < best_distance) best_distance = distance, best = q;
    }
    if (best < 0) throw std::logic_error("isoline_mesh: a saddle polygon does not close");
    for (int i = 0; i < best_distance; ++i) {
      polygon.push_back(child.vertices[(start - i + m) % m]);
    }
    k = best;
  }
  return polygon;
}

// Fans the saddle polygon from its centre: the saddle inside it (its true position) that sees all
// of it, else a point that does (its kernel's centroid) on the surface, else the centroid.
void fan_saddle_polygon(StripZipping& z, const std::vector<int>& polygon, int parent_level) {
  Builder& b = z.b;
  std::vector<Vector2d> outline;
  for (int v : polygon) outline.push_back(b.V[v].head<2>());
  std::vector<Vector3d> candidates;
  for (auto it = z.cp.saddles.rbegin(); it != z.cp.saddles.rend(); ++it) {
    if (it->z > z.heights[parent_level] && it->z < z.heights[parent_level + 1] &&
        inside(outline, z.s.xy[it->vertex])) {
      candidates.push_back(Vector3d(z.s.xy[it->vertex].x(), z.s.xy[it->vertex].y(), it->z));
    }
  }
  const auto sees = std::find_if(candidates.begin(), candidates.end(),
                                 [&](const Vector3d& c) { return fans(outline, c.head<2>()); });
  Vector3d centre;
  if (sees != candidates.end()) {
    centre = *sees;
  } else if (!candidates.empty()) {
    centre = fan_point(b, polygon, outline, candidates.front());
  } else {
    int face = -1;
    const Vector2d mean = std::accumulate(outline.begin(), outline.end(), Vector2d(0, 0)) /
                          static_cast<double>(outline.size());
    centre = fan_point(b, polygon, outline, on_surface(b, polygon.front(), mean, face));
  }
  const int c = b.add_vertex(centre, -1, -1, -1);
  for (size_t k = 0; k < polygon.size(); ++k) {
    b.add_face(c, polygon[k], polygon[(k + 1) % polygon.size()]);
  }
}

// Step 5 on one annulus: its strips zipped, its saddle chains and its saddle polygons fanned.
void mesh_annulus(StripZipping& z, Annulus& annulus) {
  AnnulusStrips st{annulus, std::vector<int>(annulus.anchors.size()), {}};
  std::iota(st.order.begin(), st.order.end(), 0);
  make_strips_zip(z, st);
  const std::vector<std::vector<int>> chain_after = emit_strips(z, st);
  if (annulus.cyclic) return;
  const int n = static_cast<int>(st.order.size());
  std::vector<bool> used(n, false);
  for (int k0 = 0; k0 < n; ++k0) {
    if (chain_after[k0].empty() || used[k0]) continue;
    const std::vector<int> polygon = saddle_polygon(z, st, chain_after, used, k0);
    fan_saddle_polygon(z, polygon, z.loops[annulus.parent].level);
  }
}

// Caps (notes §2 step 5), fanned from the summit's true highest point rather than the loop's
// centroid, which would cut the summit flat.
void cap_summits(Builder& b, const std::vector<Loop>& loops, const Surface& s) {
  for (const Loop& loop : loops) {
    if (!loop.children.empty()) continue;
    const Vector2d top = s.xy[loop.summit];
    Vector3d centre(top.x(), top.y(), s.z[loop.summit]);
    std::vector<Vector2d> outline;
    for (int v : loop.vertices) outline.push_back(b.V[v].head<2>());
    // A top loop the summit does not see all of (a bent crest): the fan moves off the summit.
    if (!fans(outline, top)) centre = fan_point(b, loop.vertices, outline, centre);
    const int c = b.add_vertex(centre, -1, -1, -1);
    const int n = static_cast<int>(loop.vertices.size());
    for (int i = 0; i < n; ++i) b.add_face(c, loop.vertices[i], loop.vertices[(i + 1) % n]);
  }
}

// Step 6, the mesh: the loops' edges are printing edges (the boundary's boundary edges), every
// other edge a bridge; every face must turn counter-clockwise seen from above.
IsolineMesh assemble_isoline_mesh(Builder& b, const std::vector<Loop>& loops,
                                  const std::vector<double>& heights, const std::string& source) {
  for (const Loop& loop : loops) {
    const int n = static_cast<int>(loop.vertices.size());
    for (int i = 0; i < n; ++i) b.add_printing(loop.vertices[i], loop.vertices[(i + 1) % n]);
  }
  IsolineMesh mesh;
  const int nvo = static_cast<int>(b.V.size());
  mesh.V.resize(nvo, 3);
  mesh.vertex_level.resize(nvo);
  mesh.vertex_loop.resize(nvo);
  for (int v = 0; v < nvo; ++v) {
    mesh.V.row(v) = b.V[v].transpose();
    mesh.vertex_level[v] = b.level[v];
    mesh.vertex_loop[v] = b.loop[v];
  }
  mesh.F.resize(static_cast<int>(b.faces.size()), 3);
  for (int f = 0; f < mesh.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) mesh.F(f, k) = b.faces[f][k];
    const double area2 = b.orient(b.faces[f][0], b.faces[f][1], b.faces[f][2]);
    if (!(area2 > 0.0)) {
      const Vector3d c = (b.V[b.faces[f][0]] + b.V[b.faces[f][1]] + b.V[b.faces[f][2]]) / 3.0;
      throw std::logic_error(fmt::format("isoline_mesh: {}: a face at {} is {} seen from above",
                                         source, at_xy(c.head<2>()),
                                         area2 == 0.0 ? "degenerate" : "flipped"));
    }
  }
  mesh.E = edge_topology(mesh.F).edges;
  std::sort(b.printing.begin(), b.printing.end());
  mesh.edge_kind.assign(mesh.E.rows(), EdgeKind::kBridge);
  for (int e = 0; e < mesh.E.rows(); ++e) {
    const std::pair<int, int> key(mesh.E(e, 0), mesh.E(e, 1));
    if (std::binary_search(b.printing.begin(), b.printing.end(), key)) {
      mesh.edge_kind[e] = b.loop[key.first] == 0 && b.loop[key.second] == 0 ? EdgeKind::kBoundary
                                                                            : EdgeKind::kPrinting;
    }
  }
  mesh.levels = Eigen::Map<const Eigen::VectorXd>(heights.data(), static_cast<int>(heights.size()));
  mesh.loops.resize(loops.size());
  for (size_t id = 0; id < loops.size(); ++id) {
    mesh.loops[id].level = loops[id].level;
    mesh.loops[id].parent = loops[id].parent;
    mesh.loops[id].vertices = loops[id].vertices;
  }
  return mesh;
}

}  // namespace

IsolineMesh isoline_mesh(const HeightField& field, const IsolineMeshOptions& options,
                         const std::string& source) {
  check_isoline_mesh_options(options, source);
  // Work on counter-clockwise faces (seen from +z), whichever way the field's faces turn.
  const std::optional<HeightField> turned = counter_clockwise_field(field);
  const Surface s = make_surface(turned ? *turned : field);
  const IsolineScales scales = isoline_scales(s, options, source);

  // 1. Levels; 2. loops and the loop tree.
  const IsolineLevels levels = isoline_levels(s, scales, options);
  IsolineLoops isolines = march_isoline_loops(s, levels.heights, scales.l_u, source);
  build_loop_tree(isolines, s, levels, source);
  std::vector<Loop>& loops = isolines.loops;

  // 3. Gradient lines between each loop and its children: anchors.
  const GradientTracer tracer = make_gradient_tracer(s, field, isolines, levels, scales);
  std::vector<Annulus> annuli = anchor_annuli(loops, tracer, scales);

  // 4. The loops' vertices. No two consecutive vertices of a loop closer than l_u / 4 (a
  // sixteenth of a small loop): a shorter printing edge is the base of a needle triangle, which
  // the sheet's simulation cannot settle. Anchors that close join one vertex (their gradient
  // lines move by at most that much).
  std::vector<double> min_gap(loops.size());
  for (size_t id = 0; id < loops.size(); ++id) {
    min_gap[id] = std::min(kMinEdgeFraction * scales.l_u, loops[id].perimeter() / kMinLoopPieces);
  }
  Builder b;
  b.surface = &s;
  place_loop_vertices(b, loops, annuli, s, levels.heights, min_gap, scales);

  // 5. Strips, saddle chains and polygons, caps.
  StripZipping zipping{b, s, loops, annuli, levels.heights, levels.cp, tracer, min_gap, scales.l_u};
  for (Annulus& annulus : annuli) mesh_annulus(zipping, annulus);
  cap_summits(b, loops, s);

  // 6. The mesh.
  return assemble_isoline_mesh(b, loops, levels.heights, source);
}

}  // namespace flatmorph
