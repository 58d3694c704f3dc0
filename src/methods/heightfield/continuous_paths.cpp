#include "methods/heightfield/continuous_paths.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "common/error.h"
#include "material/thickness_curve.h"

namespace flatmorph {
namespace {

// The band of row spacings (in path widths) within which the smoothing and the short-run filter
// may change a face's row count, and which the initial count is raised into.
constexpr double kSpacingLow = 0.5;
constexpr double kSpacingHigh = 1.5;
// Runs of faces with one row count shorter than this many path widths (along the strip's middle)
// take a neighbouring run's count: the paper's "remove short traces". The authors' code does it
// for runs of up to 3 faces (notes §5.1 item 6), a length that depends on the upsampling; a run of
// 10 g makes a double-back island at least ~5 mm long.
constexpr double kShortRunWidths = 10;
// The smoothing stops after this many passes even if a pair still differs (the authors' loop ran
// to its limit on a difference of exactly 2, notes §5.1 item 4; ours converges in practice).
constexpr int kMaxSmoothingPasses = 64;
// Points closer than this (mm) are one point: no zero-length segment is emitted.
constexpr double kSamePoint = 1e-9;

// A face of the printing graph as the row insertion sees it (SCF 2020 §6.3, Fig. 8a).
struct RowFace {
  int a = -1, b = -1, c = -1;    // base a -> b counter-clockwise, apex c
  int base = -1;                 // edge (a, b)
  int side_a = -1, side_b = -1;  // edges (a, c) and (b, c)
  bool up = true;       // the apex lies above the base (a patch centre counts as above its rim)
  bool patch = false;   // a fan face around a patch centre
  bool saddle = false;  // ... of a saddle polygon
  bool rows = false;    // gets rows: its base is printed and its sides are bridges
  double altitude = 0;  // mm, from the base to the apex in the plate
  double along = 0;     // mm, |ab| / 2: the length of the face's middle row
  int half = 0, half_min = 0, half_max = 0;  // k_f and the range keeping the spacing in band
  int hill = -1;                             // index into hill_loops, or -1
};

// How the rows of the (at most two) faces on a bridge edge meet there (§6.3, Fig. 8b-c).
struct EdgeRows {
  int first_node = -1;  // nodes first_node .. first_node + count - 1, from the lower end up
  int count = 0;        // M = (n1 + n2) / 2
  int big = -1;         // the face with more rows (its extra rows pair into corners)
  int paired = 0;       // min(n1, n2): rows continuing across the edge
  int below = 0;        // of them, those below the U-turns
  int corners = 0;      // U-turns: (n1 - n2) / 2
};

// The printing graph with its rows: nodes (mesh vertices first, then row nodes), printing edges
// (isolines, saddle chains, rows) and bridge links (along the mesh's bridge edges).
struct PrintGraph {
  std::vector<Eigen::Vector2d> position;
  std::vector<double> value;  // the "isoline value" of §6.3: level + fraction toward the next
  std::vector<double> sigma;
  std::vector<char> corner;  // a U-turn of a double-back
  struct Edge {
    int from = -1, to = -1;  // counter-clockwise: the higher side on the left
    double sigma = 0;
    int face = -1;  // the face it prints in (for the per-hill count)
    int phase = 0;  // 0: traced first; 1: saddle chains and saddle polygons, traced after
  };
  std::vector<Edge> edges;
  std::vector<std::vector<int>> incident;  // printing edges per node
  std::vector<std::vector<int>> up, down;  // bridge neighbours per node

  int add_node(const Eigen::Vector2d& p, double v, double s) {
    position.push_back(p);
    value.push_back(v);
    sigma.push_back(s);
    corner.push_back(0);
    incident.emplace_back();
    up.emplace_back();
    down.emplace_back();
    return static_cast<int>(position.size()) - 1;
  }
  void add_edge(int from, int to, double s, int face, int phase) {
    edges.push_back({from, to, s, face, phase});
    incident[from].push_back(static_cast<int>(edges.size()) - 1);
    incident[to].push_back(static_cast<int>(edges.size()) - 1);
  }
  double distance(int u, int v) const { return (position[u] - position[v]).norm(); }
};

std::string at(const Eigen::MatrixXd& plate, int v) {
  return fmt::format("({:.2f}, {:.2f}) mm", plate(v, 0), plate(v, 1));
}

// Per loop of the tree: the hill (index into `hill_loops`) whose summit is the only leaf above
// it, or -1 when two or more summits stand on it.
std::vector<int> loop_hills(const IsolineMesh& mesh, std::vector<int>& hill_loops) {
  const int num_loops = static_cast<int>(mesh.loops.size());
  std::vector<int> children(num_loops, 0);
  for (int l = 0; l < num_loops; ++l) {
    const int parent = mesh.loops[l].parent;
    if (parent >= num_loops || parent == l || (parent < 0 && l != 0))
      throw std::invalid_argument(
          fmt::format("continuous_paths: loop {} has parent {}", l, parent));
    if (parent >= 0) ++children[parent];
  }
  std::vector<int> leaves(num_loops, 0), hill(num_loops, -1);
  hill_loops.clear();
  for (int l = 0; l < num_loops; ++l) {
    if (children[l] != 0) continue;
    const int h = static_cast<int>(hill_loops.size());
    hill_loops.push_back(l);
    // Each leaf marks its ancestors; a loop reached from two leaves has no single hill.
    for (int x = l, steps = 0; x >= 0 && steps <= num_loops; x = mesh.loops[x].parent, ++steps) {
      ++leaves[x];
      hill[x] = h;
    }
  }
  for (int l = 0; l < num_loops; ++l)
    if (leaves[l] != 1) hill[l] = -1;
  return hill;
}

// Row counts (§6.3 "Printing edge upsampling", notes §5.1): along each strip (faces joined by
// shared bridge edges), smooth the half-counts, then drop short runs.
void smooth_row_counts(std::vector<RowFace>& faces, const std::vector<std::array<int, 2>>& next,
                       double width) {
  const int num_faces = static_cast<int>(faces.size());
  std::vector<char> seen(num_faces, 0);
  for (int f0 = 0; f0 < num_faces; ++f0) {
    if (!faces[f0].rows || seen[f0]) continue;
    // The strip through f0: its faces in order, from an end if it has one.
    std::vector<int> component;
    std::vector<int> stack = {f0};
    seen[f0] = 1;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      component.push_back(f);
      for (int g : next[f])
        if (g >= 0 && !seen[g]) seen[g] = 1, stack.push_back(g);
    }
    int start = *std::min_element(component.begin(), component.end());
    bool cyclic = true;
    for (int f : component) {
      if (next[f][0] < 0 || next[f][1] < 0) {
        if (cyclic || f < start) start = f;
        cyclic = false;
      }
    }
    std::vector<int> strip = {start};
    for (int prev = -1, cur = start;;) {
      const auto& n = next[cur];
      const int step = (n[1] >= 0 && n[1] != prev) ? n[1] : (n[0] != prev ? n[0] : -1);
      if (step < 0 || step == start) break;
      if (static_cast<int>(strip.size()) > num_faces) break;  // malformed adjacency
      prev = cur, cur = step;
      strip.push_back(cur);
    }
    const int m = static_cast<int>(strip.size());
    if (m < 2) continue;
    const int num_pairs = cyclic ? m : m - 1;

    // Half-count smoothing (notes §5.1 item 4). The authors adjust a pair when |p - q| > min(p, q)
    // and leave a difference of exactly 2 as it is (their loop then runs to its pass limit). Here
    // a pair differing by 2 or more moves toward each other by one each pass, each face only
    // within its spacing band: at most one double-back per edge where the geometry allows.
    for (int pass = 0; pass < kMaxSmoothingPasses; ++pass) {
      bool changed = false;
      for (int i = 0; i < num_pairs; ++i) {
        RowFace& p = faces[strip[i]];
        RowFace& q = faces[strip[(i + 1) % m]];
        if (std::abs(p.half - q.half) < 2) continue;
        RowFace& low = p.half < q.half ? p : q;
        RowFace& high = p.half < q.half ? q : p;
        if (low.half + 1 <= low.half_max) ++low.half, changed = true;
        if (high.half - 1 >= high.half_min) --high.half, changed = true;
      }
      if (!changed) break;
    }

    // Short-run filter (notes §5.1 item 6): a run of equal counts shorter than kShortRunWidths
    // path widths takes a neighbouring run's count (the one on both sides, else the closer count,
    // else the longer neighbour's), shortest run first, while the spacing stays in band.
    const double min_run = kShortRunWidths * width;
    for (int round = 0; round < m; ++round) {
      // Runs as [first, first + size) in strip order (cyclic: rotated so a run starts at 0).
      int offset = 0;
      if (cyclic) {
        while (offset < m && faces[strip[offset]].half == faces[strip[(offset + m - 1) % m]].half)
          ++offset;
        if (offset == m) break;  // one count all around
      }
      struct Run {
        int first, size, half;
        double length;
      };
      std::vector<Run> runs;
      for (int i = 0; i < m; ++i) {
        const RowFace& f = faces[strip[(offset + i) % m]];
        if (runs.empty() || runs.back().half != f.half) runs.push_back({i, 0, f.half, 0.0});
        ++runs.back().size;
        runs.back().length += f.along;
      }
      const int num_runs = static_cast<int>(runs.size());
      if (num_runs < 2) break;
      std::vector<int> order(num_runs);
      for (int r = 0; r < num_runs; ++r) order[r] = r;
      std::stable_sort(order.begin(), order.end(),
                       [&](int x, int y) { return runs[x].length < runs[y].length; });
      bool applied = false;
      for (int r : order) {
        const Run& run = runs[r];
        if (run.length >= min_run) break;
        std::vector<const Run*> around;
        if (r > 0 || cyclic) around.push_back(&runs[(r + num_runs - 1) % num_runs]);
        if (r + 1 < num_runs || cyclic) around.push_back(&runs[(r + 1) % num_runs]);
        std::vector<std::tuple<int, int, double, int>> candidates;  // (both sides, |dk|, -len, k)
        for (const Run* n : around) {
          const bool both = around.size() == 2 && around[0]->half == around[1]->half;
          candidates.emplace_back(both ? 0 : 1, std::abs(n->half - run.half), -n->length, n->half);
        }
        std::sort(candidates.begin(), candidates.end());
        for (const auto& candidate : candidates) {
          const int k = std::get<3>(candidate);
          bool fits = true;
          for (int i = 0; i < run.size && fits; ++i) {
            const RowFace& f = faces[strip[(offset + run.first + i) % m]];
            fits = k >= f.half_min && k <= f.half_max;
          }
          if (!fits) continue;
          for (int i = 0; i < run.size; ++i) faces[strip[(offset + run.first + i) % m]].half = k;
          applied = true;
          break;
        }
        if (applied) break;
      }
      if (!applied) break;
    }
  }
}

// The paper's tracing rules (§6.3 "Tool path tracing", Fig. 9) on the printing graph, read on
// edges: a vertex is "unvisited" while one of its printing edges is unprinted, so that every
// printing edge (isoline, saddle chain, row) is printed exactly once and each loop closes.
class PathRuleTracer {
 public:
  struct Step {
    int node;
    int edge;  // the printing edge that reached `node`; -1: a bridge; -2: the trace's start
  };

  explicit PathRuleTracer(const PrintGraph& graph)
      : g_(graph), used_(graph.edges.size(), 0), unused_(graph.position.size(), 0) {
    order_.resize(g_.position.size());
    for (size_t v = 0; v < order_.size(); ++v) order_[v] = static_cast<int>(v);
    std::stable_sort(order_.begin(), order_.end(),
                     [&](int x, int y) { return g_.value[x] < g_.value[y]; });
    distance_.assign(g_.position.size(), std::numeric_limits<double>::infinity());
    previous_.assign(g_.position.size(), -1);
  }

  // Traces the printing edges of `phase`.
  std::vector<std::vector<Step>> run(int phase) {
    std::fill(unused_.begin(), unused_.end(), 0);
    for (size_t e = 0; e < g_.edges.size(); ++e) {
      if (g_.edges[e].phase != phase) continue;
      ++unused_[g_.edges[e].from];
      ++unused_[g_.edges[e].to];
    }
    cursor_ = 0;
    phase_ = phase;
    std::vector<std::vector<Step>> traces;
    for (int start = next_start(); start >= 0; start = next_start()) {
      std::vector<Step> trace = {{start, -2}};
      int v = start;
      while (true) {
        int to = -1, edge = -1;
        if ((to = rule1(v)) >= 0) {
        } else if ((edge = rule2(v)) >= 0) {
          used_[edge] = 1;
          const PrintGraph::Edge& e = g_.edges[edge];
          --unused_[e.from];
          --unused_[e.to];
          to = e.from == v ? e.to : e.from;
        } else if ((to = rule3(v)) >= 0 || (to = rule4(v)) >= 0) {
        } else {
          const std::vector<int> climb = rule5(v);
          if (climb.empty()) break;
          for (int x : climb) trace.push_back({x, -1});
          v = climb.back();
          continue;
        }
        trace.push_back({to, edge});
        v = to;
      }
      traces.push_back(std::move(trace));
    }
    return traces;
  }

 private:
  // A new trace starts at the lowest node with an unprinted edge (the paper starts on the
  // boundary; the code at the lowest level, notes §5.3), preferring among equally low nodes one
  // with an odd number of unprinted edges (an end of an unprinted path: an Euler path must start
  // there), then the lowest index.
  int next_start() {
    while (cursor_ < order_.size() && unused_[order_[cursor_]] == 0) ++cursor_;
    if (cursor_ == order_.size()) return -1;
    const double lowest = g_.value[order_[cursor_]];
    int even = -1;
    for (size_t i = cursor_; i < order_.size() && g_.value[order_[i]] == lowest; ++i) {
      const int v = order_[i];
      if (unused_[v] == 0) continue;
      if (unused_[v] % 2 == 1) return v;
      if (even < 0) even = v;
    }
    return even;
  }

  // Rule 1: an unvisited corner (a double-back's U-turn) above v over a bridge: go up into it.
  // The rules then print the double-back's loop and come back down to v by rule 3: the bridge is
  // printed twice (the paper's edge doubling).
  int rule1(int v) const {
    int best = -1;
    for (int u : g_.up[v]) {
      if (!g_.corner[u] || unused_[u] == 0) continue;
      if (best < 0 || g_.distance(v, u) < g_.distance(v, best)) best = u;
    }
    return best;
  }

  // Rule 2: an unprinted printing edge at v. Left-first: the edge that leaves v counter-clockwise
  // (the higher side on its left: every loop and row is printed counter-clockwise seen from +z)
  // before one that leaves clockwise, then the lower far end, then the lower edge index.
  int rule2(int v) const {
    int best = -1;
    std::tuple<int, double, int> best_key;
    for (int e : g_.incident[v]) {
      if (used_[e] || g_.edges[e].phase != phase_) continue;
      const PrintGraph::Edge& edge = g_.edges[e];
      const int w = edge.from == v ? edge.to : edge.from;
      const std::tuple<int, double, int> key(edge.from == v ? 0 : 1, g_.value[w], e);
      if (best < 0 || key < best_key) best = e, best_key = key;
    }
    return best;
  }

  // Rule 3: an unvisited node below v over a bridge (the nearest).
  int rule3(int v) const { return nearest(v, g_.down[v]); }

  // Rule 4: v has no unprinted edge left or right: an unvisited node above over a bridge (the
  // nearest: the step up to the next row).
  int rule4(int v) const { return nearest(v, g_.up[v]); }

  int nearest(int v, const std::vector<int>& candidates) const {
    int best = -1;
    for (int u : candidates) {
      if (unused_[u] == 0) continue;
      if (best < 0 || g_.distance(v, u) < g_.distance(v, best)) best = u;
    }
    return best;
  }

  // Rule 5: climb through visited nodes above v until one has an unprinted edge; the path ends
  // when none is found. The climb goes at most up to the next isoline (v's level + 1): past it,
  // it would run over a printed hill (the paper's "until any above condition is met" has no
  // bound). The shortest such climb.
  std::vector<int> rule5(int v) {
    const double limit = std::floor(g_.value[v] + 1e-9) + 1 + 1e-9;
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    std::vector<int> touched = {v};
    distance_[v] = 0;
    queue.push({0.0, v});
    int found = -1;
    while (!queue.empty()) {
      const auto [d, x] = queue.top();
      queue.pop();
      if (d > distance_[x]) continue;
      if (x != v && unused_[x] > 0) {
        found = x;
        break;
      }
      for (int y : g_.up[x]) {
        if (g_.value[y] > limit) continue;
        const double dy = d + g_.distance(x, y);
        if (dy < distance_[y]) {
          if (std::isinf(distance_[y])) touched.push_back(y);
          distance_[y] = dy;
          previous_[y] = x;
          queue.push({dy, y});
        }
      }
    }
    std::vector<int> path;
    for (int x = found; x >= 0 && x != v; x = previous_[x]) path.push_back(x);
    std::reverse(path.begin(), path.end());
    for (int x : touched) distance_[x] = std::numeric_limits<double>::infinity(), previous_[x] = -1;
    return path;
  }

  const PrintGraph& g_;
  std::vector<char> used_;
  std::vector<int> unused_;
  std::vector<int> order_;
  size_t cursor_ = 0;
  int phase_ = 0;
  std::vector<double> distance_;
  std::vector<int> previous_;
};

// The flat printing graph the paths are made of: the mesh, its vertices in the plate (mm) and the
// σ each vertex prints.
struct ContinuousPathInput {
  const IsolineMesh& mesh;
  const Eigen::MatrixXd& plate;
  const Eigen::VectorXd& vertex_sigma;

  int level(int v) const { return mesh.vertex_level(v); }
  bool is_centre(int v) const { return mesh.vertex_level(v) < 0; }
  Eigen::Vector2d flat(int v) const { return Eigen::Vector2d(plate(v, 0), plate(v, 1)); }
  int num_vertices() const { return static_cast<int>(mesh.V.rows()); }
  int num_edges() const { return static_cast<int>(mesh.E.rows()); }
  int num_faces() const { return static_cast<int>(mesh.F.rows()); }
};

// Refuses options no print can have; returns the number of layers to stack.
int checked_num_layers(const ContinuousPathOptions& options, const ThicknessCurve& curve) {
  const double g = options.path_width;
  if (!(g > 0) || !std::isfinite(g)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("path width {} mm: give the extrusion width, a positive number of "
                                "millimetres (0.48 for a 0.5 mm nozzle)",
                                g));
  }
  const int num_layers = options.num_layers.value_or(curve.layers);
  if (num_layers < 1) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{} layers requested: print at least 1 layer", num_layers));
  }
  if (!(options.feed_rate >= 0) || !std::isfinite(options.feed_rate)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("feed rate {} mm/s: give 0 (the material's speed) or a positive "
                                "speed",
                                options.feed_rate));
  }
  return num_layers;
}

// The mesh, the plate and the shrink must agree in size, and the faces name vertices that exist:
// a broken contract of isoline_mesh.h or of the caller, not bad input.
void check_path_input(const ContinuousPathInput& in) {
  const IsolineMesh& mesh = in.mesh;
  const int num_vertices = in.num_vertices();
  if (in.plate.rows() != num_vertices || in.plate.cols() < 2 ||
      in.vertex_sigma.size() != num_vertices ||
      static_cast<int>(mesh.edge_kind.size()) != in.num_edges() ||
      mesh.vertex_level.size() != num_vertices || mesh.vertex_loop.size() != num_vertices ||
      mesh.loops.empty()) {
    throw std::invalid_argument(
        "continuous_paths: the sizes of the mesh, the plate and the shrinkage differ");
  }
  if (!in.plate.leftCols(2).allFinite())
    throw std::invalid_argument("continuous_paths: the plate has a coordinate that is not finite");
  for (int f = 0; f < in.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= num_vertices)
        throw std::invalid_argument(
            fmt::format("continuous_paths: face {} has vertex {}", f, mesh.F(f, k)));
}

// The mesh's edges by their ends.
struct MeshEdgesByVertex {
  std::vector<std::vector<std::pair<int, int>>> vertex_edges;  // per vertex: (other end, edge)

  int between(int a, int b) const {
    for (const auto& [other, e] : vertex_edges[a])
      if (other == b) return e;
    throw std::invalid_argument(
        fmt::format("continuous_paths: vertices {} and {} share a face but no edge", a, b));
  }
};

MeshEdgesByVertex mesh_edges_by_vertex(const ContinuousPathInput& in) {
  const int num_vertices = in.num_vertices();
  MeshEdgesByVertex edges;
  edges.vertex_edges.resize(num_vertices);
  for (int e = 0; e < in.num_edges(); ++e) {
    const int a = in.mesh.E(e, 0), b = in.mesh.E(e, 1);
    if (a < 0 || b < 0 || a >= num_vertices || b >= num_vertices || a == b)
      throw std::invalid_argument(fmt::format("continuous_paths: edge {} is ({}, {})", e, a, b));
    edges.vertex_edges[a].push_back({b, e});
    edges.vertex_edges[b].push_back({a, e});
  }
  return edges;
}

// Per vertex, 1 for the centre of a saddle polygon; a patch centre whose rim is one loop is a
// summit cap's (0). Counts the saddle polygons into out.num_saddle_patches.
std::vector<char> saddle_centres(const ContinuousPathInput& in, ContinuousPaths& out) {
  const IsolineMesh& mesh = in.mesh;
  const int num_vertices = in.num_vertices();
  std::vector<std::vector<int>> centre_faces(num_vertices);
  for (int f = 0; f < in.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (in.is_centre(mesh.F(f, k))) centre_faces[mesh.F(f, k)].push_back(f);
  std::vector<char> saddle_centre(num_vertices, 0);
  for (int v = 0; v < num_vertices; ++v) {
    if (!in.is_centre(v) || centre_faces[v].empty()) continue;
    int rim_loop = -2;
    bool one_loop = true;
    for (int f : centre_faces[v]) {
      for (int k = 0; k < 3; ++k) {
        const int w = mesh.F(f, k);
        if (w == v) continue;
        const int l = mesh.vertex_loop(w);
        if (rim_loop == -2) rim_loop = l;
        if (l < 0 || l != rim_loop) one_loop = false;
      }
    }
    saddle_centre[v] = one_loop ? 0 : 1;
    out.num_saddle_patches += saddle_centre[v];
  }
  return saddle_centre;
}

// Face f as the row insertion sees it: its base, apex and sides, its altitude in the plate, the
// rows it gets (n = 2⌊h / 2g⌋ within the spacing band) and the hill it belongs to.
RowFace row_face(const ContinuousPathInput& in, int f, const MeshEdgesByVertex& edges,
                 const std::vector<char>& saddle_centre, const std::vector<int>& loop_hill,
                 double g) {
  const IsolineMesh& mesh = in.mesh;
  const Eigen::MatrixXd& plate = in.plate;
  RowFace info;
  int centre_corner = -1, base_corner = -1, num_centres = 0, num_bases = 0;
  for (int k = 0; k < 3; ++k) {
    const int v = mesh.F(f, k);
    if (in.is_centre(v)) centre_corner = k, ++num_centres;
    if (in.level(mesh.F(f, (k + 1) % 3)) == in.level(mesh.F(f, (k + 2) % 3)))
      base_corner = k, ++num_bases;
  }
  if (num_centres > 1) {
    throw std::invalid_argument(fmt::format("continuous_paths: face {} at {} has {} patch centres",
                                            f, at(plate, mesh.F(f, 0)), num_centres));
  }
  const int apex_corner = num_centres == 1 ? centre_corner : base_corner;
  if (num_centres == 0 && num_bases != 1) {
    throw std::invalid_argument(
        fmt::format("continuous_paths: face {} at {} has {} edges within one level, not 1 (the "
                    "structure of isoline_mesh.h)",
                    f, at(plate, mesh.F(f, 0)), num_bases));
  }
  info.c = mesh.F(f, apex_corner);
  info.a = mesh.F(f, (apex_corner + 1) % 3);
  info.b = mesh.F(f, (apex_corner + 2) % 3);
  info.patch = num_centres == 1;
  info.saddle = info.patch && saddle_centre[info.c];
  if (!info.patch && std::abs(in.level(info.c) - in.level(info.a)) != 1) {
    throw std::invalid_argument(
        fmt::format("continuous_paths: face {} at {} has its apex {} levels from its base", f,
                    at(plate, info.c), in.level(info.c) - in.level(info.a)));
  }
  info.up = info.patch || in.level(info.c) > in.level(info.a);
  info.base = edges.between(info.a, info.b);
  info.side_a = edges.between(info.a, info.c);
  info.side_b = edges.between(info.b, info.c);
  const bool printed_base = mesh.edge_kind[info.base] != EdgeKind::kBridge;
  const bool bridge_sides = mesh.edge_kind[info.side_a] == EdgeKind::kBridge &&
                            mesh.edge_kind[info.side_b] == EdgeKind::kBridge;
  if (!info.patch && (!printed_base || !bridge_sides)) {
    throw std::invalid_argument(fmt::format(
        "continuous_paths: face {} at {}: its base must be a printing edge and its sides bridges",
        f, at(plate, info.a)));
  }
  info.rows = printed_base && bridge_sides;
  const Eigen::Vector2d ab = in.flat(info.b) - in.flat(info.a),
                        ac = in.flat(info.c) - in.flat(info.a);
  const double base_length = ab.norm();
  info.altitude = base_length > 0 ? std::abs(ab.x() * ac.y() - ab.y() * ac.x()) / base_length : 0;
  info.along = 0.5 * base_length;
  // Rows: n = 2 k, k = ⌊h / 2g⌋ (the paper's spacing twice the width, then doubled), within
  // the band: the spacing h / (2k + 1) of a face with h in [1.5 g, 2 g) would be up to 2 g with
  // no rows, leaving a gap, so such a face gets two rows (the only case the band changes).
  const double h = info.altitude;
  info.half_min = std::max(0, static_cast<int>(std::ceil((h / (kSpacingHigh * g) - 1) / 2)));
  info.half_max =
      std::max(info.half_min, static_cast<int>(std::floor((h / (kSpacingLow * g) - 1) / 2)));
  info.half = info.rows ? std::clamp(static_cast<int>(std::floor(h / (2 * g))), info.half_min,
                                     info.half_max)
                        : 0;
  // The hill: the loop below the face (a cap's rim), if one summit alone stands on it.
  int lower_loop = -1;
  if (info.patch) {
    lower_loop = info.saddle ? -1 : mesh.vertex_loop(info.a);
  } else if (info.up) {
    lower_loop =
        mesh.vertex_loop(info.a) >= 0 ? mesh.vertex_loop(info.a) : mesh.vertex_loop(info.b);
  } else {
    lower_loop = mesh.vertex_loop(info.c);
  }
  if (lower_loop >= static_cast<int>(mesh.loops.size()))
    throw std::invalid_argument(
        fmt::format("continuous_paths: loop {} does not exist", lower_loop));
  info.hill = lower_loop >= 0 ? loop_hill[lower_loop] : -1;
  return info;
}

// The strips: row faces joined across their shared bridge sides.
struct RowStrips {
  std::vector<std::vector<int>> edge_faces;  // per edge, the row faces with the edge as a side
  std::vector<std::array<int, 2>> next;      // per face, the faces across side_a and side_b
};

RowStrips row_strips(const std::vector<RowFace>& faces, int num_edges) {
  const int num_faces = static_cast<int>(faces.size());
  RowStrips strips;
  strips.edge_faces.resize(num_edges);
  for (int f = 0; f < num_faces; ++f) {
    if (!faces[f].rows) continue;
    for (int e : {faces[f].side_a, faces[f].side_b}) {
      strips.edge_faces[e].push_back(f);
      if (strips.edge_faces[e].size() > 2)
        throw std::invalid_argument(fmt::format("continuous_paths: edge {} is in 3 faces", e));
    }
  }
  strips.next.assign(num_faces, {-1, -1});
  for (int f = 0; f < num_faces; ++f) {
    if (!faces[f].rows) continue;
    const int sides[2] = {faces[f].side_a, faces[f].side_b};
    for (int s = 0; s < 2; ++s)
      for (int other : strips.edge_faces[sides[s]])
        if (other != f) strips.next[f][s] = other;
  }
  return strips;
}

// Bridge edges: merge the rows of the faces on both sides (Fig. 8b). The rows of the face with
// fewer continue across; the extra rows of the face with more pair up into U-turns whose two
// ends are one node (Fig. 8c: "move the two neighbouring nodes ... to the same location"), and
// all nodes are spaced evenly along the edge (Fig. 8c: "redistribute"). The authors pair index
// by index from the lower level, which puts the U-turns at the top (notes §5.2): every row above
// the first then shifts by up to (n1 - n2) / 2 spacings within the one face next to the edge,
// and the beads overlap there. Here the U-turns sit in the middle of the rows (half of the
// continuing rows below them, half above), halving the largest shift (on the built-in saddle at
// 100 mm: 0.46 % of the sheet under three beads or more instead of 1.25 %). Adds the nodes and the
// bridge links to `graph`; returns, per edge, how its rows meet.
std::vector<EdgeRows> add_bridge_rows(PrintGraph& graph, const ContinuousPathInput& in,
                                      const std::vector<RowFace>& faces, const RowStrips& strips,
                                      ContinuousPaths& out) {
  const IsolineMesh& mesh = in.mesh;
  std::vector<EdgeRows> edge_rows(in.num_edges());
  for (int e = 0; e < in.num_edges(); ++e) {
    if (mesh.edge_kind[e] != EdgeKind::kBridge) continue;
    int lo = mesh.E(e, 0), hi = mesh.E(e, 1);
    if (in.is_centre(lo) || (!in.is_centre(hi) && in.level(hi) < in.level(lo))) std::swap(lo, hi);
    if (in.is_centre(lo)) continue;  // between two centres: nothing to print
    EdgeRows& er = edge_rows[e];
    std::vector<int> chain = {lo};
    const std::vector<int>& fs = strips.edge_faces[e];
    if (!fs.empty()) {
      int n1 = 2 * faces[fs[0]].half, n2 = fs.size() > 1 ? 2 * faces[fs[1]].half : 0;
      er.big = fs[0];
      if (fs.size() > 1 && n2 > n1) std::swap(n1, n2), er.big = fs[1];
      er.paired = n2;
      er.corners = (n1 - n2) / 2;
      er.below = n2 / 2;
      er.count = n2 + er.corners;
      er.first_node = static_cast<int>(graph.position.size());
      out.num_double_backs += (n1 - n2) / 2;
      for (int i = 0; i < er.count; ++i) {
        const double s = double(i + 1) / (er.count + 1);
        const int node = graph.add_node((1 - s) * in.flat(lo) + s * in.flat(hi), in.level(lo) + s,
                                        (1 - s) * in.vertex_sigma(lo) + s * in.vertex_sigma(hi));
        graph.corner[node] = i >= er.below && i < er.below + er.corners;
        chain.push_back(node);
      }
    }
    if (!in.is_centre(hi) && in.level(hi) != in.level(lo)) chain.push_back(hi);
    for (size_t i = 0; i + 1 < chain.size(); ++i) {
      graph.up[chain[i]].push_back(chain[i + 1]);
      graph.down[chain[i + 1]].push_back(chain[i]);
    }
  }
  return edge_rows;
}

// Printing edges of the mesh (isolines, boundary, saddle chains), counter-clockwise: along the
// loop's order, else with the face where the edge is a base below its apex on the left.
void add_isoline_edges(PrintGraph& graph, const ContinuousPathInput& in,
                       const std::vector<RowFace>& faces) {
  const IsolineMesh& mesh = in.mesh;
  const int num_vertices = in.num_vertices();
  std::vector<std::vector<int>> edge_all_faces(in.num_edges());
  for (int f = 0; f < in.num_faces(); ++f) edge_all_faces[faces[f].base].push_back(f);
  std::vector<int> loop_position(num_vertices, -1);
  for (const IsolineLoop& loop : mesh.loops)
    for (size_t i = 0; i < loop.vertices.size(); ++i) {
      const int v = loop.vertices[i];
      if (v < 0 || v >= num_vertices)
        throw std::invalid_argument(fmt::format("continuous_paths: a loop has vertex {}", v));
      loop_position[v] = static_cast<int>(i);
    }
  for (int e = 0; e < in.num_edges(); ++e) {
    if (mesh.edge_kind[e] == EdgeKind::kBridge) continue;
    int a = mesh.E(e, 0), b = mesh.E(e, 1);
    if (in.is_centre(a) || in.is_centre(b)) continue;
    // The edge prints the mean of its ends, as a face prints the mean of its corners
    // (optimize_shrinkage.h).
    const double edge_sigma = 0.5 * (in.vertex_sigma(a) + in.vertex_sigma(b));
    if (!std::isfinite(edge_sigma)) {
      throw std::invalid_argument(
          fmt::format("continuous_paths: printing edge {} at {} has shrinkage {}", e,
                      at(in.plate, a), edge_sigma));
    }
    int face = -1;
    for (int f : edge_all_faces[e])
      if (face < 0 || (faces[f].up && !faces[face].up)) face = f;
    bool forward = face < 0 || (faces[face].a == a) == faces[face].up;  // a -> b
    bool on_loop = false;
    const int la = mesh.vertex_loop(a);
    if (la >= 0 && la == mesh.vertex_loop(b) && loop_position[a] >= 0 && loop_position[b] >= 0) {
      const int n = static_cast<int>(mesh.loops[la].vertices.size());
      if ((loop_position[a] + 1) % n == loop_position[b]) {
        forward = on_loop = true;
      } else if ((loop_position[b] + 1) % n == loop_position[a]) {
        forward = false;
        on_loop = true;
      }
    }
    if (!forward) std::swap(a, b);
    // Saddle chains (edges on no loop) are printed with their saddle polygon, after the loops
    // and strips, as the authors' code does (notes §5.3: the tracer follows loops only, the
    // saddle patches start with their chain nodes): a trace that closes a loop at a junction then
    // climbs its own hill instead of running off along the chain.
    graph.add_edge(a, b, edge_sigma, face, on_loop ? 0 : 1);
  }
}

// The node of row p (1 = lowest) of face f on its side e.
int row_node(const std::vector<EdgeRows>& edge_rows, int f, int e, int p) {
  const EdgeRows& er = edge_rows[e];
  if (p <= er.below) return er.first_node + p - 1;
  if (f != er.big) return er.first_node + er.corners + p - 1;
  if (p <= er.below + 2 * er.corners) return er.first_node + er.below + (p - er.below - 1) / 2;
  return er.first_node + p - er.corners - 1;
}

// Rows (Fig. 8a-b): row p of a face joins the p-th nodes of its two sides, counter-clockwise.
void add_rows(PrintGraph& graph, const std::vector<RowFace>& faces,
              const std::vector<EdgeRows>& edge_rows) {
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    const RowFace& info = faces[f];
    if (!info.rows) continue;
    for (int p = 1; p <= 2 * info.half; ++p) {
      int left = row_node(edge_rows, f, info.side_a, p),
          right = row_node(edge_rows, f, info.side_b, p);
      if (left == right) continue;
      if (!info.up) std::swap(left, right);
      // σ between the levels by the row's position (notes §5.4: the authors' counter bug took
      // the lower level's σ for every row).
      graph.add_edge(left, right, 0.5 * (graph.sigma[left] + graph.sigma[right]), f,
                     info.saddle ? 1 : 0);
    }
  }
}

// The printing graph with its rows: the mesh's vertices, the row nodes on the bridge edges, the
// printing edges and the bridge links.
PrintGraph print_graph(const ContinuousPathInput& in, const std::vector<RowFace>& faces,
                       const RowStrips& strips, ContinuousPaths& out) {
  PrintGraph graph;
  for (int v = 0; v < in.num_vertices(); ++v) {
    graph.add_node(in.flat(v), in.is_centre(v) ? 0.0 : in.level(v), in.vertex_sigma(v));
  }
  const std::vector<EdgeRows> edge_rows = add_bridge_rows(graph, in, faces, strips, out);
  add_isoline_edges(graph, in, faces);
  add_rows(graph, faces, edge_rows);
  return graph;
}

// Per hill, how many traces print in it.
void count_paths_per_hill(const std::vector<std::vector<PathRuleTracer::Step>>& traces,
                          const PrintGraph& graph, const std::vector<RowFace>& faces,
                          ContinuousPaths& out) {
  out.paths_per_hill.assign(out.hill_loops.size(), 0);
  for (const auto& trace : traces) {
    std::vector<char> in_hill(out.hill_loops.size(), 0);
    for (const PathRuleTracer::Step& step : trace) {
      if (step.edge < 0) continue;
      const int face = graph.edges[step.edge].face;
      if (face >= 0 && faces[face].hill >= 0) in_hill[faces[face].hill] = 1;
    }
    for (size_t h = 0; h < in_hill.size(); ++h) out.paths_per_hill[h] += in_hill[h];
  }
}

// A trace in the plane, σ and layer height per segment.
struct PlaneTrace {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> sigma;   // per segment
  std::vector<double> height;  // per segment, mm
};

// The traces in the plane, σ per segment (consecutive equal points dropped); sums the lengths
// printed and travelled into `out`.
std::vector<PlaneTrace> plane_traces(const std::vector<std::vector<PathRuleTracer::Step>>& traces,
                                     const PrintGraph& graph, ContinuousPaths& out) {
  std::vector<PlaneTrace> plane;
  for (const auto& trace : traces) {
    PlaneTrace t;
    t.points = {graph.position[trace[0].node]};
    for (size_t i = 1; i < trace.size(); ++i) {
      const PathRuleTracer::Step& step = trace[i];
      const Eigen::Vector2d& x = graph.position[step.node];
      if ((x - t.points.back()).norm() <= kSamePoint) continue;
      t.sigma.push_back(step.edge >= 0
                            ? graph.edges[step.edge].sigma
                            : 0.5 * (graph.sigma[trace[i - 1].node] + graph.sigma[step.node]));
      t.points.push_back(x);
    }
    if (t.points.size() < 2) continue;
    for (size_t i = 1; i < t.points.size(); ++i)
      out.path_length += (t.points[i] - t.points[i - 1]).norm();
    if (!plane.empty()) out.travel_length += (t.points.front() - plane.back().points.back()).norm();
    plane.push_back(std::move(t));
  }
  out.num_traces = static_cast<int>(plane.size());
  if (plane.empty()) {
    throw UserError(ErrorCategory::kGeometry,
                    "the printing graph has no printing edge to trace: give a height field with "
                    "at least one isoline");
  }
  return plane;
}

// Layer heights (§6.4: θ from σ on the thickness curve, clamped to its reachable range, as the
// simulated stack prints it).
void set_layer_heights(std::vector<PlaneTrace>& plane, const ThicknessCurve& curve,
                       ContinuousPaths& out) {
  out.min_layer_height = std::numeric_limits<double>::infinity();
  out.max_layer_height = 0;
  for (PlaneTrace& t : plane) {
    for (double s : t.sigma) {
      if (!std::isfinite(s))
        throw std::invalid_argument("continuous_paths: a segment's shrinkage is not finite");
      const PrintedShrinkage printed = printed_shrinkage(curve, s);
      if (printed.clamped != 0) ++out.clamped_segments;
      const double h = printed.layer_height;
      t.height.push_back(h);
      out.min_layer_height = std::min(out.min_layer_height, h);
      out.max_layer_height = std::max(out.max_layer_height, h);
    }
  }
}

// The stack: identical layers at z = k · h (§6.4). Between traces (and before the first) the
// nozzle travels at the layer's top, k · h_max: the layer's z varies, and a travel at the height
// of its two ends could drag through thicker beads between them (the G-code writer lifts only
// relative to the ends).
void stack_path_layers(const std::vector<PlaneTrace>& plane, int num_layers,
                       const ContinuousPathOptions& options, ContinuousPaths& out) {
  const double g = options.path_width;
  const double feed = options.feed_rate;
  for (int k = 1; k <= num_layers; ++k) {
    const double top = k * out.max_layer_height;
    std::vector<Eigen::Vector3d> points;
    std::vector<SegmentStyle> segments;
    auto add = [&](const Eigen::Vector2d& xy, double z, bool travel, double h) {
      const Eigen::Vector3d p(xy.x(), xy.y(), z);
      if (!points.empty() && (p - points.back()).norm() <= kSamePoint) return;
      if (!points.empty()) {
        SegmentStyle style;
        style.width = g;
        style.layer_height = h;
        style.feed_rate = feed;
        style.travel = travel;
        segments.push_back(style);
      }
      points.push_back(p);
    };
    for (const PlaneTrace& t : plane) {
      if (!points.empty()) add(points.back().head<2>(), top, true, t.height.front());
      add(t.points.front(), top, true, t.height.front());
      add(t.points.front(), k * t.height.front(), true, t.height.front());
      for (size_t i = 1; i < t.points.size(); ++i)
        add(t.points[i], k * t.height[i - 1], false, t.height[i - 1]);
    }
    ToolpathLayer layer;
    layer.height = out.max_layer_height;
    layer.z = top;
    PathPolyline path;
    path.type = PathType::kSolidInfill;
    path.points.resize(static_cast<Eigen::Index>(points.size()), 3);
    for (size_t i = 0; i < points.size(); ++i)
      path.points.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
    path.segments = std::move(segments);
    layer.paths.push_back(std::move(path));
    out.toolpath.layers.push_back(std::move(layer));
  }
}

}  // namespace

ContinuousPaths continuous_paths(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                 const Eigen::VectorXd& vertex_sigma, const Material& material,
                                 const ContinuousPathOptions& options) {
  const ThicknessCurve& curve = require_thickness_curve(material);
  const int num_layers = checked_num_layers(options, curve);
  const ContinuousPathInput in{mesh, plate, vertex_sigma};
  check_path_input(in);
  const MeshEdgesByVertex edges = mesh_edges_by_vertex(in);

  // Faces: base, apex, sides, altitude, rows, hill; patch centres are summit caps (the rim is one
  // loop) or saddle polygons.
  ContinuousPaths out;
  const std::vector<char> saddle_centre = saddle_centres(in, out);
  const std::vector<int> loop_hill = loop_hills(mesh, out.hill_loops);
  std::vector<RowFace> faces(in.num_faces());
  for (int f = 0; f < in.num_faces(); ++f) {
    faces[f] = row_face(in, f, edges, saddle_centre, loop_hill, options.path_width);
  }
  const RowStrips strips = row_strips(faces, in.num_edges());
  smooth_row_counts(faces, strips.next, options.path_width);
  const PrintGraph graph = print_graph(in, faces, strips, out);

  // Tracing: loops, strips and caps first, then saddle chains with their saddle polygons.
  PathRuleTracer tracer(graph);
  std::vector<std::vector<PathRuleTracer::Step>> traces = tracer.run(0);
  for (auto& trace : tracer.run(1)) traces.push_back(std::move(trace));
  count_paths_per_hill(traces, graph, faces, out);

  std::vector<PlaneTrace> plane = plane_traces(traces, graph, out);
  set_layer_heights(plane, curve, out);
  stack_path_layers(plane, num_layers, options, out);
  return out;
}

}  // namespace flatmorph
