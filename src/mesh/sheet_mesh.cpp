#include "mesh/sheet_mesh.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <queue>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "mesh/plane_geometry.h"
#include "mesh/polygon.h"

namespace flatmorph {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VertexInfo {
  int index = -1;  // into the outline points; -1 for the mesher's Steiner points
};
struct FaceInfo {
  int component = -1;  // connected set of faces not separated by an outline
};
using VertexBase = CGAL::Delaunay_mesh_vertex_base_2<
    Kernel, CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel>>;
using FaceBase = CGAL::Delaunay_mesh_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<
                FaceInfo, Kernel, CGAL::Constrained_triangulation_face_base_2<Kernel>>>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Exact_predicates_tag: outlines that cross (overlapping regions) are still triangulated, at a
// constructed crossing, so that the overlap can be found and reported rather than thrown from
// inside CGAL.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
using Mesher = CGAL::Delaunay_mesher_2<Cdt, Criteria>;
using Point = Kernel::Point_2;

// Two outline points closer than this (mm) are one vertex, and a point this close to another
// outline's segment lies on it: far below what a 0.4 mm bead resolves, far above the rounding of
// coordinates of a bed-sized sheet. Keeps joined tiles' shared edges one set of constraints.
constexpr double kSnap = 1e-6;

using Loop = std::vector<int>;  // indices into the outline points, closed implicitly

struct Outlines {
  std::vector<Eigen::Vector2d> points;
  std::vector<std::vector<Loop>> loops;  // per region: boundary, then holes
};

std::string sheet_name(const std::vector<PlaneRegion>& regions) {
  const std::string count =
      fmt::format("the sheet of {} region{}", regions.size(), regions.size() == 1 ? "" : "s");
  if (regions[0].source.empty()) return count;
  return fmt::format("{} ({}{})", count, regions[0].source, regions.size() > 1 ? ", ..." : "");
}

std::string describe(const PlaneRegion& region, size_t index) {
  return region.source.empty() ? fmt::format("region {}", index)
                               : fmt::format("region {} ({})", index, region.source);
}

void check_loop(const Eigen::MatrixX2d& loop, const std::string& who, const char* which) {
  if (loop.rows() < 3) {
    throw UserError(ErrorCategory::kGeometry,
                    fmt::format("{}: its {} has {} points; an outline needs at least 3", who, which,
                                loop.rows()));
  }
  for (Eigen::Index i = 0; i < loop.rows(); ++i) {
    if (!std::isfinite(loop(i, 0)) || !std::isfinite(loop(i, 1))) {
      throw UserError(ErrorCategory::kGeometry,
                      fmt::format("{}: point {} of its {} is not a finite number; fix the outline",
                                  who, i, which));
    }
  }
}

// The signed area of a loop of the outlines, mm².
double loop_area(const std::vector<Eigen::Vector2d>& points, const Loop& loop) {
  std::vector<Eigen::Vector2d> corners;
  corners.reserve(loop.size());
  for (int i : loop) corners.push_back(points[i]);
  return signed_area(corners);
}

// Merges points closer than kSnap (the first one met is kept), so that outlines given twice along
// a shared edge end on the same vertices.
class PointMerger {
 public:
  explicit PointMerger(std::vector<Eigen::Vector2d>& points) : points_(points) {}
  int add(const Eigen::Vector2d& p) {
    const std::int64_t cx = cell(p.x()), cy = cell(p.y());
    int found = -1;
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = cells_.find({cx + dx, cy + dy});
        if (it == cells_.end()) continue;
        for (int i : it->second) {
          if ((points_[i] - p).norm() <= kSnap && (found < 0 || i < found)) found = i;
        }
      }
    }
    if (found >= 0) return found;
    points_.push_back(p);
    cells_[{cx, cy}].push_back(static_cast<int>(points_.size()) - 1);
    return static_cast<int>(points_.size()) - 1;
  }

 private:
  static std::int64_t cell(double v) { return static_cast<std::int64_t>(std::floor(v / kSnap)); }
  std::vector<Eigen::Vector2d>& points_;
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<int>> cells_;
};

// The regions' loops on merged points, with every outline point that lies on another loop's
// segment inserted into that segment (T-junctions of tiles joined edge to edge), and every
// segment then split evenly to at most max_edge, the same way from both sides.
Outlines build_outlines(const std::vector<PlaneRegion>& regions, double max_edge) {
  Outlines out;
  PointMerger merger(out.points);
  for (size_t r = 0; r < regions.size(); ++r) {
    const PlaneRegion& region = regions[r];
    check_loop(region.boundary, describe(region, r), "boundary");
    for (const Eigen::MatrixX2d& hole : region.holes) check_loop(hole, describe(region, r), "hole");
    std::vector<Loop>& loops = out.loops.emplace_back();
    auto add_loop = [&](const Eigen::MatrixX2d& m) {
      Loop loop;
      for (Eigen::Index i = 0; i < m.rows(); ++i) {
        const int id = merger.add(m.row(i).transpose());
        if (loop.empty() || loop.back() != id) loop.push_back(id);
      }
      while (loop.size() > 1 && loop.back() == loop.front()) loop.pop_back();
      loops.push_back(std::move(loop));
    };
    add_loop(region.boundary);
    for (const Eigen::MatrixX2d& hole : region.holes) add_loop(hole);
    for (size_t k = 0; k < loops.size(); ++k) {
      const double area = loops[k].size() < 3 ? 0 : loop_area(out.points, loops[k]);
      if (std::abs(area) <= kSnap * kSnap) {
        throw UserError(ErrorCategory::kGeometry,
                        fmt::format("{}: its {} encloses no area (its points coincide within {} "
                                    "mm or lie on a line); fix the outline",
                                    describe(region, r), k == 0 ? "boundary" : "hole", kSnap));
      }
    }
  }

  // T-junctions: points sorted by x, to find those near a segment quickly.
  std::vector<int> by_x(out.points.size());
  for (size_t i = 0; i < by_x.size(); ++i) by_x[i] = static_cast<int>(i);
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) {
    return out.points[a].x() < out.points[b].x() ||
           (out.points[a].x() == out.points[b].x() && a < b);
  });
  for (std::vector<Loop>& loops : out.loops) {
    for (Loop& loop : loops) {
      Loop split;
      for (size_t i = 0; i < loop.size(); ++i) {
        const int ia = loop[i], ib = loop[(i + 1) % loop.size()];
        const Eigen::Vector2d a = out.points[ia], b = out.points[ib];
        const Eigen::Vector2d ab = b - a;
        const double length2 = ab.squaredNorm();
        const double lo = std::min(a.x(), b.x()) - kSnap, hi = std::max(a.x(), b.x()) + kSnap;
        auto first = std::lower_bound(by_x.begin(), by_x.end(), lo,
                                      [&](int k, double x) { return out.points[k].x() < x; });
        std::vector<std::pair<double, int>> on;
        for (auto it = first; it != by_x.end() && out.points[*it].x() <= hi; ++it) {
          const int k = *it;
          if (k == ia || k == ib) continue;
          const Eigen::Vector2d ap = out.points[k] - a;
          const double t = ap.dot(ab) / length2;
          if (t <= 0 || t >= 1) continue;
          if ((ap - t * ab).norm() > kSnap) continue;
          if ((out.points[k] - a).norm() <= kSnap || (out.points[k] - b).norm() <= kSnap) continue;
          on.push_back({t, k});
        }
        std::sort(on.begin(), on.end());
        split.push_back(ia);
        for (const auto& [t, k] : on) split.push_back(k);
      }
      loop = std::move(split);
    }
  }

  // Even sampling of the boundary: each undirected segment split once, from its lower index.
  std::map<std::pair<int, int>, std::vector<int>> chains;
  for (std::vector<Loop>& loops : out.loops) {
    for (Loop& loop : loops) {
      Loop sampled;
      for (size_t i = 0; i < loop.size(); ++i) {
        const int ia = loop[i], ib = loop[(i + 1) % loop.size()];
        sampled.push_back(ia);
        const std::pair<int, int> key = std::minmax(ia, ib);
        auto it = chains.find(key);
        if (it == chains.end()) {
          const Eigen::Vector2d p = out.points[key.first], q = out.points[key.second];
          const int pieces =
              std::max(1, static_cast<int>(std::ceil((q - p).norm() / max_edge - 1e-9)));
          std::vector<int> chain;
          for (int k = 1; k < pieces; ++k) {
            out.points.push_back(p + (q - p) * (static_cast<double>(k) / pieces));
            chain.push_back(static_cast<int>(out.points.size()) - 1);
          }
          it = chains.emplace(key, std::move(chain)).first;
        }
        if (ia < ib) {
          sampled.insert(sampled.end(), it->second.begin(), it->second.end());
        } else {
          sampled.insert(sampled.end(), it->second.rbegin(), it->second.rend());
        }
      }
      loop = std::move(sampled);
    }
  }
  return out;
}

// Even-odd over all of a region's loops: inside the boundary and outside every hole.
bool inside_region(const Outlines& outlines, size_t region, const Eigen::Vector2d& p) {
  bool inside = false;
  for (const Loop& loop : outlines.loops[region]) {
    for (size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
      const Eigen::Vector2d& a = outlines.points[loop[i]];
      const Eigen::Vector2d& b = outlines.points[loop[j]];
      if (side_crosses_ray(p, a, b)) inside = !inside;
    }
  }
  return inside;
}

Eigen::Vector2d to_eigen(const Point& p) { return {p.x(), p.y()}; }

Eigen::Vector2d centroid(Cdt::Face_handle f) {
  return (to_eigen(f->vertex(0)->point()) + to_eigen(f->vertex(1)->point()) +
          to_eigen(f->vertex(2)->point())) /
         3;
}

double area(Cdt::Face_handle f) {
  return triangle_signed_area(to_eigen(f->vertex(0)->point()), to_eigen(f->vertex(1)->point()),
                              to_eigen(f->vertex(2)->point()));
}

struct Component {
  Cdt::Face_handle largest;  // its centroid stands for the component: farthest from its edges
  double largest_area = -1;
  bool unbounded = false;  // reaches the infinite face without crossing an outline
};

// Connected sets of finite faces, not crossing constrained edges; restricted to the faces in the
// mesher's domain when `in_domain_only`.
std::vector<Component> components(Cdt& cdt, bool in_domain_only) {
  for (Cdt::Face_handle f : cdt.all_face_handles()) f->info().component = -1;
  std::vector<Component> out;
  for (Cdt::Face_handle start : cdt.finite_face_handles()) {
    if (start->info().component >= 0 || (in_domain_only && !start->is_in_domain())) continue;
    const int id = static_cast<int>(out.size());
    Component& c = out.emplace_back();
    std::queue<Cdt::Face_handle> queue;
    start->info().component = id;
    queue.push(start);
    while (!queue.empty()) {
      const Cdt::Face_handle f = queue.front();
      queue.pop();
      const double a = area(f);
      if (a > c.largest_area) {
        c.largest_area = a;
        c.largest = f;
      }
      for (int i = 0; i < 3; ++i) {
        if (f->is_constrained(i)) continue;
        const Cdt::Face_handle n = f->neighbor(i);
        if (cdt.is_infinite(n)) {
          c.unbounded = true;
          continue;
        }
        if (n->info().component >= 0 || (in_domain_only && !n->is_in_domain())) continue;
        n->info().component = id;
        queue.push(n);
      }
    }
  }
  return out;
}

}  // namespace

SheetMesh sheet_mesh(const std::vector<PlaneRegion>& regions, const SheetMeshOptions& options) {
  if (regions.empty()) {
    throw UserError(ErrorCategory::kGeometry, "sheet mesh: no outlines given; give at least one");
  }
  const std::string name = sheet_name(regions);
  if (!(options.max_edge > 0) || !std::isfinite(options.max_edge)) {
    throw UserError(
        ErrorCategory::kOption,
        fmt::format("{}: mesh max_edge {} mm must be a positive length", name, options.max_edge));
  }
  // CGAL's refinement terminates for angle bounds up to 20.7 degrees and in practice up to about
  // 30; beyond, it may run until max_vertices.
  if (!(options.min_angle_deg > 0 && options.min_angle_deg <= 30)) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: mesh min_angle {} degrees is outside (0, 30]; 20-28 is usual",
                                name, options.min_angle_deg));
  }
  if (options.max_vertices < 3) {
    throw UserError(ErrorCategory::kOption,
                    fmt::format("{}: mesh max_vertices {} is below 3", name, options.max_vertices));
  }

  const Outlines outlines = build_outlines(regions, options.max_edge);

  // Fail fast before meshing: an equilateral mesh of edge max_edge has 2 A / (sqrt(3) h^2)
  // vertices; the mesher's triangles come out smaller, so this is a lower bound.
  double total_area = 0;
  for (const std::vector<Loop>& loops : outlines.loops) {
    double region_area = 0;
    for (const Loop& loop : loops) region_area += loop_area(outlines.points, loop);
    total_area += std::abs(region_area);
  }
  const double h = options.max_edge;
  const double estimate =
      static_cast<double>(outlines.points.size()) + 2 * total_area / (std::sqrt(3.0) * h * h);
  auto too_many = [&](double count) {
    return UserError(
        ErrorCategory::kResource,
        fmt::format("{}: meshing {:.0f} mm^2 at max_edge {} mm needs more than {} vertices (at "
                    "least {:.0f}); raise max_edge to about {:.2g} mm, or max_vertices",
                    name, total_area, h, options.max_vertices, count,
                    h * std::sqrt(2 * count / options.max_vertices)));
  };
  if (estimate > options.max_vertices) throw too_many(estimate);

  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handles;
  handles.reserve(outlines.points.size());
  for (size_t i = 0; i < outlines.points.size(); ++i) {
    const Cdt::Vertex_handle v = cdt.insert(Point(outlines.points[i].x(), outlines.points[i].y()));
    v->info().index = static_cast<int>(i);
    handles.push_back(v);
  }
  std::set<std::pair<int, int>> constrained;
  for (const std::vector<Loop>& loops : outlines.loops) {
    for (const Loop& loop : loops) {
      for (size_t i = 0; i < loop.size(); ++i) {
        const std::pair<int, int> key = std::minmax(loop[i], loop[(i + 1) % loop.size()]);
        if (constrained.insert(key).second) {
          cdt.insert_constraint(handles[key.first], handles[key.second]);
        }
      }
    }
  }

  // Label the pieces between the outlines; each lies wholly inside or outside every region.
  const std::vector<Component> initial = components(cdt, false);
  std::vector<int> initial_label(initial.size(), -1);
  std::vector<std::pair<Eigen::Vector2d, int>> seeds;  // a point of each labelled piece
  for (size_t k = 0; k < initial.size(); ++k) {
    if (initial[k].unbounded) continue;
    const Eigen::Vector2d p = centroid(initial[k].largest);
    int label = -1;
    for (size_t r = 0; r < regions.size(); ++r) {
      if (!inside_region(outlines, r, p)) continue;
      if (label >= 0) {
        throw UserError(
            ErrorCategory::kGeometry,
            fmt::format("{}: {} and {} overlap near ({:.4f}, {:.4f}) mm; regions may share "
                        "edges or fill each other's holes but not overlap",
                        name, describe(regions[label], label), describe(regions[r], r), p.x(),
                        p.y()));
      }
      label = static_cast<int>(r);
    }
    initial_label[k] = label;
    if (label >= 0) seeds.push_back({p, label});
  }
  for (Cdt::Face_handle f : cdt.all_face_handles()) {
    f->set_in_domain(!cdt.is_infinite(f) && initial_label[f->info().component] >= 0);
  }

  Mesher mesher(cdt, Criteria(std::pow(std::sin(options.min_angle_deg * std::numbers::pi / 180), 2),
                              options.max_edge));
  mesher.init(true);
  while (mesher.step_by_step_refine_mesh()) {
    if (cdt.number_of_vertices() > static_cast<size_t>(options.max_vertices)) {
      throw too_many(static_cast<double>(cdt.number_of_vertices()));
    }
  }

  // Labels again: the refinement split faces but kept every outline edge, so each seed still lies
  // in its piece.
  const std::vector<Component> pieces = components(cdt, true);
  std::vector<int> piece_label(pieces.size(), -1);
  for (const auto& [p, label] : seeds) {
    const Cdt::Face_handle f = cdt.locate(Point(p.x(), p.y()));
    if (f == nullptr || cdt.is_infinite(f) || !f->is_in_domain()) {
      throw std::logic_error("sheet_mesh: a labelled piece lost its seed during refinement");
    }
    piece_label[f->info().component] = label;
  }

  // Vertices: the outline points in order, then the Steiner points in the order CGAL created them;
  // unreferenced ones dropped.
  std::vector<Cdt::Vertex_handle> steiner;
  for (Cdt::Vertex_handle v : cdt.finite_vertex_handles()) {
    if (v->info().index < 0) steiner.push_back(v);
  }
  const int n_outline = static_cast<int>(outlines.points.size());
  for (size_t i = 0; i < steiner.size(); ++i)
    steiner[i]->info().index = n_outline + static_cast<int>(i);
  std::vector<Cdt::Vertex_handle> by_index(handles);
  by_index.insert(by_index.end(), steiner.begin(), steiner.end());

  struct OutFace {
    int region;
    Eigen::Vector2d centroid;
    std::array<int, 3> v;
  };
  std::vector<OutFace> faces;
  for (Cdt::Face_handle f : cdt.finite_face_handles()) {
    if (!f->is_in_domain()) continue;
    const int label = piece_label[f->info().component];
    if (label < 0) throw std::logic_error("sheet_mesh: a meshed face has no region");
    faces.push_back(
        {label,
         centroid(f),
         {f->vertex(0)->info().index, f->vertex(1)->info().index, f->vertex(2)->info().index}});
  }
  std::sort(faces.begin(), faces.end(), [](const OutFace& a, const OutFace& b) {
    if (a.region != b.region) return a.region < b.region;
    if (a.centroid.x() != b.centroid.x()) return a.centroid.x() < b.centroid.x();
    return a.centroid.y() < b.centroid.y();
  });

  std::vector<int> new_index(by_index.size(), -1);
  for (const OutFace& f : faces) {
    for (int v : f.v) new_index[v] = 0;
  }
  int count = 0;
  for (int& k : new_index) {
    if (k == 0) k = count++;
  }
  SheetMesh mesh;
  mesh.V.resize(count, 2);
  for (size_t i = 0; i < by_index.size(); ++i) {
    if (new_index[i] < 0) continue;
    mesh.V(new_index[i], 0) = by_index[i]->point().x();
    mesh.V(new_index[i], 1) = by_index[i]->point().y();
  }
  mesh.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  mesh.face_region.resize(static_cast<Eigen::Index>(faces.size()));
  for (size_t k = 0; k < faces.size(); ++k) {
    for (int j = 0; j < 3; ++j) mesh.F(static_cast<Eigen::Index>(k), j) = new_index[faces[k].v[j]];
    mesh.face_region(static_cast<Eigen::Index>(k)) = faces[k].region;
  }
  return mesh;
}

RingFrame ring_frame(const PlaneRegion& outline, const Eigen::MatrixX2d& points) {
  struct Segment {
    Eigen::Vector2d a, b;
    double min_x, max_x, min_y, max_y;
  };
  std::vector<Segment> segments;
  auto add_loop = [&](const Eigen::MatrixX2d& loop, const char* which) {
    check_loop(loop, outline.source.empty() ? "ring frame" : outline.source, which);
    for (Eigen::Index i = 0; i < loop.rows(); ++i) {
      const Eigen::Vector2d a = loop.row(i).transpose();
      const Eigen::Vector2d b = loop.row((i + 1) % loop.rows()).transpose();
      if (a == b) continue;
      segments.push_back({a, b, std::min(a.x(), b.x()), std::max(a.x(), b.x()),
                          std::min(a.y(), b.y()), std::max(a.y(), b.y())});
    }
  };
  add_loop(outline.boundary, "boundary");
  for (const Eigen::MatrixX2d& hole : outline.holes) add_loop(hole, "hole");

  RingFrame frame;
  frame.depth.resize(points.rows());
  frame.direction.resize(points.rows());
  size_t hint = 0;  // the previous point's nearest segment: neighbouring points share it
  for (Eigen::Index k = 0; k < points.rows(); ++k) {
    const Eigen::Vector2d p = points.row(k).transpose();
    if (!p.allFinite()) throw std::invalid_argument("ring_frame: a point is not finite");
    double best = std::numeric_limits<double>::infinity();
    size_t best_segment = 0;
    Eigen::Vector2d nearest = Eigen::Vector2d::Zero();
    auto try_segment = [&](size_t s) {
      const Segment& g = segments[s];
      const double dx = std::max({0.0, g.min_x - p.x(), p.x() - g.max_x});
      const double dy = std::max({0.0, g.min_y - p.y(), p.y() - g.max_y});
      if (dx * dx + dy * dy > best) return;
      const Eigen::Vector2d ab = g.b - g.a;
      const double t = std::clamp((p - g.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const Eigen::Vector2d q = g.a + t * ab;
      const double d2 = (p - q).squaredNorm();
      // Ties go to the lower segment, whatever the hint, so a point's frame does not depend on
      // the points before it.
      if (d2 < best || (d2 == best && s < best_segment)) {
        best = d2;
        best_segment = s;
        nearest = q;
      }
    };
    try_segment(hint);
    for (size_t s = 0; s < segments.size(); ++s) try_segment(s);
    hint = best_segment;
    const double depth = std::sqrt(best);
    frame.depth(k) = depth;
    // The offset curve through p is perpendicular to p - q (note §7.2: grad d rotated by 90
    // degrees); on the outline itself, the segment's own direction.
    const Eigen::Vector2d away = p - nearest;
    double angle;
    if (depth > 1e-12 * (1 + p.norm())) {
      angle = std::atan2(away.y(), away.x()) + std::numbers::pi / 2;
    } else {
      const Eigen::Vector2d ab = segments[best_segment].b - segments[best_segment].a;
      angle = std::atan2(ab.y(), ab.x());
    }
    angle = std::fmod(angle, std::numbers::pi);
    if (angle < 0) angle += std::numbers::pi;
    if (angle >= std::numbers::pi) angle -= std::numbers::pi;
    frame.direction(k) = angle;
  }
  return frame;
}

}  // namespace flatmorph
