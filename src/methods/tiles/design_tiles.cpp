#include "methods/tiles/design_tiles.h"

#include <fmt/core.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/file_text.h"
#include "common/stopwatch.h"
#include "mesh/polygon.h"
#include "plate/laminate.h"

namespace flatmorph {
namespace {

// Every boundary point within 0.5 % of R from the boundary's centroid: the rings are circles.
bool is_circle(const TileOutline& outline) {
  if (!outline.holes.empty() || outline.boundary.rows() < 12) return false;
  const Eigen::RowVector2d c = outline.boundary.colwise().mean();
  const Eigen::VectorXd r = (outline.boundary.rowwise() - c).rowwise().norm();
  return r.maxCoeff() - r.minCoeff() < 5e-3 * r.maxCoeff();
}

// The polygon with the holes a profile's hole radius cuts out (the rings at depth R − r_h).
TileOutline with_profile_hole(const TileOutline& outline, double design_radius,
                              double hole_radius) {
  TileOutline out = outline;
  if (!(hole_radius > 0)) return out;
  RingOptions hole;
  hole.pitch = 4 * design_radius;
  hole.first_offset = design_radius - hole_radius;
  const TileRings rings = tile_rings(outline, hole);
  for (const Ring& ring : rings.rings) {
    if (ring.level != 0 || ring.points.rows() < 3) continue;
    out.holes.push_back(ring.points.colwise().reverse());
  }
  return out;
}

double interpolate(const Eigen::VectorXd& x, const Eigen::VectorXd& y, double at) {
  // x ascending
  const Eigen::Index n = x.size();
  if (at <= x(0)) return y(0);
  if (at >= x(n - 1)) return y(n - 1);
  const Eigen::Index i = std::upper_bound(x.data(), x.data() + n, at) - x.data() - 1;
  const double t = (at - x(i)) / (x(i + 1) - x(i));
  return y(i) + t * (y(i + 1) - y(i));
}

// 1 mm, or the edge at which the refined mesh has about 8000 faces (CGAL's 25° criterion gives
// about one face per 0.2 e² of sheet): the simulation's cost grows with the faces.
double automatic_mesh_edge(const std::vector<TileOutline>& regions) {
  double area = 0;
  for (const TileOutline& region : regions) {
    area += std::abs(signed_area(region.boundary));
    for (const Eigen::MatrixX2d& hole : region.holes) area -= std::abs(signed_area(hole));
  }
  return std::max(1.0, std::sqrt(area / (0.2 * 8000)));
}

// The vertices of tile t along its inscribed radii: within a band around the segments from its
// deepest vertex (the apex) to the boundary points nearest it (every vertex for a circle), away
// from the apex (flat radius ≥ 0.2 R), which rounds over a few sheet thicknesses whatever the
// shrink.
std::vector<int> inscribed_radius_vertices(const TileResult& tile, const TilePlate& plate, int t,
                                           double pitch) {
  const double R = tile.levels.design_radius;
  std::vector<int> vertices;
  int apex = -1;
  for (Eigen::Index v = 0; v < plate.vertex_tile.size(); ++v) {
    if (plate.vertex_tile(v) != t) continue;
    vertices.push_back(static_cast<int>(v));
    if (apex < 0 || plate.vertex_depth(v) > plate.vertex_depth(apex)) apex = static_cast<int>(v);
  }
  if (apex < 0) return vertices;
  const auto away_from_apex = [&](int v) { return plate.vertex_depth(v) <= 0.8 * R; };
  if (tile.circular) {
    std::erase_if(vertices, [&](int v) { return !away_from_apex(v); });
    return vertices;
  }
  const Eigen::Vector2d centre = plate.design.plate.row(apex).transpose();
  const double inradius = plate.vertex_depth(apex);
  std::vector<Eigen::Vector2d> directions;
  for (int v : vertices) {
    if (plate.vertex_depth(v) > 1e-6) continue;
    const Eigen::Vector2d p = plate.design.plate.row(v).transpose();
    if ((p - centre).norm() <= inradius * 1.02 + pitch)
      directions.push_back((p - centre).normalized());
  }
  const double band = std::max(pitch, 0.03 * R);
  std::vector<int> out;
  for (int v : vertices) {
    if (!away_from_apex(v)) continue;
    const Eigen::Vector2d q = plate.design.plate.row(v).transpose() - centre;
    for (const Eigen::Vector2d& u : directions) {
      if (q.dot(u) >= 0 && std::abs(q.x() * u.y() - q.y() * u.x()) <= band) {
        out.push_back(v);
        break;
      }
    }
  }
  return out;
}

// The risen profile along the inscribed radii against the target, per ring level (the levels
// the radii cross, from the rim inward): the mean over the level's vertices of their height above
// the rim's centroid (along the axis through the apex) minus the target's at their flat radius,
// mm. The mean over a level is the tile's profile as the circle's rings give it; what the radii
// add to it, the spread about that mean, is how they differ from one another: a polygon's apex is
// a vertex where four faces meet, and it flexes at almost no cost (the rounded square tilts its
// apex 1-2 mm toward one side, whichever the mesh favours), which no per-ring shrink can set.
struct ProfileResiduals {
  Eigen::VectorXd per_level;  // mm
  double spread_rms = 0;      // mm, the vertices' rms about their level's mean
};

ProfileResiduals profile_residuals(const TileResult& tile, const TilePlate& plate,
                                   const Eigen::MatrixXd& V, int t, double pitch) {
  const double R = tile.levels.design_radius;
  const std::vector<int> band = inscribed_radius_vertices(tile, plate, t, pitch);
  int apex = -1;
  Eigen::RowVector3d rim = Eigen::RowVector3d::Zero();
  int rim_count = 0;
  for (Eigen::Index v = 0; v < plate.vertex_tile.size(); ++v) {
    if (plate.vertex_tile(v) != t) continue;
    if (apex < 0 || plate.vertex_depth(v) > plate.vertex_depth(apex)) apex = static_cast<int>(v);
    if (plate.vertex_depth(v) < 1e-6) {
      rim += V.row(v);
      ++rim_count;
    }
  }
  ProfileResiduals out;
  if (apex < 0 || rim_count == 0) return out;
  rim /= rim_count;
  const Eigen::RowVector3d axis = (V.row(apex) - rim).normalized();
  const double length = profile_length(tile.profile);
  const double rim_z = profile_point_at_length(tile.profile, std::min(R, length)).y();
  const int num_levels = static_cast<int>(tile.levels.levels.size());
  std::vector<int> vertex_level(band.size());
  std::vector<double> residual(band.size());
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(num_levels);
  Eigen::VectorXi count = Eigen::VectorXi::Zero(num_levels);
  for (size_t i = 0; i < band.size(); ++i) {
    const int v = band[i];
    const double r = std::max(0.0, R - plate.vertex_depth(v));
    const double target = profile_point_at_length(tile.profile, std::min(length, r)).y() - rim_z;
    residual[i] = (V.row(v) - rim).dot(axis) - target;
    vertex_level[i] = std::clamp(static_cast<int>(std::lround(plate.vertex_depth(v) / pitch - 0.5)),
                                 0, num_levels - 1);
    sum(vertex_level[i]) += residual[i];
    ++count(vertex_level[i]);
  }
  std::vector<double> means;
  for (int l = 0; l < num_levels; ++l) {
    if (count(l) > 0) means.push_back(sum(l) / count(l));
  }
  out.per_level =
      Eigen::Map<const Eigen::VectorXd>(means.data(), static_cast<Eigen::Index>(means.size()));
  double spread = 0;
  for (size_t i = 0; i < band.size(); ++i) {
    const double d = residual[i] - sum(vertex_level[i]) / count(vertex_level[i]);
    spread += d * d;
  }
  if (!band.empty()) out.spread_rms = std::sqrt(spread / static_cast<double>(band.size()));
  return out;
}

// The rms of the residuals about their mean: the profile's shape error, whatever the height the
// rim is measured from.
double rms_about_mean(const Eigen::VectorXd& residuals) {
  if (residuals.size() == 0) return 0;
  return std::sqrt((residuals.array() - residuals.mean()).square().mean());
}

// The tile's risen shape measured against its design (TileMeasure).
TileMeasure measure_tile(const TileResult& tile, const TilePlate& plate, const Eigen::MatrixXd& V,
                         int t, double pitch) {
  TileMeasure m;
  const double R = tile.levels.design_radius;
  std::vector<int> vertices;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (plate.vertex_tile(v) == t) vertices.push_back(static_cast<int>(v));
  }
  if (vertices.empty()) return m;
  int apex = vertices[0];
  Eigen::RowVector3d rim = Eigen::RowVector3d::Zero();
  int rim_count = 0;
  for (int v : vertices) {
    if (plate.vertex_depth(v) > plate.vertex_depth(apex)) apex = v;
    if (plate.vertex_depth(v) < 1e-6) {
      rim += V.row(v);
      ++rim_count;
    }
  }
  if (rim_count == 0) return m;
  rim /= rim_count;
  const Eigen::RowVector3d to_apex = V.row(apex) - rim;
  m.height_mm = to_apex.norm();
  if (!(m.height_mm > 1e-9)) return m;
  const Eigen::RowVector3d axis = to_apex / m.height_mm;
  m.side = axis.z() >= 0 ? +1 : -1;

  // The geometric tile: the printed shrink per level, forward (tile_profile.h), by flat radius.
  const int num_levels = static_cast<int>(tile.levels.levels.size());
  std::vector<int> printed;
  for (int l = num_levels - 1; l >= 0; --l) {
    if (tile.levels.levels[l].printed) printed.push_back(l);
  }
  Eigen::VectorXd radii(printed.size()), shrink(printed.size());
  for (size_t i = 0; i < printed.size(); ++i) {
    radii(static_cast<Eigen::Index>(i)) = tile.levels.levels[printed[i]].flat_radius;
    shrink(static_cast<Eigen::Index>(i)) = tile.levels.levels[printed[i]].shrinkage;
  }
  const Eigen::MatrixX2d forward = profile_from_shrinkage(radii, shrink).points;
  // Heights above the rim: the forward profile falls from its first ring; the rim is its last.
  // Extend to the apex (r = 0) and the outline (r = R) along the end rings' slopes.
  Eigen::VectorXd r_axis(radii.size() + 2), rho_geo(radii.size() + 2), z_geo(radii.size() + 2);
  const double z_rim_ring = forward(forward.rows() - 1, 1);
  for (Eigen::Index i = 0; i < radii.size(); ++i) {
    r_axis(i + 1) = radii(i);
    rho_geo(i + 1) = forward(i, 0);
    z_geo(i + 1) = forward(i, 1) - z_rim_ring;
  }
  const Eigen::Index last = radii.size();
  const double outer_gap = R - radii(last - 1);
  const double outer_slope = 1 - shrink(last - 1);
  r_axis(last + 1) = R;
  rho_geo(last + 1) = rho_geo(last) + outer_slope * outer_gap;
  z_geo(last + 1) = -std::sqrt(std::max(0.0, 1 - outer_slope * outer_slope)) * outer_gap;
  const double inner_slope = 1 - shrink(0);
  r_axis(0) = 0;
  rho_geo(0) = 0;
  z_geo(0) = z_geo(1) + std::sqrt(std::max(0.0, 1 - inner_slope * inner_slope)) * radii(0);
  z_geo.array() -= z_geo(last + 1);
  m.expected_height_mm = z_geo(0);

  // Per level: the mean radius and height of the tile's vertices at that depth.
  Eigen::VectorXd sum_rho = Eigen::VectorXd::Zero(num_levels), sum_z = sum_rho;
  Eigen::VectorXd sum_radius_error = sum_rho;
  Eigen::VectorXi count = Eigen::VectorXi::Zero(num_levels);
  for (int v : vertices) {
    const Eigen::RowVector3d d = V.row(v) - rim;
    const double z = d.dot(axis);
    const Eigen::RowVector3d radial =
        V.row(v) - V.row(apex) - (V.row(v) - V.row(apex)).dot(axis) * axis;
    const double rho = radial.norm();
    const double r = R - plate.vertex_depth(v);
    const int l = std::clamp(static_cast<int>(std::lround(plate.vertex_depth(v) / pitch - 0.5)), 0,
                             num_levels - 1);
    sum_radius_error(l) += rho - interpolate(r_axis, rho_geo, r);
    sum_rho(l) += rho;
    sum_z(l) += z;
    ++count(l);
  }
  // A ring's radius: the mean over its vertices (the outermost ring's free edge left out).
  for (int l = 1; tile.circular && l < num_levels; ++l) {
    if (count(l) > 0) {
      m.ring_radius_error_mm =
          std::max(m.ring_radius_error_mm, std::abs(sum_radius_error(l) / count(l)));
    }
  }
  std::vector<Eigen::Vector2d> simulated;
  for (int l = num_levels - 1; l >= 0; --l) {
    if (count(l) > 0) simulated.push_back({sum_rho(l) / count(l), sum_z(l) / count(l)});
  }
  m.simulated.resize(static_cast<Eigen::Index>(simulated.size()), 2);
  for (size_t i = 0; i < simulated.size(); ++i) {
    m.simulated.row(static_cast<Eigen::Index>(i)) = simulated[i].transpose();
  }
  m.geometric.resize(r_axis.size(), 2);
  m.geometric.col(0) = rho_geo;
  m.geometric.col(1) = z_geo;

  // Depth between 0.2 R and the rim: simulated from the vertices near r = 0.2 R.
  double z_inner = 0;
  int inner_count = 0;
  for (int v : vertices) {
    const double r = R - plate.vertex_depth(v);
    if (std::abs(r - 0.2 * R) <= std::max(pitch, 0.02 * R)) {
      z_inner += (V.row(v) - rim).dot(axis);
      ++inner_count;
    }
  }
  if (inner_count > 0) {
    m.depth_mm = z_inner / inner_count;
    m.expected_depth_mm = interpolate(r_axis, z_geo, 0.2 * R);
    m.depth_error_pct = 100 * (m.depth_mm - m.expected_depth_mm) / m.expected_depth_mm;
  }

  // The target: the profile asked, at arc length r from the apex, its height above the rim.
  const double length = profile_length(tile.profile);
  const int samples = 64;
  m.target.resize(samples + 1, 2);
  const Eigen::Vector2d rim_point = profile_point_at_length(tile.profile, std::min(R, length));
  for (int i = 0; i <= samples; ++i) {
    const Eigen::Vector2d p =
        profile_point_at_length(tile.profile, std::min(length, R * i / samples));
    m.target.row(i) << p.x(), p.y() - rim_point.y();
  }
  const ProfileResiduals residuals = profile_residuals(tile, plate, V, t, pitch);
  m.profile_rms_mm = rms_about_mean(residuals.per_level);
  m.profile_spread_mm = residuals.spread_rms;
  return m;
}

// Beyond the paper (whose mapping Sh′ is exact only for circles): the per-ring shrink of the only
// tile of `design`, a polygon, refined so that its simulated profile along the inscribed radii
// comes closest to the target (the circle's profile), in shape (the residuals' mean removed).
// Sh = Sh′ + Σ_k c_k φ_k(r) with hat functions φ_k at `knots` flat radii over [0, R], by
// Levenberg–Marquardt steps on a finite-difference Jacobian, each forward solve warm-started at
// the last equilibrium. The result is judged from the flat sheet again by the caller.
Eigen::VectorXd optimized_level_shrinkage(const TilesDesign& design,
                                          const std::vector<TileOutline>& outlines,
                                          const TilesDesignOptions& options) {
  const TileResult& tile = design.tiles[0];
  const double pitch = options.levels.pitch;
  const double R = tile.levels.design_radius;
  const int num_levels = static_cast<int>(tile.levels.levels.size());
  constexpr int kKnots = 6;
  Eigen::MatrixXd basis = Eigen::MatrixXd::Zero(num_levels, kKnots);
  for (int m = 0; m < num_levels; ++m) {
    const double x = std::clamp(tile.levels.levels[m].flat_radius / R, 0.0, 1.0) * (kKnots - 1);
    const int k = std::min(static_cast<int>(std::floor(x)), kKnots - 2);
    basis(m, k) = 1 - (x - k);
    basis(m, k + 1) = x - k;
  }
  Eigen::VectorXd mapped(num_levels);
  for (int m = 0; m < num_levels; ++m) mapped(m) = tile.levels.levels[m].shrinkage;

  struct Evaluation {
    Eigen::VectorXd residual;  // about its mean
    Eigen::MatrixXd V;
    bool ok = false;
  };
  auto evaluate = [&](const Eigen::VectorXd& c, const Eigen::MatrixXd& start) {
    TileResult trial = tile;
    set_level_shrinkage(trial.levels, mapped + basis * c, options.material, options.levels);
    const TilePlate plate =
        tile_plate(design.mesh, outlines, {trial.levels}, pitch, options.material, nullptr);
    PlateProblem problem;
    problem.plate = plate.design.plate;
    problem.F = plate.design.F;
    problem.rest_forms = laminate(plate.design.stack);
    SimulationOptions simulation = options.simulation;
    simulation.max_iterations = 40;
    const SimulationResult result = simulate(problem, start, simulation);
    Evaluation e;
    e.ok = result.converged;
    e.V = result.V;
    e.residual = profile_residuals(trial, plate, result.V, 0, pitch).per_level;
    e.residual.array() -= e.residual.mean();
    return e;
  };
  Eigen::VectorXd c = Eigen::VectorXd::Zero(kKnots);
  Evaluation current = evaluate(c, design.simulation.V);
  if (!current.ok) return mapped;
  const double step = 0.005;  // half a point of shrink
  constexpr double kMaxStep = 0.02;
  double damping = 1e-3;
  for (int iteration = 0; iteration < options.optimize_iterations; ++iteration) {
    report_progress(options.progress,
                    {"optimize", iteration + 1, options.optimize_iterations,
                     std::sqrt(current.residual.squaredNorm() /
                               std::max<Eigen::Index>(1, current.residual.size())),
                     "per-ring shrink of the polygonal tile"});
    Eigen::MatrixXd J(current.residual.size(), kKnots);
    bool ok = true;
    for (int k = 0; k < kKnots && ok; ++k) {
      Eigen::VectorXd probe = c;
      probe(k) += step;
      const Evaluation e = evaluate(probe, current.V);
      ok = e.ok && e.residual.size() == current.residual.size();
      if (ok) J.col(k) = (e.residual - current.residual) / step;
    }
    if (!ok) break;
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * current.residual;
    bool accepted = false;
    for (int trial = 0; trial < 4 && !accepted; ++trial) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal().array() += damping * (JtJ.diagonal().maxCoeff() + 1e-12);
      Eigen::VectorXd delta = A.ldlt().solve(-g);
      // A trust region: no knot's shrink moves by more than 2 points per step, so the sheet stays
      // on the branch the flat sheet reaches (long steps found rims that buckle from flat).
      const double longest = delta.cwiseAbs().maxCoeff();
      if (longest > kMaxStep) delta *= kMaxStep / longest;
      const Evaluation e = evaluate(c + delta, current.V);
      if (e.ok && e.residual.size() == current.residual.size() &&
          e.residual.squaredNorm() < current.residual.squaredNorm()) {
        c += delta;
        current = e;
        damping = std::max(1e-6, damping / 3);
        accepted = true;
      } else {
        damping *= 10;
      }
    }
    if (!accepted) break;
  }
  return mapped + basis * c;
}

}  // namespace

TilesDesign design_tiles(const TileLayout& layout, const TilesDesignOptions& options) {
  const auto start = Clock::now();
  const double pitch = options.levels.pitch;
  const ProgressCallback& progress = options.progress;
  TilesDesign design;
  design.layout = layout;
  if (layout.tiles.empty()) {
    throw UserError(ErrorCategory::kOption, fmt::format("{}: no tile to design", layout.source));
  }

  report_progress(progress, {"rings", 0, 0, NAN, "offsets, profiles and layer heights"});
  auto t0 = Clock::now();
  std::vector<TileOutline> outlines;
  for (size_t i = 0; i < layout.tiles.size(); ++i) {
    const TileSpec& spec = layout.tiles[i];
    TileResult tile;
    RingOptions ring_options;
    ring_options.pitch = pitch;
    tile.rings = tile_rings(spec.outline, ring_options);
    const double R = tile.rings.max_depth;
    int num_levels = 0;
    for (const Ring& ring : tile.rings.rings) num_levels = std::max(num_levels, ring.level + 1);
    if (!spec.profile_csv.empty()) {
      // A drawn profile keeps its shape: scaled as a whole to the tile's radius.
      const std::string csv = read_file_text(spec.profile_csv, "profile CSV");
      tile.profile = scale_profile_to_length(read_profile_csv(csv, spec.profile_csv.string()), R);
    } else {
      tile.profile = tile_profile(spec.profile, R, spec.height_mm);
    }
    tile.levels = tile_levels(tile.profile, R, num_levels, spec.side, spec.hole_radius_mm,
                              options.material, options.levels);
    tile.circular = is_circle(spec.outline);
    if (tile.levels.printability.any_clamped) {
      design.warnings.push_back(
          fmt::format("{}: {}", spec.outline.source, tile.levels.printability.warning));
    }
    outlines.push_back(with_profile_hole(spec.outline, R, spec.hole_radius_mm));
    design.tiles.push_back(std::move(tile));
  }
  design.times.rings = seconds_since(t0);

  report_progress(progress, {"mesh", 0, 0, NAN, "the sheet for the simulator"});
  t0 = Clock::now();
  // The lattice's material prints with a second tool when it is another material.
  const bool second_tool = options.lattice_material.name != options.material.name;
  std::vector<TileOutline> regions = outlines;
  if (layout.has_lattice) {
    std::vector<TileOutline> tile_outlines;
    for (const TileSpec& spec : layout.tiles) tile_outlines.push_back(spec.outline);
    design.lattice = tile_lattice(tile_outlines, layout.lattice, pitch, second_tool ? 1 : 0);
    regions.insert(regions.end(), design.lattice.regions.begin(), design.lattice.regions.end());
  }
  SheetMeshOptions mesh_options;
  mesh_options.max_edge = options.mesh_edge > 0 ? options.mesh_edge : automatic_mesh_edge(regions);
  design.mesh = sheet_mesh(regions, mesh_options);
  design.mesh_edge = mesh_options.max_edge;
  std::vector<TileLevels> levels;
  std::vector<TileRings> rings;
  for (const TileResult& tile : design.tiles) {
    levels.push_back(tile.levels);
    rings.push_back(tile.rings);
  }
  TilePlateLattice lattice;
  if (layout.has_lattice) {
    lattice.material = options.lattice_material;
    lattice.layer_height = layout.lattice.layer_height_mm;
    lattice.layers = layout.lattice.layers;
    lattice.fill = design.lattice.fill;
  }
  design.plate = tile_plate(design.mesh, outlines, levels, pitch, options.material,
                            layout.has_lattice ? &lattice : nullptr);
  design.times.mesh = seconds_since(t0);

  // The judge: the printed stack simulated from the flat sheet.
  auto simulate_sheet = [&](const std::vector<TileLevels>& tile_levels_now) {
    PlateProblem problem;
    problem.plate = design.plate.design.plate;
    problem.F = design.plate.design.F;
    problem.rest_forms = laminate(design.plate.design.stack);
    return simulate(problem, tile_start(design.plate, tile_levels_now), options.simulation);
  };
  if (options.simulate) {
    report_progress(progress, {"simulate", 0, 0, NAN, "the printed sheet in hot water"});
    t0 = Clock::now();
    design.simulation = simulate_sheet(levels);
    design.simulated = true;
    for (size_t i = 0; i < design.tiles.size(); ++i) {
      design.tiles[i].measure = measure_tile(design.tiles[i], design.plate, design.simulation.V,
                                             static_cast<int>(i), pitch);
    }
    design.times.simulation = seconds_since(t0);

    for (TileResult& tile : design.tiles) tile.mapped_profile_rms_mm = tile.measure.profile_rms_mm;
    TileResult& only = design.tiles[0];
    if (options.optimize && design.tiles.size() == 1 && !only.circular && !layout.has_lattice &&
        design.simulation.converged) {
      t0 = Clock::now();
      const Eigen::VectorXd shrinkage = optimized_level_shrinkage(design, outlines, options);
      TileResult optimized = only;
      set_level_shrinkage(optimized.levels, shrinkage, options.material, options.levels);
      const TilePlate mapped_plate = design.plate;
      design.plate =
          tile_plate(design.mesh, outlines, {optimized.levels}, pitch, options.material, nullptr);
      const SimulationResult judged = simulate_sheet({optimized.levels});
      optimized.measure = measure_tile(optimized, design.plate, judged.V, 0, pitch);
      if (judged.converged && optimized.measure.profile_rms_mm < only.measure.profile_rms_mm) {
        optimized.optimized = true;
        only = std::move(optimized);
        design.simulation = judged;
        levels[0] = only.levels;
      } else {
        design.plate = mapped_plate;
      }
      design.times.optimization = seconds_since(t0);
    }
  }

  report_progress(progress, {"paths", 0, 0, NAN, "one continuous path per tile and pass"});
  t0 = Clock::now();
  TilePassOptions pass_options;
  pass_options.pitch = pitch;
  pass_options.feed_rate = options.feed_rate;
  design.print = tiles_toolpath(rings, levels, design.lattice.passes, pass_options);
  design.times.paths = seconds_since(t0);
  design.times.total = seconds_since(start);
  return design;
}

}  // namespace flatmorph
