#include "toolpath/layer_paths.h"

#include <fmt/core.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "common/angles.h"
#include "common/error.h"
#include "common/stopwatch.h"
#include "mesh/operators.h"
#include "mesh/topology.h"
#include "plate/layer_stack.h"
#include "toolpath/isolines.h"
#include "toolpath/line_field.h"
#include "toolpath/perimeters.h"
#include "toolpath/refine_plate.h"
#include "toolpath/simplify.h"

namespace flatmorph {
namespace {

// The stripe patterns trace one direction field per layer over the whole plate at one bead
// height with one tool: a layer that varies, or leaves faces out, needs another tracing.
void check_options(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F, const LayerStack& stack,
                   const LayerPathOptions& o) {
  const auto fail = [](const std::string& message) {
    throw UserError(ErrorCategory::kOption, "toolpaths: " + message);
  };
  if (plate.cols() < 2 || F.rows() == 0) fail("the plate has no faces; give a flattened plate");
  if (stack.num_layers() < 1) fail("the stack has no layer; give at least one printed layer");
  if (stack.num_faces() != F.rows()) {
    fail(fmt::format("the stack has {} faces for a plate of {}; give one value per face",
                     stack.num_faces(), F.rows()));
  }
  check_layer_stack(stack);
  for (int k = 0; k < stack.num_layers(); ++k) {
    const Layer& l = stack.layers[k];
    if ((l.material.array() != l.material(0)).any() || l.material(0) == Layer::kNotCovered) {
      fail(
          fmt::format("layer {} does not print one material over the whole plate; the stripe "
                      "toolpaths need layers that cover every face with one material",
                      k + 1));
    }
    if ((l.printed_thickness.array() != l.printed_thickness(0)).any()) {
      fail(
          fmt::format("layer {}'s printed thickness varies over the plate; the stripe toolpaths "
                      "print each layer at one height",
                      k + 1));
    }
  }
  if (!(o.spacing > 0)) fail("the path spacing (extrusion width) must be positive (mm)");
  if (!(o.edge_ratio > 0)) fail("the refinement edge ratio must be positive");
  if (!(o.min_path_length >= 0)) fail("the minimum path length must not be negative");
  if (!(o.min_end_gap >= 0)) fail("the minimum gap at path ends must not be negative");
  if (!(o.simplify_tolerance_mm >= 0)) fail("the simplification tolerance must not be negative");
  if (o.perimeters < 0) fail("the number of perimeter loops must not be negative");
  if (o.field_corrections < 0) fail("the number of field corrections must not be negative");
}

// Per fine vertex direction from the coarse per-vertex line field, interpolated linearly.
Eigen::VectorXd refined_theta(const RefinedPlate& refined, const Eigen::VectorXcd& coarse) {
  const Eigen::VectorXd re = refined.S * coarse.real(), im = refined.S * coarse.imag();
  Eigen::VectorXcd u(re.size());
  u.real() = re;
  u.imag() = im;
  return line_field_angle(u);
}

// Per plate face, how far the stripes of one layer turned from the layer's direction theta (rad):
// the area-weighted mean direction of the stripes over the face's refined faces (doubled angles)
// minus theta. 0 where no refined face has a direction (singularities, forks).
// Per vertex the area-weighted mean of the values of the faces around it.
Eigen::VectorXd face_to_vertex_mean(const Eigen::MatrixXi& F, const Eigen::VectorXd& areas,
                                    const Eigen::VectorXd& values, Eigen::Index num_vertices) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(num_vertices), weight = sum;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int j = 0; j < 3; ++j) {
      sum(F(f, j)) += areas(f) * values(f);
      weight(F(f, j)) += areas(f);
    }
  }
  return sum.cwiseQuotient(weight.cwiseMax(1e-300));
}

Eigen::VectorXd stripe_turn(const Eigen::MatrixXi& F, const RefinedPlate& refined,
                            const Eigen::VectorXd& refined_areas, const StripePattern& pattern,
                            const Eigen::VectorXd& theta) {
  const Eigen::VectorXd direction = stripe_direction(refined.V, refined.F, pattern);
  Eigen::VectorXcd sum = Eigen::VectorXcd::Zero(F.rows());
  for (Eigen::Index f = 0; f < refined.F.rows(); ++f) {
    if (std::isnan(direction(f))) continue;
    sum(refined.face_parent(f)) += refined_areas(f) * std::polar(1.0, 2 * direction(f));
  }
  Eigen::VectorXd turn = Eigen::VectorXd::Zero(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (std::abs(sum(f)) > 0) turn(f) = std::remainder(std::arg(sum(f)) / 2 - theta(f), kPi);
  }
  return turn;
}

// The layers' stripes and how far they turned from the stack's directions, per layer and plate
// face (rad), with the area-weighted mean |turn| over every layer and face.
struct TracedStripes {
  std::vector<StripePattern> patterns;
  std::vector<Eigen::VectorXd> turn;
  double mean_turn = 0;
};

TracedStripes measure_stripes(const Eigen::MatrixXi& F, const Eigen::VectorXd& areas,
                              const RefinedPlate& refined, const Eigen::VectorXd& refined_areas,
                              const LayerStack& stack, std::vector<StripePattern> patterns) {
  TracedStripes out;
  out.patterns = std::move(patterns);
  for (size_t k = 0; k < out.patterns.size(); ++k) {
    out.turn.push_back(
        stripe_turn(F, refined, refined_areas, out.patterns[k], stack.layers[k].theta));
    out.mean_turn += areas.dot(out.turn.back().cwiseAbs());
  }
  out.mean_turn /= areas.sum() * static_cast<double>(out.patterns.size());
  return out;
}

}  // namespace

Eigen::VectorXd layer_direction_vertex(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                                       const Eigen::VectorXd& layer_theta_face) {
  return line_field_angle(face_to_vertex_line_field(plate, F, layer_theta_face));
}

LayerPaths stack_layer_paths(const Eigen::MatrixXd& plate, const Eigen::MatrixXi& F,
                             const LayerStack& stack, const LayerPathOptions& options) {
  check_options(plate, F, stack, options);
  const int num_layers = stack.num_layers();
  LayerPaths out;
  const double s = options.spacing;

  Clock::time_point start = Clock::now();
  const RefinedPlate refined = refine_plate(plate.leftCols<2>(), F, options.edge_ratio * s);
  const EdgeTopology topology = edge_topology(refined.F);
  out.refined_faces = static_cast<int>(refined.F.rows());
  out.refined_mean_edge_mm = mean_edge(refined.V, refined.F);
  out.refined_max_edge_mm = longest_edge(refined.V, refined.F);
  out.timings.refinement = seconds_since(start);

  start = Clock::now();
  std::vector<Eigen::VectorXd> thetas;
  for (const Layer& layer : stack.layers) {
    thetas.push_back(
        refined_theta(refined, face_to_vertex_line_field(plate.leftCols<2>(), F, layer.theta)));
  }
  out.timings.fields = seconds_since(start);

  report_progress(options.progress, {"trajectories", 0, num_layers, NAN,
                                     fmt::format("stripe patterns on {} faces", refined.F.rows())});
  start = Clock::now();
  StripeOptions stripe_options = options.stripes;
  stripe_options.spacing = s;
  const Eigen::VectorXd areas = face_areas(plate.leftCols<2>(), F).cwiseAbs();
  const Eigen::VectorXd refined_areas = face_areas(refined.V, refined.F).cwiseAbs();
  TracedStripes traced =
      measure_stripes(F, areas, refined, refined_areas, stack,
                      stripe_patterns(refined.V, refined.F, topology, thetas, stripe_options));
  out.stripe_turn_deg.push_back(traced.mean_turn * 180 / kPi);
  for (int pass = 1; pass <= options.field_corrections; ++pass) {
    report_progress(options.progress,
                    {"trajectories", 0, num_layers, NAN,
                     fmt::format("re-aiming the fields by the stripes' turn ({} of {})", pass,
                                 options.field_corrections)});
    std::vector<Eigen::VectorXd> aimed = thetas;
    for (int k = 0; k < num_layers; ++k) {
      aimed[k] -= refined.S * face_to_vertex_mean(F, areas, traced.turn[k], plate.rows());
    }
    TracedStripes next =
        measure_stripes(F, areas, refined, refined_areas, stack,
                        restripe_patterns(refined.V, refined.F, topology, aimed, thetas,
                                          traced.patterns, stripe_options));
    out.stripe_turn_deg.push_back(next.mean_turn * 180 / kPi);
    // Where the stripes cannot follow the field (lines that diverge need forks, e.g. a radial
    // field), aiming them moves the forks and the turn grows: keep the better pattern.
    if (next.mean_turn >= traced.mean_turn) break;
    traced = std::move(next);
    thetas = std::move(aimed);
    ++out.field_corrections;
  }
  const std::vector<StripePattern>& patterns = traced.patterns;
  out.timings.eigenvector = seconds_since(start);

  // Perimeter loops are the same in every layer.
  std::vector<Polyline2> perimeters;
  if (options.perimeters > 0) {
    start = Clock::now();
    const Eigen::VectorXd distance = boundary_distance(refined.V, plate.leftCols<2>(), F);
    perimeters = perimeter_loops(refined.V, refined.F, distance, options.perimeters, s,
                                 options.min_path_length * s);
    for (Polyline2& loop : perimeters) {
      loop.points = simplify_polyline(loop.points, options.simplify_tolerance_mm);
    }
    out.timings.extraction += seconds_since(start);
  }

  SegmentStyle style;
  style.width = s;
  style.feed_rate = options.feed_rate;
  style.travel = false;
  double z = 0;
  Eigen::Vector2d travel_start = plate.leftCols<2>().colwise().minCoeff().transpose();
  for (int k = 1; k <= num_layers; ++k) {
    const StripePattern& pattern = patterns[k - 1];
    LayerPathReport report;
    report.layer = k;
    const Layer& printed = stack.layers[k - 1];
    style.layer_height = printed.printed_thickness(0);
    style.tool = printed.material(0);
    z += style.layer_height;
    report.z = z;
    report.power_iterations = pattern.iterations;
    report.eigen_residual = pattern.residual;
    for (int f = 0; f < refined.F.rows(); ++f) {
      if (pattern.doubled_index(f) == 0 && pattern.stripe_index(f) == 0) continue;
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      for (int j = 0; j < 3; ++j) c += refined.V.row(refined.F(f, j)).transpose() / 3;
      if (pattern.doubled_index(f) != 0) {
        ++report.field_singular_faces;
        report.singular_points.push_back(c);
      } else {
        ++report.stripe_singular_faces;
        report.fork_points.push_back(c);
      }
    }

    start = Clock::now();
    std::vector<Polyline2> lines = stripe_isolines(refined.V, refined.F, topology, pattern, 0);
    if (options.perimeters > 0) {
      clip_to_inner_region(lines, plate.leftCols<2>(), F,
                           (options.perimeters - 0.5 + options.min_end_gap) * s);
    }
    trim_converging_ends(lines, options.min_end_gap * s);
    report.dropped_fragments = drop_short_polylines(lines, options.min_path_length * s);
    for (Polyline2& line : lines) {
      line.points = simplify_polyline(line.points, options.simplify_tolerance_mm);
    }
    out.timings.extraction += seconds_since(start);

    start = Clock::now();
    ToolpathLayer layer;
    layer.z = report.z;
    layer.height = style.layer_height;
    const auto add_path = [&](const Eigen::MatrixX2d& points, bool reversed, bool closed,
                              PathType type) {
      const int m = static_cast<int>(points.rows());
      PathPolyline path;
      path.points.resize(m, 3);
      for (int i = 0; i < m; ++i) {
        const int from = reversed ? m - 1 - i : i;
        path.points.row(i) << points(from, 0), points(from, 1), report.z;
      }
      path.segments.assign(m - 1, style);
      path.type = type;
      path.closed = closed;
      report.extrusion_mm += polyline_length(points);
      layer.paths.push_back(std::move(path));
    };
    const auto head = [&] {
      const auto& P = layer.paths.back().points;
      return Eigen::Vector2d(P.row(P.rows() - 1).head<2>().transpose());
    };
    for (size_t loop = 0; loop < perimeters.size(); ++loop) {
      // A closed loop may start anywhere: at its point nearest the head.
      const Eigen::MatrixX2d& P = perimeters[loop].points;
      Eigen::Index nearest = 0;
      (P.rowwise() - travel_start.transpose()).rowwise().squaredNorm().minCoeff(&nearest);
      const int m = static_cast<int>(P.rows()) - 1;  // the last point repeats the first
      Eigen::MatrixX2d rotated(m + 1, 2);
      for (int i = 0; i <= m; ++i) rotated.row(i) = P.row((nearest + i) % m);
      if (!layer.paths.empty()) {
        const double jump = (rotated.row(0).transpose() - travel_start).norm();
        report.travel_mm += jump;
        report.travel_greedy_mm += jump;
      }
      add_path(rotated, false, true,
               loop == 0 ? PathType::kExternalPerimeter : PathType::kPerimeter);
      travel_start = head();
    }
    const int n = static_cast<int>(lines.size());
    Eigen::MatrixX2d first(n, 2), last(n, 2);
    for (int p = 0; p < n; ++p) {
      first.row(p) = lines[p].points.row(0);
      last.row(p) = lines[p].points.row(lines[p].points.rows() - 1);
    }
    const PathOrder order = order_paths(first, last, travel_start, options.order);
    const PathOrder greedy = greedy_order(first, last, travel_start);
    // After perimeter loops, the jump from the last loop to the first path is travel too.
    const bool after_loops = !layer.paths.empty();
    report.travel_mm += order.travel + (after_loops ? order.approach : 0);
    report.travel_greedy_mm += greedy.travel + (after_loops ? greedy.approach : 0);
    for (int pos = 0; pos < n; ++pos) {
      const Polyline2& line = lines[order.order[pos]];
      add_path(line.points, order.reversed[pos], line.closed, PathType::kSolidInfill);
    }
    if (!layer.paths.empty()) travel_start = head();
    report.paths = static_cast<int>(layer.paths.size());
    out.timings.ordering += seconds_since(start);
    out.toolpath.layers.push_back(std::move(layer));
    report_progress(options.progress, {"trajectories", k, num_layers, NAN,
                                       fmt::format("layer {}: {} paths", k, report.paths)});
    out.layers.push_back(std::move(report));
  }
  return out;
}

}  // namespace flatmorph
