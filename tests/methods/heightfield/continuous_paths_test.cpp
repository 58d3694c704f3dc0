#include "methods/heightfield/continuous_paths.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "examples/height_field_examples.h"
#include "gcode/gcode_writer.h"
#include "gcode/printer_profile.h"
#include "material/material.h"
#include "material/thickness_curve.h"
#include "methods/heightfield/cap_printing_graph.h"
#include "methods/heightfield/isoline_mesh.h"
#include "methods/heightfield/shrinkage_field.h"
#include "toolpath/path_quality.h"

namespace flatmorph::continuous_paths_test {
namespace {

// The paths of a sheet whose printing edges shrink by `edge_shrinkage`, spread over the vertices
// as the design spreads the flattening's.
ContinuousPaths paths_from_edges(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                 const Eigen::VectorXd& edge_shrinkage, const Material& material,
                                 const ContinuousPathOptions& options = {}) {
  return continuous_paths(mesh, plate, vertex_shrinkage(mesh, plate.leftCols(2), edge_shrinkage),
                          material, options);
}

// --- Printing graphs built from closed rings (isolines), zipped into triangles by angle around
// a centre, with fans at patch centres: the structure of isoline_mesh.h without the isoline
// extraction. The plate is the rings' xy (a flat sheet is any layout; these tests need none other).
struct RingMesh {
  std::vector<Eigen::Vector2d> xy;
  std::vector<int> level, loop;
  std::vector<Eigen::Vector3i> faces;
  std::vector<IsolineLoop> loops;
  int num_levels = 0;

  int add_vertex(const Eigen::Vector2d& p, int lev, int lp) {
    xy.push_back(p);
    level.push_back(lev);
    loop.push_back(lp);
    num_levels = std::max(num_levels, lev + 1);
    return static_cast<int>(xy.size()) - 1;
  }
  // A loop through `points` (counter-clockwise), at `lev`, inside loop `parent`.
  std::vector<int> add_loop(const std::vector<Eigen::Vector2d>& points, int lev, int parent) {
    const int id = static_cast<int>(loops.size());
    std::vector<int> vs;
    for (const Eigen::Vector2d& p : points) vs.push_back(add_vertex(p, lev, id));
    loops.push_back({lev, parent, vs});
    return vs;
  }
  // Triangles between the closed counter-clockwise sequences `outer` and `inner` (one level
  // apart), zipped by their polar angles around `centre` (both star-shaped around it).
  void zip(const std::vector<int>& outer, const std::vector<int>& inner,
           const Eigen::Vector2d& centre) {
    auto angle = [&](int v) {
      const Eigen::Vector2d d = xy[v] - centre;
      return std::atan2(d.y(), d.x());
    };
    auto unwrap = [&](const std::vector<int>& ring, int first, double start) {
      const int n = static_cast<int>(ring.size());
      std::vector<double> a(n + 1);
      a[0] = start;
      for (int j = 1; j < n; ++j) {
        double step = std::remainder(
            angle(ring[(first + j) % n]) - angle(ring[(first + j - 1) % n]), 2 * kPi);
        if (step < 0) step += 2 * kPi;
        a[j] = a[j - 1] + step;
      }
      a[n] = start + 2 * kPi;
      return a;
    };
    const int no = static_cast<int>(outer.size()), ni = static_cast<int>(inner.size());
    const double a0 = angle(outer[0]);
    int k0 = 0;
    double best = 1e9;
    for (int k = 0; k < ni; ++k) {
      const double d = std::abs(std::remainder(angle(inner[k]) - a0, 2 * kPi));
      if (d < best) best = d, k0 = k;
    }
    const std::vector<double> oa = unwrap(outer, 0, a0);
    const std::vector<double> ia =
        unwrap(inner, k0, a0 + std::remainder(angle(inner[k0]) - a0, 2 * kPi));
    int j = 0, k = 0;
    while (j < no || k < ni) {
      const bool advance_outer = k == ni || (j < no && oa[j + 1] < ia[k + 1]);
      const int o = outer[j % no], i = inner[(k0 + k) % ni];
      if (advance_outer) {
        faces.emplace_back(o, outer[(j + 1) % no], i);
        ++j;
      } else {
        faces.emplace_back(inner[(k0 + k + 1) % ni], i, o);
        ++k;
      }
    }
  }
  // A fan from the closed counter-clockwise `rim` to a new patch centre at `centre`.
  int fan(const std::vector<int>& rim, const Eigen::Vector2d& centre) {
    const int c = add_vertex(centre, -1, -1);
    for (size_t j = 0; j < rim.size(); ++j)
      faces.emplace_back(rim[j], rim[(j + 1) % rim.size()], c);
    return c;
  }

  IsolineMesh mesh() const {
    IsolineMesh m;
    const int n = static_cast<int>(xy.size());
    m.V.resize(n, 3);
    m.vertex_level.resize(n);
    m.vertex_loop.resize(n);
    for (int v = 0; v < n; ++v) {
      m.V.row(v) << xy[v].x(), xy[v].y(), 3.0 * std::max(level[v], 0);
      m.vertex_level(v) = level[v];
      m.vertex_loop(v) = loop[v];
    }
    m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
    std::set<std::pair<int, int>> edges;
    for (size_t f = 0; f < faces.size(); ++f) {
      m.F.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
      for (int c = 0; c < 3; ++c) edges.insert(std::minmax(faces[f](c), faces[f]((c + 1) % 3)));
    }
    m.E.resize(static_cast<Eigen::Index>(edges.size()), 2);
    int e = 0;
    for (const auto& [a, b] : edges) {
      m.E.row(e++) << a, b;
      const bool same = level[a] == level[b] && level[a] >= 0;
      m.edge_kind.push_back(!same           ? EdgeKind::kBridge
                            : level[a] == 0 ? EdgeKind::kBoundary
                                            : EdgeKind::kPrinting);
    }
    m.levels.resize(num_levels);
    for (int l = 0; l < num_levels; ++l) m.levels(l) = 3.0 * l;
    m.loops = loops;
    return m;
  }
  Eigen::MatrixXd plate() const {
    Eigen::MatrixXd p(static_cast<Eigen::Index>(xy.size()), 2);
    for (size_t v = 0; v < xy.size(); ++v) p.row(static_cast<Eigen::Index>(v)) = xy[v].transpose();
    return p;
  }
};

std::vector<Eigen::Vector2d> circle(const Eigen::Vector2d& centre, double radius, double spacing,
                                    double phase = 0) {
  const int n = std::max(8, static_cast<int>(std::lround(2 * kPi * radius / spacing)));
  std::vector<Eigen::Vector2d> p;
  for (int j = 0; j < n; ++j) {
    const double a = phase + 2 * kPi * j / n;
    p.push_back(centre + radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return p;
}

// Points from a to b (a included, b not), about `spacing` apart.
void straight(std::vector<Eigen::Vector2d>& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
              double spacing) {
  const int n = std::max(1, static_cast<int>(std::lround((b - a).norm() / spacing)));
  for (int j = 0; j < n; ++j) p.push_back(a + (b - a) * (double(j) / n));
}
// Points on the arc of `radius` around `centre` from angle a0 to a1 (a0 included, a1 not).
void arc(std::vector<Eigen::Vector2d>& p, const Eigen::Vector2d& centre, double radius, double a0,
         double a1, double spacing) {
  const int n = std::max(1, static_cast<int>(std::lround(std::abs(a1 - a0) * radius / spacing)));
  for (int j = 0; j < n; ++j) {
    const double a = a0 + (a1 - a0) * j / n;
    p.push_back(centre + radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
}

struct TestGraph {
  IsolineMesh mesh;
  Eigen::MatrixXd plate;
  Eigen::VectorXd edge_shrinkage;
};

// σ per printing edge from its midpoint in the plate; NaN on bridges.
Eigen::VectorXd shrinkage_by_position(const IsolineMesh& mesh, const Eigen::MatrixXd& plate,
                                      const std::function<double(const Eigen::Vector2d&)>& sigma) {
  Eigen::VectorXd s(mesh.E.rows());
  for (Eigen::Index e = 0; e < mesh.E.rows(); ++e) {
    const Eigen::Vector2d mid =
        0.5 * (plate.row(mesh.E(e, 0)) + plate.row(mesh.E(e, 1))).transpose();
    s(e) = mesh.edge_kind[e] == EdgeKind::kBridge ? std::numeric_limits<double>::quiet_NaN()
                                                  : sigma(mid);
  }
  return s;
}

// A dome of `rings` circular isolines (all but the boundary moved in and out by `jitter`, vertex
// by vertex), ring i of radius R (1 - i / rings) around (i e, 0): with
// e != 0 the strips are wider on one side than on the other, so the row counts vary along them
// and the rows double back. A cap fan above the top ring.
TestGraph dome(double radius, int rings, double eccentricity, double spacing,
               const std::function<double(const Eigen::Vector2d&)>& sigma, double jitter = 0) {
  RingMesh r;
  std::vector<std::vector<int>> ring(rings);
  std::vector<Eigen::Vector2d> centre(rings);
  for (int i = 0; i < rings; ++i) {
    centre[i] = Eigen::Vector2d(eccentricity * i, 0);
    std::vector<Eigen::Vector2d> p =
        circle(centre[i], radius * (1 - double(i) / rings), spacing, 0.37 * i);
    for (size_t j = 0; i > 0 && j < p.size(); ++j)  // every other vertex in or out by `jitter`
      p[j] += (j % 2 ? jitter : -jitter) * (p[j] - centre[i]).normalized();
    ring[i] = r.add_loop(p, i, i - 1);
  }
  for (int i = 0; i + 1 < rings; ++i) r.zip(ring[i], ring[i + 1], centre[i + 1]);
  r.fan(ring[rings - 1], centre[rings - 1]);
  TestGraph t{r.mesh(), r.plate(), {}};
  t.edge_shrinkage = shrinkage_by_position(t.mesh, t.plate, sigma);
  return t;
}

// Two hills at (-d, 0) and (d, 0) joined by a saddle: trunk loops (stadiums around both), then at
// the saddle level loop A, loop B and two straight saddle chains between them (y = ±y0) closing
// the "envelope", a rectangular saddle polygon (the chains and the straight inner sides of A and
// B, "D"-shaped loops: a fan from one centre needs a star-shaped polygon, and the envelope must be
// star-shaped around the origin too, which a circle through both corners cannot give), fanned
// from the origin, and each hill's circles up to a cap.
TestGraph two_hills(const std::function<double(const Eigen::Vector2d&)>& sigma) {
  const double d = 20, r0 = 18, w = 5, spacing = 1.0, t0 = kPi / 6;
  const int trunk = 4, hill_rings = 4;  // trunk levels 0..3, hills from level 4
  RingMesh r;
  const Eigen::Vector2d ca(-d, 0), cb(d, 0), origin(0, 0);
  std::vector<std::vector<int>> trunk_loops;
  for (int i = 0; i < trunk; ++i) {
    const double rt = r0 + (trunk - i) * w;  // a stadium: two half circles and two lines
    std::vector<Eigen::Vector2d> p;
    arc(p, cb, rt, -kPi / 2, kPi / 2, spacing);
    straight(p, cb + Eigen::Vector2d(0, rt), ca + Eigen::Vector2d(0, rt), spacing);
    arc(p, ca, rt, kPi / 2, 3 * kPi / 2, spacing);
    straight(p, ca - Eigen::Vector2d(0, rt), cb - Eigen::Vector2d(0, rt), spacing);
    trunk_loops.push_back(r.add_loop(p, i, i - 1));
  }
  auto on = [&](const Eigen::Vector2d& c, double a) {
    return Eigen::Vector2d(c + r0 * Eigen::Vector2d(std::cos(a), std::sin(a)));
  };
  // Loop A: from J2 (angle t0) over the west to J1 (-t0), then straight back up to J2.
  std::vector<Eigen::Vector2d> pa, pb;
  arc(pa, ca, r0, t0, 2 * kPi - t0, spacing);
  const int a_outer = static_cast<int>(pa.size());  // pa[0] = J2, pa[a_outer] = J1
  straight(pa, on(ca, -t0), on(ca, t0), spacing);
  // Loop B: from J_B1 (pi + t0) over the east to J_B2 (pi - t0), then straight down to J_B1.
  arc(pb, cb, r0, kPi + t0, 3 * kPi - t0, spacing);
  const int b_outer = static_cast<int>(pb.size());  // pb[0] = J_B1, pb[b_outer] = J_B2
  straight(pb, on(cb, kPi - t0), on(cb, kPi + t0), spacing);
  const int level_a = trunk;
  const std::vector<int> la = r.add_loop(pa, level_a, trunk - 1);
  const std::vector<int> lb = r.add_loop(pb, level_a, trunk - 1);
  const int j2 = la[0], j1 = la[a_outer], jb1 = lb[0], jb2 = lb[b_outer];
  // Saddle chains (no loop): J1 -> J_B1 along y = -y0 and J_B2 -> J2 along y = +y0.
  std::vector<int> chain1, chain2;
  {
    std::vector<Eigen::Vector2d> p;
    straight(p, r.xy[j1], r.xy[jb1], spacing);
    for (size_t i = 1; i < p.size(); ++i) chain1.push_back(r.add_vertex(p[i], level_a, -1));
    p.clear();
    straight(p, r.xy[jb2], r.xy[j2], spacing);
    for (size_t i = 1; i < p.size(); ++i) chain2.push_back(r.add_vertex(p[i], level_a, -1));
  }
  // The envelope, counter-clockwise around the origin: J1, chain 1, B's outer arc, chain 2, A's
  // outer arc.
  std::vector<int> envelope = {j1};
  envelope.insert(envelope.end(), chain1.begin(), chain1.end());
  for (int i = 0; i < b_outer; ++i) envelope.push_back(lb[i]);
  envelope.push_back(jb2);
  envelope.insert(envelope.end(), chain2.begin(), chain2.end());
  for (int i = 0; i < a_outer; ++i) envelope.push_back(la[i]);
  // The saddle polygon, counter-clockwise: J1, chain 1, B's inner side backwards (J_B1 up to
  // J_B2), chain 2, A's inner side backwards (J2 down to J1).
  std::vector<int> polygon = {j1};
  polygon.insert(polygon.end(), chain1.begin(), chain1.end());
  polygon.push_back(jb1);
  for (int i = static_cast<int>(lb.size()) - 1; i > b_outer; --i) polygon.push_back(lb[i]);
  polygon.push_back(jb2);
  polygon.insert(polygon.end(), chain2.begin(), chain2.end());
  polygon.push_back(j2);
  for (int i = static_cast<int>(la.size()) - 1; i > a_outer; --i) polygon.push_back(la[i]);

  for (int i = 0; i + 1 < trunk; ++i) r.zip(trunk_loops[i], trunk_loops[i + 1], origin);
  r.zip(trunk_loops[trunk - 1], envelope, origin);
  r.fan(polygon, origin);
  for (const auto& [base, centre] : {std::pair{la, ca}, std::pair{lb, cb}}) {
    std::vector<int> lower = base;
    int parent = base == la ? trunk : trunk + 1;
    for (int j = 1; j < hill_rings; ++j) {
      const std::vector<int> ring =
          r.add_loop(circle(centre, r0 - j * w, spacing, 0.3 * j), level_a + j, parent);
      r.zip(lower, ring, centre);
      lower = ring;
      parent = static_cast<int>(r.loops.size()) - 1;
    }
    r.fan(lower, centre);
  }
  TestGraph t{r.mesh(), r.plate(), {}};
  t.edge_shrinkage = shrinkage_by_position(t.mesh, t.plate, sigma);
  return t;
}

const Material& geodesy() {
  static const Material m = load_material("pla-geodesy");
  return m;
}

// --- Reading the toolpath back.

// The traces of a layer: maximal runs of extruding segments, as point index ranges.
std::vector<std::pair<int, int>> traces_of(const PathPolyline& path) {
  std::vector<std::pair<int, int>> traces;
  for (size_t i = 0; i < path.segments.size(); ++i) {
    if (path.segments[i].travel) continue;
    if (i == 0 || path.segments[i - 1].travel) traces.push_back({static_cast<int>(i), 0});
    traces.back().second = static_cast<int>(i) + 1;
  }
  return traces;
}

double extruded_length(const Toolpath& toolpath) {
  double total = 0;
  for (const ToolpathLayer& layer : toolpath.layers) total += extrusion_length(layer);
  return total;
}

// How the beads of one layer (width g) cover a 0.1 mm raster: per pixel the number of distinct
// passes over it (consecutive segments of a trace, within 2 g along it, are one pass: a bead
// does not overlap itself at its joints or U-turn tips).
struct Coverage {
  double covered = 0;  // fraction of the judged pixels with at least one bead
  double triple = 0;   // fraction with three beads or more
  int judged = 0;
};

Coverage coverage(const PathPolyline& path, double width,
                  const std::vector<Eigen::Vector2d>& boundary, double inset) {
  const double step = 0.1, r = width / 2;
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const Eigen::Vector2d& p : boundary) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  lo.array() -= 1, hi.array() += 1;
  const int nx = static_cast<int>((hi.x() - lo.x()) / step) + 1;
  const int ny = static_cast<int>((hi.y() - lo.y()) / step) + 1;
  auto centre = [&](int i, int j) {
    return Eigen::Vector2d(lo.x() + (i + 0.5) * step, lo.y() + (j + 0.5) * step);
  };
  // Stamps a capsule of radius `radius` around segment ab; `visit(pixel, t)` with t the position
  // of the pixel's projection along ab (0..|ab|).
  auto stamp = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double radius,
                   const std::function<void(int, double)>& visit) {
    const Eigen::Vector2d mn = a.cwiseMin(b).array() - radius, mx = a.cwiseMax(b).array() + radius;
    const int i0 = std::max(0, static_cast<int>((mn.x() - lo.x()) / step));
    const int i1 = std::min(nx - 1, static_cast<int>((mx.x() - lo.x()) / step));
    const int j0 = std::max(0, static_cast<int>((mn.y() - lo.y()) / step));
    const int j1 = std::min(ny - 1, static_cast<int>((mx.y() - lo.y()) / step));
    const Eigen::Vector2d ab = b - a;
    const double len2 = ab.squaredNorm(), len = std::sqrt(len2);
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const Eigen::Vector2d p = centre(i, j);
        const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
        if ((a + t * ab - p).norm() <= radius) visit(j * nx + i, t * len);
      }
    }
  };
  // The judged region: inside the boundary polygon and at least `inset` from it.
  std::vector<char> judged(static_cast<size_t>(nx) * ny, 0);
  for (int j = 0; j < ny; ++j) {
    const double y = lo.y() + (j + 0.5) * step;
    std::vector<double> xs;
    for (size_t k = 0; k < boundary.size(); ++k) {
      const Eigen::Vector2d& a = boundary[k];
      const Eigen::Vector2d& b = boundary[(k + 1) % boundary.size()];
      if ((a.y() > y) != (b.y() > y))
        xs.push_back(a.x() + (y - a.y()) / (b.y() - a.y()) * (b.x() - a.x()));
    }
    std::sort(xs.begin(), xs.end());
    for (size_t k = 0; k + 1 < xs.size(); k += 2)
      for (int i = 0; i < nx; ++i) {
        const double x = lo.x() + (i + 0.5) * step;
        if (x > xs[k] && x < xs[k + 1]) judged[static_cast<size_t>(j) * nx + i] = 1;
      }
  }
  for (size_t k = 0; k < boundary.size(); ++k)
    stamp(boundary[k], boundary[(k + 1) % boundary.size()], inset,
          [&](int pixel, double) { judged[pixel] = 0; });
  std::vector<int> count(judged.size(), 0), last_trace(judged.size(), -1);
  std::vector<double> last_at(judged.size(), 0);
  int trace = 0;
  double along = 0;
  for (size_t s = 0; s < path.segments.size(); ++s) {
    if (path.segments[s].travel) {
      ++trace;
      along = 0;
      continue;
    }
    const Eigen::Vector2d a = path.points.row(static_cast<Eigen::Index>(s)).head<2>().transpose();
    const Eigen::Vector2d b =
        path.points.row(static_cast<Eigen::Index>(s) + 1).head<2>().transpose();
    stamp(a, b, r, [&](int pixel, double t) {
      const double here = along + t;
      if (last_trace[pixel] != trace || std::abs(here - last_at[pixel]) > 2 * width) ++count[pixel];
      last_trace[pixel] = trace;
      last_at[pixel] = here;
    });
    along += (b - a).norm();
  }
  Coverage c;
  int covered = 0, triple = 0;
  for (size_t p = 0; p < judged.size(); ++p) {
    if (!judged[p]) continue;
    ++c.judged;
    covered += count[p] >= 1;
    triple += count[p] >= 3;
  }
  c.covered = double(covered) / c.judged;
  c.triple = double(triple) / c.judged;
  return c;
}

std::vector<Eigen::Vector2d> boundary_of(const TestGraph& t) {
  std::vector<Eigen::Vector2d> b;
  for (int v : t.mesh.loops[0].vertices) b.push_back(t.plate.row(v).transpose());
  return b;
}

// σ rising from 10 % on the rim to 35 % at the top (radius 0 .. `radius`).
std::function<double(const Eigen::Vector2d&)> rising_sigma(const Eigen::Vector2d& top,
                                                           double radius) {
  return [=](const Eigen::Vector2d& p) {
    return 0.35 - 0.25 * std::min(1.0, (p - top).norm() / radius);
  };
}

// ------------------------------------------------------------------------------------------------

TEST(ContinuousPaths, DomeIsOneTracePerLayer) {
  const TestGraph t = dome(50, 10, 0.0, 1.0, rising_sigma({0, 0}, 50));
  const ContinuousPaths result = paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy());
  ASSERT_EQ(result.toolpath.layers.size(), 6u);  // the curve's layers
  EXPECT_EQ(result.num_traces, 1);
  ASSERT_EQ(result.hill_loops.size(), 1u);
  EXPECT_EQ(result.hill_loops[0], 9);
  EXPECT_EQ(result.paths_per_hill, std::vector<int>{1});
  EXPECT_EQ(result.num_saddle_patches, 0);
  for (const ToolpathLayer& layer : result.toolpath.layers) {
    ASSERT_EQ(layer.paths.size(), 1u);
    const PathPolyline& path = layer.paths[0];
    for (size_t i = 0; i < path.segments.size(); ++i) {
      // At most the descent to the start: no travel across the plate.
      if (path.segments[i].travel) {
        EXPECT_EQ(i, 0u);
        EXPECT_LT((path.points.row(1) - path.points.row(0)).head<2>().norm(), 1e-12);
      }
    }
  }
  // Concentric strips of equal width: ~ area / g of path per layer.
  const double area = kPi * 50 * 50;
  EXPECT_NEAR(result.path_length, area / 0.48, 0.08 * area / 0.48);
}

TEST(ContinuousPaths, LayerHeightsFollowTheCurveAndZFollowsTheSegments) {
  const TestGraph t = dome(50, 10, 1.5, 1.0, rising_sigma({13.5, 0}, 50));
  ContinuousPathOptions options;
  options.num_layers = 4;
  options.feed_rate = 35;
  const ContinuousPaths result =
      paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy(), options);
  const ThicknessCurve& curve = *geodesy().thickness_curve;
  ASSERT_EQ(result.toolpath.layers.size(), 4u);
  EXPECT_GE(result.min_layer_height, curve.min_layer_height);
  EXPECT_LE(result.max_layer_height, curve.max_layer_height);
  EXPECT_LT(result.min_layer_height, result.max_layer_height);
  for (size_t k = 0; k < result.toolpath.layers.size(); ++k) {
    const PathPolyline& path = result.toolpath.layers[k].paths[0];
    const int layer = static_cast<int>(k) + 1;
    for (size_t i = 0; i < path.segments.size(); ++i) {
      const SegmentStyle& s = path.segments[i];
      EXPECT_DOUBLE_EQ(s.width, 0.48);
      if (s.travel) continue;
      EXPECT_DOUBLE_EQ(s.feed_rate, 35);
      EXPECT_GE(s.layer_height, curve.min_layer_height - 1e-12);
      EXPECT_LE(s.layer_height, curve.max_layer_height + 1e-12);
      // The point a segment ends at lies at k h; the first point of a trace at its first segment's.
      EXPECT_NEAR(path.points(static_cast<Eigen::Index>(i) + 1, 2), layer * s.layer_height, 1e-12);
      if (i == 0 || path.segments[i - 1].travel) {
        EXPECT_NEAR(path.points(static_cast<Eigen::Index>(i), 2), layer * s.layer_height, 1e-12);
      }
    }
  }
  // Every layer prints the same xy.
  const auto& first = result.toolpath.layers[0].paths[0].points;
  for (const ToolpathLayer& layer : result.toolpath.layers)
    EXPECT_EQ(layer.paths[0].points.leftCols(2), first.leftCols(2));
}

TEST(ContinuousPaths, RowShrinkageIsInterpolatedBetweenTheLevels) {
  // σ linear in the distance from the top's centre: every segment, isoline or row, must print
  // the height of the σ at its own position (to the chord error of the rings), not the lower
  // level's (the authors' bug, notes §5.4, would be off by up to one strip's σ step, 0.025).
  const Eigen::Vector2d top(0, 0);
  const auto sigma = rising_sigma(top, 50);
  const TestGraph t = dome(50, 10, 0.0, 1.0, sigma);
  const ContinuousPaths result = paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy());
  const ThicknessCurve& curve = *geodesy().thickness_curve;
  const PathPolyline& path = result.toolpath.layers[0].paths[0];
  double worst = 0;
  int judged = 0;
  for (size_t i = 0; i < path.segments.size(); ++i) {
    const Eigen::Vector2d a = path.points.row(static_cast<Eigen::Index>(i)).head<2>().transpose();
    const Eigen::Vector2d b =
        path.points.row(static_cast<Eigen::Index>(i) + 1).head<2>().transpose();
    if (path.segments[i].travel || (a - top).norm() < 5.5) continue;  // the cap: a fan average
    const double expected = layer_height_for_shrinkage(curve, sigma(0.5 * (a + b)));
    worst = std::max(worst, std::abs(path.segments[i].layer_height - expected));
    ++judged;
  }
  EXPECT_GT(judged, 1000);
  // dθ/dσ is at most ~2.5 mm on this curve, and the chords put σ off by < 0.002.
  EXPECT_LT(worst, 0.006);
}

TEST(ContinuousPaths, TracesAreConnectedAndTravelsClearTheLayer) {
  const TestGraph t = two_hills(rising_sigma({0, 0}, 70));
  const ContinuousPaths result = paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy());
  double longest_edge = 0;
  for (Eigen::Index e = 0; e < t.mesh.E.rows(); ++e) {
    longest_edge =
        std::max(longest_edge, (t.plate.row(t.mesh.E(e, 0)) - t.plate.row(t.mesh.E(e, 1))).norm());
  }
  for (size_t k = 0; k < result.toolpath.layers.size(); ++k) {
    const ToolpathLayer& layer = result.toolpath.layers[k];
    EXPECT_DOUBLE_EQ(layer.z, (k + 1) * result.max_layer_height);
    const PathPolyline& path = layer.paths[0];
    for (size_t i = 0; i < path.segments.size(); ++i) {
      const auto a = path.points.row(static_cast<Eigen::Index>(i));
      const auto b = path.points.row(static_cast<Eigen::Index>(i) + 1);
      EXPECT_GT((b - a).norm(), 1e-9) << "segment " << i;  // no repeated point
      const double xy = (b - a).head<2>().norm();
      if (path.segments[i].travel) {
        // Across the plate only at the layer's top: never through a thicker bead of the layer.
        if (xy > 1e-9) {
          EXPECT_DOUBLE_EQ(a(2), layer.z) << "segment " << i;
          EXPECT_DOUBLE_EQ(b(2), layer.z) << "segment " << i;
        }
      } else {
        // An extruding segment stays within a face or along an edge: no hidden jump.
        EXPECT_GT(xy, 1e-9) << "segment " << i;
        EXPECT_LE(xy, longest_edge + 1e-9) << "segment " << i;
      }
    }
    EXPECT_EQ(static_cast<int>(traces_of(path).size()), result.num_traces);
  }
  EXPECT_NEAR(result.travel_length, travel_length(result.toolpath.layers[0]), 1e-6);
}

TEST(ContinuousPaths, DomeCoversTheSheetWithEvenSpacing) {
  // Eccentric rings: strips 3.5 to 6.5 mm wide, so the row counts change along them.
  const TestGraph t = dome(50, 10, 1.5, 1.0, rising_sigma({13.5, 0}, 50));
  const ContinuousPaths result = paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy());
  EXPECT_GT(result.num_double_backs, 0);
  EXPECT_EQ(result.paths_per_hill, std::vector<int>{1});
  const Coverage c = coverage(result.toolpath.layers[0].paths[0], 0.48, boundary_of(t), 1.0);
  EXPECT_GT(c.judged, 500000);
  EXPECT_GE(c.covered, 0.95);
  EXPECT_LT(c.triple, 0.02);
  std::printf(
      "dome: %d traces, %d double-backs, %.1f m per layer, covered %.2f %%, 3+ beads %.2f %%\n",
      result.num_traces, result.num_double_backs, result.path_length / 1000, 100 * c.covered,
      100 * c.triple);
}

TEST(ContinuousPaths, TwoHillsHaveOneTraceEachAndCoverTheSaddle) {
  const TestGraph t = two_hills(rising_sigma({0, 0}, 70));
  const ContinuousPaths result = paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy());
  EXPECT_EQ(result.num_saddle_patches, 1);
  ASSERT_EQ(result.hill_loops.size(), 2u);
  EXPECT_EQ(result.paths_per_hill, (std::vector<int>{1, 1}));
  const Coverage c = coverage(result.toolpath.layers[0].paths[0], 0.48, boundary_of(t), 1.0);
  EXPECT_GE(c.covered, 0.95);
  EXPECT_LT(c.triple, 0.02);
  std::printf(
      "two hills: %d traces, %d double-backs, %.1f m per layer, covered %.2f %%, 3+ beads "
      "%.2f %%\n",
      result.num_traces, result.num_double_backs, result.path_length / 1000, 100 * c.covered,
      100 * c.triple);
}

// The spacing criterion of the brief, measured by flatmorph's own path judge (toolpath/
// path_quality.h): the distance from samples every g along the paths to the nearest other path
// (or a far part of the same one) lies in [0.5 g, 1.5 g] for nearly all of them, and no point
// leaves the sheet.
TEST(ContinuousPaths, NeighbouringRowsAreSpacedByAboutOnePathWidth) {
  for (const TestGraph& t :
       {dome(50, 10, 1.5, 1.0, rising_sigma({13.5, 0}, 50)), two_hills(rising_sigma({0, 0}, 70))}) {
    const ContinuousPaths result = paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy());
    std::vector<PathPolyline> traces;
    const PathPolyline& path = result.toolpath.layers[0].paths[0];
    for (const auto& [first, last] : traces_of(path)) {
      PathPolyline trace;
      trace.points = path.points.middleRows(first, last - first + 1);
      trace.segments.assign(path.segments.begin() + first, path.segments.begin() + last);
      traces.push_back(std::move(trace));
    }
    PathQualityOptions options;
    options.spacing = 0.48;
    options.spacing_low = 0.5;
    options.spacing_high = 1.5;
    options.sample_step = 1;  // a sample every g
    const PathQuality q = evaluate_path_quality(
        t.plate, t.mesh.F, Eigen::VectorXd::Zero(t.plate.rows()), traces, {}, options);
    EXPECT_GT(q.spacing_in_range, 0.95);
    EXPECT_NEAR(q.spacing_median, 1.0, 0.1);
    EXPECT_EQ(q.points_outside, 0);
    std::printf("spacing in [0.5 g, 1.5 g]: %.2f %% of %d samples, median %.3f g\n",
                100 * q.spacing_in_range, q.samples, q.spacing_median);
  }
}

TEST(ContinuousPaths, RotatingThePlateRotatesThePaths) {
  const TestGraph t = two_hills(rising_sigma({0, 0}, 70));
  const ContinuousPaths a = paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy());
  Eigen::MatrixXd turned(t.plate.rows(), 2);
  turned.col(0) = -t.plate.col(1);
  turned.col(1) = t.plate.col(0);
  const ContinuousPaths b = paths_from_edges(t.mesh, turned, t.edge_shrinkage, geodesy());
  EXPECT_NEAR(extruded_length(a.toolpath), extruded_length(b.toolpath), 1e-6);
  EXPECT_EQ(a.num_traces, b.num_traces);
  const auto& pa = a.toolpath.layers[0].paths[0].points;
  const auto& pb = b.toolpath.layers[0].paths[0].points;
  ASSERT_EQ(pa.rows(), pb.rows());
  double worst = 0;
  for (Eigen::Index i = 0; i < pa.rows(); ++i) {
    worst = std::max(worst, std::abs(pb(i, 0) + pa(i, 1)) + std::abs(pb(i, 1) - pa(i, 0)) +
                                std::abs(pb(i, 2) - pa(i, 2)));
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(ContinuousPaths, OutOfRangeShrinkageIsClampedAndCounted) {
  // σ from -5 % (the path would have to grow) to 50 %: beyond both ends of pla-geodesy's 7.9 to
  // 37.3 %.
  const TestGraph t = dome(30, 6, 0.0, 1.0, [](const Eigen::Vector2d& p) {
    return 0.5 - 0.55 * std::min(1.0, p.norm() / 30);
  });
  const ContinuousPaths result = paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy());
  const ThicknessCurve& curve = *geodesy().thickness_curve;
  EXPECT_GT(result.clamped_segments, 0);
  EXPECT_DOUBLE_EQ(result.min_layer_height, curve.min_layer_height);
  EXPECT_NEAR(result.max_layer_height, curve.max_layer_height, 1e-9);
}

TEST(ContinuousPaths, GcodeWriterAcceptsVaryingZWithinALayer) {
  const TestGraph t = two_hills(rising_sigma({0, 0}, 70));  // 126 x 76 mm
  const ContinuousPaths result = paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy());
  const GcodeResult gcode =
      make_gcode(result.toolpath, load_printer("generic-marlin"), {geodesy()});
  EXPECT_GT(gcode.print_time, 0);
  // Extruding moves of the first layer end at several heights.
  std::istringstream in(gcode.text);
  std::string line;
  int layer = 0;
  std::set<std::string> heights;
  int height_notes = 0;  // ;HEIGHT: annotations (PrusaSlicer's viewer reads them per move)
  while (std::getline(in, line)) {
    if (line.rfind(";LAYER_CHANGE", 0) == 0) ++layer;
    if (layer == 1 && line.rfind(";HEIGHT:", 0) == 0) ++height_notes;
    if (layer != 1 || line.rfind("G1 X", 0) != 0) continue;
    const size_t z = line.find(" Z"), e = line.find(" E");
    if (z != std::string::npos && e != std::string::npos)
      heights.insert(line.substr(z + 2, e - z - 2));
  }
  EXPECT_GT(heights.size(), 10u);
  EXPECT_GT(height_notes, 10);
  std::printf("two hills: print time %.1f min, %zu layer heights in layer 1\n",
              gcode.print_time / 60, heights.size());
}

TEST(ContinuousPaths, RefusesBadInput) {
  const TestGraph t = dome(20, 4, 0.0, 1.0, rising_sigma({0, 0}, 20));
  Material plain = geodesy();
  plain.thickness_curve.reset();
  try {
    paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, plain);
    FAIL() << "no thickness curve";
  } catch (const UserError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::kOption);
  }
  ContinuousPathOptions options;
  options.path_width = 0;
  EXPECT_THROW(paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy(), options), UserError);
  options = {};
  options.num_layers = 0;
  EXPECT_THROW(paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy(), options), UserError);
  EXPECT_THROW(paths_from_edges(t.mesh, t.plate.topRows(3), t.edge_shrinkage, geodesy()),
               std::invalid_argument);
  Eigen::VectorXd bad = t.edge_shrinkage;
  for (Eigen::Index e = 0; e < bad.size(); ++e)
    if (t.mesh.edge_kind[e] != EdgeKind::kBridge) {
      bad(e) = std::numeric_limits<double>::quiet_NaN();
      break;
    }
  EXPECT_THROW(paths_from_edges(t.mesh, t.plate, bad, geodesy()), std::invalid_argument);
}

TEST(ContinuousPaths, ShortRunsOfRowCountsAreMerged) {
  // Strips 5 mm wide printed at g = 0.5 mm sit on the threshold between 8 and 10 rows; rings
  // jittered by ±0.2 mm make the count flip from face to face. The short-run filter must leave
  // runs of at least 10 g, i.e. at most one double-back per 5 mm of strip (110 here); the raw
  // counts make 234.
  const TestGraph t = dome(30, 6, 0.0, 1.0, rising_sigma({0, 0}, 30), 0.2);
  ContinuousPathOptions options;
  options.path_width = 0.5;
  const ContinuousPaths result =
      paths_from_edges(t.mesh, t.plate, t.edge_shrinkage, geodesy(), options);
  double strips = 0;  // total length of the strips' middles
  for (int i = 0; i + 1 < 6; ++i) strips += 2 * kPi * 30 * (1 - (i + 0.5) / 6);
  EXPECT_LE(result.num_double_backs, strips / (10 * 0.5));
  EXPECT_EQ(result.num_traces, 1);
  std::printf("jittered dome: %d double-backs over %.0f mm of strips\n", result.num_double_backs,
              strips);
}

// The real meshing (isoline_mesh) of the built-in height fields at 100 mm, its plate the
// footprint itself (any planar layout of the mesh will do for the toolpaths): one trace per hill,
// the sheet covered.
class RealMesh : public ::testing::TestWithParam<std::string> {};

TEST_P(RealMesh, OneTracePerHillAndCovered) {
  HeightFieldExampleOptions size;
  size.diameter_mm = 100;
  size.height_mm = 22;
  const IsolineMesh m = isoline_mesh(height_field_example(GetParam(), size), {}, GetParam());
  const Eigen::MatrixXd plate = m.V.leftCols(2);
  const Eigen::VectorXd sigma = shrinkage_by_position(m, plate, rising_sigma({0, 0}, 50));
  const ContinuousPaths result = paths_from_edges(m, plate, sigma, geodesy());
  ASSERT_GE(result.hill_loops.size(), 1u);
  for (int count : result.paths_per_hill) EXPECT_EQ(count, 1);
  std::vector<Eigen::Vector2d> boundary;
  for (int v : m.loops[0].vertices) boundary.push_back(plate.row(v).transpose());
  const Coverage c = coverage(result.toolpath.layers[0].paths[0], 0.48, boundary, 1.0);
  EXPECT_GE(c.covered, 0.95);
  EXPECT_LT(c.triple, 0.02);
  std::printf(
      "%s: %zu hills, %d traces, %d double-backs, %d saddle patches, %.1f m per layer, "
      "covered %.2f %%, 3+ beads %.2f %%\n",
      GetParam().c_str(), result.hill_loops.size(), result.num_traces, result.num_double_backs,
      result.num_saddle_patches, result.path_length / 1000, 100 * c.covered, 100 * c.triple);
}

INSTANTIATE_TEST_SUITE_P(ContinuousPaths, RealMesh,
                         ::testing::Values("hill", "saddle", "island", "ridge"));

TEST(ContinuousPaths, CapPrintingGraphIsOneTrace) {
  // The shared cap fixture (rings turned against each other, zipped by angle): 120 mm across.
  const testing::CapPrintingGraph cap = testing::cap_printing_graph(80, 0.8, 8, 1.0, 1.08);
  const Eigen::VectorXd sigma =
      shrinkage_by_position(cap.mesh, cap.plate, rising_sigma({0, 0}, 60));
  const ContinuousPaths result = paths_from_edges(cap.mesh, cap.plate, sigma, geodesy());
  EXPECT_EQ(result.num_traces, 1);
  EXPECT_EQ(result.paths_per_hill, std::vector<int>{1});
}

}  // namespace
}  // namespace flatmorph::continuous_paths_test
