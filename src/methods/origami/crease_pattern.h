// A flat sheet that folds (Thermorph, CHI 2018, Steps 2-3; notes §3-4): plane polygon faces seen
// from above (+z, the solid's outward side up), the creases between them with FOLD's assignment
// and signed fold angle, and the tree of hinges the sheet folds along; then the same sheet with
// every hinge replaced by its curved actuator (Algorithm 1). The inverse flow makes one crease
// pattern per net of a solid; the forward flow reads one from an SVG. Millimetres and radians.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "methods/origami/unfold.h"

namespace flatmorph {

// FOLD 1.2's edges_assignment: a border (cut) edge, a mountain, a valley, a flat (unfolded) crease.
enum class CreaseKind { kBorder, kMountain, kValley, kFlat };

struct Crease {
  int v0 = 0, v1 = 0;        // sheet vertices; v0 → v1 runs counter-clockwise around `left`
  int left = 0, right = -1;  // faces; right = −1 on the outline
  CreaseKind kind = CreaseKind::kBorder;
  // π − the dihedral angle, FOLD's sign: a valley > 0, a mountain < 0; 0 for borders and flat
  // creases. rad.
  double fold_angle = 0;
};

struct CreasePattern {
  std::string name;                     // "net 1": names the sheet in messages and files
  Eigen::MatrixX2d V;                   // mm
  std::vector<std::vector<int>> faces;  // counter-clockwise seen from +z
  std::vector<Crease> creases;          // every edge of the sheet once
  // How it folds: the face that stays put, and per face the crease to its parent in a spanning
  // tree of the faces joined by mountain and valley creases (−1 for the root). Creases off the
  // tree close loops: folding the tree must bring their two sides together.
  int root = 0;
  std::vector<int> parent_crease;
  std::vector<int> fold_order;  // every face once, each after its parent (the root first)
  // Per face, the face of the solid it unfolds (−1 when the sheet came from a drawing).
  std::vector<int> solid_face;

  int num_faces() const { return static_cast<int>(faces.size()); }
  // The face across crease `c` from face `f`.
  int other_face(int c, int f) const;
  // Whether crease `c` is a fold of the tree (a hinge an actuator is printed on).
  bool is_hinge(int c) const;
};

// Net `net` of `unfolding` as a sheet: its faces' flat corners joined where a hinge joins them,
// the tree and order of the net, every crease's kind from its fold angle (|θ| < `flat_angle` rad:
// flat). Throws std::invalid_argument for a net index out of range.
CreasePattern crease_pattern_of_net(const Unfolding& unfolding, int net, const std::string& name,
                                    double flat_angle);

// The sheet turned over (printed with its other side up): y ↦ −y, every face still
// counter-clockwise from +z, mountains become valleys and fold angles change sign. Folded, it gives
// the same solid, turned half a turn about the x axis.
CreasePattern turned_over(const CreasePattern& pattern);

// How one hinge's actuator is printed and bends (notes §4-5): it bends to an arc of `radius`,
// so it is W = r|θ| wide, each face gives up L/2 = r tan(|θ|/2) along it, and the child side moves
// δ = L − W toward the parent. Case A (PLA on the bed, TPU on top) curls the faces toward the bed:
// a mountain seen from above; case B (TPU on the bed) a valley.
struct HingeDesign {
  int crease = 0;          // index into CreasePattern::creases
  double fold_angle = 0;   // rad, signed as the crease's
  double radius = 0;       // r, mm
  double width = 0;        // W = r|θ|, mm
  double cut = 0;          // L = 2 r tan(|θ|/2), mm
  double shift = 0;        // δ = L − W, mm
  bool pla_on_bed = true;  // case A; false: case B
  double pla_speed = 0;    // mm/s, the active PLA lines
};

// The sheet as printed: faces trimmed and shifted, and an actuator between the two sides of each
// hinge (Algorithm 1).
struct Actuator {
  HingeDesign hinge;
  int parent_face = 0, child_face = 0;
  // The strip, counter-clockwise: corners 0, 1 on the parent's trimmed edge, 2, 3 on the child's.
  Eigen::Matrix<double, 4, 2> quad;
  Eigen::Vector2d across{0, 0};  // unit, perpendicular to the hinge, from the parent to the child
};

struct ActuatedSheet {
  std::string name;
  std::vector<Eigen::MatrixX2d> faces;  // per face of the pattern: trimmed and shifted, mm, CCW
  std::vector<Actuator> actuators;      // one per hinge, in the pattern's fold order
};

}  // namespace flatmorph
