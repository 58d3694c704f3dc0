// The sheet folding (Thermorph, issue 27 item 6; notes §7): the crease pattern folded sharply about
// its hinges, the printed sheet folded with every actuator bent on its arc, and the first collision
// between pieces on the way from flat to folded. Millimetres and radians; the sheet lies in z = 0
// seen from +z, its root face stays put, and a valley (fold angle > 0) lifts the child toward +z.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "methods/origami/crease_pattern.h"

namespace flatmorph {

// Throws std::invalid_argument unless the pattern's tree is whole: a parent crease per face (−1 for
// the root only) joining it to another face, and a fold order listing every face once, the root
// first, each face after its parent.
void check_fold_tree(const CreasePattern& pattern);

// Every face turned about its crease to its parent by `progress` (0 flat, 1 folded) times the
// crease's fold angle (notes §7, sharp model): per face its corners in 3D, mm. Throws
// std::invalid_argument for a pattern without a tree over its faces.
std::vector<Eigen::MatrixX3d> fold_sharp(const CreasePattern& pattern, double progress);

// Folded fully, the largest distance between the two sides of a crease off the tree, mm: 0 for a
// net (its other creases are cuts); for a drawn pattern with loops, whether it folds rigidly.
double loop_closure_error(const CreasePattern& pattern);

// An actuator bent on its arc: its two ends (the side from quad corner 0 to 3 and the side from
// corner 1 to 2) as polylines of arc_steps + 1 points, mm.
struct ActuatorStrip {
  Eigen::MatrixX3d side0, side1;
};

struct FoldedSheet {
  std::vector<Eigen::MatrixX3d> faces;   // per face of the sheet: its trimmed corners in 3D, mm
  std::vector<ActuatorStrip> actuators;  // per actuator of the sheet
};

// The printed sheet folded (notes §7, curved model): across an actuator a point at distance
// s ∈ [0, W] from the parent's trimmed edge goes to the arc (ρ sin(s/ρ), ±ρ (1 − cos(s/ρ))), and
// the child continues from the arc's end turned by the arc's angle. At `progress` t every hinge
// bends to t·θ with its width W unchanged (radius ρ = W / (t |θ|)); at t = 1 every face lies in the
// plane its sharp fold gives it (notes §4). `arc_steps` ≥ 1 segments per arc. Throws
// std::invalid_argument for a sheet that is not `pattern` actuated, progress outside [0, 1] or
// arc_steps < 1.
FoldedSheet fold_curved(const CreasePattern& pattern, const ActuatedSheet& sheet, double progress,
                        int arc_steps);

// The folded sheet as one triangle mesh (folded.ply): each face ear-clipped, each step of an
// actuator's strip a quad cut in two, normals on the sheet's upper side; pieces are not welded.
Mesh folded_mesh(const FoldedSheet& folded);

// Whether two triangles (rows: corners, mm) cross by more than `tolerance`: each is shrunk by
// `tolerance` toward its incentre first, so triangles touching along a side or at a corner do not
// count, while coplanar ones that share area do. A triangle narrower than the tolerance never does.
bool triangles_intersect(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, double tolerance);

// Pieces are numbered faces first (0 … F − 1), then actuators (F + a for sheet.actuators[a]).
struct FoldCollision {
  int piece_a = 0, piece_b = 0;  // piece_a < piece_b
  double progress = 0;           // of the whole fold, in [0, 1]
  // In fold order: the actuator (index into sheet.actuators) that was bending; −1 when every hinge
  // bends together.
  int folding_actuator = -1;
};

// Folds the sheet from flat (progress 0) to folded in `steps` steps per stage, every hinge together
// or, with `in_fold_order`, one actuator after another in the sheet's order (the pattern's fold
// order; progress then counts the finished actuators), and returns the first pair of pieces that
// cross (triangles_intersect at 1e-6 of the sheet's diagonal) from the first step on; the flat
// sheet is sheet_overlaps' to check. Neighbours are not tested: a face and its own actuators, two
// faces joined by a crease of the tree. Throws std::invalid_argument for steps < 1.
std::optional<FoldCollision> first_collision(const CreasePattern& pattern,
                                             const ActuatedSheet& sheet, int steps = 50,
                                             bool in_fold_order = false);

// "face 3" or "actuator 2 (faces 1–3)": a piece as messages name it, numbered from 1 as net.svg
// and design.json number faces.
std::string piece_name(const ActuatedSheet& sheet, int piece);

}  // namespace flatmorph
