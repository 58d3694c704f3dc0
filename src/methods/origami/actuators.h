// Curved-crease actuators (Thermorph, CHI 2018, Step 3, Algorithm 1; notes §4): every hinge of a
// crease pattern's tree becomes a strip that bends on an arc, the faces give up the material the
// arc replaces and the far side of each hinge moves back toward it. Millimetres and radians.
#pragma once

#include <utility>
#include <vector>

#include "methods/origami/crease_pattern.h"

namespace flatmorph {

// A hinge folding by `fold_angle` (rad, signed as its crease) on an arc of `radius` mm: W = r|θ|,
// L = 2r tan(|θ|/2), δ = L − W (notes §4); the stacking case and the active PLA speed (mm/s) are
// only carried along. Throws std::invalid_argument for a radius that is not positive and finite.
HingeDesign hinge_design(int crease, double fold_angle, double radius, bool pla_on_bed,
                         double pla_speed);

struct ActuateOptions {
  // A trimmed face narrower than this (its smallest caliper width) is refused: two 0.4 mm lines.
  double min_face_width = 0.8;  // mm
};

// Algorithm 1 on the whole pattern, given one design per hinge of its tree (pattern.is_hinge),
// in any order. Each face's hinge sides move inward by their L/2 and its other sides (cuts, flat
// creases) stay, the corners at the crossings of consecutive lines (notes §4: a hinge side meeting
// a cut at an interior angle α shortens by (L/2) cot α there); then each child and its whole
// subtree move by δ toward the parent, the shifts adding up along the fold order, and the actuator
// fills the W wide gap. A crease off the tree keeps both its sides (folding closes it, or does not:
// loop_closure_error). Throws UserError (kInfeasible) for a hinge folding more than 170° (its L
// grows without bound), naming its faces and angle; and for faces that the trims leave empty,
// inside out, self-intersecting or narrower than options.min_face_width, naming the face that needs
// the largest scale, the uniform scale of the pattern at which every face works (trims follow r,
// not the pattern's size) and the arc radius at which they would work unscaled. Throws
// std::invalid_argument for designs that do not match the pattern's hinges one to one, or a pattern
// without a tree.
ActuatedSheet actuate(const CreasePattern& pattern, const std::vector<HingeDesign>& hinges,
                      const ActuateOptions& options = {});

// The faces (0 ...) that actuate would refuse: left empty, inside out, self-intersecting or
// narrower than options.min_face_width by their hinges' trims; checks the designs as actuate.
std::vector<int> faces_too_narrow(const CreasePattern& pattern,
                                  const std::vector<HingeDesign>& hinges,
                                  const ActuateOptions& options = {});

// The pairs of pieces of the flat printed sheet that overlap (polygons_overlap), pieces numbered
// faces first, then actuators (F + a), each pair (smaller, larger), an actuator and its own two
// faces excepted; empty for a sheet that prints as drawn.
std::vector<std::pair<int, int>> sheet_overlaps(const ActuatedSheet& sheet);

// The widest hole the actuators leave in the folded sheet (curved model, fully folded) at a corner
// of the pattern where two or more hinges meet: the largest distance between the folded corners the
// trimmed faces there keep of it, mm (about L/2 √3 at a cube's corner); 0 without such a corner.
double largest_corner_gap(const CreasePattern& pattern, const ActuatedSheet& sheet);

}  // namespace flatmorph
