#include "methods/origami/design_origami.h"

#include <fmt/core.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

#include "common/error.h"
#include "common/stopwatch.h"
#include "methods/origami/sheet_layout.h"
#include "plate/actuator_stack.h"
#include "plate/layer_stack.h"
#include "simulate/distance.h"

namespace flatmorph {
namespace {

// Between two beds laid side by side in plate coordinates, mm.
constexpr double kBedSpacing = 20;

// The curve the hinges fold by: the PLA's calibrated one, else the laminate's default for this
// actuator.
HingeCurve hinge_curve_of(const OrigamiOptions& options) {
  if (options.pla.hinge_curve) return *options.pla.hinge_curve;
  return default_hinge_curve(options.pla, options.tpu, options.print.stack);
}

// Mountains print case A (PLA on the bed: the stronger, more repeatable bend, notes §3), so the
// sheet goes the side up that makes most of the folding (by |θ|) mountains.
bool mostly_valleys(const CreasePattern& pattern) {
  double mountains = 0, valleys = 0;
  for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
    if (!pattern.is_hinge(c)) continue;
    const double angle = pattern.creases[c].fold_angle;
    (angle < 0 ? mountains : valleys) += std::abs(angle);
  }
  return valleys > mountains;
}

// Per hinge: case A for a mountain, B for a valley; r from the curve at the actuator speed, or
// the speed from the curve at the fixed width.
std::vector<HingeDesign> design_hinges(const CreasePattern& pattern, const HingeCurve& curve,
                                       const OrigamiOptions& options) {
  std::vector<HingeDesign> hinges;
  for (int c = 0; c < static_cast<int>(pattern.creases.size()); ++c) {
    if (!pattern.is_hinge(c)) continue;
    const Crease& crease = pattern.creases[c];
    const bool pla_on_bed = crease.fold_angle < 0;
    double speed = options.actuator_speed;
    double curvature = 0;
    try {
      if (options.actuator_width > 0) {
        curvature = std::abs(crease.fold_angle) / options.actuator_width;
        speed = hinge_speed_for_curvature(curve, curvature, pla_on_bed);
      } else {
        curvature = hinge_curvature(curve, speed, pla_on_bed);
      }
    } catch (const UserError& e) {
      throw UserError(
          e.category(),
          fmt::format("{}: the hinge between faces {} and {} folds {:.1f}° ({}): {}", pattern.name,
                      crease.left + 1, crease.right + 1, crease.fold_angle * 180 / std::numbers::pi,
                      hinge_case_name(pla_on_bed), e.what()));
    }
    hinges.push_back(hinge_design(c, crease.fold_angle, 1 / curvature, pla_on_bed, speed));
  }
  return hinges;
}

// Actuates, lays on the bed, folds and checks each pattern; the toolpath of them all.
// The pattern the side up that makes most folds mountains, with its hinges designed.
OrigamiSheet prepared_sheet(CreasePattern pattern, const HingeCurve& curve,
                            const OrigamiOptions& options) {
  OrigamiSheet sheet;
  sheet.turned_over = mostly_valleys(pattern);
  sheet.pattern = sheet.turned_over ? turned_over(pattern) : std::move(pattern);
  sheet.hinges = design_hinges(sheet.pattern, curve, options);
  return sheet;
}

// When the printed sheet does not fit the room (x, y mm), the face whose hinge to its parent
// cuts it into the two parts that come nearest to fitting (the larger room_overfill of the two
// the smallest); −1 when it fits. Last resort of the retree: the solid then prints as more nets.
int bed_splitting_face(const CreasePattern& pattern, const ActuatedSheet& sheet,
                       const Eigen::Vector2d& room) {
  if (room_overfill(sheet_points(sheet), room) <= 1) return -1;
  const int num_faces = pattern.num_faces();
  int best = -1;
  double best_overfill = INFINITY;
  for (int child = 0; child < num_faces; ++child) {
    if (child == pattern.root) continue;
    std::vector<bool> below(num_faces, false);  // the child's subtree
    for (int f = 0; f < num_faces; ++f) {
      for (int g = f; g != pattern.root;) {
        if (g == child) {
          below[f] = true;
          break;
        }
        const Crease& crease = pattern.creases[pattern.parent_crease[g]];
        g = crease.left == g ? crease.right : crease.left;
      }
    }
    std::vector<Eigen::Vector2d> parts[2];
    for (int f = 0; f < num_faces; ++f) {
      for (Eigen::Index k = 0; k < sheet.faces[f].rows(); ++k) {
        parts[below[f]].push_back(sheet.faces[f].row(k).transpose());
      }
    }
    for (const Actuator& actuator : sheet.actuators) {
      if (actuator.child_face == child) continue;  // the cut strip goes
      for (int k = 0; k < 4; ++k) {
        parts[below[actuator.child_face]].push_back(actuator.quad.row(k).transpose());
      }
    }
    double overfill = 0;
    for (const std::vector<Eigen::Vector2d>& part : parts) {
      Eigen::MatrixX2d points(part.size(), 2);
      for (size_t i = 0; i < part.size(); ++i) points.row(i) = part[i].transpose();
      overfill = std::max(overfill, room_overfill(points, room));
    }
    if (overfill < best_overfill) {
      best_overfill = overfill;
      best = child;
    }
  }
  return best;
}

// The solid's edges (polyhedron_edges) of the hinges that keep this net from printing: per face
// its trims eat, the hinge of that face with the largest cut; per pair of pieces that overlap
// once the actuators are in, the hinge to the parent of each; for a sheet larger than the room,
// the hinge that splits it best (bed_splitting_face). Empty when the net prints.
std::vector<int> unprintable_hinges(const OrigamiSheet& sheet, const Unfolding& unfolding,
                                    const OrigamiOptions& options) {
  const CreasePattern& pattern = sheet.pattern;
  // A hinge is the parent crease of its child face, whose solid face's parent edge it is.
  const auto solid_edge_to_parent = [&](int f) {
    return unfolding.parent_edge(pattern.solid_face[f]);
  };
  std::vector<int> edges;
  const std::vector<int> narrow = faces_too_narrow(pattern, sheet.hinges, options.actuate);
  for (int f : narrow) {
    int child = -1;  // the face below the hinge with the largest cut at f
    double largest = 0;
    for (const HingeDesign& hinge : sheet.hinges) {
      const Crease& crease = pattern.creases[hinge.crease];
      if (crease.left != f && crease.right != f) continue;
      const int below =
          pattern.parent_crease[crease.left] == hinge.crease ? crease.left : crease.right;
      if (hinge.cut > largest) {
        largest = hinge.cut;
        child = below;
      }
    }
    if (child >= 0) edges.push_back(solid_edge_to_parent(child));
  }
  if (!edges.empty()) return edges;
  const ActuatedSheet actuated = actuate(pattern, sheet.hinges, options.actuate);
  const int num_faces = pattern.num_faces();
  for (const auto& [a, b] : sheet_overlaps(actuated)) {
    for (int piece : {a, b}) {
      const int f = piece < num_faces ? piece : actuated.actuators[piece - num_faces].child_face;
      if (f != pattern.root) edges.push_back(solid_edge_to_parent(f));
    }
  }
  if (!edges.empty()) return edges;
  const int split = bed_splitting_face(pattern, actuated, options.room);
  if (split >= 0) edges.push_back(solid_edge_to_parent(split));
  return edges;
}

// What the design says of a sheet whose pieces collide on the way to the folded shape.
std::string collision_warning(const OrigamiSheet& sheet) {
  return fmt::format("{}: folding every hinge together, {} runs into {} at {:.0f} % of the fold{}",
                     sheet.pattern.name, piece_name(sheet.sheet, sheet.collision->piece_a),
                     piece_name(sheet.sheet, sheet.collision->piece_b),
                     100 * sheet.collision->progress,
                     sheet.order_collision ? "; folding hinge after hinge does not avoid it"
                                           : "; folding hinge after hinge in the fold order "
                                             "avoids it: hold the faces back as the report shows");
}

void make_sheets(std::vector<OrigamiSheet> prepared, const OrigamiOptions& options,
                 OrigamiDesign& design) {
  const auto start = Clock::now();
  std::vector<Eigen::AlignedBox2d> boxes;
  std::vector<std::string> names;
  for (OrigamiSheet& sheet : prepared) {
    sheet.sheet = actuate(sheet.pattern, sheet.hinges, options.actuate);
    sheet.sheet.name = sheet.pattern.name;
    const std::vector<std::pair<int, int>> overlaps = sheet_overlaps(sheet.sheet);
    if (!overlaps.empty()) {
      throw UserError(
          ErrorCategory::kInfeasible,
          fmt::format("{}: with its actuators in place, {} and {} overlap in the flat sheet: "
                      "print the actuators narrower (a faster --actuator-speed) or make the "
                      "solid larger (--size)",
                      sheet.pattern.name, piece_name(sheet.sheet, overlaps[0].first),
                      piece_name(sheet.sheet, overlaps[0].second)));
    }
    // Turned so that its smallest bounding rectangle lies along the axes, then placed below.
    const double angle = turn_to_room(sheet_points(sheet.sheet), options.room);
    place_sheet(angle, Eigen::Vector2d::Zero(), sheet.pattern, sheet.sheet);
    const Eigen::MatrixX2d points = sheet_points(sheet.sheet);
    boxes.emplace_back(points.colwise().minCoeff().transpose(),
                       points.colwise().maxCoeff().transpose());
    names.push_back(sheet.pattern.name);
    design.sheets.push_back(std::move(sheet));
  }
  // The beds lie side by side in plate coordinates (flat.ply shows them all); each bed's G-code
  // is placed on the printer on its own.
  const BedPlacement placement = pack_on_beds(boxes, names, options.room, options.sheet_gap);
  design.num_beds = placement.num_beds;
  for (size_t i = 0; i < design.sheets.size(); ++i) {
    OrigamiSheet& sheet = design.sheets[i];
    sheet.bed = placement.bed[i];
    const Eigen::Vector2d bed_origin(sheet.bed * (options.room.x() + kBedSpacing), 0);
    place_sheet(0, bed_origin + placement.corner[i] - boxes[i].min(), sheet.pattern, sheet.sheet);
  }
  design.times.actuate = seconds_since(start);

  const auto fold_start = Clock::now();
  for (size_t i = 0; i < design.sheets.size(); ++i) {
    OrigamiSheet& sheet = design.sheets[i];
    report_progress(options.progress,
                    {"fold", static_cast<int>(i) + 1, static_cast<int>(design.sheets.size()), NAN,
                     sheet.pattern.name});
    sheet.folded = fold_curved(sheet.pattern, sheet.sheet, 1.0, 8);
    sheet.collision = first_collision(sheet.pattern, sheet.sheet, options.fold_steps, false);
    sheet.order_collision = first_collision(sheet.pattern, sheet.sheet, options.fold_steps, true);
    sheet.corner_gap = largest_corner_gap(sheet.pattern, sheet.sheet);
    sheet.loop_closure = loop_closure_error(sheet.pattern);
    if (sheet.collision) design.warnings.push_back(collision_warning(sheet));
  }
  design.times.fold = seconds_since(fold_start);

  const auto toolpath_start = Clock::now();
  report_progress(options.progress, {"toolpath", 0, 0, NAN, "faces in PLA, actuators in PLA/TPU"});
  design.bed_toolpaths.assign(design.num_beds, Toolpath{});
  for (const OrigamiSheet& sheet : design.sheets) {
    const Toolpath part = origami_toolpath(sheet.sheet, options.print);
    Toolpath& toolpath = design.bed_toolpaths[sheet.bed];
    if (toolpath.layers.empty()) {
      toolpath = part;
      continue;
    }
    for (size_t k = 0; k < part.layers.size(); ++k) {
      std::vector<PathPolyline>& paths = toolpath.layers[k].paths;
      paths.insert(paths.end(), part.layers[k].paths.begin(), part.layers[k].paths.end());
    }
  }
  // Every sheet's layer prints one material, then the other (notes §8): each layer first takes
  // the tool the layer below ended with, so that the sheets together change no more often than
  // one does.
  for (Toolpath& toolpath : design.bed_toolpaths) {
    int last_tool = -1;
    for (ToolpathLayer& layer : toolpath.layers) {
      if (layer.paths.empty()) continue;
      const int first = last_tool >= 0 ? last_tool : layer.paths.front().segments.front().tool;
      std::stable_partition(layer.paths.begin(), layer.paths.end(), [&](const PathPolyline& path) {
        return path.segments.front().tool == first;
      });
      last_tool = layer.paths.back().segments.front().tool;
    }
  }
  design.times.toolpath = seconds_since(toolpath_start);
}

// Notes §11: every fold angle is π − the dihedral; folded back, the nets give the solid, and each
// face of the curved model lies on its face's plane.
void check_against_solid(OrigamiDesign& design) {
  const Polyhedron& solid = *design.solid;
  const Unfolding& unfolding = *design.unfolding;
  design.fold_angle_error = 0;
  design.sharp_error_pct = 0;
  design.curved_plane_error_pct = 0;
  const double diagonal = (solid.V.colwise().maxCoeff() - solid.V.colwise().minCoeff()).norm();
  for (int e = 0; e < static_cast<int>(unfolding.edges.size()); ++e) {
    const PolyhedronEdge& edge = unfolding.edges[e];
    if (edge.right < 0) continue;
    const double cosine =
        std::clamp(face_normal(solid, edge.left).dot(face_normal(solid, edge.right)), -1.0, 1.0);
    const double dihedral = std::numbers::pi - std::acos(cosine);
    design.fold_angle_error =
        std::max(design.fold_angle_error,
                 std::abs(std::abs(unfolding.fold_angle(e)) - (std::numbers::pi - dihedral)));
  }
  for (const OrigamiSheet& sheet : design.sheets) {
    const CreasePattern& pattern = sheet.pattern;
    const std::vector<Eigen::MatrixX3d> sharp = fold_sharp(pattern, 1.0);
    Eigen::Index corners = 0;
    for (const Eigen::MatrixX3d& face : sharp) corners += face.rows();
    Eigen::MatrixXd folded(corners, 3), target(corners, 3);
    Eigen::Index row = 0;
    for (int f = 0; f < pattern.num_faces(); ++f) {
      const std::vector<int>& face = solid.faces[pattern.solid_face[f]];
      for (size_t k = 0; k < face.size(); ++k, ++row) {
        // Turned over, the sheet runs each face's corners the other way round.
        const size_t corner = sheet.turned_over ? face.size() - 1 - k : k;
        folded.row(row) = sharp[f].row(static_cast<Eigen::Index>(corner));
        target.row(row) = solid.V.row(face[k]);
      }
    }
    const RigidFit fit = best_rigid_fit(folded, target);
    const Eigen::MatrixXd aligned =
        (folded * fit.rotation.transpose()).rowwise() + fit.translation.transpose();
    design.sharp_error_pct = std::max(
        design.sharp_error_pct, 100 * (aligned - target).rowwise().norm().maxCoeff() / diagonal);
    for (int f = 0; f < pattern.num_faces(); ++f) {
      const int s = pattern.solid_face[f];
      const Eigen::Vector3d normal = face_normal(solid, s);
      const Eigen::Vector3d on_plane = solid.V.row(solid.faces[s][0]).transpose();
      const Eigen::MatrixX3d& curved = sheet.folded.faces[f];
      for (Eigen::Index k = 0; k < curved.rows(); ++k) {
        const Eigen::Vector3d p = fit.rotation * curved.row(k).transpose() + fit.translation;
        design.curved_plane_error_pct = std::max(
            design.curved_plane_error_pct, 100 * std::abs(normal.dot(p - on_plane)) / diagonal);
      }
    }
  }
}

// With the uncalibrated curve, a case B actuator folds less than promised once its hinge is
// longer than it is wide (docs/origami.md): each sheet that prints some says which.
void warn_of_case_b(OrigamiDesign& design) {
  if (design.curve.calibrated) return;
  for (const OrigamiSheet& sheet : design.sheets) {
    std::vector<std::string> weak;  // "3-4": face numbers from 1, as net.svg shows them
    for (const HingeDesign& hinge : sheet.hinges) {
      const Crease& crease = sheet.pattern.creases[hinge.crease];
      if (!hinge.pla_on_bed) {
        weak.push_back(fmt::format("{}-{}", crease.left + 1, crease.right + 1));
      }
    }
    if (weak.empty()) continue;
    design.warnings.push_back(fmt::format(
        "{}: {} print{} case B (TPU on the bed; between faces {}): with the uncalibrated hinge "
        "curve a case B actuator folds less than promised once its hinge is longer than it is "
        "wide (it curls along the hinge); calibrate the hinges ('flatmorph calibrate print "
        "--hinge-sheet') or check them with --simulate",
        sheet.pattern.name, weak.size() == 1 ? "1 hinge" : fmt::format("{} hinges", weak.size()),
        weak.size() == 1 ? "s" : "", fmt::join(weak, ", ")));
  }
}

}  // namespace

LayerStack printed_sheet_stack(const std::vector<OrigamiSheet>& sheets,
                               const Eigen::VectorXi& sheet_of, const Eigen::VectorXi& piece,
                               const OrigamiOptions& options) {
  const HingeStack& stack = options.print.stack;
  const int num_faces = static_cast<int>(piece.size());
  LayerStack out;
  out.materials = {thermorph_pla(options.pla, stack), options.tpu};
  // The faces shrink by the same rule as the active PLA (active_lambda1 at their slower speed,
  // the bed side more), their directions crossed as the toolpath lays them.
  const auto [slowest, fastest] = active_speed_range(options.pla);
  const double face_lambda1 =
      active_lambda1(options.pla, stack, std::clamp(options.print.face_speed, slowest, fastest));
  const int num_layers = stack.pla_layers + stack.tpu_layers;
  const double rise = std::abs(options.pla.delta_lambda1);
  for (int k = 0; k < num_layers; ++k) {
    Layer layer = uniform_layer(num_faces, 0, options.pla, stack.layer_height);
    layer.lambda1.setConstant(face_lambda1 + ((k + 0.5) / num_layers - 0.5) * rise);
    layer.delta_lambda1.setConstant(rise / num_layers);
    layer.lambda2.setOnes();
    layer.lambda3.setOnes();
    layer.theta.setConstant(face_lines_along_y(k, num_layers) ? std::numbers::pi / 2 : 0.0);
    out.layers.push_back(layer);
  }
  // Each actuator's own layers (actuator_layer_stack), once per actuator.
  std::vector<std::vector<LayerStack>> own(sheets.size());
  for (size_t s = 0; s < sheets.size(); ++s) {
    for (const Actuator& actuator : sheets[s].sheet.actuators) {
      own[s].push_back(actuator_layer_stack(
          options.pla, options.tpu, stack,
          active_lambda1(options.pla, stack, actuator.hinge.pla_speed), actuator.hinge.pla_on_bed,
          std::atan2(actuator.across.y(), actuator.across.x()), 1));
    }
  }
  for (int t = 0; t < num_faces; ++t) {
    const int faces = static_cast<int>(sheets[sheet_of(t)].sheet.faces.size());
    if (piece(t) < faces) continue;
    const LayerStack& from = own[sheet_of(t)][piece(t) - faces];
    for (size_t k = 0; k < out.layers.size(); ++k) {
      const Layer& a = from.layers[k];
      Layer& b = out.layers[k];
      b.printed_thickness(t) = a.printed_thickness(0);
      b.material(t) = a.material(0);
      b.theta(t) = a.theta(0);
      b.lambda1(t) = a.lambda1(0);
      b.delta_lambda1(t) = a.delta_lambda1(0);
      b.lambda2(t) = a.lambda2(0);
      b.lambda3(t) = a.lambda3(0);
      b.cover(t) = a.cover(0);
    }
  }
  return out;
}

OrigamiPlate origami_plate(const OrigamiDesign& design, const OrigamiOptions& options,
                           int arc_steps) {
  std::vector<Eigen::MatrixXd> flat_parts, folded_parts;
  std::vector<Eigen::MatrixXi> face_parts;
  std::vector<double> piece, sheet_of;
  int num_vertices = 0;
  for (size_t s = 0; s < design.sheets.size(); ++s) {
    const OrigamiSheet& sheet = design.sheets[s];
    const Mesh flat = folded_mesh(fold_curved(sheet.pattern, sheet.sheet, 0.0, arc_steps));
    const Mesh folded = folded_mesh(fold_curved(sheet.pattern, sheet.sheet, 1.0, arc_steps));
    flat_parts.push_back(flat.V.leftCols(2));
    folded_parts.push_back(folded.V);
    face_parts.push_back(flat.F.array() + num_vertices);
    num_vertices += flat.num_vertices();
    // folded_mesh's order: each face's n − 2 triangles, then 2 per arc step of each actuator.
    for (size_t f = 0; f < sheet.sheet.faces.size(); ++f) {
      piece.insert(piece.end(), sheet.sheet.faces[f].rows() - 2, static_cast<double>(f));
    }
    for (size_t a = 0; a < sheet.sheet.actuators.size(); ++a) {
      piece.insert(piece.end(), 2 * arc_steps, static_cast<double>(sheet.sheet.faces.size() + a));
    }
    sheet_of.resize(piece.size(), static_cast<double>(s));
  }
  OrigamiPlate out;
  PlateDesign& plate = out.plate;
  plate.method = "origami";
  plate.plate.resize(num_vertices, 2);
  out.folded.V.resize(num_vertices, 3);
  Eigen::Index rows = 0, v = 0;
  for (const Eigen::MatrixXi& F : face_parts) rows += F.rows();
  plate.F.resize(rows, 3);
  rows = 0;
  for (size_t s = 0; s < flat_parts.size(); ++s) {
    plate.plate.middleRows(v, flat_parts[s].rows()) = flat_parts[s];
    out.folded.V.middleRows(v, folded_parts[s].rows()) = folded_parts[s];
    v += flat_parts[s].rows();
    plate.F.middleRows(rows, face_parts[s].rows()) = face_parts[s];
    rows += face_parts[s].rows();
  }
  out.folded.F = plate.F;
  if (static_cast<Eigen::Index>(piece.size()) != rows) {
    throw std::logic_error("origami_plate: folded_mesh's triangles are not its pieces'");
  }

  plate.stack = printed_sheet_stack(
      design.sheets, Eigen::Map<const Eigen::VectorXd>(sheet_of.data(), rows).cast<int>(),
      Eigen::Map<const Eigen::VectorXd>(piece.data(), rows).cast<int>(), options);
  const int num_faces = static_cast<int>(rows);
  plate.design_fields.set_face("piece", Eigen::Map<const Eigen::VectorXd>(piece.data(), num_faces));
  plate.design_fields.set_face("sheet",
                               Eigen::Map<const Eigen::VectorXd>(sheet_of.data(), num_faces));
  return out;
}

Eigen::MatrixXi bed_faces(const OrigamiPlate& plate, const OrigamiDesign& design, int bed) {
  const Eigen::VectorXd& sheet_of = *plate.plate.design_fields.find_face("sheet");
  std::vector<int> rows;
  for (Eigen::Index t = 0; t < sheet_of.size(); ++t) {
    if (design.sheets[static_cast<int>(sheet_of(t))].bed == bed) rows.push_back(t);
  }
  return plate.plate.F(rows, Eigen::all);
}

Polyhedron scaled_to_size(const Polyhedron& solid, double size) {
  Polyhedron out = solid;
  const Eigen::RowVector3d lo = solid.V.colwise().minCoeff(), hi = solid.V.colwise().maxCoeff();
  const double longest = (hi - lo).maxCoeff();
  if (!(size > 0) || !(longest > 0)) {
    throw std::invalid_argument("scaled_to_size: a size and a solid of positive extent");
  }
  const Eigen::RowVector3d centre = 0.5 * (lo + hi);
  out.V = ((solid.V.rowwise() - centre) * (size / longest)).rowwise() + centre;
  return out;
}

OrigamiDesign design_origami(const Polyhedron& solid, const OrigamiOptions& options) {
  const auto start = Clock::now();
  OrigamiDesign design;
  design.curve = hinge_curve_of(options);
  report_progress(options.progress,
                  {"unfold", 0, 0, NAN, fmt::format("{} faces", solid.faces.size())});
  // Case B hinges bend less, so they need wider actuators: the tree prefers to cut them, the more
  // the weaker they are. Uncalibrated, it cuts them all: the default model's case B actuator
  // curls along its hinge and folds far less than its curve promises once the hinge is longer
  // than it is wide (docs/origami.md), so the nets fold on case A actuators alone, as every
  // polyhedron of the paper does (Fig. 10f).
  UnfoldOptions unfold_options = options.unfold;
  const double mid = 0.5 * (design.curve.min_speed + design.curve.max_speed);
  unfold_options.minority_weight = design.curve.calibrated || options.case_b_hinges
                                       ? std::min(1.0, hinge_curvature(design.curve, mid, false) /
                                                           hinge_curvature(design.curve, mid, true))
                                       : 0.0;
  unfold_options.edge_weight.assign(polyhedron_edges(solid).size(), 1.0);
  // A tree whose trims eat a face, or whose shifted faces overlap, is unfolded again with those
  // hinges turned down, so that the next tree cuts them (bounded: the last tree's problem is
  // then refused by actuate with what would fix it).
  std::vector<OrigamiSheet> prepared, first_tree;
  std::optional<Unfolding> first_unfolding;
  for (int round = 0;; ++round) {
    design.unfolding = unfold(solid, unfold_options);
    prepared.clear();
    std::vector<int> unprintable;
    for (size_t n = 0; n < design.unfolding->nets.size(); ++n) {
      prepared.push_back(
          prepared_sheet(crease_pattern_of_net(*design.unfolding, static_cast<int>(n),
                                               fmt::format("net {}", n + 1), options.flat_angle),
                         design.curve, options));
      if (round < options.retrees) {
        for (int e : unprintable_hinges(prepared.back(), *design.unfolding, options)) {
          unprintable.push_back(e);
        }
      }
    }
    if (round == 0) {
      first_tree = prepared;
      first_unfolding = design.unfolding;
    }
    if (unprintable.empty()) break;
    // Turned down once, the next tree may route around it; at fault again, it is cut for good
    // (the solid may then print as several nets).
    for (int e : unprintable) {
      double& weight = unfold_options.edge_weight[e];
      weight = weight < 1 ? 0 : 1e-3;
    }
  }
  // Cut apart into loose faces, the solid would no longer fold itself: below that share of the
  // first tree's hinges (those the case policy above leaves), the first tree is actuated and
  // refused with the scale that saves it.
  size_t hinges = 0, first_hinges = 0;
  for (const OrigamiSheet& sheet : prepared) hinges += sheet.hinges.size();
  for (const OrigamiSheet& sheet : first_tree) first_hinges += sheet.hinges.size();
  if (hinges < options.min_hinge_share * first_hinges) {
    prepared = std::move(first_tree);
    design.unfolding = std::move(first_unfolding);
  }
  const Unfolding& unfolding = *design.unfolding;
  design.times.unfold = seconds_since(start);
  if (unfolding.nets.size() > 1) {
    design.warnings.push_back(fmt::format(
        "no single net of the {} faces lies flat and prints without overlapping itself: printed "
        "as {} nets to join after folding",
        solid.faces.size(), unfolding.nets.size()));
  }
  make_sheets(std::move(prepared), options, design);
  warn_of_case_b(design);

  design.solid = solid;
  check_against_solid(design);
  design.times.total = seconds_since(start);
  return design;
}

OrigamiDesign with_hinges_widened(const OrigamiDesign& design,
                                  const std::vector<std::vector<double>>& width_scale,
                                  const OrigamiOptions& options) {
  const auto start = Clock::now();
  if (width_scale.size() != design.sheets.size()) {
    throw std::invalid_argument("with_hinges_widened: one list of scales per sheet");
  }
  OrigamiDesign out;
  out.solid = design.solid;
  out.unfolding = design.unfolding;
  out.curve = design.curve;
  // The sheets' collisions are found anew.
  out.warnings = design.warnings;
  for (const OrigamiSheet& sheet : design.sheets) {
    if (sheet.collision) std::erase(out.warnings, collision_warning(sheet));
  }
  std::vector<OrigamiSheet> prepared;
  for (size_t s = 0; s < design.sheets.size(); ++s) {
    const OrigamiSheet& from = design.sheets[s];
    const std::vector<Actuator>& actuators = from.sheet.actuators;
    if (width_scale[s].size() != actuators.size()) {
      throw std::invalid_argument("with_hinges_widened: one scale per actuator");
    }
    OrigamiSheet sheet;
    sheet.pattern = from.pattern;
    sheet.turned_over = from.turned_over;
    for (const HingeDesign& hinge : from.hinges) {
      double scale = 1;
      for (size_t a = 0; a < actuators.size(); ++a) {
        if (actuators[a].hinge.crease == hinge.crease) scale = width_scale[s][a];
      }
      if (!(scale > 0) || !std::isfinite(scale)) {
        throw std::invalid_argument("with_hinges_widened: scales must be positive and finite");
      }
      sheet.hinges.push_back(hinge_design(hinge.crease, hinge.fold_angle, hinge.radius * scale,
                                          hinge.pla_on_bed, hinge.pla_speed));
    }
    prepared.push_back(std::move(sheet));
  }
  make_sheets(std::move(prepared), options, out);
  if (out.solid) check_against_solid(out);
  out.times.total = seconds_since(start);
  return out;
}

OrigamiDesign design_origami_pattern(const CreasePattern& pattern, const OrigamiOptions& options) {
  const auto start = Clock::now();
  OrigamiDesign design;
  design.curve = hinge_curve_of(options);
  std::vector<OrigamiSheet> prepared;
  prepared.push_back(prepared_sheet(pattern, design.curve, options));
  make_sheets(std::move(prepared), options, design);
  if (design.sheets[0].loop_closure > 1e-3) {
    design.warnings.push_back(fmt::format(
        "{}: folded rigidly along its tree, two sides of a crease off the tree end {:.2f} mm "
        "apart: the drawn angles do not close around a vertex",
        pattern.name, design.sheets[0].loop_closure));
  }
  warn_of_case_b(design);
  design.times.total = seconds_since(start);
  return design;
}

}  // namespace flatmorph
