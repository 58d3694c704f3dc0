#include "mesh/validate.h"

#include <fmt/core.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "mesh/topology.h"

namespace flatmorph {
namespace {

// Coordinates beyond this are taken as garbage (a unit mix-up or an uninitialized value).
constexpr double kAbsurdCoordinate = 1e12;
// A face is degenerate when its area is below this fraction of the squared bounding-box diagonal:
// far below any real triangle (a million-face mesh has faces of ~1e-6 diag^2) but above round-off.
constexpr double kZeroAreaRelative = 1e-14;

bool is_sane(const Eigen::MatrixXd& V, int v) {
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(V(v, c)) || std::abs(V(v, c)) > kAbsurdCoordinate) return false;
  }
  return true;
}

// Bounding-box diagonal over the vertices with sane coordinates, so that one NaN or a stray 1e300
// does not make every face look degenerate or every vertex coincident.
double sane_diagonal(const Eigen::MatrixXd& V) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  bool any = false;
  for (int v = 0; v < V.rows(); ++v) {
    if (!is_sane(V, v)) continue;
    lo = lo.cwiseMin(V.row(v).transpose());
    hi = hi.cwiseMax(V.row(v).transpose());
    any = true;
  }
  return any ? (hi - lo).norm() : 0.0;
}

bool has_repeated_index(const Eigen::MatrixXi& F, int f) {
  return F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0);
}

// True when face f has zero area: a repeated index, or corners collinear to within round-off.
// Faces with non-finite corners are not called degenerate (the coordinate check reports them).
bool is_zero_area(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f, double min_area) {
  if (has_repeated_index(F, f)) return true;
  const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
  const double area = 0.5 * (b - a).cross(c - a).norm();
  return area <= min_area;  // false for NaN
}

bool indices_in_range(const Eigen::MatrixXi& F, int f, int num_vertices) {
  for (int k = 0; k < 3; ++k) {
    if (F(f, k) < 0 || F(f, k) >= num_vertices) return false;
  }
  return true;
}

// Undirected edges of a triangle soup that may be non-manifold (edge_topology refuses those).
// The face sides of edge e are sides[side_begin[e] .. side_begin[e+1]), in increasing face order.
struct TolerantEdges {
  struct Side {
    int face;
    int k;  // edge k of the face, from F(face,k) to F(face,(k+1)%3)
  };
  std::vector<std::array<int, 2>> edges;  // (min, max) vertex indices, sorted
  std::vector<int> side_begin;            // #E + 1 offsets into sides
  std::vector<Side> sides;
  std::vector<std::array<int, 3>> face_edges;  // edge index of edge k of each face

  int num_edges() const { return static_cast<int>(edges.size()); }
  int num_sides(int e) const { return side_begin[e + 1] - side_begin[e]; }
};

// F must have indices in range and three distinct indices per face.
TolerantEdges tolerant_edges(const Eigen::MatrixXi& F) {
  const int nf = static_cast<int>(F.rows());
  std::vector<std::array<int, 4>> half(3 * static_cast<size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      half[3 * f + k] = {std::min(a, b), std::max(a, b), f, k};
    }
  }
  std::sort(half.begin(), half.end());
  TolerantEdges t;
  t.face_edges.assign(nf, {-1, -1, -1});
  t.sides.reserve(half.size());
  for (size_t i = 0; i < half.size();) {
    size_t j = i;
    const int e = t.num_edges();
    t.edges.push_back({half[i][0], half[i][1]});
    t.side_begin.push_back(static_cast<int>(t.sides.size()));
    for (; j < half.size() && half[j][0] == half[i][0] && half[j][1] == half[i][1]; ++j) {
      t.sides.push_back({half[j][2], half[j][3]});
      t.face_edges[half[j][2]][half[j][3]] = e;
    }
    i = j;
  }
  t.side_begin.push_back(static_cast<int>(t.sides.size()));
  return t;
}

// Consistent orientation by breadth-first search from the first face of each component, crossing
// only manifold edges (two faces). A conflict means the component is non-orientable.
struct Orientation {
  std::vector<char> flip;        // per face: reversing it makes it agree with its component's seed
  std::vector<int> component;    // per face, numbered in order of first face
  std::vector<char> orientable;  // per component
  // First conflict per component: the edge and the two faces that cannot agree, or -1.
  std::vector<std::array<int, 3>> conflict;
};

Orientation orient(const Eigen::MatrixXi& F, const TolerantEdges& t) {
  const int nf = static_cast<int>(F.rows());
  Orientation o;
  o.flip.assign(nf, 0);
  o.component.assign(nf, -1);
  std::vector<int> queue;
  queue.reserve(nf);
  for (int seed = 0; seed < nf; ++seed) {
    if (o.component[seed] >= 0) continue;
    const int c = static_cast<int>(o.orientable.size());
    o.orientable.push_back(1);
    o.conflict.push_back({-1, -1, -1});
    queue.assign(1, seed);
    o.component[seed] = c;
    for (size_t head = 0; head < queue.size(); ++head) {
      const int f = queue[head];
      for (int k = 0; k < 3; ++k) {
        const int e = t.face_edges[f][k];
        if (t.num_sides(e) != 2) continue;
        const TolerantEdges::Side s0 = t.sides[t.side_begin[e]], s1 = t.sides[t.side_begin[e] + 1];
        const TolerantEdges::Side other = s0.face == f && s0.k == k ? s1 : s0;
        const int g = other.face;
        // Both faces run along the edge in the same direction: they disagree unless one is flipped.
        const bool same_direction = F(f, k) == F(g, other.k);
        const char wanted = static_cast<char>(o.flip[f] ^ same_direction);
        if (o.component[g] < 0) {
          o.component[g] = c;
          o.flip[g] = wanted;
          queue.push_back(g);
        } else if (o.flip[g] != wanted && o.orientable[c]) {
          o.orientable[c] = 0;
          o.conflict[c] = {e, std::min(f, g), std::max(f, g)};
        }
      }
    }
  }
  return o;
}

// Boundary loops from the edges used by exactly one face, walked along the direction the
// (virtually reoriented) faces give them when possible, so that meshes with inconsistent
// orientation or one-sided surfaces are counted right. Each loop starts at its smallest vertex;
// sorted longest first, ties by first vertex, as boundary_loops does.
std::vector<std::vector<int>> tolerant_boundary_loops(const Eigen::MatrixXi& F,
                                                      const TolerantEdges& t,
                                                      const std::vector<char>& flip) {
  struct Directed {
    int tail, head;
  };
  std::vector<Directed> boundary;
  for (int e = 0; e < t.num_edges(); ++e) {
    if (t.num_sides(e) != 1) continue;
    const TolerantEdges::Side s = t.sides[t.side_begin[e]];
    int a = F(s.face, s.k), b = F(s.face, (s.k + 1) % 3);
    if (flip[s.face]) std::swap(a, b);
    boundary.push_back({a, b});
  }
  // Incident boundary edges per vertex, in edge order.
  std::vector<std::pair<int, int>> incidence;  // (vertex, boundary edge)
  for (int i = 0; i < static_cast<int>(boundary.size()); ++i) {
    incidence.emplace_back(boundary[i].tail, i);
    incidence.emplace_back(boundary[i].head, i);
  }
  std::sort(incidence.begin(), incidence.end());
  auto incident = [&](int v) {
    const auto lo = std::lower_bound(incidence.begin(), incidence.end(), std::make_pair(v, -1));
    auto hi = lo;
    while (hi != incidence.end() && hi->first == v) ++hi;
    return std::make_pair(lo, hi);
  };
  std::vector<char> used(boundary.size(), 0);
  std::vector<std::vector<int>> loops;
  // Each loop starts at the smallest vertex that still has an unused edge.
  for (size_t i = 0; i < incidence.size(); ++i) {
    const int start = incidence[i].first;
    if (i > 0 && incidence[i - 1].first == start) continue;
    for (;;) {
      auto [lo, hi] = incident(start);
      if (std::none_of(lo, hi, [&](const auto& p) { return !used[p.second]; })) break;
      std::vector<int> loop{start};
      int current = start;
      for (;;) {
        auto [l, h] = incident(current);
        int pick = -1;
        for (auto it = l; it != h && pick < 0; ++it) {
          if (!used[it->second] && boundary[it->second].tail == current) pick = it->second;
        }
        for (auto it = l; it != h && pick < 0; ++it) {
          if (!used[it->second]) pick = it->second;
        }
        if (pick < 0) break;  // open chain: only at non-manifold vertices
        used[pick] = 1;
        const Directed d = boundary[pick];
        current = d.tail == current ? d.head : d.tail;
        if (current == start) break;
        loop.push_back(current);
      }
      loops.push_back(std::move(loop));
    }
  }
  std::stable_sort(loops.begin(), loops.end(), [](const auto& a, const auto& b) {
    return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
  });
  return loops;
}

// The loop to name as a hole: the first one that is not the outer boundary, taken to be the
// loop of greatest length in space (an annulus's two rings may have as many vertices).
int first_hole(const Eigen::MatrixXd& V, const std::vector<std::vector<int>>& loops) {
  int outer = 0;
  double longest = -1.0;
  for (int i = 0; i < static_cast<int>(loops.size()); ++i) {
    double length = 0.0;
    for (size_t j = 0; j < loops[i].size(); ++j) {
      length += (V.row(loops[i][j]) - V.row(loops[i][(j + 1) % loops[i].size()])).norm();
    }
    if (length > longest) {  // false for NaN: such a loop is not taken as the outer one
      longest = length;
      outer = i;
    }
  }
  return outer == 0 ? 1 : 0;
}

// Number of edge-connected fans of faces around each vertex (0 for unused vertices).
std::vector<int> fans_per_vertex(const Eigen::MatrixXi& F, int num_vertices) {
  // (vertex, other end of an edge at the vertex, face): faces sharing (vertex, other) are joined.
  std::vector<std::array<int, 3>> spokes;
  spokes.reserve(6 * F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      spokes.push_back({F(f, k), F(f, (k + 1) % 3), f});
      spokes.push_back({F(f, k), F(f, (k + 2) % 3), f});
    }
  }
  std::sort(spokes.begin(), spokes.end());
  std::vector<int> fans(num_vertices, 0);
  std::vector<int> faces, parent;
  for (size_t i = 0; i < spokes.size();) {
    size_t j = i;
    while (j < spokes.size() && spokes[j][0] == spokes[i][0]) ++j;
    faces.clear();
    for (size_t s = i; s < j; ++s) faces.push_back(spokes[s][2]);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    parent.resize(faces.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    auto local = [&](int f) {
      return static_cast<int>(std::lower_bound(faces.begin(), faces.end(), f) - faces.begin());
    };
    int count = static_cast<int>(faces.size());
    for (size_t s = i + 1; s < j; ++s) {
      if (spokes[s][1] != spokes[s - 1][1]) continue;
      const int r1 = find(local(spokes[s - 1][2])), r2 = find(local(spokes[s][2]));
      if (r1 != r2) {
        parent[std::max(r1, r2)] = std::min(r1, r2);
        --count;
      }
    }
    fans[spokes[i][0]] = count;
    i = j;
  }
  return fans;
}

std::string face_string(const Eigen::MatrixXi& F, int f) {
  return fmt::format("face {} ({}, {}, {})", f, F(f, 0), F(f, 1), F(f, 2));
}

const char* ordinal(int i) {
  static const char* const kWords[] = {"first", "second", "third", "fourth", "fifth"};
  return i < 5 ? kWords[i] : "next";
}

// Welds vertices closer than `tolerance` (each to the lowest-indexed representative within reach)
// and returns the representative of every vertex. Vertices with non-finite coordinates stay alone.
std::vector<int> weld_map(const Eigen::MatrixXd& V, double tolerance) {
  const int nv = static_cast<int>(V.rows());
  std::vector<int> rep(nv);
  std::iota(rep.begin(), rep.end(), 0);
  if (!(tolerance > 0.0)) {
    // Exact coincidence only: sort by coordinates, stable so that the lowest index comes first.
    std::vector<int> order;
    for (int v = 0; v < nv; ++v) {
      if (V.row(v).allFinite()) order.push_back(v);
    }
    auto key = [&](int v) { return std::array<double, 3>{V(v, 0), V(v, 1), V(v, 2)}; };
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
    for (size_t i = 1; i < order.size(); ++i) {
      if (key(order[i]) == key(order[i - 1])) rep[order[i]] = rep[order[i - 1]];
    }
    return rep;
  }
  // Grid hashing with cells twice the tolerance: a vertex within reach lies in the same cell or,
  // along each axis, in the neighbouring cell on the side nearer to the point, so 8 cells are
  // enough. Cell coordinates are clamped so that a huge ratio of extent to tolerance cannot
  // overflow; clamped cells only get more crowded, the distance test stays exact.
  const double cell_size = 2.0 * tolerance;
  struct CellHash {
    size_t operator()(const std::array<int64_t, 3>& c) const {
      uint64_t h = 0;
      for (int64_t x : c) h = (h ^ static_cast<uint64_t>(x)) * 0x9E3779B97F4A7C15ull;
      return static_cast<size_t>(h ^ (h >> 29));
    }
  };
  // First representative in each cell; the others are chained through `next`.
  std::unordered_map<std::array<int64_t, 3>, int, CellHash> head;
  head.reserve(nv);
  std::vector<int> next(nv, -1);
  const double tol2 = tolerance * tolerance;
  for (int v = 0; v < nv; ++v) {
    if (!V.row(v).allFinite()) continue;
    std::array<int64_t, 3> cell, side;
    for (int c = 0; c < 3; ++c) {
      const double q = std::clamp(V(v, c) / cell_size, -1e15, 1e15);
      const double base = std::floor(q);
      cell[c] = static_cast<int64_t>(base);
      side[c] = q - base < 0.5 ? -1 : 1;
    }
    int best = -1;
    for (int corner = 0; corner < 8; ++corner) {
      std::array<int64_t, 3> probe = cell;
      for (int c = 0; c < 3; ++c) probe[c] += (corner >> c & 1) ? side[c] : 0;
      const auto it = head.find(probe);
      if (it == head.end()) continue;
      for (int r = it->second; r >= 0; r = next[r]) {
        if ((best < 0 || r < best) && (V.row(r) - V.row(v)).squaredNorm() <= tol2) best = r;
      }
    }
    if (best >= 0) {
      rep[v] = best;
      continue;
    }
    // Every candidate is looked at, so the order within a chain does not matter.
    const auto [it, inserted] = head.emplace(cell, v);
    if (!inserted) {
      next[v] = it->second;
      it->second = v;
    }
  }
  return rep;
}

}  // namespace

RepairReport repair_mesh(Mesh& mesh, const RepairOptions& options) {
  RepairReport report;
  const int nv = mesh.num_vertices();
  if (mesh.V.cols() != 3 || (mesh.F.rows() > 0 && mesh.F.cols() != 3)) return report;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    // Faces pointing at missing vertices cannot be repaired; leave the mesh for diagnose_mesh.
    if (!indices_in_range(mesh.F, f, nv)) return report;
  }
  const double diagonal = sane_diagonal(mesh.V);

  const std::vector<int> rep = weld_map(mesh.V, options.weld_tolerance * diagonal);
  for (int v = 0; v < nv; ++v) report.welded_vertices += rep[v] != v;
  Eigen::MatrixXi F = mesh.F;
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) F(f, k) = rep[F(f, k)];
  }

  // Keep faces with area and a vertex set not seen before, in their order.
  const double min_area = kZeroAreaRelative * diagonal * diagonal;
  std::vector<std::array<int, 4>> sorted_sets;  // (sorted corners, face)
  std::vector<char> keep(F.rows(), 1);
  for (int f = 0; f < F.rows(); ++f) {
    if (is_zero_area(mesh.V, F, f, min_area)) {
      keep[f] = 0;
      ++report.degenerate_faces;
      continue;
    }
    std::array<int, 3> s{F(f, 0), F(f, 1), F(f, 2)};
    std::sort(s.begin(), s.end());
    sorted_sets.push_back({s[0], s[1], s[2], f});
  }
  std::sort(sorted_sets.begin(), sorted_sets.end());
  for (size_t i = 1; i < sorted_sets.size(); ++i) {
    if (std::equal(sorted_sets[i].begin(), sorted_sets[i].begin() + 3,
                   sorted_sets[i - 1].begin())) {
      keep[sorted_sets[i][3]] = 0;  // the later face of the two: sets sort by face index last
      ++report.duplicate_faces;
    }
  }
  Eigen::MatrixXi kept(std::count(keep.begin(), keep.end(), 1), 3);
  for (int f = 0, row = 0; f < F.rows(); ++f) {
    if (keep[f]) kept.row(row++) = F.row(f);
  }

  // Compact: the surviving vertices keep their relative order.
  std::vector<int> new_index(nv, -1);
  for (int f = 0; f < kept.rows(); ++f) {
    for (int k = 0; k < 3; ++k) new_index[kept(f, k)] = 0;
  }
  int count = 0;
  for (int v = 0; v < nv; ++v) {
    if (new_index[v] == 0) {
      new_index[v] = count++;
    } else if (rep[v] == v) {
      ++report.unreferenced_vertices;
    }
  }
  Eigen::MatrixXd V(count, 3);
  for (int v = 0; v < nv; ++v) {
    if (new_index[v] >= 0) V.row(new_index[v]) = mesh.V.row(v);
  }
  for (int f = 0; f < kept.rows(); ++f) {
    for (int k = 0; k < 3; ++k) kept(f, k) = new_index[kept(f, k)];
  }

  if (options.fix_orientation) {
    const Orientation o = orient(kept, tolerant_edges(kept));
    for (int f = 0; f < kept.rows(); ++f) {
      // A one-sided component has no right orientation: leave it as it came.
      if (!o.flip[f] || !o.orientable[o.component[f]]) continue;
      std::swap(kept(f, 1), kept(f, 2));
      ++report.flipped_faces;
    }
  }
  mesh.V = std::move(V);
  mesh.F = std::move(kept);
  return report;
}

MeshDiagnosis diagnose_mesh(const Mesh& mesh) {
  MeshDiagnosis d;
  const Eigen::MatrixXd& V = mesh.V;
  const Eigen::MatrixXi& F = mesh.F;
  d.num_vertices = mesh.num_vertices();
  d.num_faces = mesh.num_faces();
  auto add = [&](MeshProblemKind kind, ErrorCategory category, std::string what, int count,
                 std::string first, std::string fix) {
    d.problems.push_back(
        {kind, category, std::move(what), count, std::move(first), std::move(fix)});
  };

  if (d.num_faces == 0) {
    add(MeshProblemKind::kEmpty, ErrorCategory::kGeometry, "empty mesh", 0,
        "there are no triangles",
        "check that the file holds a surface and export it again with its faces");
    return d;
  }
  // Without vertices every face is out of range, which the index check below reports.
  if ((d.num_vertices > 0 && V.cols() != 3) || F.cols() != 3) {
    add(MeshProblemKind::kNotTriangles, ErrorCategory::kGeometry, "not a triangle mesh in 3D", 1,
        fmt::format("{} coordinates per vertex, {} corners per face", V.cols(), F.cols()),
        "export the surface as triangles with x, y, z coordinates");
    return d;
  }

  int bad_vertices = 0, first_bad_vertex = -1;
  for (int v = 0; v < d.num_vertices; ++v) {
    if (is_sane(V, v)) continue;
    if (bad_vertices++ == 0) first_bad_vertex = v;
  }
  if (bad_vertices > 0) {
    const int v = first_bad_vertex;
    add(MeshProblemKind::kBadCoordinates, ErrorCategory::kGeometry,
        "NaN, infinite or absurdly large (> 1e12) coordinates", bad_vertices,
        fmt::format("vertex {} ({}, {}, {})", v, V(v, 0), V(v, 1), V(v, 2)),
        "fix or delete these vertices in a mesh editor and export again");
  }

  // Faces with valid, distinct indices carry the topology; the rest are reported on their own.
  std::vector<int> topo_faces;
  int out_of_range = 0, first_out = -1;
  for (int f = 0; f < d.num_faces; ++f) {
    if (!indices_in_range(F, f, d.num_vertices)) {
      if (out_of_range++ == 0) first_out = f;
      continue;
    }
    if (!has_repeated_index(F, f)) topo_faces.push_back(f);
  }
  if (out_of_range > 0) {
    add(MeshProblemKind::kMissingVertices, ErrorCategory::kTopology,
        "faces use vertices that do not exist", out_of_range,
        fmt::format("{}; the mesh has {} vertices", face_string(F, first_out), d.num_vertices),
        "the file is damaged: export it again");
  }

  const double diagonal = sane_diagonal(V);
  const double min_area = kZeroAreaRelative * diagonal * diagonal;
  int degenerate = 0, first_degenerate = -1;
  for (int f = 0; f < d.num_faces; ++f) {
    if (!indices_in_range(F, f, d.num_vertices) || !is_zero_area(V, F, f, min_area)) continue;
    if (degenerate++ == 0) first_degenerate = f;
  }
  if (degenerate > 0) {
    add(MeshProblemKind::kZeroAreaFaces, ErrorCategory::kGeometry, "zero-area faces", degenerate,
        face_string(F, first_degenerate),
        "delete them (flatmorph's repair does; MeshLab: Remove Zero Area Faces)");
  }

  Eigen::MatrixXi T(static_cast<int>(topo_faces.size()), 3);
  for (int i = 0; i < T.rows(); ++i) T.row(i) = F.row(topo_faces[i]);
  const TolerantEdges edges = tolerant_edges(T);
  d.num_edges = edges.num_edges();

  int nonmanifold_edges = 0, first_nonmanifold_edge = -1;
  for (int e = 0; e < edges.num_edges(); ++e) {
    if (edges.num_sides(e) <= 2) continue;
    if (nonmanifold_edges++ == 0) first_nonmanifold_edge = e;
  }
  if (nonmanifold_edges > 0) {
    const int e = first_nonmanifold_edge;
    add(MeshProblemKind::kNonManifoldEdges, ErrorCategory::kTopology,
        "non-manifold edges (more than two faces on one edge)", nonmanifold_edges,
        fmt::format("edge ({}, {}) shared by {} faces", edges.edges[e][0], edges.edges[e][1],
                    edges.num_sides(e)),
        "delete the extra faces or re-export as a manifold surface");
  }

  const std::vector<int> fans = fans_per_vertex(T, d.num_vertices);
  int nonmanifold_vertices = 0, first_nonmanifold_vertex = -1;
  for (int v = 0; v < d.num_vertices; ++v) {
    if (fans[v] <= 1) continue;
    if (nonmanifold_vertices++ == 0) first_nonmanifold_vertex = v;
  }
  if (nonmanifold_vertices > 0) {
    const int v = first_nonmanifold_vertex;
    add(MeshProblemKind::kNonManifoldVertices, ErrorCategory::kTopology,
        "non-manifold vertices (pieces touching at a single point)", nonmanifold_vertices,
        fmt::format("vertex {} joins {} separate fans of faces", v, fans[v]),
        "split the vertex (MeshLab: Repair non Manifold Vertices) or delete the faces of one fan");
  }

  const Orientation o = orient(T, edges);
  int nonorientable = 0, first_conflict = -1;
  for (int c = 0; c < static_cast<int>(o.orientable.size()); ++c) {
    if (o.orientable[c]) continue;
    if (nonorientable++ == 0) first_conflict = c;
  }
  if (nonorientable > 0) {
    const auto [e, f, g] = o.conflict[first_conflict];
    add(MeshProblemKind::kNonOrientable, ErrorCategory::kTopology,
        "non-orientable surface (one-sided, like a Moebius strip)", nonorientable,
        fmt::format("edge ({}, {}) between faces {} and {}", edges.edges[e][0], edges.edges[e][1],
                    topo_faces[f], topo_faces[g]),
        "cut the surface open so that it has two sides, or choose another surface");
  }
  int flipped = 0, first_flipped = -1;
  for (int i = 0; i < T.rows(); ++i) {
    if (!o.flip[i] || !o.orientable[o.component[i]]) continue;
    if (flipped++ == 0) first_flipped = topo_faces[i];
  }
  if (flipped > 0) {
    add(MeshProblemKind::kInconsistentOrientation, ErrorCategory::kTopology,
        "faces oriented against their neighbours", flipped, fmt::format("face {}", first_flipped),
        "run repair (flatmorph does before designing) or unify the normals (MeshLab: Re-Orient "
        "all faces coherently)");
  }

  Eigen::VectorXi component;
  d.num_components = face_components(T, component);
  if (d.num_components > 1) {
    int first = 0;
    while (component[first] != 1) ++first;
    add(MeshProblemKind::kSeveralPieces, ErrorCategory::kTopology, "more than one connected piece",
        d.num_components, fmt::format("face {} in the {} component", topo_faces[first], ordinal(1)),
        "keep one piece (e.g. MeshLab: Remove Isolated pieces)");
  }

  // A piece is closed when none of its edges is on the boundary.
  std::vector<char> has_boundary(d.num_components, 0);
  std::vector<int> piece_faces(d.num_components, 0);
  for (int i = 0; i < T.rows(); ++i) ++piece_faces[component[i]];
  for (int e = 0; e < edges.num_edges(); ++e) {
    if (edges.num_sides(e) == 1) has_boundary[component[edges.sides[edges.side_begin[e]].face]] = 1;
  }
  int closed = 0, first_closed = -1;
  for (int c = 0; c < d.num_components; ++c) {
    if (has_boundary[c]) continue;
    if (closed++ == 0) first_closed = c;
  }
  if (closed > 0) {
    int first = 0;
    while (component[first] != first_closed) ++first;
    add(MeshProblemKind::kClosed, ErrorCategory::kTopology, "closed surface (no boundary)", closed,
        fmt::format("the piece with face {}, {} faces", topo_faces[first],
                    piece_faces[first_closed]),
        "cut the closed surface open, e.g. delete a face or a cap");
  }

  const auto loops = tolerant_boundary_loops(T, edges, o.flip);
  d.num_boundary_loops = static_cast<int>(loops.size());
  if (loops.size() > 1) {
    const int hole = first_hole(V, loops);
    add(MeshProblemKind::kHoles, ErrorCategory::kTopology, "holes (boundary loops; a disk has one)",
        d.num_boundary_loops,
        fmt::format("hole along vertex {}, {} edges", loops[hole].front(), loops[hole].size()),
        "fill the holes (e.g. MeshLab: Close Holes) or keep only the outer part");
  }

  d.euler_characteristic = T.rows() > 0 ? euler_characteristic(T) : 0;
  return d;
}

std::string problem_line(const std::string& source, const MeshProblem& problem) {
  return fmt::format("{}: {}: {} (first: {}); {}", source, problem.what, problem.count,
                     problem.first, problem.fix);
}

void require_disk(const Mesh& mesh, const std::string& source) {
  const MeshDiagnosis d = diagnose_mesh(mesh);
  if (d.is_disk()) return;
  const MeshProblem& p = d.problems.front();
  throw UserError(p.category, problem_line(source, p));
}

}  // namespace flatmorph
