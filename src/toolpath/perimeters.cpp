#include "toolpath/perimeters.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/angles.h"
#include "mesh/topology.h"

namespace flatmorph {
namespace {

struct Outline {
  std::vector<Eigen::Vector2d> a, b;  // boundary edges
};

Outline outline(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const EdgeTopology topology = edge_topology(F);
  Outline o;
  for (int e = 0; e < topology.num_edges(); ++e) {
    if (!topology.is_boundary_edge(e)) continue;
    o.a.push_back(V.row(topology.edges(e, 0)).head<2>());
    o.b.push_back(V.row(topology.edges(e, 1)).head<2>());
  }
  return o;
}

double distance_to(const Outline& o, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < o.a.size(); ++k) {
    const Eigen::Vector2d ab = o.b[k] - o.a[k];
    const double t = std::clamp((p - o.a[k]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (o.a[k] + t * ab - p).squaredNorm());
  }
  return std::sqrt(best);
}

}  // namespace

Eigen::VectorXd boundary_distance(const Eigen::MatrixXd& V, const Eigen::MatrixXd& V_plate,
                                  const Eigen::MatrixXi& F_plate) {
  const Outline o = outline(V_plate, F_plate);
  Eigen::VectorXd d(V.rows());
  for (int v = 0; v < V.rows(); ++v) d(v) = distance_to(o, V.row(v).head<2>());
  return d;
}

std::vector<Polyline2> perimeter_loops(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const Eigen::VectorXd& distance, int count,
                                       double spacing_mm, double min_length_mm) {
  if (count <= 0) return {};
  // The level sets d = (m + 1/2) s are the isolines 2 pi m of the phase 2 pi d / s - pi: a stripe
  // pattern without singularities, so the stripe isoline extraction traces them.
  const EdgeTopology topology = edge_topology(F);
  StripePattern phase;
  const int nv = static_cast<int>(V.rows());
  phase.vertex_phase.resize(nv);
  for (int v = 0; v < nv; ++v) {
    double p = kTwoPi * distance(v) / spacing_mm - std::numbers::pi;
    const double level = kTwoPi * std::round(p / kTwoPi);
    if (std::abs(p - level) < 1e-9) p = level + 1e-9;
    phase.vertex_phase(v) = p;
  }
  phase.edge_phase.resize(topology.num_edges());
  phase.edge_sign.setOnes(topology.num_edges());
  for (int e = 0; e < topology.num_edges(); ++e) {
    phase.edge_phase(e) =
        phase.vertex_phase(topology.edges(e, 1)) - phase.vertex_phase(topology.edges(e, 0));
  }
  phase.corner_phase.resize(F.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) phase.corner_phase(f, k) = phase.vertex_phase(F(f, k));
  }
  phase.doubled_index.setZero(F.rows());
  phase.stripe_index.setZero(F.rows());
  // Only faces that can hold one of the wanted levels.
  phase.usable.assign(F.rows(), false);
  for (int f = 0; f < F.rows(); ++f) {
    double lo = distance(F(f, 0));
    for (int k = 1; k < 3; ++k) lo = std::min(lo, distance(F(f, k)));
    phase.usable[f] = lo < count * spacing_mm;
  }
  std::vector<Polyline2> all = stripe_isolines(V, F, topology, phase, min_length_mm);
  // The level of a loop from the distance of its first point; keep the wanted levels, outermost
  // first (stable: extraction order within a level).
  const Outline o = outline(V, F);
  std::vector<std::pair<long, size_t>> by_level;
  for (size_t i = 0; i < all.size(); ++i) {
    const double d = distance_to(o, all[i].points.row(0).transpose());
    const long level = std::lround(d / spacing_mm - 0.5);
    if (level < count) by_level.emplace_back(level, i);
  }
  std::stable_sort(by_level.begin(), by_level.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<Polyline2> loops;
  for (const auto& [level, i] : by_level) loops.push_back(std::move(all[i]));
  return loops;
}

void clip_to_inner_region(std::vector<Polyline2>& polylines, const Eigen::MatrixXd& V_plate,
                          const Eigen::MatrixXi& F_plate, double min_distance_mm) {
  const Outline o = outline(V_plate, F_plate);
  const auto inside = [&](const Eigen::Vector2d& x) {
    return distance_to(o, x) >= min_distance_mm;
  };
  std::vector<Polyline2> kept;
  for (const Polyline2& line : polylines) {
    const int n = static_cast<int>(line.points.rows());
    std::vector<Eigen::Vector2d> current;
    const auto flush = [&] {
      if (current.size() >= 2) {
        Polyline2 piece;
        piece.points.resize(static_cast<int>(current.size()), 2);
        for (size_t i = 0; i < current.size(); ++i) piece.points.row(i) = current[i].transpose();
        piece.closed = false;
        kept.push_back(std::move(piece));
      }
      current.clear();
    };
    std::vector<bool> in(n);
    for (int i = 0; i < n; ++i) in[i] = inside(line.points.row(i).transpose());
    if (line.closed && std::all_of(in.begin(), in.end(), [](bool b) { return b; })) {
      kept.push_back(line);
      continue;
    }
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d x = line.points.row(i).transpose();
      if (i > 0 && in[i] != in[i - 1]) {
        // Bisection for the crossing of the clip distance on segment (i-1, i).
        Eigen::Vector2d out_end = in[i] ? line.points.row(i - 1).transpose() : x;
        Eigen::Vector2d in_end = in[i] ? x : line.points.row(i - 1).transpose();
        for (int b = 0; b < 30; ++b) {
          const Eigen::Vector2d mid = 0.5 * (out_end + in_end);
          (inside(mid) ? in_end : out_end) = mid;
        }
        current.push_back(in_end);
        if (!in[i]) flush();
      }
      if (in[i]) current.push_back(x);
    }
    flush();
  }
  polylines = std::move(kept);
}

}  // namespace flatmorph
